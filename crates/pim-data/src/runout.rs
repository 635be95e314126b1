//! The document of `pim runout`: each vehicle from its separation velocities to rest, and the
//! separation velocities estimated from the scene when the case gives no other source.
//!
//! The JSON is SI in the natural frame with angles in degrees (counter-clockwise from +x),
//! like every other document of the toolkit.

use crate::documents::DocumentError;
use pim_case::case::Case;
use pim_case::scene::VehicleRunout;
use pim_core::{VehicleId, Velocities};
use pim_runout::{Candidate, End, Estimate, EstimateSettings, Motion, Runout, Settings};
use serde::Serialize;

/// Most samples of a path in the document (a longer motion is sampled more coarsely).
pub const MAX_PATH_SAMPLES: usize = 100_000;

/// Where the separation velocities come from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Source {
    /// The case's `[final]`.
    Final,
    /// The solve of `[coefficients]` and `[initial]`.
    Solve,
    /// The fit of the case (its estimates, with the cost function given).
    Fit,
    /// Estimated from the scene (`[scene.vehicleN]`) through the run-out model.
    Scene,
}

impl Source {
    /// How the source is named in tables.
    pub fn describe(self) -> &'static str {
        match self {
            Source::Final => "the case's [final]",
            Source::Solve => "the solve of [coefficients] and [initial]",
            Source::Fit => "the fit of the case",
            Source::Scene => "estimated from the scene (rest position, heading, marks)",
        }
    }
}

/// A pose or motion in the document: m, deg, m/s, rad/s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct MotionOut {
    /// CG x, m.
    pub x: f64,
    /// CG y, m.
    pub y: f64,
    /// Heading, deg (whole turns kept).
    pub heading: f64,
    /// CG velocity, m/s.
    pub vx: f64,
    /// CG velocity, m/s.
    pub vy: f64,
    /// Yaw rate, rad/s.
    pub yaw_rate: f64,
}

impl From<&Motion> for MotionOut {
    fn from(m: &Motion) -> Self {
        MotionOut {
            x: m.x,
            y: m.y,
            heading: m.heading.to_degrees(),
            vx: m.vx,
            vy: m.vy,
            yaw_rate: m.yaw_rate,
        }
    }
}

/// The rest pose: m, deg.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PoseOut {
    /// CG x, m.
    pub x: f64,
    /// CG y, m.
    pub y: f64,
    /// Heading, deg (whole turns kept: the heading at separation plus the rotation).
    pub heading: f64,
}

/// One sample of the path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PathPoint {
    /// Time since separation, s.
    pub t: f64,
    /// CG x, m.
    pub x: f64,
    /// CG y, m.
    pub y: f64,
    /// Heading, deg.
    pub heading: f64,
    /// CG speed, m/s.
    pub speed: f64,
    /// Yaw rate, rad/s.
    pub yaw_rate: f64,
}

/// One piece of evidence against the run-out: fitted minus given.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ResidualOut {
    /// `rest.x`, `rest.y`, `rest.heading`, `mark 1`, `mark 1 heading`, `friction`.
    pub name: String,
    /// Fitted minus given: m, deg, or the friction coefficient.
    pub value: f64,
    /// Its standard deviation, same unit.
    pub sigma: f64,
    /// value / sigma.
    pub z: f64,
}

/// A candidate of the estimate (one count of turns).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct CandidateOut {
    /// Full turns beyond the rotation to the nearest rest heading (null without a rest
    /// heading).
    pub turns: Option<i64>,
    /// The separation velocities: m/s, rad/s.
    pub separation: MotionOut,
    /// The friction (estimated when `[runout] friction_sigma` is given).
    pub friction: f64,
    /// Sum of the squared residuals in sigmas.
    pub cost: f64,
    /// Equally consistent with the best (cost within 1e-6).
    pub consistent: bool,
    /// Not excluded by the evidence (cost within 4 of the best: a likelihood ratio above
    /// e^-2).
    pub plausible: bool,
    /// The search converged.
    pub converged: bool,
    /// Run-outs simulated for it.
    pub runouts: usize,
    /// Standard errors of `vx`, `vy`, `yaw_rate` (and `friction`), null where not determined.
    pub sigma: Vec<Option<f64>>,
    /// Directions in (`vx`, `vy`, `yaw_rate`[, `friction`]) the evidence leaves free.
    pub free: Vec<Vec<f64>>,
    /// Every piece of evidence.
    pub residuals: Vec<ResidualOut>,
    /// Why it does not reach the evidence, when it does not.
    pub reason: Option<String>,
}

