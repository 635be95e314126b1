//! Settings of a fit: the coefficient box and bounds a user sets, and every tolerance, grid size
//! and iteration limit of the search, each with its default.

use crate::error::{FitError, Result};
use crate::problem::MomentBranch;
use pim_core::MomentForm;
use serde::{Deserialize, Serialize};

/// The impact model a fit estimates.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum FitModel {
    /// Planar Impact Mechanics: `e`, `mu`, `e_m` (the moment branches).
    #[default]
    Pim,
    /// Normal and tangential restitution with a friction limit (pim-core's
    /// [`pim_core::tangential`]): `e`, `et`, `friction`; no moment impulse, so one branch
    /// ([`MomentBranch::Zero`]).
    Tangential,
}

impl FitModel {
    /// Both models, PIM first.
    pub const ALL: [FitModel; 2] = [FitModel::Pim, FitModel::Tangential];

    /// What the fit asks of the model (the one place a model is registered for the fit).
    pub(crate) fn family(self) -> &'static dyn crate::family::Family {
        match self {
            FitModel::Pim => &crate::family::Pim,
            FitModel::Tangential => &crate::family::Tangential,
        }
    }

    /// What the model fits, in a line.
    pub fn description(self) -> &'static str {
        self.family().description()
    }

    /// The moment branches the model fits, of those asked: all of them for a model with a
    /// moment impulse (PIM), only the zero branch for one without (the tangential model).
    pub fn branches(self, asked: &[MomentBranch]) -> Vec<MomentBranch> {
        self.family().branches(asked)
    }

    /// The model's name in case files and on the command line.
    pub fn name(self) -> &'static str {
        self.family().name()
    }
}

/// The default range of e: [0, 0.2], Vossou & Koulocheris's setting for the RICSAC tests (Brach
/// 1984 needed up to 0.42, so it is a setting).
pub const DEFAULT_E_RANGE: [f64; 2] = [0.0, 0.2];

/// Settings of a fit, before checking ([`FitSettings::check`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct FitSettings {
    /// Range of e (default [0, 0.2]).
    pub e: [f64; 2],
    /// Range of mu (default [-1.2, 1.2]); mu must also lie between 0 and mu_max unless
    /// `mu_max_condition` is off.
    pub mu: [f64; 2],
    /// Whether mu must lie between 0 and mu_max (default true: a larger tangential impulse
    /// than sticking needs would reverse the sliding at the impact centre, pushing one surface
    /// back along the other). Off reproduces fits that bound mu by a box alone, as Vossou &
    /// Koulocheris (2018) did; their answers may then reverse the sliding, which the reports
    /// say (`admissible: false`) without rejecting them.
    #[serde(default = "yes")]
    pub mu_max_condition: bool,
    /// The model fitted (default PIM).
    #[serde(default)]
    pub model: FitModel,
    /// Range of the tangential restitution et of the tangential model (default [-1, 1]).
    #[serde(default = "et_default")]
    pub et: [f64; 2],
    /// Range of the friction limit of the tangential model (default [0, 1.2]).
    #[serde(default = "friction_default")]
    pub friction: [f64; 2],
    /// Bound on every linear velocity component, m/s (default 20).
    pub velocity_bound: f64,
    /// Bound on every yaw rate, rad/s (default 5).
    pub yaw_rate_bound: f64,
    /// Form of the moment equation (default corrected).
    pub moment_form: MomentForm,
    /// Branches to fit (default both; the tangential model has the zero branch only).
    pub branches: Vec<MomentBranch>,
    /// Grid resolution of the global search: points along e, mu and em (default 5, 17, 6).
    pub grid: [usize; 3],
    /// Relative cost tolerance of the identifiability ranges (default 0.01 = 1 %).
    pub identifiability_tolerance: f64,
    /// Compute the identifiability ranges (the scans through the optimum; default true). A fit
    /// that needs only its optimum, such as a bootstrap draw, turns them off: its branches then
    /// report no ranges, and the optimum is the same.
    #[serde(default = "yes")]
    pub ranges: bool,
    /// Prove the optimum over the geometry box when geometry inputs are estimated (default
    /// true; see [`crate::GeometryProof`]). A fit that needs only its best point, such as an
    /// uncertainty draw, turns it off: the geometry is then the best found, and says so.
    #[serde(default = "yes")]
    pub geometry_proof: bool,
    /// Tolerances and limits of the search itself.
    #[serde(default)]
    pub search: SearchSettings,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            e: DEFAULT_E_RANGE,
            mu: [-1.2, 1.2],
            mu_max_condition: true,
            model: FitModel::Pim,
            et: et_default(),
            friction: friction_default(),
            velocity_bound: 20.0,
            yaw_rate_bound: 5.0,
            moment_form: MomentForm::Corrected,
            branches: MomentBranch::ALL.to_vec(),
            grid: [5, 17, 6],
            identifiability_tolerance: 0.01,
            ranges: true,
            geometry_proof: true,
            search: SearchSettings::default(),
        }
    }
}

