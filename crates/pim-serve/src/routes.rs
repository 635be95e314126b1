//! The routes: the page, its assets and the API.

use crate::edit_routes::{edited, outside, refused, stored_error, unanswered, units_of};
use crate::guard::{inside, inside_of, Guard, COOKIE};
use crate::headers::{image_kind, secured, IMAGE_POLICY, MAX_IMAGE_BYTES};
use crate::served::{Server, BODY_LIMIT};
use axum::body::Body;
use axum::extract::{DefaultBodyLimit, Query, Request, State};
use axum::http::{header, StatusCode};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::{get, post};
use axum::{Json, Router};
use serde::Deserialize;
use serde_json::json;
use std::sync::Arc;

/// The page's files, embedded in the binary.
#[derive(rust_embed::Embed)]
#[folder = "assets/"]
struct Assets;

type App = Arc<Server>;

pub(crate) fn router(served: App) -> Router {
    Router::new()
        .route("/", get(index))
        .route("/assets/{file}", get(asset))
        .route("/api/cases", get(cases))
        .route("/api/case", get(case))
        .route("/api/answer", post(answer))
        .route("/api/move", post(crate::edit_routes::move_rest))
        .route("/api/mark", post(crate::edit_routes::add_mark))
        .route("/api/trace", post(crate::edit_routes::add_trace))
        .route("/api/zone", post(crate::edit_routes::add_zone))
        .route("/api/survey", post(crate::edit_routes::survey))
        .route("/api/edr", post(crate::edit_routes::edr))
        .route("/api/rest", post(crate::edit_routes::place_rest))
        .route(
            "/api/rest-tyres",
            post(crate::edit_routes::place_rest_tyres),
        )
        .route("/api/new", post(crate::build::new_case))
        .route("/api/sections", post(crate::build::sections))
        .route("/api/section", post(crate::build::add_section))
        .route("/api/section/remove", post(crate::build::remove_section))
        .route("/api/contact", post(crate::edit_routes::contact))
        .route("/api/skid", post(crate::edit_routes::skid))
        .route("/api/form", post(form))
        .route("/api/set", post(set_field))
        .route("/api/save", post(save))
        .route("/api/study", get(study_report).post(study_start))
        .route("/api/study/cancel", post(study_cancel))
        .route("/api/batch", post(batch_start))
        .route("/api/report", post(report))
        .route("/api/dxf", post(scene_dxf))
        .route("/api/photo-plan", post(photo_plan))
        .route("/api/image", get(image))
        .route("/api/background", post(background))
        .layer(middleware::from_fn_with_state(served.clone(), guard))
        .layer(DefaultBodyLimit::max(BODY_LIMIT))
        .with_state(served)
}

/// Every request: a Host that names this server, and the token (as the cookie, or in the
/// address of the page itself).
async fn guard(State(s): State<App>, req: Request, next: Next) -> Response {
    let g = Guard {
        token: s.served.token.clone(),
        hosts: s.served.hosts.clone(),
    };
    let headers = req.headers();
    let text = |h: header::HeaderName| headers.get(h).and_then(|v| v.to_str().ok());
    if headers.get_all(header::HOST).iter().count() > 1 {
        return secured(refused(
            StatusCode::BAD_REQUEST,
            "refused: more than one Host header (a request names one server)",
        ));
    }
    if !g.host_allowed(text(header::HOST)) {
        return refused(
            StatusCode::FORBIDDEN,
            "refused: the Host header does not name this server (pim serve answers only to \
             the names of this machine it was started for)",
        );
    }
    let with_token = req.uri().path() == "/"
        && req.uri().query().is_some_and(|q| {
            q.split('&').any(|kv| {
                kv.strip_prefix("token=")
                    .is_some_and(|t| crate::guard::same_secret(t, &s.served.token))
            })
        });
    if !(with_token || g.cookie_allowed(text(header::COOKIE))) {
        return secured(refused(
            StatusCode::FORBIDDEN,
            "refused: no token; open the address pim serve printed (it carries the token)",
        ));
    }
    secured(next.run(req).await)
}

