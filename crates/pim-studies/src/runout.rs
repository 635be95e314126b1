//! The document of `pim runout`: each vehicle from its separation velocities to rest, and the
//! separation velocities estimated from the scene when the case gives no other source.
//!
//! The JSON is SI in the natural frame with angles in degrees (counter-clockwise from +x),
//! like every other document of the toolkit.

use crate::documents::DocumentError;
use pim_case::case::Case;
use pim_case::scene::VehicleRunout;
use pim_core::{VehicleId, Velocities};
pub use pim_documents::runout::{
    CandidateOut, EstimateOut, MotionOut, PathPoint, PoseOut, ResidualOut, RunoutOut, Source,
    VehicleRunoutOut, WheelOut,
};
use pim_runout::{Candidate, End, Estimate, EstimateSettings, Motion, Runout, Settings};

/// Most samples of a path in the document (a longer motion is sampled more coarsely).
pub const MAX_PATH_SAMPLES: usize = 100_000;

/// The units of a run-out document.
const UNITS: &str =
    "SI (m, s, m/s, rad/s, J); angles in degrees counter-clockwise from +x (natural frame)";

/// A computed run-out: the document and the typed results (for drawings).
#[derive(Debug, Clone)]
pub struct RunoutResult {
    /// The inputs per vehicle.
    pub inputs: Vec<VehicleRunout>,
    /// The run-out of each vehicle, same order.
    pub runouts: Vec<Runout>,
    /// The estimate of each vehicle (source `scene`).
    pub estimates: Vec<Option<Estimate>>,
    /// The document.
    pub document: RunoutOut,
    /// `[runout] duration`: each run-out followed for this long, s.
    pub duration: Option<f64>,
}

impl RunoutResult {
    /// True when some run-out reached its time limit or no candidate reaches the evidence.
    pub fn no_answer(&self) -> Option<String> {
        for ((r, v), input) in self
            .runouts
            .iter()
            .zip(&self.document.vehicles)
            .zip(&self.inputs)
        {
            // A vehicle set up to roll on (no rolling resistance) ends at the time limit by
            // design: the state there is its answer.
            if r.end == End::TimeLimit && !input.chassis.rolls_on() && self.duration.is_none() {
                return Some(format!(
                    "vehicle {}: the run-out reached its time limit ({:.1} s) still moving at \
                     {:.3} m/s: it does not come to rest (raise [runout] time_limit, or check \
                     the wheels: free-rolling wheels roll far)",
                    v.vehicle,
                    r.time,
                    r.rest.vx.hypot(r.rest.vy)
                ));
            }
        }
        for (e, v) in self.estimates.iter().zip(&self.document.vehicles) {
            if let Some(best) = e.as_ref().and_then(|e| e.best()) {
                if let Some(why) = &best.reason {
                    return Some(format!("vehicle {}: {why}", v.vehicle));
                }
            }
        }
        None
    }
}

/// The separation velocities of the case from `source`, or the first the case has: `[final]`,
/// then `[coefficients]` with `[initial]`; `None` when it has neither (the scene decides).
fn separation(
    case: &Case,
    source: Option<Source>,
) -> Result<Option<(Velocities, Source)>, DocumentError> {
    if case.is_motion() {
        return match source {
            None | Some(Source::Start) => Ok(None),
            Some(_) => Err(DocumentError::Input(format!(
                "{}: a motion case starts from [start]; --from final, solve, fit and scene \
                 belong to a case with an impact",
                case.file
            ))),
        };
    }
    let wanted = source.or(if case.states_final() {
        Some(Source::Final)
    } else if case.solvable() {
        Some(Source::Solve)
    } else {
        None
    });
    match wanted {
        None | Some(Source::Scene) => Ok(None),
        Some(Source::Final) => {
            if !case.states_final() {
                return Err(DocumentError::Input(format!(
                    "{}: --from final needs [final]",
                    case.file
                )));
            }
            let (state, forward) = case.known_state()?;
            if forward {
                // [initial] and [final] both given: the [final] section is the one asked for.
                let solved = crate::documents::solve(case, &pim_core::SolveOptions::default())?;
                return Ok(Some((solved.report.separation, Source::Final)));
            }
            Ok(Some((state, Source::Final)))
        }
        Some(Source::Solve) => {
            let solved = crate::documents::solve(case, &pim_core::SolveOptions::default())?;
            if !solved.forward {
                return Err(DocumentError::Input(format!(
                    "{}: --from solve needs [coefficients] and [initial]",
                    case.file
                )));
            }
            Ok(Some((solved.report.separation, Source::Solve)))
        }
        Some(Source::Start) => Err(DocumentError::Input(format!(
            "{}: [start] belongs to a motion case (no impact)",
            case.file
        ))),
        Some(Source::Fit | Source::Reconstruction) => Err(DocumentError::Input(format!(
            "{}: a fit's separation velocities are passed in by the caller",
            case.file
        ))),
    }
}

