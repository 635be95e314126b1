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
//! A candidate whose contact state has `vt = 0` (the sliding-direction row active) counts like
//! any other: pim-core's friction rule then takes the sign of the no-slip impulse, and the
//! ratio condition of this sign (mu between 0 and mu_max) holds exactly when that is this sign
//! or mu = 0, so the closure of each sign's set is the forward model's.

use super::constraints::{ConstraintSet, RowX};
use super::objective::OverX;
use super::qp::{
    certainly_infeasible, nearly_singular, qp, solve_spd, to6, to_d, QpHooks, QpOutcome,
};
use super::{At, Candidate, Eval, Inner};
use crate::report::Violation;
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

/// A QP answer: the contact state, the energy multiplier.
struct Answer {
    x: Vector6<f64>,
    lambda: f64,
}

/// The pieces of `cost + lambda E` over y, shared by the polyhedra of one evaluation:
/// `y' (hy + lambda zq) y - 2 (gy - lambda lq)' y`, and `E(x) = x' qe x`.
struct Lagrangian {
    hy: DMatrix<f64>,
    gy: DVector<f64>,
    qe: Matrix6<f64>,
    zq: DMatrix<f64>,
    lq: DVector<f64>,
}

impl Lagrangian {
    fn new(ox: &OverX, cs: &ConstraintSet<'_>) -> Self {
        let (hy, gy) = ox.reduced();
        let m = Matrix6::from_diagonal(&cs.mass);
        let qe = (ox.r.transpose() * m * ox.r - m) * 0.5;
        let zq =
            ox.z.tr_mul(&(DMatrix::from_iterator(6, 6, qe.iter().copied()) * &*ox.z));
        let lq = ox.z.tr_mul(&to_d(&(qe * ox.xp)));
        Lagrangian { hy, gy, qe, zq, lq }
    }
}

