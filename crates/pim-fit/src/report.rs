//! The fit report.

use crate::problem::MomentBranch;
use pim_core::{DeltaV, Impulse, Residuals, Velocities};
use serde::{Deserialize, Serialize};

/// Outcome of a branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// The global optimum within the stated tolerances was found.
    Optimal,
    /// No coefficients in the box and no velocities within the bounds satisfy every constraint.
    Infeasible,
    /// A solution was found but a local refinement hit its iteration limit.
    LimitReached,
}

/// How well the data pin one coefficient (or contact speed) down.
///
/// The range is that of the points seen by the search and by scans through the optimum along
/// each coefficient. When one whole state is known (Q1, Q2) those scans run along mu and em with
/// e at its best, and on each scanned line the ends of the e interval whose cost is within the
/// tolerance are computed exactly (the cost is a quadratic along e there).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Identifiability {
    /// `e`, `mu`, `em`, or `speed1` / `speed2` (speed of each vehicle at contact, m/s).
    pub coefficient: String,
    /// Smallest value seen whose cost is within the tolerance of the optimum.
    pub low: f64,
    /// Largest such value.
    pub high: f64,
    /// The relative cost tolerance used.
    pub tolerance: f64,
    /// False when that range covers half of the coefficient's box or more (flat cost); for a
    /// speed, when it spans more than 10 % of the speed or the cost is flat along it.
    pub identifiable: bool,
    /// The cost is exactly flat along a velocity direction near the optimum: the range seen is
    /// only part of the set of equally good values (a speed is then at least `low`).
    pub open_ended: bool,
}

/// How the optimum was established.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Certificate {
    /// The method, in words.
    pub method: String,
    /// Grid points over the coefficient boxes (all modes).
    pub grid_points: usize,
    /// Inner problems evaluated (each friction sign counts).
    pub evaluations: usize,
    /// Inner problems solved exactly with their inequalities.
    pub exact_solves: usize,
    /// Of those, solved by the QP solver.
    pub qp_solves: usize,
    /// Nelder-Mead refinements run.
    pub refinements: usize,
    /// Refinements that reached the same optimum (to 1e-6 relative).
    pub refinements_agreeing: usize,
    /// Points where the energy constraint could not be enforced exactly (treated as infeasible).
    pub energy_uncertified_points: usize,
}

/// The fitted solution of one moment branch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Solution {
    /// Restitution.
    pub e: f64,
    /// Friction ratio of equation 5 (equals mu_max when the vehicles stick).
    pub mu: f64,
    /// Moment restitution.
    pub em: f64,
    /// Weighted sum of squares at the optimum.
    pub cost: f64,
    /// Fitted velocities at contact.
    pub initial: Velocities,
    /// Fitted velocities at separation.
    #[serde(rename = "final")]
    pub separation: Velocities,
    /// True when the optimum sticks (mu = mu_max, equation 5a).
    pub sticking: bool,
    /// Friction sign sgn(vn) sgn(vt) at contact.
    pub friction_sign: f64,
    /// Residuals of the six equations.
    pub residuals: Residuals,
    /// Largest relative residual.
    pub max_residual: f64,
    /// Inequality constraints active at the optimum, in words.
    pub active_constraints: Vec<String>,
    /// Kinetic energy loss, percent.
    pub energy_loss_percent: f64,
    /// Signed critical friction of the fitted contact state.
    pub mu_max: Option<f64>,
    /// mu / mu_max.
    pub mu_ratio: Option<f64>,
    /// Delta-V of both vehicles.
    pub delta_v: [DeltaV; 2],
    /// Impulses on vehicle 1.
    pub impulse: Impulse,
    /// Physically admissible by pim-core's own check (friction domain, energy).
    pub admissible: bool,
    /// Velocity components the data leave undetermined (the cost is flat along a combination
    /// of them); empty when the fitted velocities are unique. The values shown are then the
    /// smallest-norm choice among equally good ones.
    pub undetermined: Vec<String>,
}

/// The result of one moment branch.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BranchReport {
    /// The branch.
    pub moment: MomentBranch,
    /// Outcome.
    pub status: Status,
    /// Why, in words, when not optimal; for an optimal branch, a caveat (undetermined
    /// velocities) when there is one.
    pub reason: Option<String>,
    /// The solution (none when infeasible).
    pub solution: Option<Solution>,
    /// Identifiability of each coefficient (empty when infeasible).
    pub identifiability: Vec<Identifiability>,
    /// How the optimum was established.
    pub certificate: Certificate,
}

/// The result of a fit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitReport {
    /// One report per branch, in the order asked.
    pub branches: Vec<BranchReport>,
    /// The optimal branch with the lower cost, if any; on a tie (costs within 1e-6 relative)
    /// the zero branch, which has one coefficient fewer.
    pub best: Option<MomentBranch>,
    /// Remarks on the whole fit, for example that both branches fit equally well.
    pub notes: Vec<String>,
}

impl FitReport {
    /// The report of the best branch.
    pub fn best_branch(&self) -> Option<&BranchReport> {
        self.best
            .and_then(|b| self.branches.iter().find(|r| r.moment == b))
    }
}