/// The separation velocities of the case's fit (`pim runout --from fit`): the best branch of
/// the fit under `cost` (the case's own estimates with `None`).
///
/// # Errors
/// Bad input, or [`DocumentError::NoAnswer`] when the fit has no admissible solution.
pub fn fitted_separation(
    case: &Case,
    cost: Option<pim_fit::CostPreset>,
) -> Result<Velocities, DocumentError> {
    let fitted = crate::documents::fit(
        case,
        cost,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::default(),
        pim_fit::MomentBranch::ALL.to_vec(),
    )?;
    fitted
        .report
        .best_branch()
        .and_then(|b| b.solution.as_ref())
        .map(|s| s.separation)
        .ok_or_else(|| {
            DocumentError::NoAnswer(format!(
                "{}: the fit has no admissible solution, so there are no separation velocities \
                 to run out (see `pim fit`)",
                case.file
            ))
        })
}

/// `pim runout`: every vehicle with a `[runout.vehicleN]` from its separation velocities to
/// rest. `given` are separation velocities from elsewhere (a fit); otherwise they come from
/// `source` or the first source the case has, and from the scene when it has none.
///
/// # Errors
/// Bad input ([`DocumentError::Input`], located), or an impact that cannot be solved.
pub fn runout(
    case: &Case,
    source: Option<Source>,
    given: Option<Velocities>,
    sample: f64,
    wheels: bool,
) -> Result<RunoutResult, DocumentError> {
    let inputs = case.scene_inputs()?;
    let settings = Settings {
        time_limit: inputs.time_limit,
        ..Settings::default()
    };
    let from = match given {
        Some(v) => Some((v, Source::Fit)),
        None => separation(case, source)?,
    };
    let source = match from {
        Some((_, s)) => s,
        None if case.is_motion() => Source::Start,
        None => Source::Scene,
    };
    let mut runouts = Vec::new();
    let mut estimates = Vec::new();
    let mut vehicles = Vec::new();
    let mut notes = Vec::new();
    for v in &inputs.vehicles {
        let k = v.id.index();
        let name = format!("vehicle{}", k + 1);
        let (runout, estimate) = match &from {
            Some((state, _)) => (separated(case, v, state, &settings)?, None),
            None if case.is_motion() => {
                let r = pim_runout::simulate(&v.chassis, &v.start, &settings)
                    .map_err(|e| runout_failure(case, &name, e))?;
                (r, None)
            }
            None => {
                let Some(evidence) = &v.evidence else {
                    return Err(DocumentError::Input(format!(
                        "{}: {name}: no separation velocities and no scene evidence: give \
                         [final], [coefficients] with [initial], or [scene.{name}] with the rest \
                         position",
                        case.file
                    )));
                };
                let es = EstimateSettings {
                    runout: settings,
                    ..EstimateSettings::default()
                };
                let e = pim_runout::estimate(&v.chassis, &v.start, evidence, &es)
                    .map_err(|e| runout_failure(case, &name, e))?;
                let best = e
                    .best()
                    .expect("an estimate has at least one candidate")
                    .runout
                    .clone();
                (best, Some(e))
            }
        };
        // The evidence against a run-out from given separation velocities.
        let evidence = match (&estimate, &v.evidence) {
            (None, Some(ev)) => evidence_against(v, ev, &runout),
            (Some(e), _) => e
                .best()
                .map(|c| c.residuals.iter().map(residual_out).collect())
                .unwrap_or_default(),
            _ => Vec::new(),
        };
        let estimate_out = estimate
            .as_ref()
            .map(|e| estimate_out(e, &name, &mut notes));
        vehicles.push(vehicle_out(
            k,
            v,
            &runout,
            evidence,
            estimate_out,
            (sample, wheels),
        ));
        runouts.push(runout);
        estimates.push(estimate);
    }
    for ((r, v), input) in runouts.iter().zip(&vehicles).zip(&inputs.vehicles) {
        notes.extend(unfinished(r, v.vehicle, input, inputs.duration));
    }
    Ok(RunoutResult {
        duration: inputs.duration,
        inputs: inputs.vehicles,
        runouts,
        estimates,
        document: RunoutOut {
            units: UNITS,
            source,
            vehicles,
            notes,
            duration: inputs.duration,
        },
    })
}

