//! The documents of a reconstruction (`pim fit --format json` of a scene case): the answer,
//! every piece of evidence against it, the counts of turns compared, and the evidence
//! consistency table. SI units in the natural frame, angles in degrees, like every other
//! document.

use crate::runout::{MotionOut, PoseOut};
use pim_fit::{Certificate, MomentBranch};
use pim_reconstruct::Status;
use serde::{Deserialize, Serialize};

/// What a row of the evidence table is: its identity. The tables, the figures, the
/// consistency table, the page and Python tell rows apart by it; the name is for display.
/// Indices count from 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum EvidenceSource {
    /// An estimated component of the contact state (`[estimates]` with `[sigma]`): 0-5 the
    /// contact velocities (`initial.vehicle1.vx`, `vy`, `omega`, then vehicle 2's), 6-11 the
    /// separation's.
    Estimate {
        /// The component.
        component: usize,
    },
    /// One of the case's `[[observations]]`.
    Observation {
        /// Which, in the file's order.
        index: usize,
    },
    /// An EDR record's speed (`[[pre_impact.vehicleN.edr]]`).
    Edr {
        /// 1 or 2.
        vehicle: u8,
        /// Which record of that vehicle's, in the file's order.
        index: usize,
    },
    /// A linear combination of the contact state the case gives.
    Combination {
        /// Which, in the contact problem's order.
        index: usize,
    },
    /// Evidence not linear in the velocities (the crush energy).
    Nonlinear {
        /// Which, in the reconstruction's order.
        index: usize,
    },
    /// A fitted road friction against its stated value.
    Friction {
        /// Which fitted friction, in the reconstruction's order.
        index: usize,
    },
    /// A piece of a vehicle's run-out evidence: its rest, a mark.
    Scene {
        /// 1 or 2.
        vehicle: u8,
        /// What it measures.
        what: pim_runout::Quantity,
    },
    /// The prior of an unknown of the pose at contact (`[contact_sigma]`).
    ContactPrior {
        /// Which unknown, in the order the case's pose unknowns are listed.
        index: usize,
    },
}

/// One piece of evidence against the reconstruction.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct EvidenceOut {
    /// What it is.
    pub source: EvidenceSource,
    /// Its display name (`initial.vehicle1.omega`, `vehicle2 rest.x`, `vehicle1 mark 1`, ...).
    pub name: String,
    /// The phase it belongs to: `pre_impact`, `impact` or `run_out`.
    pub phase: &'static str,
    /// What it measures, and so its unit here and in a table: `speed` (m/s), `yaw_rate`
    /// (rad/s), `length` (m) or `angle` (deg).
    pub quantity: &'static str,
    /// Fitted minus given (m/s, rad/s, m or deg).
    pub residual: f64,
    /// Its standard deviation, same unit.
    pub sigma: f64,
    /// Residual over sigma.
    pub z: f64,
    /// Its share of the chi-square, percent.
    pub share_percent: f64,
}

/// One unknown of the pose at contact (`[contact_sigma]`): as the case states it and as the
/// reconstruction fits it. Lengths in m, angles in degrees, the natural frame.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ContactPoseOut {
    /// Which (`vehicle1.heading`, `vehicle2.impact_point.x`, `centre.y`, `crush_angle`).
    pub name: String,
    /// `length` (m) or `angle` (deg).
    pub quantity: &'static str,
    /// A y coordinate or an angle: its sign changes in a frame with y to the right (SAE).
    pub mirrored: bool,
    /// The value the case states (a vehicle's heading, its CG's coordinate, the impact centre's
    /// on the vehicle or in the scene, the crush angle).
    pub stated: f64,
    /// The fitted value.
    pub fitted: f64,
    /// Its standard deviation after the fit (linearised).
    pub sigma: f64,
    /// The prior's standard deviation (`[contact_sigma]`).
    pub prior_sigma: f64,
    /// Fitted minus stated over the prior's deviation.
    pub z: f64,
}

