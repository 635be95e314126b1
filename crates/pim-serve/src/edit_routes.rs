//! The routes that edit the case text from the plan: a rest or mark moved, a mark, a traced
//! mark or a friction zone added, the geometry at contact moved, a skid set. Each answers the edited text
//! (not saved) or the refusal that says why.

use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use pim_case::units::UnitSystem;
use serde::Deserialize;
use serde_json::json;

pub(crate) fn refused(status: StatusCode, why: &str) -> Response {
    (status, Json(json!({ "error": why }))).into_response()
}

/// The display units a request names (`None`: the case's own).
pub(crate) fn units_of(name: Option<&str>) -> Result<Option<UnitSystem>, String> {
    match name {
        None | Some("") => Ok(None),
        Some("si") => Ok(Some(UnitSystem::Si)),
        Some("us") => Ok(Some(UnitSystem::Us)),
        Some("kmh") => Ok(Some(UnitSystem::Kmh)),
        Some(other) => Err(format!("units {other:?}: accepted: si, us, kmh")),
    }
}

pub(crate) fn unanswered(e: crate::AnswerError) -> Response {
    refused(StatusCode::UNPROCESSABLE_ENTITY, &e.to_string())
}

/// The answer to an edit of the case text made in the display units `units` (a name, `None`:
/// the case's own): `{text}`, the edited text (not saved), or the refusal that says why.
pub(crate) fn edited(
    units: Option<&str>,
    edit: impl FnOnce(Option<UnitSystem>) -> Result<String, crate::AnswerError>,
) -> Response {
    match units_of(units)
        .map_err(crate::AnswerError::Input)
        .and_then(edit)
    {
        Ok(text) => Json(json!({ "text": text })).into_response(),
        Err(e) => unanswered(e),
    }
}

#[derive(Deserialize)]
pub(crate) struct Move {
    path: String,
    text: String,
    vehicle: u8,
    at: [f64; 2],
    /// The units of `at`'s length (default the case's own).
    #[serde(default)]
    units: Option<String>,
    /// A tyre mark of the vehicle (from 0) instead of its rest.
    #[serde(default)]
    mark: Option<usize>,
}

pub(crate) async fn move_rest(Json(m): Json<Move>) -> Response {
    edited(m.units.as_deref(), |units| match m.mark {
        Some(i) => crate::move_mark(&m.path, &m.text, (m.vehicle, i), m.at, units),
        None => crate::move_rest_in(&m.path, &m.text, m.vehicle, m.at, units),
    })
}

/// An edit the page asks of a case's text (not saved): the file, its text, the display units
/// and what to change.
#[derive(Deserialize)]
pub(crate) struct EditAsk<T> {
    path: String,
    text: String,
    #[serde(default)]
    units: Option<String>,
    #[serde(flatten)]
    change: T,
}

/// The text with a tyre mark added where the page was clicked (not saved).
pub(crate) async fn add_mark(Json(m): Json<EditAsk<crate::NewMark>>) -> Response {
    edited(m.units.as_deref(), |u| {
        crate::add_mark(&m.path, &m.text, &m.change, u)
    })
}

/// The text with a traced mark added through the points clicked on the page (not saved).
pub(crate) async fn add_trace(Json(t): Json<EditAsk<crate::NewTrace>>) -> Response {
    edited(t.units.as_deref(), |u| {
        crate::add_trace(&t.path, &t.text, &t.change, u)
    })
}

/// The text with a friction zone added where the page was clicked (not saved).
pub(crate) async fn add_zone(Json(z): Json<EditAsk<crate::NewZone>>) -> Response {
    edited(z.units.as_deref(), |u| {
        crate::add_zone(&z.path, &z.text, &z.change, u)
    })
}

/// The text with the geometry at contact moved (a vehicle's CG or heading, the impact centre,
/// the crush surface's normal), not saved.
pub(crate) async fn contact(Json(c): Json<EditAsk<crate::ContactChange>>) -> Response {
    edited(c.units.as_deref(), |u| {
        crate::edit_contact(&c.path, &c.text, &c.change, u)
    })
}

#[derive(Deserialize)]
pub(crate) struct SkidAsk {
    path: String,
    text: String,
    vehicle: u8,
    length: f64,
    #[serde(default)]
    units: Option<String>,
}

/// The text with a vehicle's skid up to contact set (not saved).
pub(crate) async fn skid(Json(k): Json<SkidAsk>) -> Response {
    edited(k.units.as_deref(), |u| {
        crate::set_skid(&k.path, &k.text, (k.vehicle, k.length), u)
    })
}
