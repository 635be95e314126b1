//! A case built in the page: a new case named and started (its frame and units), its sections
//! added one at a time with starting values ([`pim_case::templates`]), saved by creating its
//! file; and, while the text is not yet a case that answers, the plan of what it gives so far
//! (its background, its survey).

use crate::edit_routes::{edited, refused};
use crate::guard::inside;
use crate::served::Server;
use axum::extract::State;
use axum::http::StatusCode;
use axum::response::{IntoResponse, Response};
use axum::Json;
use pim_case::templates;
use pim_case::units::{UnitSystem, UnitsSection};
use pim_core::Convention;
use serde::Deserialize;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// A new case the page asks for.
#[derive(Debug, Deserialize)]
pub(crate) struct NewCase {
    /// Its file name inside the folder (`main_and_oak.toml`; `.toml` added when missing).
    name: String,
    /// Its title (default: the name).
    #[serde(default)]
    title: Option<String>,
    /// `us` (mph, ft, lb) or `si` (m/s, m, kg; the default).
    #[serde(default)]
    units: Option<String>,
    /// `sae` (x north, y east, headings clockwise) or `natural` (the default).
    #[serde(default)]
    convention: Option<String>,
}

/// The `[units]` of a new case in the unit system `name`.
fn units_named(name: Option<&str>) -> Result<UnitsSection, String> {
    let text = match name.unwrap_or("si") {
        "si" => "speed = \"m/s\"\nlength = \"m\"\nmass = \"kg\"\nyaw_inertia = \"kg m^2\"\nyaw_rate = \"deg/s\"",
        "us" => "speed = \"mph\"\nlength = \"ft\"\nmass = \"lb\"\nyaw_inertia = \"slug ft^2\"\nyaw_rate = \"deg/s\"",
        "kmh" => "speed = \"km/h\"\nlength = \"m\"\nmass = \"kg\"\nyaw_inertia = \"kg m^2\"\nyaw_rate = \"deg/s\"",
        other => return Err(format!("units {other:?}: accepted: si, us, kmh")),
    };
    toml::from_str(text).map_err(|e| e.to_string())
}

/// `/api/new`: the text of a new case and the path it will be saved at (nothing is written
/// until it is saved): refused for a name outside the folder or one that exists.
pub(crate) async fn new_case(State(s): State<Arc<Server>>, Json(n): Json<NewCase>) -> Response {
    let name = n.name.trim();
    let name = if name.to_ascii_lowercase().ends_with(".toml") {
        name.to_string()
    } else {
        format!("{name}.toml")
    };
    let Some(file) = inside(&s.served.root, &name).filter(|_| name.len() > ".toml".len()) else {
        return crate::edit_routes::outside(&name);
    };
    if std::fs::symlink_metadata(&file).is_ok() {
        return refused(
            StatusCode::CONFLICT,
            &format!("{name} exists already: open it, or give the new case another name"),
        );
    }
    let convention = match n.convention.as_deref().unwrap_or("natural") {
        name @ ("natural" | "sae") => Convention::named(name).expect("a frame's name"),
        other => {
            return refused(
                StatusCode::UNPROCESSABLE_ENTITY,
                &format!("convention {other:?}: accepted: natural, sae"),
            )
        }
    };
    let units = match units_named(n.units.as_deref()) {
        Ok(u) => u,
        Err(why) => return refused(StatusCode::UNPROCESSABLE_ENTITY, &why),
    };
    let stem = name.trim_end_matches(".toml").replace('_', " ");
    let title = n
        .title
        .as_deref()
        .map(str::trim)
        .filter(|t| !t.is_empty())
        .unwrap_or(&stem);
    let text = templates::new_case(title, convention, &units);
    Json(json!({ "path": name, "text": text })).into_response()
}

#[derive(Deserialize)]
pub(crate) struct SectionsAsk {
    path: String,
    text: String,
}

/// `/api/sections`: the sections the text does not write yet, each with what it is for.
pub(crate) async fn sections(Json(a): Json<SectionsAsk>) -> Response {
    match templates::missing(&a.path, &a.text) {
        Ok(list) => {
            let list: Vec<_> = list
                .iter()
                .map(|s| json!({ "name": s.table, "what": s.what }))
                .collect();
            Json(json!({ "sections": list })).into_response()
        }
        Err(e) => refused(StatusCode::UNPROCESSABLE_ENTITY, &e.to_string()),
    }
}

#[derive(Deserialize)]
pub(crate) struct SectionAsk {
    path: String,
    text: String,
    name: String,
}

/// `/api/section`: the text with a section added with its starting values (not saved).
pub(crate) async fn add_section(Json(a): Json<SectionAsk>) -> Response {
    edited(None, |_| {
        templates::with_section(&a.path, &a.text, &a.name)
            .map_err(|e| crate::AnswerError::Input(e.to_string()))
    })
}

/// `/api/section/remove`: the text without a section (not saved).
pub(crate) async fn remove_section(Json(a): Json<SectionAsk>) -> Response {
    edited(None, |_| {
        templates::without_section(&a.path, &a.text, &a.name)
            .map_err(|e| crate::AnswerError::Input(e.to_string()))
    })
}

/// A new case saved: its file created (see [`pim_store::create`]).
pub(crate) async fn create(root: &Path, file: PathBuf, path: &str, text: String) -> Response {
    let root = root.to_path_buf();
    let name = path.to_string();
    let written = tokio::task::spawn_blocking(move || {
        let options = pim_store::WriteOptions {
            expected: None,
            inside: Some(&root),
            name: Some(&name),
        };
        pim_store::create(&file, &text, &options)
    })
    .await;
    match written {
        Ok(Ok(stored)) => Json(json!({
            "saved": path, "bytes": stored.text.len(), "version": stored.version.0,
        }))
        .into_response(),
        Ok(Err(e)) => crate::edit_routes::stored_error(path, &e),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

/// An answer refused for its text (`e`), with the plan of what the text gives so far (its
/// background and survey, while it is being built) as `sketch` when it gives one.
pub(crate) fn unanswered_with_sketch(
    e: crate::AnswerError,
    (path, text, units): &(String, String, Option<UnitSystem>),
) -> Response {
    let Some(sketch) = crate::plan::Sketch::of(text) else {
        return crate::edit_routes::unanswered(e);
    };
    let units = units.unwrap_or_else(|| sketch.system());
    let plan = sketch.plan(path, units);
    (
        StatusCode::UNPROCESSABLE_ENTITY,
        Json(json!({ "error": e.to_string(), "sketch": plan })),
    )
        .into_response()
}
