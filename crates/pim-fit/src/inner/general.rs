//! The general inner solve (nothing or part of the states known).
//!
//! 1. The optimum subject to the fixed components only. When it satisfies the constraint set it
//!    is the answer; otherwise its cost is a lower bound of the exact value.
//! 2. The QP on the linear rows. The friction condition (sliding) or the mu bounds (sticking) are
//!    a ratio of two linear forms, whose admissible set is two polyhedra, one for each sign of
//!    the normal impulse: when the QP's answer violates the ratio condition, the QP is solved on
//!    each polyhedron ("wedge") and the better answer kept.
//! 3. The condition "no kinetic energy created", `E(x) = x' Qe x <= 0`, is not convex; when a QP
//!    answer violates it, the Lagrangian `cost + lambda E` is minimised for the lambda at which
//!    `E = 0`, found by bisection while the Lagrangian stays convex. By weak duality that point is
//!    then optimal for the energy-constrained problem on that polyhedron.
//!
//! A candidate whose contact state has `vt = 0` is not counted: equation 5's friction sign is
//! undefined there, and the other sign is evaluated on its own.

use super::constraints::{ConstraintSet, RowX};
use super::objective::OverX;
use super::qp::{nearly_singular, qp, solve_spd, to6, to_d, QpOutcome};
use super::{At, Candidate, Eval, Inner};
use crate::report::Violation;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

/// A QP answer: the contact state, the energy multiplier.
struct Answer {
    x: Vector6<f64>,
    lambda: f64,
}

impl Inner {
    pub(super) fn evaluate_general(&self, at: &At, exact: bool, cutoff: f64) -> Eval {
        let Some(r) = self.reduction.transfer(&at.c, at.mode, at.sign) else {
            return Eval::Infeasible(Violation::Singular);
        };
        let Some(ox) = self.objective.over_x(r) else {
            return Eval::Infeasible(Violation::Singular);
        };
        let Some((x, flat)) = self.equality_optimum(&ox) else {
            return Eval::Infeasible(Violation::Singular);
        };
        let cs = self.constraints(at);
        let make = |x: Vector6<f64>, qp: bool, lambda: f64| {
            let xf = r * x;
            Candidate {
                cost: self.objective.cost(&x, &xf),
                mu_eff: self.mu_eff(at, &x, &xf),
                x,
                xf,
                qp,
                lambda,
                flat,
            }
        };
        let check = cs.check(at.c.e, &x, &(r * x));
        if check.ok() {
            return Eval::Feasible(make(x, false, 0.0));
        }
        if check.only_direction {
            // The optimum would have vt = 0 at contact (see the module docs).
            return Eval::Infeasible(Violation::SlidingDirection);
        }
        let ratio_kind = cs.ratio.map_or(Violation::Friction, |r| r.kind);
        let first = check.linear.unwrap_or(if check.ratio_ok {
            Violation::Energy
        } else {
            ratio_kind
        });
        if ox.z.ncols() == 0 {
            return Eval::Infeasible(first);
        }
        let lower_bound = self.objective.cost(&x, &(r * x));
        if !exact || lower_bound >= cutoff {
            return Eval::Pending {
                lower_bound,
                violation: first,
            };
        }
        let base = cs.rows_over_x(&r);
        let linear_only = self.solve_rows(&ox, &cs, &base);
        let mut best: Option<Answer> = None;
        let mut why = first;
        match linear_only {
            Ok(a) if cs.check(at.c.e, &a.x, &(r * a.x)).ok() => best = Some(a),
            Ok(_) => why = ratio_kind,
            Err(v) => why = v,
        }
        if best.is_none() && why == ratio_kind && cs.ratio.is_some() {
            for side in [1.0, -1.0] {
                let Some(wedge) = cs.wedge(&r, at.c.e, side) else {
                    continue;
                };
                let rows: Vec<RowX> = base.iter().copied().chain(wedge).collect();
                if let Ok(a) = self.solve_rows(&ox, &cs, &rows) {
                    let better = best.as_ref().is_none_or(|b| {
                        self.objective.cost(&a.x, &(r * a.x))
                            < self.objective.cost(&b.x, &(r * b.x))
                    });
                    if cs.check(at.c.e, &a.x, &(r * a.x)).ok() && better {
                        best = Some(a);
                    }
                }
            }
        }
        match best {
            Some(a) => Eval::Feasible(make(a.x, true, a.lambda)),
            None => Eval::Infeasible(why),
        }
    }