/// The page; with the token in its address, the token becomes a cookie and the address drops
/// it.
async fn index(State(s): State<App>, req: Request) -> Response {
    let html = Assets::get("index.html").expect("embedded");
    let mut res = Response::new(Body::from(html.data.into_owned()));
    let h = res.headers_mut();
    h.insert(
        header::CONTENT_TYPE,
        "text/html; charset=utf-8".parse().expect("header"),
    );
    if req.uri().query().is_some() {
        let cookie = format!(
            "{COOKIE}={}; HttpOnly; SameSite=Strict; Path=/",
            s.served.token
        );
        h.insert(header::SET_COOKIE, cookie.parse().expect("header"));
    }
    res
}

async fn asset(axum::extract::Path(file): axum::extract::Path<String>) -> Response {
    let Some(f) = Assets::get(&file) else {
        return refused(StatusCode::NOT_FOUND, "no such file");
    };
    let kind = match file.rsplit('.').next() {
        Some("js") => "text/javascript; charset=utf-8",
        Some("css") => "text/css; charset=utf-8",
        Some("svg") => "image/svg+xml",
        _ => "application/octet-stream",
    };
    ([(header::CONTENT_TYPE, kind)], f.data.into_owned()).into_response()
}

/// The case files and the images of the folder served (sorted; subfolders to a depth of 8
/// included, links not followed).
async fn cases(State(s): State<App>) -> Response {
    let (mut out, mut images) = (Vec::new(), Vec::new());
    let root = &s.served.root;
    let mut dirs = vec![(root.clone(), 0)];
    while let Some((d, depth)) = dirs.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            let Ok(kind) = e.file_type() else { continue };
            if kind.is_symlink() {
                continue;
            }
            if kind.is_dir() {
                if depth < 8 {
                    dirs.push((p, depth + 1));
                }
            } else if !kind.is_file() {
                // A FIFO, device or socket named like a case is not listed (nor ever opened).
                continue;
            } else if let Ok(rel) = p.strip_prefix(root) {
                let rel = rel.to_string_lossy().replace('\\', "/");
                let kind = p
                    .extension()
                    .and_then(|x| x.to_str())
                    .map(str::to_ascii_lowercase);
                match kind.as_deref() {
                    Some("toml") => out.push(rel),
                    Some(k) if pim_case::scene_sections::BackgroundSection::KINDS.contains(&k) => {
                        images.push(rel)
                    }
                    _ => {}
                }
            }
        }
    }
    out.sort();
    images.sort();
    Json(json!({
        "root": root.display().to_string(),
        "cases": out,
        "images": images,
        "initial": s.served.initial,
    }))
    .into_response()
}

#[derive(Deserialize)]
struct CasePath {
    path: String,
}

