//! A case's answer as the page shows it: the document `pim fit --format json` writes, the table
//! `pim fit` prints, and the scene drawn to scale.

use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_core::{Convention, MomentForm};
use pim_fit::{FitModel, MomentBranch};
use pim_studies::consistency::PieceId;
use pim_studies::question::Question;
use pim_studies::reconstruct::EvidenceSource;
use serde::Serialize;

/// Why a case has no answer to show.
#[derive(Debug, thiserror::Error)]
pub enum AnswerError {
    /// The text is not a valid case (the message names the file, line and field).
    #[error("{0}")]
    Input(String),
    /// The case is valid but its question cannot be answered here yet.
    #[error("{0}")]
    Unsupported(String),
}

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

/// The scene on the page: positions to the right and up, in the case's display length unit
/// (`length_label`), the frame's way round (`frame`: an SAE case is drawn as a map, x up).
#[derive(Debug, Serialize, Default)]
pub struct Plan {
    /// `natural` or `sae`.
    pub frame: &'static str,
    /// The length unit's label (`m`, `ft`).
    pub length_label: &'static str,
    /// Metres per display length unit.
    pub metres: f64,
    /// The speed unit's label.
    pub speed_label: &'static str,
    /// Metres per second per display speed unit.
    pub speed_metres: f64,
    /// Each vehicle.
    pub vehicles: Vec<PlanVehicle>,
    /// The case's `[background]` image, placed on the page.
    pub background: Option<PlanBackground>,
    /// The impact centre and the crush surface's normal, on the page.
    pub impact: Option<PlanImpact>,
    /// The ground's friction zones (`[[runout.zones]]`), on the page.
    pub zones: Vec<PlanZone>,
    /// The answer's motion in time (a reconstruction's), for the time slider.
    pub motion: Option<crate::motion::PlanMotion>,
}

/// A friction zone on the page: its corners and its friction.
#[derive(Debug, Serialize, Default)]
pub struct PlanZone {
    /// The polygon's corners, the display length unit on the page.
    pub corners: Vec<[f64; 2]>,
    /// Its friction coefficient.
    pub friction: f64,
}

/// The impact on the page: the centre and the direction of the crush surface's normal as the
/// case gives it (`crush_angle`), degrees counter-clockwise from the page's right.
#[derive(Debug, Serialize, Default)]
pub struct PlanImpact {
    /// The impact centre.
    pub centre: [f64; 2],
    /// The normal's direction.
    pub normal: f64,
}

/// A background image on the page: pixel `(u, v)` (right, down from its top left) lies at
/// `at + per_pixel R(rotation) ((u, v) - pixels[0])` with the pixel's down turned to the
/// page's down.
#[derive(Debug, Serialize, Default)]
pub struct PlanBackground {
    /// The image's path inside the folder served (`GET /api/image?path=`).
    pub image: String,
    /// The two points on the image that set its scale, pixels.
    pub pixels: [[f64; 2]; 2],
    /// Their distance, the display length unit.
    pub distance: f64,
    /// Where the first point lies on the page.
    pub at: [f64; 2],
    /// Display length units per pixel.
    pub per_pixel: f64,
    /// Degrees turned counter-clockwise on the page.
    pub rotation: f64,
    /// Not moved by dragging.
    pub locked: bool,
}

/// One vehicle on the page.
#[derive(Debug, Serialize, Default)]
pub struct PlanVehicle {
    /// 1 or 2.
    pub vehicle: u8,
    /// Its outline at contact (closed polygon).
    pub contact: Vec<[f64; 2]>,
    /// Its outline at rest, where the run-out ends.
    pub rest: Vec<[f64; 2]>,
    /// Its outline every half second of the run-out.
    pub every: Vec<Vec<[f64; 2]>>,
    /// The CG's path.
    pub path: Vec<[f64; 2]>,
    /// The rest position the scene gives (CG), its heading on the page (deg counter-clockwise
    /// from the page's right) and its standard deviations.
    pub given_rest: Option<GivenRest>,
    /// The marks the scene gives: position and standard deviation.
    pub marks: Vec<[f64; 3]>,
    /// The path of each tyre that left a mark (a mark's residual is its distance from it).
    pub traces: Vec<Vec<[f64; 2]>>,
    /// Its CG at contact.
    pub cg: [f64; 2],
    /// Its heading at contact, degrees counter-clockwise from the page's right.
    pub heading: f64,
    /// The length of its skid up to contact (`[pre_impact.vehicleN] skid`), display unit.
    pub skid: Option<f64>,
    /// Its crush profile on its outline at contact (`[damage.vehicleN]`), a closed polygon.
    pub damage: Vec<[f64; 2]>,
}