    /// The optimum subject to the fixed components only, and whether the cost is flat along
    /// some direction there.
    pub(super) fn equality_optimum(&self, ox: &OverX) -> Option<(Vector6<f64>, bool)> {
        if self.objective.nothing_fixed() {
            if let Some(ch) = ox.h.cholesky() {
                if !nearly_singular(ch.l_dirty().diagonal().iter(), ox.h.diagonal().amax()) {
                    return Some((ch.solve(&ox.g), false));
                }
            }
            let (hy, gy) = ox.reduced();
            let y = solve_spd(&hy, &gy)?;
            return Some((ox.xp + to6(&(&ox.z * &y)), true));
        }
        if ox.z.ncols() == 0 {
            return Some((ox.xp, false));
        }
        let (hy, gy) = ox.reduced();
        let flat = hy
            .clone()
            .cholesky()
            .is_none_or(|ch| nearly_singular(ch.l_dirty().diagonal().iter(), hy.diagonal().amax()));
        let y = solve_spd(&hy, &gy)?;
        Some((ox.xp + to6(&(&ox.z * &y)), flat))
    }

    /// The energy-constrained optimum on the polyhedron `rows`.
    fn solve_rows(
        &self,
        ox: &OverX,
        cs: &ConstraintSet<'_>,
        rows: &[RowX],
    ) -> Result<Answer, Violation> {
        let (hy, gy) = ox.reduced();
        let m = Matrix6::from_diagonal(&cs.mass);
        let qe = (ox.r.transpose() * m * ox.r - m) * 0.5;
        let zq = ox.z.transpose() * DMatrix::from_iterator(6, 6, qe.iter().copied()) * &ox.z;
        let lq = ox.z.transpose() * to_d(&(qe * ox.xp));
        let over_y: Vec<(DVector<f64>, f64)> = rows
            .iter()
            .map(|(row, rhs, _)| {
                (
                    ox.z.transpose() * to_d(&row.transpose()),
                    rhs - (row * ox.xp)[0],
                )
            })
            .collect();
        let inside = |x: &Vector6<f64>| {
            rows.iter()
                .all(|(row, rhs, _)| (row * x)[0] <= rhs + cs.tol)
        };
        // Minimiser of cost + lambda E over the rows.
        let solve = |lambda: f64| -> Result<Vector6<f64>, Violation> {
            let p = &hy + &zq * lambda;
            let q = &gy - &lq * lambda;
            if let Some(y) = solve_spd(&p, &q) {
                let xl = ox.xp + to6(&(&ox.z * &y));
                if inside(&xl) {
                    return Ok(xl);
                }
            }
            match qp(&p, &q, &over_y, self.settings.qp_iterations) {
                QpOutcome::Solved(y) => Ok(ox.xp + to6(&(&ox.z * &y))),
                QpOutcome::Infeasible => Err(Violation::Infeasible),
                QpOutcome::Failed => Err(Violation::EnergyUncertified),
            }
        };
        let x0 = solve(0.0)?;
        if self.direction_active(cs, &x0) {
            return Err(Violation::SlidingDirection);
        }
        let energy_of = |x: &Vector6<f64>| (x.transpose() * qe * x)[0];
        if !pim_core::creates_energy(cs.energy(&x0), cs.energy(&(ox.r * x0))) {
            return Ok(Answer { x: x0, lambda: 0.0 });
        }
        // Energy condition active: bisection on lambda while the Lagrangian stays convex.
        let convex = |lambda: f64| (&hy + &zq * lambda).cholesky().is_some();
        let scale = hy.trace().abs() / zq.abs().max().max(1e-300);
        let mut lo = 0.0;
        let mut hi = 1e-6 * scale;
        let mut best = None;
        for _ in 0..self.settings.energy_doublings {
            if !convex(hi) {
                return Err(Violation::EnergyUncertified);
            }
            match solve(hi) {
                Ok(xh) if energy_of(&xh) <= 0.0 => {
                    best = Some(xh);
                    break;
                }
                Ok(_) => {
                    lo = hi;
                    hi *= 2.0;
                }
                Err(_) => return Err(Violation::EnergyUncertified),
            }
        }
        let Some(mut best) = best else {
            return Err(Violation::EnergyUncertified);
        };
        for _ in 0..self.settings.energy_bisections {
            if hi - lo <= 1e-8 * hi {
                break;
            }
            let mid = 0.5 * (lo + hi);
            match solve(mid) {
                Ok(xm) if energy_of(&xm) <= 0.0 => {
                    hi = mid;
                    best = xm;
                }
                Ok(_) => lo = mid,
                Err(_) => break,
            }
        }
        Ok(Answer {
            x: best,
            lambda: hi,
        })
    }

    /// True when the contact state has vt = 0 (the sliding-direction row is active).
    fn direction_active(&self, cs: &ConstraintSet<'_>, x: &Vector6<f64>) -> bool {
        let tol = 1e-7 * self.objective.scale;
        cs.linear.iter().any(|c| match *c {
            super::Linear::Contact { row, rhs, kind } => {
                kind == Violation::SlidingDirection && ((row * x)[0] - rhs).abs() <= tol
            }
            _ => false,
        })
    }
}