async fn case(State(s): State<App>, Query(q): Query<CasePath>) -> Response {
    let Some(file) = inside(&s.served.root, &q.path) else {
        return outside(&q.path);
    };
    let read =
        tokio::task::spawn_blocking(move || pim_store::read(&file, pim_store::MAX_CASE_BYTES))
            .await;
    match read {
        Ok(Ok(stored)) => Json(json!({
            "path": q.path, "text": stored.text, "version": stored.version.0,
        }))
        .into_response(),
        Ok(Err(e)) => stored_error(&q.path, &e),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

#[derive(Deserialize)]
struct CaseText {
    path: String,
    text: String,
    /// A live answer (while a handle is dragged): follow the case's last reconstruction.
    #[serde(default)]
    live: bool,
    /// Display units, `si`, `us` or `kmh` (default the case's own).
    #[serde(default)]
    units: Option<String>,
    /// Pieces of evidence switched off (their names, as the answer's `pieces` give them).
    #[serde(default)]
    off: Vec<String>,
}

async fn answer(State(s): State<App>, Json(c): Json<CaseText>) -> Response {
    let units = match units_of(c.units.as_deref()) {
        Ok(u) => u,
        Err(why) => return refused(StatusCode::UNPROCESSABLE_ENTITY, &why),
    };
    let sketch = (c.path.clone(), c.text.clone(), units);
    let done = tokio::task::spawn_blocking(move || {
        let started = std::time::Instant::now();
        let previous = if c.live {
            s.last.lock().ok().and_then(|m| m.get(&c.path).cloned())
        } else {
            None
        };
        let (a, outcome) =
            crate::answer_without(&c.path, &c.text, previous.as_ref(), units, &c.off)?;
        if let (Some(o), Ok(mut m)) = (outcome, s.last.lock()) {
            m.insert(c.path.clone(), o);
        }
        Ok::<_, crate::AnswerError>((a, started.elapsed()))
    })
    .await;
    match done {
        Ok(Ok((a, took))) => {
            let mut res = Json(a).into_response();
            // The server's time, for the page's performance marks.
            let timing = format!("solve;dur={:.1}", took.as_secs_f64() * 1e3);
            res.headers_mut()
                .insert("server-timing", timing.parse().expect("header"));
            res
        }
        Ok(Err(e)) => crate::build::unanswered_with_sketch(e, &sketch),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

#[derive(Deserialize)]
struct TextOnly {
    path: String,
    text: String,
}

/// The case text as forms, one per section.
async fn form(Json(c): Json<TextOnly>) -> Response {
    match crate::form(&c.path, &c.text) {
        Ok(sections) => Json(json!({ "sections": sections })).into_response(),
        Err(e) => unanswered(e),
    }
}

#[derive(Deserialize)]
struct SetAsk {
    path: String,
    text: String,
    key: String,
    value: crate::FieldValue,
}

/// The text with one field of the forms set (not saved).
async fn set_field(Json(a): Json<SetAsk>) -> Response {
    edited(None, |_| {
        crate::set_field(&a.path, &a.text, &a.key, &a.value)
    })
}

#[derive(Deserialize)]
struct SaveAsk {
    path: String,
    text: String,
    /// The version of the file the text was made from (as `/api/case` or the last save gave
    /// it): the save is refused (409) if the file is no longer that version.
    version: Option<String>,
    /// A new case (`/api/new`): the file is created, and the save refused if one of that name
    /// exists.
    #[serde(default)]
    create: bool,
}

/// Saves a case: only a case `pim fit` reads, only inside the folder, only over the version
/// it was made from (see pim-store: checked, written beside the file and renamed over it,
/// serialised with every other writer of the file).
async fn save(State(s): State<App>, Json(c): Json<SaveAsk>) -> Response {
    let Some(file) = inside(&s.served.root, &c.path) else {
        return outside(&c.path);
    };
    if c.create {
        return crate::build::create(&s.served.root, file, &c.path, c.text).await;
    }
    let Some(version) = c.version else {
        return refused(
            StatusCode::PRECONDITION_REQUIRED,
            &format!(
                "not saved: {}: give the version the text was made from (as /api/case gave \
                 it), so that a change made meanwhile on disk is not overwritten",
                c.path
            ),
        );
    };
    let root = s.served.root.clone();
    let path = c.path.clone();
    let written = tokio::task::spawn_blocking(move || {
        let options = pim_store::WriteOptions {
            expected: Some(&version),
            inside: Some(&root),
            name: Some(&path),
        };
        pim_store::write(&file, &c.text, &options)
    })
    .await;
    match written {
        Ok(Ok(stored)) => Json(json!({
            "saved": c.path, "bytes": stored.text.len(), "version": stored.version.0,
        }))
        .into_response(),
        Ok(Err(e)) => stored_error(&c.path, &e),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

#[derive(Deserialize)]
struct StudyAsk {
    path: String,
    text: String,
    #[serde(default = "default_draws")]
    draws: usize,
    #[serde(default = "default_seed")]
    seed: u64,
    /// Pieces of evidence switched off.
    #[serde(default)]
    off: Vec<String>,
    /// Display units of the bands on the plan.
    #[serde(default)]
    units: Option<String>,
}

/// `pim uncertainty`'s defaults.
fn default_draws() -> usize {
    200
}

fn default_seed() -> u64 {
    1
}

#[derive(Deserialize)]
struct StudyId {
    id: u64,
}

/// Starts a study; bad draws are refused at once, a bad case when the study ends.
async fn study_start(State(s): State<App>, Json(a): Json<StudyAsk>) -> Response {
    if !(1..=crate::study::MAX_DRAWS).contains(&a.draws) {
        return refused(
            StatusCode::UNPROCESSABLE_ENTITY,
            &format!(
                "draws {}: must be between 1 and {}",
                a.draws,
                crate::study::MAX_DRAWS
            ),
        );
    }
    let units = match units_of(a.units.as_deref()) {
        Ok(u) => u,
        Err(why) => return refused(StatusCode::UNPROCESSABLE_ENTITY, &why),
    };
    let started = s
        .studies
        .start((a.path, a.text), (a.draws, a.seed), (a.off, units));
    study_started(started)
}

#[derive(Deserialize)]
struct BatchAsk {
    /// The case files, relative to the folder served.
    paths: Vec<String>,
}

/// Starts a batch of case files (`pim batch`'s records) in the background; polled and
/// cancelled as a study is. A path outside the folder refuses the whole batch.
async fn batch_start(State(s): State<App>, Json(a): Json<BatchAsk>) -> Response {
    let mut files = Vec::new();
    for p in &a.paths {
        let Some(file) = inside(&s.served.root, p) else {
            return outside(p);
        };
        files.push(pim_studies::case_batch::CaseText {
            name: p.clone(),
            text: pim_store::read(&file, pim_store::MAX_CASE_BYTES)
                .map(|s| s.text)
                .map_err(|e| format!("{p}: cannot be read: {e}")),
        });
    }
    if files.is_empty() {
        return refused(StatusCode::UNPROCESSABLE_ENTITY, "no case files to batch");
    }
    let started = s.studies.start_job(move |run| {
        Ok(crate::study::Studied {
            document: crate::batch::batch(&files, run),
            bands: Vec::new(),
        })
    });
    study_started(started)
}

/// A study's number, or the refusal of one too many (429).
fn study_started(started: Result<u64, crate::study::Busy>) -> Response {
    match started {
        Ok(id) => Json(json!({ "id": id })).into_response(),
        Err(crate::study::Busy) => refused(
            StatusCode::TOO_MANY_REQUESTS,
            &format!(
                "refused: {} studies or batches are running and {} waiting; cancel one or let \
                 one end, then ask again",
                crate::study::RUNNING_AT_ONCE,
                crate::study::WAITING_AT_MOST
            ),
        ),
    }
}

async fn study_report(State(s): State<App>, Query(q): Query<StudyId>) -> Response {
    match s.studies.get(q.id) {
        Some(r) => Json(r.report(q.id)).into_response(),
        None => refused(StatusCode::NOT_FOUND, &format!("no study {}", q.id)),
    }
}

async fn study_cancel(State(s): State<App>, Json(q): Json<StudyId>) -> Response {
    match s.studies.get(q.id) {
        Some(r) => {
            r.cancel();
            Json(r.report(q.id)).into_response()
        }
        None => refused(StatusCode::NOT_FOUND, &format!("no study {}", q.id)),
    }
}

/// The case's HTML report, as `pim report FILE` writes it.
async fn report(Json(c): Json<CaseText>) -> Response {
    let made = tokio::task::spawn_blocking(move || crate::study::report(&c.path, &c.text)).await;
    match made {
        Ok(Ok(html)) => {
            ([(header::CONTENT_TYPE, "text/html; charset=utf-8")], html).into_response()
        }
        Ok(Err(e)) => unanswered(e),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

/// The plan of the case's reconstruction for CAD, as `pim fit FILE --out` writes `scene.dxf`.
async fn scene_dxf(Json(c): Json<CaseText>) -> Response {
    let made = tokio::task::spawn_blocking(move || {
        let units = units_of(c.units.as_deref()).map_err(crate::AnswerError::Input)?;
        crate::study::scene_dxf(&c.path, &c.text, units)
    })
    .await;
    match made {
        Ok(Ok(bytes)) => ([(header::CONTENT_TYPE, "image/vnd.dxf")], bytes).into_response(),
        Ok(Err(e)) => unanswered(e),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

#[derive(Deserialize)]
struct PhotoAsk {
    path: String,
    text: String,
    #[serde(default)]
    units: Option<String>,
    /// The photo, a path inside the folder served.
    photo: String,
    points: Vec<crate::PhotoPoint>,
}

/// A photo of the folder made into a plan-view image written beside it, and the case's text
/// with it as its `[background]` (not saved).
async fn photo_plan(State(s): State<App>, Json(a): Json<PhotoAsk>) -> Response {
    let Some(file) = inside_of(&s.served.root, &a.photo, &["png", "jpg", "jpeg"]) else {
        return refused(
            StatusCode::FORBIDDEN,
            &format!(
                "refused: {}: only a photo (PNG, JPEG) inside the folder served is rectified",
                a.photo
            ),
        );
    };
    let root = s.served.root.clone();
    let made = tokio::task::spawn_blocking(move || {
        let bytes = pim_store::read_bytes(&file, MAX_IMAGE_BYTES)
            .map_err(|e| crate::AnswerError::Input(format!("{}: {e}", a.photo)))?;
        let units = units_of(a.units.as_deref()).map_err(crate::AnswerError::Input)?;
        crate::photo_plan(
            &root,
            (&a.path, &a.text),
            (&a.photo, &bytes),
            &a.points,
            units,
        )
    })
    .await;
    match made {
        Ok(Ok(plan)) => Json(plan).into_response(),
        Ok(Err(e)) => unanswered(e),
        Err(e) => refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    }
}

/// An image of the folder served, for the background of a plan.
async fn image(State(s): State<App>, Query(q): Query<CasePath>) -> Response {
    let kinds = pim_case::scene_sections::BackgroundSection::KINDS;
    let Some(file) = inside_of(&s.served.root, &q.path, &kinds) else {
        return refused(
            StatusCode::FORBIDDEN,
            &format!(
                "refused: {}: only the images (PNG, JPEG, SVG) inside the folder served can be \
                 read",
                q.path
            ),
        );
    };
    let read =
        tokio::task::spawn_blocking(move || pim_store::read_bytes(&file, MAX_IMAGE_BYTES)).await;
    let bytes = match read {
        Ok(Ok(b)) => b,
        Ok(Err(e)) => return stored_error(&q.path, &e),
        Err(e) => return refused(StatusCode::INTERNAL_SERVER_ERROR, &e.to_string()),
    };
    // The type by what the bytes are, not by the name; anything else is not served.
    let Some(kind) = image_kind(&bytes) else {
        return refused(
            StatusCode::UNSUPPORTED_MEDIA_TYPE,
            &format!("{}: not a PNG, JPEG or SVG image", q.path),
        );
    };
    let mut res = ([(header::CONTENT_TYPE, kind)], bytes).into_response();
    // An image opened on its own (an SVG can hold scripts) runs nothing, loads nothing and
    // is an origin of its own.
    res.headers_mut().insert(
        header::CONTENT_SECURITY_POLICY,
        header::HeaderValue::from_static(IMAGE_POLICY),
    );
    res
}

#[derive(Deserialize)]
struct BackgroundAsk {
    path: String,
    text: String,
    #[serde(default)]
    units: Option<String>,
    #[serde(flatten)]
    change: crate::BackgroundChange,
}

/// The case's text with its `[background]` changed as the page asks.
async fn background(Json(b): Json<BackgroundAsk>) -> Response {
    edited(b.units.as_deref(), |units| {
        crate::set_background(&b.path, &b.text, &b.change, units)
    })
}
