//! One whole state known (Q1, Q2): the six equations fix U through pim-core's reduced solve,
//! and the candidate is checked against the constraint set.

use super::{At, Candidate, Eval, Inner};
use crate::report::Violation;
use nalgebra::Vector6;
use pim_core::reduction::Reduced;
use pim_core::TangentialCondition;

impl Inner {
    /// The candidate of a problem with one state known. `None` when the problem is not of that
    /// kind or the reduced system is singular for these coefficients (the general path then
    /// decides).
    pub(super) fn evaluate_known(&self, at: &At) -> Option<Eval> {
        let known = self.known.as_ref()?;
        if self.family.sticking() == crate::family::Sticking::Restitution
            && at.mode == TangentialCondition::NoSlip
        {
            // The tangential model's sticking: its own transfer matrix, X = R x.
            let (v, contact) = self.known_state?;
            let r = self.transfer(at)?;
            let (x, xf) = if contact {
                (v, r * v)
            } else {
                (r.lu().solve(&v)?, v)
            };
            return Some(self.checked(at, x, xf));
        }
        match known.solve(&at.c, at.mode, at.sign) {
            Reduced::States(x, xf) => Some(self.checked(at, x, xf)),
            Reduced::Inconsistent => Some(Eval::Infeasible(Violation::Inconsistent)),
            Reduced::Singular => None,
        }
    }

    /// A fully determined candidate `(x, X)`: checked, with its cost and friction ratio.
    pub(super) fn checked(&self, at: &At, x: Vector6<f64>, xf: Vector6<f64>) -> Eval {
        let check = self.constraints(at).check(at.c.e, &x, &xf);
        if let Some(v) = check.linear {
            return Eval::Infeasible(v);
        }
        if !check.ratio_ok {
            let kind = self.constraints(at).ratio.map(|r| r.kind);
            return Eval::Infeasible(kind.unwrap_or(match at.mode {
                TangentialCondition::Sliding => Violation::Friction,
                TangentialCondition::NoSlip => Violation::MuBound,
            }));
        }
        if !check.energy_ok {
            return Eval::Infeasible(Violation::Energy);
        }
        Eval::Feasible(Candidate {
            cost: self.objective.cost(&x, &xf),
            mu_eff: self.mu_eff(at, &x, &xf),
            x,
            xf,
            qp: false,
            lambda: 0.0,
            flat: false,
        })
    }
}
