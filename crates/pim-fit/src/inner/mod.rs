//! The inner problem: for fixed coefficients, friction sign and tangential condition, the best U.
//!
//! With `F X + G x = 0` and F regular, `X = R x` (pim-core's reduction), so the cost is a convex
//! quadratic in the contact state x ([`objective`]). Its conditions are one constraint set
//! ([`constraints`]): linear bounds, approach and sliding direction, the exact friction
//! condition (a union of two polyhedra), and no energy created. Two paths solve it:
//! - one whole state known (Q1, Q2): the six equations fix U; it is checked ([`known`]), and
//!   along e both states are affine, so e is minimised exactly ([`profile`]);
//! - otherwise: the equality-only optimum, then QPs on the linear rows and on each wedge of the
//!   friction condition, and the energy condition through its Lagrangian ([`general`]).
//!
//! [`diagnosis`] explains what a solution leaves undetermined and which constraints are active.

mod constraints;
mod diagnosis;
mod general;
mod known;
mod linear;
mod objective;
mod prepared;
mod profile;
mod qp;

pub(crate) use constraints::{RowOf, RowU};
pub(crate) use diagnosis::{direct_reason, explain_infeasible};
pub(crate) use prepared::{At, Candidate, Eval, Inner};
pub(crate) use profile::LineAt;

#[cfg(test)]
mod tests;

/// Sum of weight x target^2 of a problem's data (a scale for cost tolerances).
pub(crate) fn data_scale_of(problem: &crate::problem::FitProblem) -> f64 {
    objective::Objective::new(problem).data_scale()
}

/// A problem's cost as `U'HU - 2g'U + c0`, and its components known exactly (index, value).
pub(crate) fn quadratic_of(
    problem: &crate::problem::FitProblem,
) -> (
    nalgebra::SMatrix<f64, 12, 12>,
    crate::problem::Vector12,
    f64,
    Vec<(usize, f64)>,
) {
    let o = objective::Objective::new(problem);
    let (h, g, c0) = o.quadratic();
    (*h, *g, c0, o.fixed.clone())
}
