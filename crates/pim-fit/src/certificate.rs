//! How a branch's optimum was established: the solver route, the reason for a fallback, and the
//! counts of the search.

use serde::{Deserialize, Serialize};

/// The solver route that decided a branch (see the crate docs, "Which route a problem takes").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Route {
    /// The exact convex decomposition over the contact state and the impulse.
    Convex,
    /// The grid over the coefficient box, refinements and the exact inner solves.
    Grid,
}

/// Why a branch was decided by the grid search instead of the convex decomposition.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Fallback {
    /// Turned off in the settings (`SearchSettings::convex = false`).
    Disabled,
    /// A component is known exactly or carries no weight: the cost is not strictly convex in
    /// the velocities (Q1, Q2 and costs that leave a component out).
    NotStrictlyConvex,
    /// Vehicle 2 is a barrier.
    Barrier,
    /// mu is bounded by its box alone, without mu <= mu_max (`mu_max_condition` off): the
    /// convex route's patterns are written for the friction rule.
    NoMuMaxCondition,
    /// The momentum equations do not leave a velocity-change space of the expected dimension.
    DegenerateGeometry,
    /// The branch-and-bound over e_m needed more intervals than it allows. Where this happens
    /// the optimum lies, in practice, next to a pole of mu_max (the no-slip normal impulse
    /// vanishes, |mu_max| of 1e8 to 1e12), where the relaxation of that impulse's sign over an
    /// e_m interval tightens only in proportion to the interval's width.
    NodeLimit,
    /// A pattern's optimum lies where the six equations are singular.
    Singular,
    /// The best pattern's point lies where the six equations are so ill-conditioned that its
    /// coefficients, read to round-off, do not reproduce its velocities through the forward
    /// model (to 1e-9 relative).
    IllConditioned,
    /// A QP's answer did not pass its KKT verification.
    QpFailed,
    /// The best pattern's point fails the exact constraint set (it creates energy, whose
    /// condition is not convex over these variables, or its normal impulse changes sign).
    ExactCheckFailed,
    /// No sign pattern is feasible (the branch is infeasible) and the data alone do not say
    /// why: the grid search decides and explains which conditions the candidates violate.
    NoPatternFeasible,
    /// The components known exactly contradict the momentum equations: the grid search
    /// decides (and explains) infeasibility.
    KnownInconsistent,
}

impl Fallback {
    /// The reason in words.
    pub fn words(self) -> &'static str {
        match self {
            Fallback::Disabled => "the convex route is turned off in the settings",
            Fallback::NotStrictlyConvex => {
                "a direction of the velocities that the known components leave free carries no \
                 weight, so the cost is not strictly convex there"
            }
            Fallback::KnownInconsistent => {
                "the components known exactly contradict the momentum equations"
            }
            Fallback::Barrier => "vehicle 2 is a barrier",
            Fallback::NoMuMaxCondition => {
                "mu is bounded by its box alone (no mu <= mu_max), for which the convex route \
                 is not written"
            }
            Fallback::DegenerateGeometry => {
                "the momentum equations leave a velocity-change space of unexpected dimension"
            }
            Fallback::NodeLimit => "the branch-and-bound over e_m reached its interval limit",
            Fallback::Singular => "a pattern's optimum lies where the six equations are singular",
            Fallback::IllConditioned => {
                "the best pattern's point lies where the six equations are so ill-conditioned \
                 that its coefficients do not reproduce its velocities"
            }
            Fallback::QpFailed => "a QP's answer failed its KKT verification",
            Fallback::ExactCheckFailed => "the best pattern's point fails the exact constraints",
            Fallback::NoPatternFeasible => "no sign pattern is feasible",
        }
    }
}

/// How a branch was solved: the route, why the convex route was not taken (if it was not),
/// and the method in words.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Method {
    /// The route that decided the branch.
    pub route: Route,
    /// Why the convex route did not decide it (`None` on the convex route).
    pub fallback: Option<Fallback>,
    /// The method, in words.
    pub description: String,
}

/// How the optimum was established.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Certificate {
    /// The route, the reason for a fallback and the method in words.
    pub method: Method,
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
    /// Elementary operations of the inner problems of the whole fit (every branch): linear
    /// solves, active-set steps, and ten
    /// per iteration of the interior-point QP solver. A count, not a time: the same on every
    /// machine, it is what a caller's budget of work charges for the fit.
    #[serde(default)]
    pub operations: u64,
}