/// The estimate of one vehicle's separation velocities.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct EstimateOut {
    /// The unknowns, in the order of each candidate's `sigma` and `free`.
    pub unknowns: Vec<String>,
    /// Every count of turns, lowest cost first.
    pub candidates: Vec<CandidateOut>,
    /// Run-outs simulated in all.
    pub runouts: usize,
    /// What the evidence leaves undetermined, in words (empty when it determines everything).
    pub undetermined: Vec<String>,
}

/// One vehicle's run-out.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct VehicleRunoutOut {
    /// 1 or 2.
    pub vehicle: u8,
    /// Position, heading and velocities at separation.
    pub separation: MotionOut,
    /// Road friction used.
    pub friction: f64,
    /// The wheels: front left, front right, rear left, rear right.
    pub wheels: [pim_runout::WheelState; 4],
    /// `rest` or `time_limit`.
    pub end: End,
    /// Where it stopped (or was at the time limit).
    pub rest: PoseOut,
    /// Distance along the CG's path, m.
    pub distance: f64,
    /// Time to rest, s.
    pub time: f64,
    /// Rotation from separation to rest, deg.
    pub rotation: f64,
    /// Full turns of that rotation beyond the shortest rotation between the headings at
    /// separation and at rest (the count of turns of the candidates and of a
    /// reconstruction; counter-clockwise positive in this natural-frame document).
    pub turns: i64,
    /// Kinetic energy at separation, J.
    pub initial_energy: f64,
    /// Work of the tyre forces, J.
    pub tyre_work: f64,
    /// The path sampled in time.
    pub path: Vec<PathPoint>,
    /// The scene's evidence against this run-out (when the case gives it).
    pub evidence: Vec<ResidualOut>,
    /// The estimate from the scene (source `scene`).
    pub estimate: Option<EstimateOut>,
}

/// The document of `pim runout`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct RunoutOut {
    /// The units of every number.
    pub units: &'static str,
    /// Where the separation velocities come from.
    pub source: Source,
    /// One entry per vehicle with a run-out.
    pub vehicles: Vec<VehicleRunoutOut>,
    /// Warnings (a motion ended by the time limit, equally consistent candidates).
    pub notes: Vec<String>,
}

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
}

impl RunoutResult {
    /// True when some run-out reached its time limit or no candidate reaches the evidence.
    pub fn no_answer(&self) -> Option<String> {
        for (r, v) in self.runouts.iter().zip(&self.document.vehicles) {
            if r.end == End::TimeLimit {
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
    let c = &case.content;
    let wanted = source.or(if c.final_.is_some() {
        Some(Source::Final)
    } else if c.coefficients.is_some() && c.initial.is_some() {
        Some(Source::Solve)
    } else {
        None
    });
    match wanted {
        None | Some(Source::Scene) => Ok(None),
        Some(Source::Final) => {
            if c.final_.is_none() {
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
        Some(Source::Fit) => Err(DocumentError::Input(format!(
            "{}: the fit's separation velocities are passed in by the caller",
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
    let source = from.map_or(Source::Scene, |(_, s)| s);
    let mut runouts = Vec::new();
    let mut estimates = Vec::new();
    let mut vehicles = Vec::new();
    let mut notes = Vec::new();
    for v in &inputs.vehicles {
        let k = v.id.index();
        let name = format!("vehicle{}", k + 1);
        let (runout, estimate) = match &from {
            Some((state, _)) => {
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
                let r = pim_runout::simulate(&v.chassis, &start, &settings)
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
        vehicles.push(vehicle_out(k, v, &runout, evidence, estimate_out, sample));
        runouts.push(runout);
        estimates.push(estimate);
    }
    for (r, v) in runouts.iter().zip(&vehicles) {
        if r.end == End::TimeLimit {
            notes.push(format!(
                "vehicle {}: the run-out reached its time limit ({:.1} s) still moving",
                v.vehicle, r.time
            ));
        }
    }
    Ok(RunoutResult {
        inputs: inputs.vehicles,
        runouts,
        estimates,
        document: RunoutOut {
            units: "SI (m, s, m/s, rad/s, J); angles in degrees counter-clockwise from +x (natural frame)",
            source,
            vehicles,
            notes,
        },
    })
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
    let angle = r.name.contains("heading");
    let f = |x: f64| if angle { x.to_degrees() } else { x };
    ResidualOut {
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
    sample: f64,
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
