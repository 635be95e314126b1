//! `pim serve`: the scene editor in the browser, served by the `pim` binary itself.
//!
//! The page shows a case's scene to scale (the plan view of every figure of the case: the
//! natural frame with x to the right and y up, an SAE case as a map with x up and y to the
//! right), the vehicles at contact and at rest with their run-out paths, the scene's evidence
//! (rest positions with their one-sigma circles, tyre marks), the speeds of every phase and the
//! case's TOML beside it. Dragging a rest position rewrites that position in the TOML (an
//! edit-preserving write: comments and layout kept, [`pim_case::edit::CaseEdit`]) and solves
//! the case again; an edit of the TOML does the same. Saving writes the text back into the
//! served folder, where `pim fit FILE` gives exactly what the page showed.
//!
//! The server answers in the documents `pim ... --format json` writes: `POST /api/answer` of a
//! case gives `{question, document, table, plan}`, whose `document` is the JSON of `pim fit
//! FILE --format json` (a reconstruction for a case with scene evidence, the impact fit
//! otherwise), `table` the text `pim fit` prints, and `plan` the drawing of the scene in the
//! case's frame and length unit (the page's only own geometry). `POST /api/study` starts the
//! case's uncertainty study in the background (`{path, text, draws, seed}`, answered with its
//! `id`); `GET /api/study?id=N` gives its progress and, once ended, the document `pim
//! uncertainty FILE --format json` writes; `POST /api/study/cancel` (`{id}`) stops it, and the
//! draws finished make the answer. `POST /api/report` (`{path, text}`) gives the HTML report
//! `pim report FILE` writes. `GET /api/image?path=` gives an image of the folder (PNG, JPEG,
//! SVG) and `POST /api/background` writes the case's `[background]` as the page sets it.
//!
//! A case is built in the page from nothing: `POST /api/new` (`{name, title, units,
//! convention}`) gives a new case's text and path (nothing written), `POST /api/sections` the
//! sections its text does not write yet and `POST /api/section` (`{path, text, name}`) the text
//! with one added ([`pim_case::templates`]); `POST /api/survey` imports a survey's CSV as
//! `[survey]` ([`SurveyImport`]) and `POST /api/rest` places a rest ([`NewRest`]), both on a
//! text that is not yet a case too; `POST /api/save` with `create` creates the file
//! ([`pim_store::create`]). An answer refused for a text being built carries the plan of what
//! it gives so far (`sketch`: its background and survey).
//!
//! # Safety of a local server
//! - It binds 127.0.0.1 unless told otherwise.
//! - Every request needs the run's token: the address `pim serve` prints carries it
//!   (`/?token=...`); the page then holds it as a cookie (`HttpOnly`, `SameSite=Strict`).
//! - A request whose `Host` header is not a loopback name (or the host the server was told to
//!   bind) is refused: a page of another site cannot reach the server through a DNS name that
//!   resolves to 127.0.0.1 (DNS rebinding).
//! - Files are read and written only inside the folder served: a path with `..`, an absolute
//!   path, or one that leads outside through a link is refused; only `.toml` files are read or
//!   written.
//! - Request bodies are limited to [`BODY_LIMIT`] bytes.

mod answer;
mod background;
mod batch;
mod build;
mod contact;
mod edit_routes;
mod edits;
mod edr;
mod error;
mod form;
mod guard;
mod headers;
mod motion;
mod photo;
mod plan;
mod rest;
mod routes;
mod served;
mod study;
mod survey;

pub use answer::{
    answer, answer_following, answer_in, answer_without, Answer, AnswerError, EvidencePiece,
    VehiclePath,
};
pub use background::{set_background, BackgroundChange};
pub use batch::batch;
pub use contact::{edit_contact, ContactChange};
pub use edits::{
    add_mark, add_trace, add_zone, move_mark, move_onto, move_rest, move_rest_in, set_skid,
    NewMark, NewTrace, NewZone,
};
pub use edr::{import_edr, EdrImport};
pub use form::{form, set_field, FieldValue, FormField, FormSection};
pub use guard::{inside, inside_of, same_secret, Guard};
pub use headers::{image_kind, MAX_IMAGE_BYTES};
pub use motion::{PlanMotion, PlanTrack, STEP as MOTION_STEP};
pub use photo::{photo_plan, PhotoPlan, PhotoPoint};
pub use plan::{
    GivenRest, Plan, PlanBackground, PlanImpact, PlanSurveyPoint, PlanVehicle, PlanZone,
};
pub use rest::{place_rest, place_rest_tyres, NewRest, NewRestTyres, NewTyre};
use served::Server;
pub use served::{Served, BODY_LIMIT};
pub use study::{report, studied, study, Studied, BAND_DRAWS, MAX_DRAWS};
pub use survey::{import_survey, SurveyImport};

use std::sync::Arc;

/// The web application of `served`.
pub fn app(served: Served) -> axum::Router {
    routes::router(Arc::new(Server {
        served,
        last: Default::default(),
        studies: Default::default(),
    }))
}

/// Serves `served` on `listener` until the process ends.
///
/// # Errors
/// The listener's I/O errors.
pub async fn run(listener: tokio::net::TcpListener, served: Served) -> std::io::Result<()> {
    axum::serve(listener, app(served)).await
}
