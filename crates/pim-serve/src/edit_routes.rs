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
    /// The survey point it was dropped on (`[survey]`'s id), if any.
    #[serde(default)]
    point: Option<String>,
}

pub(crate) async fn move_rest(Json(m): Json<Move>) -> Response {
    edited(m.units.as_deref(), |units| {
        crate::move_onto(
            &m.path,
            &m.text,
            (m.vehicle, m.mark),
            (m.at, m.point.as_deref()),
            units,
        )
    })
}

/// The text with a vehicle's rest placed where the page was clicked (not saved).
pub(crate) async fn place_rest(Json(r): Json<EditAsk<crate::NewRest>>) -> Response {
    edited(r.units.as_deref(), |u| {
        crate::place_rest(&r.path, &r.text, &r.change, u)
    })
}

/// The text with a vehicle's rest given by the tyre points or corners placed (not saved).
pub(crate) async fn place_rest_tyres(Json(r): Json<EditAsk<crate::NewRestTyres>>) -> Response {
    edited(r.units.as_deref(), |u| {
        crate::place_rest_tyres(&r.path, &r.text, &r.change, u)
    })
}

/// The text with a survey's points imported as `[survey]` (not saved).
pub(crate) async fn survey(Json(s): Json<EditAsk<crate::SurveyImport>>) -> Response {
    edited(None, |_| crate::import_survey(&s.path, &s.text, &s.change))
}

/// The text with an EDR's pasted table imported (not saved).
pub(crate) async fn edr(Json(e): Json<EditAsk<crate::EdrImport>>) -> Response {
    edited(None, |_| crate::import_edr(&e.path, &e.text, &e.change))
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

/// A store's refusal as the page is told it, the file named by its path in the folder: a
/// missing file 404, a file that is not a regular file (or leads outside, or is read-only,
/// or too large) 403, a text `pim fit` refuses 422, a file changed on disk 409 (with the
/// file's text and version now), the system's failure 500.
pub(crate) fn stored_error(path: &str, e: &pim_store::StoreError) -> Response {
    use pim_store::StoreError as E;
    let named = |m: String| match m.split_once(": ") {
        Some((_, rest)) => format!("{path}: {rest}"),
        None => m,
    };
    match e {
        E::Missing { .. } => refused(StatusCode::NOT_FOUND, &format!("{path}: no such file")),
        E::Unusable { .. } => refused(StatusCode::FORBIDDEN, &named(e.to_string())),
        E::Refused(m) => refused(StatusCode::UNPROCESSABLE_ENTITY, &format!("not saved: {m}")),
        E::Conflict { current, .. } => (
            StatusCode::CONFLICT,
            Json(json!({
                "error": format!(
                    "not saved: {path} changed on disk since it was opened (by another editor, \
                     another page or pim set): reload it, or compare the two and save again"
                ),
                "conflict": { "text": current.text, "version": current.version.0 },
            })),
        )
            .into_response(),
        E::Io { .. } => refused(StatusCode::INTERNAL_SERVER_ERROR, &named(e.to_string())),
    }
}

pub(crate) fn outside(path: &str) -> Response {
    refused(
        StatusCode::FORBIDDEN,
        &format!(
            "refused: {path}: only the case files (.toml) inside the folder served can be read \
             or written"
        ),
    )
}