/// One vehicle through the three phases.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct VehiclePhasesOut {
    /// 1 or 2.
    pub vehicle: u8,
    /// Where the braking before the impact began, m/s (with `skid`).
    pub speed_before_braking: Option<f64>,
    /// At contact, m/s.
    pub speed_at_contact: f64,
    /// At separation, m/s.
    pub speed_at_separation: f64,
    /// At rest: 0 with a scene (the run-out ends there), none without.
    pub speed_at_rest: Option<f64>,
    /// The velocities at contact (m/s, rad/s).
    pub contact: MotionOut,
    /// The velocities at separation.
    pub separation: MotionOut,
    /// Full turns to rest beyond the nearest rest heading (with a rest heading).
    pub turns: Option<i64>,
    /// Where the run-out ends (with a scene).
    pub rest: Option<PoseOut>,
    /// The run-out's distance, m, and time, s.
    pub runout_distance: Option<f64>,
    /// The run-out's time, s.
    pub runout_time: Option<f64>,
}

/// One combination of counts of turns compared.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct CountsOut {
    /// Per scene vehicle (in the order of `scene_vehicles`).
    pub turns: Vec<Option<i64>>,
    /// The scenes alone at the best their search found for these counts (a lower bound of the
    /// combination's cost where that search found each count's minimum).
    pub scene_alone: f64,
    /// The momentum bound of the linearised problem.
    pub momentum_bound: Option<f64>,
    /// The chi-square reached, when refined.
    pub chi_square: Option<f64>,
    /// `best`, `refined`, `abandoned`, `not_refined` or `no_impact`.
    pub state: &'static str,
    /// Why not refined, or why no impact.
    pub reason: Option<String>,
}

/// The reconstruction found.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BestOut {
    /// The moment branch.
    pub branch: MomentBranch,
    /// Restitution.
    pub e: f64,
    /// Equivalent friction.
    pub mu: f64,
    /// Moment restitution.
    pub em: f64,
    /// Kinetic energy lost in the impact, percent.
    pub energy_loss_percent: f64,
    /// The whole chi-square.
    pub chi_square: f64,
    /// Its degrees of freedom.
    pub degrees_of_freedom: i64,
    /// `P(chi2 >= value)`.
    pub p_value: Option<f64>,
    /// Per vehicle, every phase.
    pub vehicles: Vec<VehiclePhasesOut>,
    /// Every piece of evidence against the fit.
    pub evidence: Vec<EvidenceOut>,
    /// Gauss-Newton iterations, and whether they met their tolerance.
    pub iterations: usize,
    /// The iterations met their tolerance.
    pub converged: bool,
    /// How the impact fit at the found separation state was established.
    pub certificate: Certificate,
    /// The search bounds the impact ends on (the bound, not the evidence, ends it there),
    /// each with who set it.
    pub bounds_reached: Vec<crate::records::BoundReached>,
    /// The fitted frictions the run-outs ran on, in the order of the `friction` rows of
    /// `evidence` (the road's, then each zone's whose friction is fitted); absent where no
    /// friction is fitted. `pim fit --from` starts its run-outs on them again.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub frictions: Vec<f64>,
    /// The pose at contact, where the case fits it (`[contact_sigma]`): each unknown stated and
    /// fitted. Its priors are rows of `evidence` and terms of `chi_square`.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub contact_pose: Vec<ContactPoseOut>,
}

/// The document of a reconstruction (`pim fit --format json` of a scene case).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ReconstructionOut {
    /// Units of the numbers.
    pub units: crate::records::SiUnits,
    /// `reconstruction`.
    pub kind: &'static str,
    /// `found` or `no_solution`.
    pub status: Status,
    /// Why there is no answer.
    pub reason: Option<String>,
    /// The answer.
    pub best: Option<BestOut>,
    /// The vehicles whose scene was fitted (1, 2).
    pub scene_vehicles: Vec<u8>,
    /// Every combination of counts of turns, compared.
    pub counts: Vec<CountsOut>,
    /// Run-outs simulated and impact fits solved.
    pub runouts: usize,
    /// Impact fits solved.
    pub fits: usize,
    /// The refinements' work: run-out right-hand side evaluations and the impact fits'
    /// equivalents, counted against their budget (`pim_reconstruct::REFINE_WORK`), so that the
    /// answer is the same on every machine.
    pub work: u64,
    /// The work of the first search alone: `work` without that of the second search from a
    /// scatter of separation states, when the first answer fit poorly.
    pub first_search_work: u64,
    /// How the answer was found.
    pub method: String,
    /// What is proven.
    pub proven: String,
    /// What the evidence leaves undetermined or the search does not prove.
    pub undetermined: Vec<String>,
    /// For a refused or poorly fitting reconstruction: the evidence left out piece by piece
    /// (pim-studies' `consistency`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub consistency: Option<Consistency>,
}