fn yes() -> bool {
    true
}

fn et_default() -> [f64; 2] {
    [-1.0, 1.0]
}

fn friction_default() -> [f64; 2] {
    [0.0, 1.2]
}

/// Tolerances, grid sizes and iteration limits of the search (the defaults are what the
/// benchmarks and the RICSAC results were measured with).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default)]
pub struct SearchSettings {
    /// Smallest closing speed at the impact centre at contact, m/s (default 1e-3).
    pub min_approach_speed: f64,
    /// Feasibility tolerance of every linear condition, relative to the largest velocity in the
    /// data (default 1e-9). Constructions aim at half of it, so what they build passes the check.
    pub feasibility_tolerance: f64,
    /// Distance to a bound, relative to the velocity scale (or to the coefficient box), within
    /// which a constraint is listed as active (default 1e-6).
    pub active_tolerance: f64,
    /// Nelder-Mead refinements started per search space from the best grid points of distinct
    /// cells (default 3).
    pub refinement_starts: usize,
    /// Further refinements from the other local minima of the grid (points no worse than any
    /// grid neighbour), best first, up to this many starts in all (default 8).
    pub max_refinement_starts: usize,
    /// Before a branch is reported infeasible, its grids are refined this many times, each
    /// doubling the points per dimension (default 2).
    pub infeasible_refinements: usize,
    /// Nelder-Mead stops when its simplex values agree to this relative spread (default 1e-6).
    pub nelder_mead_tolerance: f64,
    /// Nelder-Mead iteration limit per dimension (default 100; plus 100).
    pub nelder_mead_iterations_per_dimension: u64,
    /// Refinements ending within this relative cost of the best are polished (default 1e-3).
    pub polish_within: f64,
    /// First compass step, as a fraction of the grid spacing (default 1/16).
    pub polish_first_step: f64,
    /// Smallest compass step, as a fraction of the box (default 1e-7).
    pub polish_last_step: f64,
    /// Compass rounds at most (default 400).
    pub polish_rounds: usize,
    /// A compass move gaining less than this relative cost keeps the step size (default 1e-10).
    pub polish_creep: f64,
    /// The compass search also moves along the diagonals of the box (default true).
    pub polish_diagonals: bool,
    /// Refinements agree when their costs are within this relative distance (default 1e-6);
    /// the same tolerance decides ties between the moment branches.
    pub agreement_tolerance: f64,
    /// Points per coefficient of the scans through the optimum for the identifiability ranges
    /// (default 13; 17 along mu in the sliding mode through a sticking optimum).
    pub scan_points: usize,
    /// Points along mu of the sliding scan through a sticking optimum (default 17).
    pub scan_points_mu: usize,
    /// Doublings of the energy multiplier before giving up (default 60).
    pub energy_doublings: usize,
    /// Bisection steps of the energy multiplier (default 40), stopped at a relative width of
    /// 1e-8.
    pub energy_bisections: usize,
    /// Iteration limit of the QP solver (default 200).
    pub qp_iterations: u32,
    /// Solve PIM fits whose cost is strictly convex in the velocities (every component
    /// estimated, as in Q3) as a union of convex QPs over the contact state and the impulse
    /// (default true); false runs the grid search on them too.
    pub convex: bool,
}

impl Default for SearchSettings {
    fn default() -> Self {
        SearchSettings {
            min_approach_speed: 1e-3,
            feasibility_tolerance: 1e-9,
            active_tolerance: 1e-6,
            refinement_starts: 3,
            max_refinement_starts: 8,
            infeasible_refinements: 2,
            nelder_mead_tolerance: 1e-6,
            nelder_mead_iterations_per_dimension: 100,
            polish_within: 1e-3,
            polish_first_step: 1.0 / 16.0,
            polish_last_step: 1e-7,
            polish_rounds: 400,
            polish_creep: 1e-10,
            polish_diagonals: true,
            agreement_tolerance: 1e-6,
            scan_points: 13,
            scan_points_mu: 17,
            energy_doublings: 60,
            energy_bisections: 40,
            qp_iterations: 200,
            convex: true,
        }
    }
}

