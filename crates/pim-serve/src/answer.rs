//! A case's answer as the page shows it: the document `pim fit --format json` writes, the table
//! `pim fit` prints, and the scene drawn to scale.

use crate::plan::{plan, Plan};
use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_core::MomentForm;
use pim_fit::{FitModel, MomentBranch};
use pim_studies::consistency::PieceId;
use pim_studies::question::Question;
use pim_studies::reconstruct::EvidenceSource;
use serde::Serialize;

pub use crate::error::AnswerError;

/// The answer of one case.
#[derive(Debug, Serialize)]
pub struct Answer {
    /// `reconstruction` (a scene case), `solve` (a case that gives its coefficients and
    /// nothing to fit, as `pim solve` answers it) or `fit`.
    pub question: &'static str,
    /// A live answer: the reconstruction refined from the previous answer's ends
    /// ([`pim_reconstruct::follow`]), not searched, and without its consistency table; the
    /// page asks for the whole answer when the drag ends.
    pub live: bool,
    /// The document of `pim fit FILE --format json`.
    pub document: serde_json::Value,
    /// The text `pim fit FILE` prints.
    pub table: String,
    /// The scene to scale.
    pub plan: Plan,
    /// The pieces of evidence of a scene case, each on or switched off.
    pub pieces: Vec<EvidencePiece>,
}

/// A piece of a scene case's evidence as the consistency table groups it (a rest position, a
/// mark, an EDR speed, an observation, the estimates), which the page can switch off to see
/// the answer without it.
#[derive(Debug, Serialize)]
pub struct EvidencePiece {
    /// What it is (the plan finds the piece it draws by it).
    pub id: PieceId,
    /// Its name (`vehicle2 mark 1`), as the consistency table's rows name it.
    pub name: String,
    /// Switched off: the answer is the reconstruction without it.
    pub off: bool,
    /// Its residual farthest from the answer, in standard deviations (`None` when it is off
    /// or there is no answer).
    pub z: Option<f64>,
}

/// Each piece of `case`'s evidence, on or off, with its largest residual in `document`: the
/// rows are told to a piece by their typed source, not their names.
fn pieces_of(case: &Case, off: &[String], document: &serde_json::Value) -> Vec<EvidencePiece> {
    let rows: Vec<(PieceId, f64)> = document["best"]["evidence"]
        .as_array()
        .map(|rows| {
            rows.iter()
                .filter_map(|r| {
                    let source: EvidenceSource =
                        serde_json::from_value(r["source"].clone()).ok()?;
                    Some((
                        pim_studies::consistency::piece_of(case, source)?,
                        r["z"].as_f64()?,
                    ))
                })
                .collect()
        })
        .unwrap_or_default();
    pim_studies::consistency::pieces_named(case)
        .into_iter()
        .map(|(id, name)| {
            let is_off = off.contains(&name);
            let z = (!is_off)
                .then(|| {
                    rows.iter()
                        .filter(|(piece, _)| *piece == id)
                        .map(|(_, z)| *z)
                        .max_by(|a, b| a.abs().total_cmp(&b.abs()))
                })
                .flatten();
            EvidencePiece {
                id,
                name,
                off: is_off,
                z,
            }
        })
        .collect()
}

/// The answer of the case text `text` (named `file` in messages).
///
/// # Errors
/// [`AnswerError::Input`] for text that is not a valid case, with `pim`'s message.
pub fn answer(file: &str, text: &str) -> Result<Answer, AnswerError> {
    answer_following(file, text, None).map(|(a, _)| a)
}

/// [`answer`]; with `previous` (the outcome of the case's last reconstruction) a live answer
/// that follows it. Also gives the reconstruction's outcome, to follow next time.
///
/// # Errors
/// As [`answer`].
pub fn answer_following(
    file: &str,
    text: &str,
    previous: Option<&pim_reconstruct::Outcome>,
) -> Result<(Answer, Option<pim_reconstruct::Outcome>), AnswerError> {
    answer_in(file, text, previous, None)
}

