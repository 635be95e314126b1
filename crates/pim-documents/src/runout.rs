//! The document types of `runout` (what the study of the same name in pim-studies writes).

use pim_runout::{End, Motion};
use serde::Serialize;

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
    /// The state a motion case states (`[start.vehicleN]`, no impact).
    Start,
    /// The reconstruction's answer: each scene vehicle's run-out as it was fitted, on the road
    /// friction it was fitted on.
    Reconstruction,
}

impl Source {
    /// How the source is named in tables.
    pub fn describe(self) -> &'static str {
        match self {
            Source::Final => "the case's [final]",
            Source::Solve => "the solve of [coefficients] and [initial]",
            Source::Fit => "the fit of the case",
            Source::Scene => "estimated from the scene (rest position, heading, marks)",
            Source::Start => "the state stated in [start] (no impact)",
            Source::Reconstruction => {
                "the reconstruction (each run-out as fitted, on its fitted road)"
            }
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

/// One wheel at one sample of the path.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct WheelOut {
    /// Normal load, N (0 when the wheel lifts).
    pub load: f64,
    /// Slip angle, deg: the contact patch's velocity from the wheel's axis, positive when the
    /// patch slides to the wheel's left.
    pub slip_angle: f64,
    /// Tyre force along the vehicle (x forward), N.
    pub force_x: f64,
    /// Tyre force across the vehicle (y to its left), N.
    pub force_y: f64,
}

impl From<pim_runout::WheelAt> for WheelOut {
    fn from(w: pim_runout::WheelAt) -> Self {
        WheelOut {
            load: w.load,
            slip_angle: w.slip_angle.to_degrees(),
            force_x: w.force[0],
            force_y: w.force[1],
        }
    }
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
    /// Each wheel (front left, front right, rear left, rear right), when asked for
    /// (`pim runout --wheels`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub wheels: Option<[WheelOut; 4]>,
}

/// One piece of evidence against the run-out: fitted minus given.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ResidualOut {
    /// What it measures (its identity; tell residuals apart by it, not by the name).
    pub what: pim_runout::Quantity,
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
    /// `[runout] duration`, s: each run-out followed for this long, its end (`end: time_limit`)
    /// the state then.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
}