/// A rest position given by the scene, on the page.
#[derive(Debug, Serialize)]
pub struct GivenRest {
    /// Its CG.
    pub at: [f64; 2],
    /// Its standard deviations along the written frame's x and y.
    pub sigma: [f64; 2],
    /// The vehicle's outline there.
    pub outline: Vec<[f64; 2]>,
    /// The tyres measured at rest, when the rest is given by them.
    pub tyres: Vec<[f64; 2]>,
    /// The heading given at rest on the page, degrees counter-clockwise from the page's right
    /// (a rest given as its CG and heading: the page turns it by a knob).
    pub heading: Option<f64>,
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
        _ if case.content.coefficients.is_some()
            && case.content.estimates.is_none()
            && case.content.known.is_none()
            && case.content.observations.is_empty() =>
        {
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
        _ => {
            let fitted = pim_studies::documents::fit(
                &case,
                None,
                FitModel::Pim,
                MomentForm::Corrected,
                branches,
            )
            .map_err(|e| input(&e))?;
            let table = pim_render::tables::fit_table(
                &title,
                "custom",
                &fitted.report,
                units,
                case.written,
            );
            let separation = fitted
                .report
                .best_branch()
                .and_then(|b| b.solution.as_ref())
                .map(|s| s.separation);
            let plan = if case.has_runout() {
                separation
                    .map(|sep| run_out(&case, sep))
                    .transpose()
                    .and_then(|r| plan(&case, r.as_ref(), units))
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
    }
}

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

/// The friction `zones` (SI, natural frame) on the page (`on_page`).
fn zones_on_page(
    zones: &[pim_runout::Zone],
    on_page: impl Fn(f64, f64) -> [f64; 2],
) -> Vec<PlanZone> {
    zones
        .iter()
        .map(|z| PlanZone {
            corners: z.corners.iter().map(|c| on_page(c[0], c[1])).collect(),
            friction: z.friction,
        })
        .collect()
}

/// The scene on the page: the run-outs `runouts` (or without them, the vehicles where they
/// stand and the evidence only).
fn plan(
    case: &Case,
    runouts: Option<&pim_studies::runout::RunoutResult>,
    units: UnitSystem,
) -> Result<Plan, AnswerError> {
    let page = pim_render::plan::Page::of(case.written);
    let metres = units.length(1.0).recip();
    let speed_metres = units.speed(1.0).recip();
    let mut out = Plan {
        frame: match case.written {
            Convention::Sae => "sae",
            _ => "natural",
        },
        length_label: units.length_label(),
        metres,
        speed_label: units.speed_label(),
        speed_metres,
        vehicles: Vec::new(),
        background: None,
        impact: None,
        zones: Vec::new(),
        motion: None,
    };
    // A direction (natural frame, radians) on the page, degrees counter-clockwise from the
    // page's right.
    let page_angle = |a: f64| {
        let (o, d) = (page.xy((0.0, 0.0)), page.xy((a.cos(), a.sin())));
        (d.1 - o.1).atan2(d.0 - o.0).to_degrees()
    };
    if let Ok(impact) = case.impact() {
        let c = case.impact_centre();
        let (h, v) = page.xy((units.length(c[0]), units.length(c[1])));
        out.impact = Some(PlanImpact {
            centre: [h, v],
            normal: page_angle(impact.collision().crush_angle.to_radians()),
        });
    }
    if let Some(b) = &case.content.background {
        let (length, flip) = case.length_and_flip();
        let at = b.at.map_or([0.0, 0.0], |p| [p.x, p.y]);
        let (h, v) = page.xy((
            units.length(at[0] * length),
            units.length(flip * at[1] * length),
        ));
        let [p, q] = b.pixels;
        let distance = units.length(b.distance * length);
        let folder = std::path::Path::new(&case.file)
            .parent()
            .unwrap_or(std::path::Path::new(""));
        out.background = Some(PlanBackground {
            image: folder.join(&b.image).to_string_lossy().replace('\\', "/"),
            pixels: b.pixels,
            distance,
            at: [h, v],
            per_pixel: distance / (q[0] - p[0]).hypot(q[1] - p[1]),
            rotation: b.rotation,
            locked: b.locked,
        });
    }
    let Some(r) = runouts else {
        return Ok(out);
    };
    let on_page = |x: f64, y: f64| {
        let (h, v) = page.xy((units.length(x), units.length(y)));
        [h, v]
    };
    out.zones = r
        .inputs
        .first()
        .map_or(Vec::new(), |v| zones_on_page(&v.chassis.zones, on_page));
    let outline = |k: usize, m: &pim_runout::Motion| -> Vec<[f64; 2]> {
        pim_render::runout::outline_on_page(r, k, m, units, case.written)
            .into_iter()
            .map(|(h, v)| [h, v])
            .collect()
    };
    let damage = pim_case::damage::Damage::of(case).ok().flatten();
    for (k, (input, run)) in r.inputs.iter().zip(&r.runouts).enumerate() {
        let crush = damage
            .as_ref()
            .and_then(|d| d.vehicles[input.id.index()].as_ref())
            .map(|d| {
                pim_render::runout::damage_on_page(r, k, &run.start, d, units, case.written)
                    .into_iter()
                    .map(|(h, v)| [h, v])
                    .collect()
            })
            .unwrap_or_default();
        let evidence = input.evidence.as_ref();
        let given_rest = evidence.and_then(|e| e.rest).map(|rest| {
            // Where the CG rests as measured (the tyres' rest is of their centroid).
            let (x, y) = rest.cg();
            let pose = pim_runout::Motion {
                x,
                y,
                heading: rest.heading.unwrap_or(run.rest.heading),
                ..pim_runout::Motion::default()
            };
            GivenRest {
                at: on_page(x, y),
                sigma: [
                    units.length(rest.sigma_xy[0]),
                    units.length(rest.sigma_xy[1]),
                ],
                outline: outline(k, &pose),
                tyres: input
                    .rest_tyres
                    .iter()
                    .map(|t| on_page(t[0], t[1]))
                    .collect(),
                heading: rest
                    .heading
                    .filter(|_| input.rest_tyres.is_empty())
                    .map(page_angle),
            }
        });
        let marks = evidence
            .map(|e| {
                e.marks
                    .iter()
                    .map(|m| {
                        let [h, v] = on_page(m.x, m.y);
                        [h, v, units.length(m.sigma)]
                    })
                    .collect()
            })
            .unwrap_or_default();
        let traces = pim_render::runout::tyre_traces(run, evidence)
            .into_iter()
            .map(|t| t.into_iter().map(|(x, y)| on_page(x, y)).collect())
            .collect();
        let every = run.sample(0.5).iter().map(|(_, m)| outline(k, m)).collect();
        out.vehicles.push(PlanVehicle {
            vehicle: input.id.index() as u8 + 1,
            contact: outline(k, &run.start),
            rest: outline(k, &run.rest),
            every,
            path: run
                .sample(0.05)
                .iter()
                .map(|(_, m)| on_page(m.x, m.y))
                .collect(),
            given_rest,
            marks,
            traces,
            cg: on_page(run.start.x, run.start.y),
            heading: page_angle(run.start.heading),
            skid: case
                .content
                .pre_impact
                .as_ref()
                .and_then(|p| match input.id {
                    pim_core::VehicleId::One => p.vehicle1.as_ref(),
                    pim_core::VehicleId::Two => p.vehicle2.as_ref(),
                })
                .and_then(|p| p.skid)
                .map(|l| units.length(l * case.written_units.length.to_si())),
            damage: crush,
        });
    }
    Ok(out)
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