impl Inner {
    pub(super) fn evaluate_general(&self, at: &At, exact: bool, cutoff: f64) -> Eval {
        let Some(r) = self.transfer(at) else {
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
        let lag = Lagrangian::new(&ox, &cs);
        let linear_only = self.solve_rows(&ox, &lag, &cs, &base);
        let mut best: Option<Answer> = None;
        let mut why = first;
        match linear_only {
            Ok(a) if cs.check(at.c.e, &a.x, &(r * a.x)).ok() => best = Some(a),
            Ok(a) => {
                // The wedges lie inside the linear rows: this is a lower bound of their value.
                let lower_bound = self.objective.cost(&a.x, &(r * a.x));
                if lower_bound >= cutoff {
                    return Eval::Pending {
                        lower_bound,
                        violation: ratio_kind,
                    };
                }
                why = ratio_kind
            }
            Err(v) => why = v,
        }
        if best.is_none() && why == ratio_kind && cs.ratio.is_some() {
            for side in [1.0, -1.0] {
                let Some(wedge) = cs.wedge(&r, at.c.e, side) else {
                    continue;
                };
                let rows: Vec<RowX> = base.iter().copied().chain(wedge).collect();
                if let Ok(a) = self.solve_rows(&ox, &lag, &cs, &rows) {
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
            return Some((ox.xp + to6(&(&*ox.z * &y)), true));
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
        Some((ox.xp + to6(&(&*ox.z * &y)), flat))
    }

    /// The energy-constrained optimum on the polyhedron `rows`.
    fn solve_rows(
        &self,
        ox: &OverX,
        lag: &Lagrangian,
        cs: &ConstraintSet<'_>,
        rows: &[RowX],
    ) -> Result<Answer, Violation> {
        let (hy, gy, zq, lq) = (&lag.hy, &lag.gy, &lag.zq, &lag.lq);
        let over_y: Vec<(DVector<f64>, f64)> = rows
            .iter()
            .map(|(row, rhs, _)| (ox.z.tr_mul(&to_d(&row.transpose())), rhs - (row * ox.xp)[0]))
            .collect();
        // A polyhedron that its non-bound rows already make empty needs no QP solver; the test
        // runs (once) only when the active-set path has failed.
        let empty = std::cell::OnceCell::new();
        let proven_empty = || {
            *empty.get_or_init(|| {
                let contact: Vec<usize> = (0..rows.len())
                    .filter(|&i| !matches!(rows[i].2, Violation::Bound(_)))
                    .collect();
                certainly_infeasible(&over_y, &contact, cs.tol, self.radius(rows, &ox.xp))
            })
        };
        let inside = |x: &Vector6<f64>| {
            rows.iter()
                .all(|(row, rhs, _)| (row * x)[0] <= rhs + cs.tol)
        };
        // Minimiser of cost + lambda E over the rows; the active set of one solve starts the
        // next.
        let active = std::cell::RefCell::new(Vec::new());
        let solve = |lambda: f64| -> Result<Vector6<f64>, Violation> {
            let p = hy + zq * lambda;
            let q = gy - lq * lambda;
            self.spend(1);
            if let Some(y) = solve_spd(&p, &q) {
                let xl = ox.xp + to6(&(&*ox.z * &y));
                if inside(&xl) {
                    return Ok(xl);
                }
            }
            let mut active = active.borrow_mut();
            match qp(
                &p,
                &q,
                &over_y,
                cs.tol,
                self.settings.qp_iterations,
                &mut active,
                QpHooks {
                    proven_empty: &proven_empty,
                    spend: &|n| self.spend(n),
                },
            ) {
                QpOutcome::Solved(y) => Ok(ox.xp + to6(&(&*ox.z * &y))),
                QpOutcome::Infeasible => Err(Violation::Infeasible),
                QpOutcome::Failed => Err(Violation::EnergyUncertified),
            }
        };
        let x0 = solve(0.0)?;
        if !pim_core::creates_energy(cs.energy(&x0), cs.energy(&(ox.r * x0))) {
            return Ok(Answer { x: x0, lambda: 0.0 });
        }
        self.energy_root(&solve, x0, (lag, cs))
    }

    /// The answer where the energy condition is active: the multiplier lambda with E = 0 of
    /// the minimisers `solve(lambda)` of cost + lambda E (`x0` that of lambda = 0).
    fn energy_root(
        &self,
        solve: &dyn Fn(f64) -> Result<Vector6<f64>, Violation>,
        x0: Vector6<f64>,
        (lag, cs): (&Lagrangian, &ConstraintSet<'_>),
    ) -> Result<Answer, Violation> {
        let (hy, qe, zq) = (&lag.hy, lag.qe, &lag.zq);
        let energy_of = |x: &Vector6<f64>| (x.transpose() * qe * x)[0];
        // Energy condition active: the multiplier lambda with E = 0, while the Lagrangian stays
        // convex. E falls as lambda grows; a bracket is found by doubling, then narrowed by the
        // Illinois variant of regula falsi (superlinear on a smooth piece, never leaving the
        // bracket) until E = 0 to a relative 1e-12 of the kinetic energy, or the bracket is
        // narrower than a relative 1e-8.
        let convex = |lambda: f64| (hy + zq * lambda).cholesky().is_some();
        let scale = hy.trace().abs() / zq.abs().max().max(1e-300);
        let (mut lo, mut e_lo) = (0.0, energy_of(&x0));
        let mut hi = 1e-6 * scale;
        let mut bracket = None;
        for _ in 0..self.settings.energy_doublings {
            if !convex(hi) {
                return Err(Violation::EnergyUncertified);
            }
            match solve(hi) {
                Ok(xh) if energy_of(&xh) <= 0.0 => {
                    bracket = Some((xh, energy_of(&xh)));
                    break;
                }
                Ok(xh) => {
                    (lo, e_lo) = (hi, energy_of(&xh));
                    hi *= 2.0;
                }
                Err(_) => return Err(Violation::EnergyUncertified),
            }
        }
        let Some((mut best, mut e_hi)) = bracket else {
            return Err(Violation::EnergyUncertified);
        };
        let done = |x: &Vector6<f64>, e: f64| e >= -1e-12 * cs.energy(x).max(1e-300);
        let mut side = 0i8;
        for _ in 0..self.settings.energy_bisections {
            if hi - lo <= 1e-8 * hi || done(&best, e_hi) {
                break;
            }
            let mut mid = (lo * e_hi - hi * e_lo) / (e_hi - e_lo);
            if !(mid > lo && mid < hi) {
                mid = 0.5 * (lo + hi);
            }
            match solve(mid) {
                Ok(xm) if energy_of(&xm) <= 0.0 => {
                    (hi, e_hi, best) = (mid, energy_of(&xm), xm);
                    if side == 1 {
                        e_lo *= 0.5;
                    }
                    side = 1;
                }
                Ok(xm) => {
                    (lo, e_lo) = (mid, energy_of(&xm));
                    if side == -1 {
                        e_hi *= 0.5;
                    }
                    side = -1;
                }
                Err(_) => break,
            }
        }
        Ok(Answer {
            x: best,
            lambda: hi,
        })
    }

    /// A bound on `|y|` over the rows, where `x = xp + Z y` (Z orthonormal): from the bounds of
    /// the six contact-state components (infinite when one is missing).
    fn radius(&self, rows: &[RowX], xp: &Vector6<f64>) -> f64 {
        let mut limit = [f64::INFINITY; 6];
        for (row, rhs, kind) in rows {
            if let Violation::Bound(c) = kind {
                let k = c.0;
                if k < 6 && (row[k].abs() - 1.0).abs() <= f64::EPSILON {
                    limit[k] = rhs.abs() + 2.0 * self.tol;
                }
            }
        }
        limit.iter().map(|l| l * l).sum::<f64>().sqrt() + xp.norm()
    }
}