/// Settings that passed [`FitSettings::check`].
#[derive(Debug, Clone, PartialEq)]
pub struct ValidSettings(pub(crate) FitSettings);

impl ValidSettings {
    /// The settings.
    pub fn get(&self) -> &FitSettings {
        &self.0
    }

    /// The same settings without the identifiability scans ([`FitSettings::ranges`] off): for a
    /// caller that needs each fit's optimum only. Still valid: no check depends on the scans.
    pub fn without_ranges(&self) -> ValidSettings {
        ValidSettings(FitSettings {
            ranges: false,
            ..self.0.clone()
        })
    }
}

impl FitSettings {
    /// Checks the settings once, so that a fit only runs on valid ones.
    pub fn check(mut self) -> Result<ValidSettings> {
        self.branches = self.model.branches(&self.branches);
        let [elo, ehi] = self.e;
        if !(elo.is_finite() && ehi.is_finite() && 0.0 <= elo && elo <= ehi && ehi <= 1.0) {
            return Err(FitError::BadBounds(format!(
                "e = [{elo}, {ehi}] must satisfy 0 <= low <= high <= 1"
            )));
        }
        let [mlo, mhi] = self.mu;
        if !(mlo.is_finite() && mhi.is_finite() && mlo <= mhi && mlo >= -100.0 && mhi <= 100.0) {
            return Err(FitError::BadBounds(format!(
                "mu = [{mlo}, {mhi}] must satisfy -100 <= low <= high <= 100"
            )));
        }
        let [tlo, thi] = self.et;
        if !(tlo.is_finite() && thi.is_finite() && -1.0 <= tlo && tlo <= thi && thi <= 1.0) {
            return Err(FitError::BadBounds(format!(
                "et = [{tlo}, {thi}] must satisfy -1 <= low <= high <= 1"
            )));
        }
        let [flo, fhi] = self.friction;
        if !(flo.is_finite() && fhi.is_finite() && 0.0 <= flo && flo <= fhi && fhi <= 100.0) {
            return Err(FitError::BadBounds(format!(
                "friction = [{flo}, {fhi}] must satisfy 0 <= low <= high <= 100"
            )));
        }
        for (name, b, limit) in [
            ("velocity_bound", self.velocity_bound, pim_core::MAX_SPEED),
            (
                "yaw_rate_bound",
                self.yaw_rate_bound,
                pim_core::MAX_YAW_RATE,
            ),
        ] {
            if !(b.is_finite() && b > 0.0 && b <= limit) {
                return Err(FitError::BadBounds(format!(
                    "{name} = {b} must be > 0 and <= {limit}"
                )));
            }
        }
        if self.branches.is_empty() {
            return Err(FitError::BadBounds("no moment branch selected".into()));
        }
        if self.grid.iter().any(|&n| !(2..=400).contains(&n)) {
            return Err(FitError::BadBounds(format!(
                "grid {:?}: each count must be between 2 and 400",
                self.grid
            )));
        }
        let t = self.identifiability_tolerance;
        if !(t.is_finite() && t > 0.0) {
            return Err(FitError::BadBounds(format!(
                "identifiability_tolerance = {t} must be > 0"
            )));
        }
        let s = &self.search;
        let positive = [
            ("min_approach_speed", s.min_approach_speed),
            ("feasibility_tolerance", s.feasibility_tolerance),
            ("active_tolerance", s.active_tolerance),
            ("nelder_mead_tolerance", s.nelder_mead_tolerance),
            ("polish_within", s.polish_within),
            ("polish_first_step", s.polish_first_step),
            ("polish_last_step", s.polish_last_step),
            ("agreement_tolerance", s.agreement_tolerance),
        ];
        for (name, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(FitError::BadBounds(format!(
                    "search.{name} = {v} must be > 0"
                )));
            }
        }
        if s.refinement_starts == 0 || s.scan_points < 2 || s.scan_points_mu < 2 {
            return Err(FitError::BadBounds(
                "search: refinement_starts must be >= 1 and scan points >= 2".into(),
            ));
        }
        Ok(ValidSettings(self))
    }
}

impl std::str::FromStr for FitModel {
    type Err = pim_core::UnknownName;
    /// By [`FitModel::name`]; the error lists the accepted names.
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        pim_core::parse_name(s, &Self::ALL, Self::name)
    }
}
