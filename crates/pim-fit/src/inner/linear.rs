//! The linear conditions of the inner problem (velocity bounds, approach, sliding direction),
//! written once, and their rows over the twelve components, which every solve path places in
//! its own variables.

use crate::problem::Component;
use crate::report::Violation;
use nalgebra::RowVector6;

/// A linear condition on U.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Linear {
    /// `|U_k| <= limit`.
    Bound { k: usize, limit: f64 },
    /// `row . x <= rhs` over the contact state.
    Contact {
        row: RowVector6<f64>,
        rhs: f64,
        kind: Violation,
    },
}

/// One linear row as the conditions write it: `sign U_k` (a bound) or a row over the contact
/// state x.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum RowOf {
    /// `sign` times component k of `U = (x, X)`.
    Component { k: usize, sign: f64 },
    /// A row over x.
    Contact(RowVector6<f64>),
}

/// A row over U and its right-hand side: `row . U <= rhs`.
pub(crate) type RowU = (RowOf, f64, Violation);

/// Linear conditions as rows over `U = (x, X)`, aimed inside by the tolerance `tol`; the sliding
/// direction is closed (`vt = 0` is admissible by the friction rule). Every solve path that
/// writes rows (the QPs over x, the convex route over its own variables) reads them here.
pub(crate) fn rows_over_u(linear: &[Linear], tol: f64) -> impl Iterator<Item = RowU> + '_ {
    linear
        .iter()
        .flat_map(move |c| match *c {
            Linear::Bound { k, limit } => {
                let v = Violation::Bound(Component(k));
                [
                    Some((RowOf::Component { k, sign: 1.0 }, limit - tol, v)),
                    Some((RowOf::Component { k, sign: -1.0 }, limit - tol, v)),
                ]
            }
            Linear::Contact { row, rhs, kind } => {
                let aimed = if kind == Violation::SlidingDirection {
                    rhs
                } else {
                    rhs - tol
                };
                [Some((RowOf::Contact(row), aimed, kind)), None]
            }
        })
        .flatten()
}
