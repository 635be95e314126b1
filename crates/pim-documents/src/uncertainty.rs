//! The document types of `uncertainty` (what the study of the same name in pim-studies writes).

use crate::intervals::Summary;
use pim_fit::{FitModel, MomentBranch};
use serde::Serialize;
use std::collections::BTreeMap;

/// The names of the summarised quantities of a PIM fit, in output order.
pub const QUANTITIES: [&str; 8] = [
    "e",
    "mu",
    "em",
    "speed1",
    "speed2",
    "delta_v1",
    "delta_v2",
    "energy_loss_percent",
];

/// The names of the summarised quantities of the tangential model's fit: its coefficients e,
/// et and the friction limit (sticking: the smallest limit that sticks, the impulse ratio)
/// in the places of PIM's e, mu and em.
pub const TANGENTIAL_QUANTITIES: [&str; 8] = [
    "e",
    "et",
    "friction",
    "speed1",
    "speed2",
    "delta_v1",
    "delta_v2",
    "energy_loss_percent",
];

/// The names of the summarised quantities of a model's fit.
pub fn quantities(model: FitModel) -> &'static [&'static str; 8] {
    match model {
        FitModel::Pim => &QUANTITIES,
        FitModel::Tangential => &TANGENTIAL_QUANTITIES,
    }
}

/// One input's share of a quantity's spread.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Sensitivity {
    /// The quantity.
    pub quantity: String,
    /// Inputs by first-order index, largest first (only those above 0.02).
    pub inputs: Vec<(String, f64)>,
}

/// The whole study.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Study {
    /// The units of the document's numbers (always SI: speeds and delta-V in m/s).
    pub units: crate::records::SiUnits,
    /// The model fitted by every draw; it names the coefficients ([`quantities`]).
    pub model: FitModel,
    /// Draws made (those asked for, unless the study was cancelled).
    pub draws: usize,
    /// Seed of the random streams.
    pub seed: u64,
    /// Draws with an admissible fit.
    pub feasible_draws: usize,
    /// The fit without perturbation (its best branch), by quantity.
    pub nominal: BTreeMap<String, f64>,
    /// The nominal best branch.
    pub nominal_branch: Option<MomentBranch>,
    /// The search bounds the nominal fit rests on (absent when none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub nominal_bounds: Vec<crate::records::BoundReached>,
    /// Share of the feasible draws whose fit rests on each search bound (only those reached).
    pub bound_share: BTreeMap<String, f64>,
    /// Summaries by quantity.
    pub quantities: BTreeMap<String, Summary>,
    /// Share of the feasible draws whose best branch is each branch.
    pub branch_share: BTreeMap<String, f64>,
    /// Which inputs dominate each quantity: the correlation ratio (first-order index) of each
    /// perturbed input, estimated from the same draws with ten quantile bins.
    pub sensitivity: Vec<Sensitivity>,
    /// The linearised (delta-method) standard deviation of each quantity: central differences
    /// of the refit in each input (step half its standard deviation) combined as
    /// `sqrt(sum (dq/dx_i sd_i)^2)`, independent inputs; a uniform input counts with its
    /// standard deviation `(hi - lo) / sqrt 12`. Absent when a refit at a step fails.
    pub linearised_sd: BTreeMap<String, f64>,
    /// Present when the study was cancelled: the draws asked for and finished (`draws` is
    /// then the draws finished, and the intervals are theirs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cancelled: Option<crate::watch::Cancelled>,
    /// The values of [`Study::names`] of every feasible draw, in draw order (for figures; not
    /// serialised).
    #[serde(skip)]
    pub samples: Vec<[f64; 8]>,
}

/// The quantities that are speeds (m/s in a study).
pub const SPEEDS: [&str; 4] = ["speed1", "speed2", "delta_v1", "delta_v2"];

impl Study {
    /// Whether the model has moment branches to choose between ([`Study::branch_share`]).
    pub fn has_branches(&self) -> bool {
        self.model.branches(&MomentBranch::ALL).len() > 1
    }

    /// The names of this study's quantities, in output order.
    pub fn names(&self) -> &'static [&'static str; 8] {
        quantities(self.model)
    }

    /// The same study with its speeds (see [`SPEEDS`]) multiplied by `per_mps`: in a display
    /// unit, e.g. `1 / 0.44704` for mph. Everything else keeps.
    pub fn in_speed_unit(&self, per_mps: f64) -> Study {
        let mut s = self.clone();
        let is_speed = |q: &str| SPEEDS.contains(&q);
        for (q, v) in s.nominal.iter_mut() {
            if is_speed(q) {
                *v *= per_mps;
            }
        }
        for (q, v) in s.linearised_sd.iter_mut() {
            if is_speed(q) {
                *v *= per_mps;
            }
        }
        for (q, x) in s.quantities.iter_mut() {
            if is_speed(q) {
                for v in [&mut x.p05, &mut x.p50, &mut x.p95, &mut x.mean, &mut x.sd] {
                    *v *= per_mps;
                }
            }
        }
        for (i, q) in self.names().iter().enumerate() {
            if is_speed(q) {
                for d in &mut s.samples {
                    d[i] *= per_mps;
                }
            }
        }
        s
    }
}