/// The reconstruction with some evidence left out.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct LeftOut {
    /// What was left out (empty: nothing, the whole evidence).
    pub left_out: Vec<String>,
    /// `found`, `inconsistent` or `no_solution`; `failed` when the rest cannot be
    /// reconstructed at all (e.g. no scene evidence left).
    pub status: String,
    /// The chi-square of the rest (with an answer).
    pub chi_square: Option<f64>,
    /// Its degrees of freedom.
    pub degrees_of_freedom: Option<i64>,
    /// `P(chi^2 >= value)`, judged as every chi-square is ([`pim_fit::judged_dof`]).
    pub p_value: Option<f64>,
    /// The rest fits within its standard deviations (found, p at least
    /// [`pim_reconstruct::POOR_FIT_P`]).
    pub consistent: bool,
    /// Each vehicle's speed at contact, m/s.
    pub speed_at_contact: [Option<f64>; 2],
    /// Each vehicle's speed where its braking began, m/s (with a skid).
    pub speed_before_braking: [Option<f64>; 2],
    /// The largest remaining residual, as the evidence table names it, and its z.
    pub largest: Option<(String, f64)>,
    /// Why there is no row (a reconstruction that failed on its input).
    pub error: Option<String>,
}

/// The evidence consistency table of a reconstruction.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Consistency {
    /// The reconstruction with all of its evidence.
    pub all: LeftOut,
    /// One row per piece left out, then (when no single piece explains the conflict) per pair.
    pub rows: Vec<LeftOut>,
    /// What can be left out to make the rest consistent (each entry one row's `left_out`).
    pub consistent_without: Vec<Vec<String>>,
    /// In words: which pieces disagree.
    pub summary: String,
    /// Present when the table was cancelled: the rows asked for and finished (`rows` holds
    /// those).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cancelled: Option<crate::watch::Cancelled>,
}

/// A vehicle through the phases of a batch's reconstruction (SI, natural frame).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct SceneVehicleRecord {
    /// 1 or 2.
    pub vehicle: u8,
    /// Where its braking began, m/s (with a skid).
    pub speed_before_braking: Option<f64>,
    /// At contact, m/s.
    pub speed_at_contact: f64,
    /// At separation, m/s.
    pub speed_at_separation: f64,
    /// Full turns to rest beyond the shortest rotation to the rest heading (counter-clockwise
    /// positive), with a rest heading.
    pub turns: Option<i64>,
}

/// The reconstruction of a batch record.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct SceneRecord {
    /// `found`, `inconsistent` or `no_solution`.
    pub status: pim_reconstruct::Status,
    /// Why there is no answer, or what contradicts it.
    pub reason: Option<String>,
    /// The whole chi-square.
    pub chi_square: Option<f64>,
    /// Its degrees of freedom.
    pub degrees_of_freedom: Option<i64>,
    /// Its probability ([`pim_fit::judged_dof`]).
    pub p_value: Option<f64>,
    /// Per vehicle, every phase.
    pub vehicles: Vec<SceneVehicleRecord>,
}

impl SceneRecord {
    /// The summary of a reconstruction's document.
    pub fn of(d: &ReconstructionOut) -> Self {
        let b = d.best.as_ref();
        SceneRecord {
            status: d.status,
            reason: d.reason.clone(),
            chi_square: b.map(|b| b.chi_square),
            degrees_of_freedom: b.map(|b| b.degrees_of_freedom),
            p_value: b.and_then(|b| b.p_value),
            vehicles: b
                .map(|b| {
                    b.vehicles
                        .iter()
                        .map(|v| SceneVehicleRecord {
                            vehicle: v.vehicle,
                            speed_before_braking: v.speed_before_braking,
                            speed_at_contact: v.speed_at_contact,
                            speed_at_separation: v.speed_at_separation,
                            turns: v.turns,
                        })
                        .collect()
                })
                .unwrap_or_default(),
        }
    }
}