/// [`answer_following`] with the plan and the table in `units` (`None`: the case's own, as
/// `pim fit` prints them without `--units`); the document stays SI.
///
/// # Errors
/// As [`answer`].
pub fn answer_in(
    file: &str,
    text: &str,
    previous: Option<&pim_reconstruct::Outcome>,
    units: Option<UnitSystem>,
) -> Result<(Answer, Option<pim_reconstruct::Outcome>), AnswerError> {
    answer_without(file, text, previous, units, &[])
}

/// [`answer_in`] with the pieces of evidence named `off` switched off
/// ([`pim_studies::consistency::switched_off`]): the answer is the reconstruction without
/// them (the document `pim fit` writes for the case with them deleted), the plan still shows
/// them.
///
/// # Errors
/// As [`answer`], and a name that is no piece of the case's evidence.
pub fn answer_without(
    file: &str,
    text: &str,
    previous: Option<&pim_reconstruct::Outcome>,
    units: Option<UnitSystem>,
    off: &[String],
) -> Result<(Answer, Option<pim_reconstruct::Outcome>), AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let shown = Case::from_text(file, text).map_err(|e| input(&e))?;
    let case = if off.is_empty() {
        shown.clone()
    } else {
        pim_studies::consistency::switched_off(&shown, off).map_err(|e| input(&e))?
    };
    let asked = Question::of(&case, None);
    let units = units.unwrap_or_else(|| UnitSystem::of(&case.written_units));
    let title = pim_render::text::case_title(&case);
    let branches = vec![MomentBranch::Free, MomentBranch::Zero];
    match asked.question {
        Question::Reconstruction => {
            let live = previous.is_some();
            let done = match previous {
                Some(p) => follow(&case, branches, p)?,
                None => pim_studies::consistency::answer(
                    &case,
                    FitModel::Pim,
                    MomentForm::Corrected,
                    branches,
                    &pim_studies::watch::Unwatched,
                )
                .map_err(|e| input(&e))?,
            };
            let table = pim_render::reconstruct::reconstruction_table(
                &title,
                &done.document,
                units,
                case.written,
            );
            // The plan shows every piece, those switched off too.
            let plan = reconstruction_plan(&shown, &done, units)?;
            let document = serde_json::to_value(&done.document).map_err(|e| input(&e))?;
            Ok((
                Answer {
                    question: "reconstruction",
                    live,
                    pieces: pieces_of(&shown, off, &document),
                    document,
                    table,
                    plan,
                },
                Some(done.outcome),
            ))
        }
        // A case that gives its coefficients and nothing to fit is solved, as `pim solve`
        // solves it (`pim fit` refuses it).
        Question::Solve => {
            let solved = pim_studies::documents::solve(&case, &pim_core::SolveOptions::default())
                .map_err(|e| input(&e))?;
            let table = pim_render::solved::solved_table(&title, &solved, units, case.written);
            let plan = if case.has_runout() {
                run_out(&case, solved.report.separation)
                    .and_then(|r| plan(&case, Some(&r), units))
                    .unwrap_or_default()
            } else {
                Plan::default()
            };
            Ok((
                Answer {
                    question: "solve",
                    live: false,
                    pieces: Vec::new(),
                    document: serde_json::to_value(&solved.document).map_err(|e| input(&e))?,
                    table,
                    plan,
                },
                None,
            ))
        }
        Question::Impact => fit_answer(&case, &title, units, branches),
    }
}

/// The answer of a case that fits its coefficients (`pim fit` of a case without a scene):
/// the fit's table, its document and the run-outs from its separation.
fn fit_answer(
    case: &Case,
    title: &str,
    units: UnitSystem,
    branches: Vec<MomentBranch>,
) -> Result<(Answer, Option<pim_reconstruct::Outcome>), AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let fitted =
        pim_studies::documents::fit(case, None, FitModel::Pim, MomentForm::Corrected, branches)
            .map_err(|e| input(&e))?;
    let table = pim_render::tables::fit_table(title, "custom", &fitted.report, units, case.written);
    let separation = fitted
        .report
        .best_branch()
        .and_then(|b| b.solution.as_ref())
        .map(|s| s.separation);
    let plan = if case.has_runout() {
        separation
            .map(|sep| run_out(case, sep))
            .transpose()
            .and_then(|r| plan(case, r.as_ref(), units))
            .unwrap_or_default()
    } else {
        Plan::default()
    };
    Ok((
        Answer {
            question: "fit",
            live: false,
            pieces: Vec::new(),
            document: serde_json::to_value(&fitted.document).map_err(|e| input(&e))?,
            table,
            plan,
        },
        None,
    ))
}