/// The run-outs of a reconstruction's answer, as it found them: each scene vehicle's fitted
/// run-out (on the friction it was fitted on, with the residuals its evidence table prints),
/// and a vehicle without scene evidence run out from the answer's separation velocities on
/// its stated road. What every figure of a reconstruction draws: none simulates again.
///
/// # Errors
/// Bad run-out input in the case ([`DocumentError::Input`]), or a run-out that cannot be
/// simulated for a vehicle without scene evidence.
pub fn fitted(
    case: &Case,
    found: &pim_reconstruct::Found,
    sample: f64,
    wheels: bool,
) -> Result<RunoutResult, DocumentError> {
    let inputs = case.scene_inputs()?;
    let settings = Settings {
        time_limit: inputs.time_limit,
        ..Settings::default()
    };
    let sep = &found.solution.separation;
    let mut vehicles = Vec::new();
    let mut runouts = Vec::new();
    let mut used = Vec::new();
    for v in &inputs.vehicles {
        let k = v.id.index();
        let mut v = v.clone();
        let (runout, evidence) = match found.scene.iter().find(|f| f.vehicle == v.id) {
            Some(f) => {
                f.ground(&mut v.chassis);
                let evidence = f.residuals.iter().map(residual_out).collect();
                (f.runout.clone(), evidence)
            }
            None => {
                let r = separated(case, &v, sep, &settings)?;
                let evidence = v
                    .evidence
                    .as_ref()
                    .map(|ev| evidence_against(&v, ev, &r))
                    .unwrap_or_default();
                (r, evidence)
            }
        };
        vehicles.push(vehicle_out(
            k,
            &v,
            &runout,
            evidence,
            None,
            (sample, wheels),
        ));
        runouts.push(runout);
        used.push(v);
    }
    Ok(RunoutResult {
        duration: inputs.duration,
        estimates: vec![None; used.len()],
        inputs: used,
        runouts,
        document: RunoutOut {
            units: UNITS,
            source: Source::Reconstruction,
            vehicles,
            notes: Vec::new(),
            duration: inputs.duration,
        },
    })
}

/// What a run-out that ended at its time limit is (the state at the stated duration, a
/// free-rolling vehicle that does not stop, or one still moving), in words; nothing for one
/// at rest.
fn unfinished(
    r: &Runout,
    vehicle: u8,
    input: &VehicleRunout,
    duration: Option<f64>,
) -> Option<String> {
    if r.end != End::TimeLimit {
        return None;
    }
    Some(if let Some(d) = duration {
        format!(
            "vehicle {vehicle}: followed for the stated duration ({d} s): its end is the state \
             then, still moving at {:.3} m/s",
            r.rest.vx.hypot(r.rest.vy)
        )
    } else if input.chassis.rolls_on() {
        format!(
            "vehicle {vehicle}: free-rolling wheels without rolling resistance do not stop: the \
             run-out is followed to its time limit ({:.1} s), and its end is the state there, \
             still moving at {:.3} m/s",
            r.time,
            r.rest.vx.hypot(r.rest.vy)
        )
    } else {
        format!(
            "vehicle {vehicle}: the run-out reached its time limit ({:.1} s) still moving",
            r.time
        )
    })
}

/// Vehicle `v`'s run-out from its velocities in the separation state `state`.
fn separated(
    case: &Case,
    v: &VehicleRunout,
    state: &Velocities,
    settings: &Settings,
) -> Result<Runout, DocumentError> {
    let vel = if v.id == VehicleId::One {
        state.vehicle1
    } else {
        state.vehicle2
    };
    let start = Motion {
        vx: vel.vx,
        vy: vel.vy,
        yaw_rate: vel.omega,
        ..v.start
    };
    pim_runout::simulate(&v.chassis, &start, settings)
        .map_err(|e| runout_failure(case, &format!("vehicle{}", v.id.index() + 1), e))
}

fn runout_failure(case: &Case, name: &str, e: pim_runout::RunoutError) -> DocumentError {
    match e {
        pim_runout::RunoutError::Input { .. } => {
            DocumentError::Input(case.runout_error(name, e).message)
        }
        other => DocumentError::NoAnswer(format!("{}: {name}: {other}", case.file)),
    }
}

fn residual_out(r: &pim_runout::inverse::Residual) -> ResidualOut {
    let f = |x: f64| if r.what.is_angle() { x.to_degrees() } else { x };
    ResidualOut {
        what: r.what,
        name: r.name.clone(),
        value: f(r.value),
        sigma: f(r.sigma),
        z: r.value / r.sigma,
    }
}

/// The residuals of given evidence against a run-out: the nearest rest heading counts (the
/// run-out's own rotation decides the turns).
fn evidence_against(v: &VehicleRunout, ev: &pim_runout::Evidence, r: &Runout) -> Vec<ResidualOut> {
    pim_runout::inverse::residuals_of(&v.chassis, ev, r)
        .iter()
        .map(residual_out)
        .collect()
}

fn candidate_out(c: &Candidate) -> CandidateOut {
    CandidateOut {
        turns: c.turns,
        separation: MotionOut::from(&c.separation),
        friction: c.friction,
        cost: c.cost,
        consistent: c.consistent,
        plausible: c.plausible,
        converged: c.converged,
        runouts: c.runouts,
        sigma: c.sigma.clone(),
        free: c.free.clone(),
        residuals: c.residuals.iter().map(residual_out).collect(),
        reason: c.reason.clone(),
    }
}

fn estimate_out(e: &Estimate, name: &str, notes: &mut Vec<String>) -> EstimateOut {
    let mut undetermined = Vec::new();
    let consistent: Vec<&Candidate> = e.consistent().collect();
    // Whether the evidence is reached at all (when not, that is the answer, said elsewhere).
    let reached = e.best().is_some_and(|b| b.reason.is_none());
    if reached && consistent.len() > 1 {
        let counts: Vec<String> = consistent
            .iter()
            .map(|c| c.turns.map_or("-".into(), |t| t.to_string()))
            .collect();
        let line = format!(
            "{name}: the count of turns to rest: {} candidates reach the evidence equally well \
             (turns {}); the run-out shown is the first, not the answer: marks along the path, \
             a stated count ([scene.{name}] turns) or the impact decide",
            consistent.len(),
            counts.join(", ")
        );
        undetermined.push(line.clone());
        notes.push(line);
    }
    let plausible: Vec<&Candidate> = e.candidates.iter().filter(|c| c.plausible).collect();
    if reached && consistent.len() == 1 && plausible.len() > 1 {
        let others: Vec<String> = plausible
            .iter()
            .skip(1)
            .map(|c| {
                format!(
                    "{} (cost {:+.2})",
                    c.turns.map_or("-".into(), |t| t.to_string()),
                    c.cost - plausible[0].cost
                )
            })
            .collect();
        undetermined.push(format!(
            "{name}: the count of turns: the evidence favours {} but does not exclude {} \
             (within a cost of {} of the best: a likelihood ratio above e^-2)",
            plausible[0].turns.map_or("-".into(), |t| t.to_string()),
            others.join(", "),
            pim_runout::PLAUSIBLE_COST
        ));
    }
    if let Some(best) = e.best() {
        for dir in &best.free {
            let parts: Vec<String> = e
                .unknowns
                .iter()
                .zip(dir)
                .filter(|(_, x)| x.abs() > 1e-3)
                .map(|(n, x)| format!("{x:+.3} {n}"))
                .collect();
            undetermined.push(format!(
                "{name}: the evidence does not determine the direction ({}) of the unknowns: \
                 along it the cost does not change",
                parts.join(", ")
            ));
        }
    }
    EstimateOut {
        unknowns: e.unknowns.clone(),
        candidates: e.candidates.iter().map(candidate_out).collect(),
        runouts: e.candidates.iter().map(|c| c.runouts).sum(),
        undetermined,
    }
}

fn vehicle_out(
    k: usize,
    v: &VehicleRunout,
    r: &Runout,
    evidence: Vec<ResidualOut>,
    estimate: Option<EstimateOut>,
    (sample, wheels): (f64, bool),
) -> VehicleRunoutOut {
    // At most MAX_PATH_SAMPLES samples, whatever the interval asked for and the motion's time.
    let path = r
        .sample(sample.max(r.time / MAX_PATH_SAMPLES as f64))
        .iter()
        .map(|(t, m)| PathPoint {
            t: *t,
            x: m.x,
            y: m.y,
            heading: m.heading.to_degrees(),
            speed: m.vx.hypot(m.vy),
            yaw_rate: m.yaw_rate,
            wheels: wheels.then(|| pim_runout::wheels_at(&v.chassis, m, *t).map(WheelOut::from)),
        })
        .collect();
    VehicleRunoutOut {
        vehicle: k as u8 + 1,
        separation: MotionOut::from(&r.start),
        friction: estimate
            .as_ref()
            .and_then(|e| e.candidates.first())
            .map_or(v.chassis.friction, |c| c.friction),
        wheels: v.chassis.wheels,
        end: r.end,
        rest: PoseOut {
            x: r.rest.x,
            y: r.rest.y,
            heading: r.rest.heading.to_degrees(),
        },
        distance: r.distance,
        time: r.time,
        rotation: r.rotation.to_degrees(),
        turns: r.turns(),
        initial_energy: r.initial_energy,
        tyre_work: r.tyre_work,
        path,
        evidence,
        estimate,
    }
}