/// The width of the speeds before contact in the page's side pane, pixels (drawn at the
/// size shown, so that its text is read at its own size).
const SPEED_HISTORY_WIDTH: u32 = 500;

/// The plan of the reconstruction `done` of the case `shown` (every piece drawn, those
/// switched off too): its fitted run-outs and their motion in time.
fn reconstruction_plan(
    shown: &Case,
    done: &pim_studies::reconstruct::Reconstructed,
    units: UnitSystem,
) -> Result<Plan, AnswerError> {
    let Some(best) = &done.outcome.best else {
        return Ok(plan(shown, None, units).unwrap_or_default());
    };
    let fitted = pim_studies::runout::fitted(shown, best, 0.02, false)
        .map_err(|e| AnswerError::Unsupported(e.to_string()))?;
    let mut plan = plan(shown, Some(&fitted), units)?;
    plan.motion = Some(crate::motion::motion_on_page(
        shown, done, best, &fitted, units,
    ));
    plan.speed_history =
        pim_render::speed_history::figure(shown, done, units, SPEED_HISTORY_WIDTH)?.map(|f| f.svg);
    Ok(plan)
}

/// The case reconstructed by following `previous` ([`pim_reconstruct::follow`]).
fn follow(
    case: &Case,
    branches: Vec<MomentBranch>,
    previous: &pim_reconstruct::Outcome,
) -> Result<pim_studies::reconstruct::Reconstructed, AnswerError> {
    let how = pim_studies::reconstruct::How {
        model: FitModel::Pim,
        moment_form: MomentForm::Corrected,
        branches,
    };
    let input = pim_studies::reconstruct::case_reconstruction(
        case,
        how.model,
        how.moment_form,
        how.branches.clone(),
    )
    .map_err(|e| AnswerError::Input(e.to_string()))?;
    let outcome = pim_reconstruct::follow(&input.reconstruction, &input.settings, previous)
        .map_err(|e| AnswerError::Input(format!("{}: {e}", case.file)))?;
    pim_studies::reconstruct::finish(case, how, true, input, outcome)
        .map_err(|e| AnswerError::Input(e.to_string()))
}

/// Each run-out of `case` from the separation velocities `sep` (of a solved or fitted impact:
/// no scene was fitted, the stated road is the one).
fn run_out(
    case: &Case,
    sep: pim_core::Velocities,
) -> Result<pim_studies::runout::RunoutResult, AnswerError> {
    pim_studies::runout::runout(case, None, Some(sep), 0.02, false)
        .map_err(|e| AnswerError::Unsupported(e.to_string()))
}

/// A vehicle (1 or 2) and its CG path on the page.
pub type VehiclePath = (u8, Vec<[f64; 2]>);

/// Each vehicle's CG path (every 0.05 s) from the velocities at separation `sep`, on the page
/// in `units` (`None`: the case's own).
pub(crate) fn paths(
    case: &Case,
    sep: pim_core::Velocities,
    units: Option<UnitSystem>,
) -> Result<Vec<VehiclePath>, AnswerError> {
    let units = units.unwrap_or_else(|| UnitSystem::of(&case.written_units));
    let page = pim_render::plan::Page::of(case.written);
    let r = pim_studies::runout::runout(case, None, Some(sep), 0.05, false)
        .map_err(|e| AnswerError::Unsupported(e.to_string()))?;
    Ok(r.inputs
        .iter()
        .zip(&r.runouts)
        .map(|(input, run)| {
            let path = run
                .sample(0.05)
                .iter()
                .map(|(_, m)| {
                    let (h, v) = page.xy((units.length(m.x), units.length(m.y)));
                    [h, v]
                })
                .collect();
            (input.id.index() as u8 + 1, path)
        })
        .collect())
}
