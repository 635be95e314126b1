//! What a solution leaves undetermined, which constraints it touches, and why a branch has no
//! solution.

use super::qp::{to6, MAX_ITER};
use super::{At, Candidate, Inner};
use crate::problem::Component;
use crate::report::{ActiveConstraint, Limits, Reason, Violation};
use nalgebra::Vector6;
use pim_core::{TangentialCondition, Velocities};
use std::collections::BTreeMap;

impl Inner {
    /// The contact state (`start` 0) or the separation state (`start` 6) when all six of its
    /// components are known exactly.
    pub(crate) fn fixed_state(&self, start: usize) -> Option<Vector6<f64>> {
        let mut v = Vector6::zeros();
        for k in 0..6 {
            let &(_, value) = self.objective.fixed.iter().find(|(i, _)| *i == start + k)?;
            v[k] = value;
        }
        Some(v)
    }

    /// Velocity components that the data leave undetermined at a point: directions in which the
    /// reduced cost is flat (its Hessian is singular).
    pub fn undetermined_components(&self, at: &At) -> Vec<Component> {
        let Some(r) = self.transfer(at) else {
            return Vec::new();
        };
        let Some(ox) = self.objective.over_x(r) else {
            return Vec::new();
        };
        if ox.z.ncols() == 0 {
            return Vec::new();
        }
        let (hy, _) = ox.reduced();
        let Some(eig) = hy.clone().try_symmetric_eigen(f64::EPSILON, MAX_ITER) else {
            return Vec::new();
        };
        let emax = eig.eigenvalues.amax().max(1e-300);
        let mut names = Vec::new();
        for i in 0..eig.eigenvalues.len() {
            if eig.eigenvalues[i].abs() > 1e-9 * emax {
                continue;
            }
            let dx = to6(&(&*ox.z * eig.eigenvectors.column(i)));
            let dxf = ox.r * dx;
            let du: Vec<f64> = dx.iter().chain(dxf.iter()).copied().collect();
            let big = du.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
            for (k, v) in du.iter().enumerate() {
                if v.abs() > 0.05 * big && !names.contains(&Component(k)) {
                    names.push(Component(k));
                }
            }
        }
        names
    }

    /// The constraints active at a candidate, including coefficients at the ends of their
    /// ranges. `free_em`: e_m is a coefficient of the fit (not fixed at 1).
    pub fn active_constraints(
        &self,
        at: &At,
        c: &Candidate,
        free_em: bool,
    ) -> Vec<ActiveConstraint> {
        let tol = self.settings.active_tolerance;
        let mut out = self
            .constraints(at)
            .active(at.c.e, &c.x, &c.xf, tol * self.objective.scale);
        let near = |v: f64, b: f64, size: f64| (v - b).abs() <= tol * size.max(1e-12);
        let [elo, ehi] = self.e_range;
        let e_box = (ehi - elo).max(1e-3);
        if near(at.c.e, elo, e_box) {
            out.push(ActiveConstraint::ELow);
        } else if near(at.c.e, ehi, e_box) {
            out.push(ActiveConstraint::EHigh);
        }
        if free_em {
            if near(at.c.em, -1.0, 1.0) {
                out.push(ActiveConstraint::EmLow);
            } else if near(at.c.em, 0.0, 1.0) {
                out.push(ActiveConstraint::EmHigh);
            }
        }
        let [mlo, mhi] = self.mu_bounds;
        let mu_box = (mhi - mlo).max(1e-3);
        if self.family.friction() == crate::family::Friction::Limit {
            // The coefficient that decides the answer: the friction limit when sliding, et when
            // sticking (the other only bounds it).
            let (v, [lo, hi], low, high) = match at.mode {
                TangentialCondition::Sliding => (
                    at.c.mu,
                    self.friction,
                    ActiveConstraint::FrictionLow,
                    ActiveConstraint::FrictionHigh,
                ),
                TangentialCondition::NoSlip => (
                    at.et,
                    self.et_range,
                    ActiveConstraint::EtLow,
                    ActiveConstraint::EtHigh,
                ),
            };
            let size = (hi - lo).max(1e-3);
            if hi > lo && near(v, lo, size) {
                out.push(low);
            } else if hi > lo && near(v, hi, size) {
                out.push(high);
            }
            return out;
        }
        match at.mode {
            TangentialCondition::Sliding => {
                if near(c.mu_eff, 0.0, mu_box) {
                    out.push(ActiveConstraint::MuZero);
                } else if near(c.mu_eff, mlo, mu_box) {
                    out.push(ActiveConstraint::MuLow);
                } else if near(c.mu_eff, mhi, mu_box) {
                    out.push(ActiveConstraint::MuHigh);
                }
            }
            TangentialCondition::NoSlip => {
                if !out.contains(&ActiveConstraint::MuMax) {
                    out.push(ActiveConstraint::MuMax);
                }
            }
        }
        out
    }
}

/// A reason the data alone give for a branch to have no solution, whatever the search finds:
/// fixed separation velocities that still approach at the impact centre while e may not be
/// negative (`e = -Vn / vn >= e_min >= 0` needs them not to approach), or fixed contact
/// velocities that do not approach. Each is a proof of infeasibility, not a statistic.
pub(crate) fn direct_reason(inner: &Inner, limits: Limits) -> Option<Reason> {
    let impact = &inner.impact;
    let side = if impact.side() == 0.0 {
        1.0
    } else {
        impact.side()
    };
    if let Some(xf) = inner.fixed_state(6) {
        let (vn, _) = impact.relative_velocity(&Velocities::from_vector(&xf));
        if side * vn < -1e-9 && limits.e[0] >= 0.0 {
            return Some(Reason::SeparationApproaches {
                normal_velocity: vn,
                e_range: limits.e,
            });
        }
    }
    if let Some(x) = inner.fixed_state(0) {
        if let Err(e) = impact.check_approach(&Velocities::from_vector(&x)) {
            return Some(Reason::ContactNotApproaching(e));
        }
    }
    None
}

/// Why no candidate of a branch is admissible, from the data and the violations the search met.
pub(crate) fn explain_infeasible(
    inner: &Inner,
    limits: Limits,
    violations: &BTreeMap<Violation, usize>,
) -> Reason {
    if let Some(reason) = direct_reason(inner, limits) {
        return reason;
    }
    // Separation velocities fixed and the search stopped by the sliding direction: the
    // collision would have to reverse the sliding at the impact centre.
    if let Some(xf) = inner.fixed_state(6) {
        let (_, vt) = inner
            .impact
            .relative_velocity(&Velocities::from_vector(&xf));
        let top = violations.iter().max_by_key(|(_, n)| **n).map(|(v, _)| *v);
        if matches!(top, Some(Violation::SlidingDirection | Violation::Friction)) {
            return Reason::SeparationReversesSliding {
                tangential_velocity: vt,
            };
        }
    }
    if violations.is_empty() {
        return Reason::NoCandidate;
    }
    // Sticking candidates against separation velocities that still slide are expected to fail;
    // they say nothing about why the data cannot be fitted when other failures exist.
    let mut counts: Vec<(Violation, usize)> = violations
        .iter()
        .filter(|(v, _)| violations.len() == 1 || **v != Violation::Inconsistent)
        .map(|(v, n)| (*v, *n))
        .collect();
    let total: usize = counts.iter().map(|c| c.1).sum();
    counts.sort_by_key(|c| std::cmp::Reverse(c.1));
    let pct = |n: usize| 100.0 * n as f64 / total as f64;
    Reason::Constraints {
        main: (counts[0].0, pct(counts[0].1)),
        second: counts.get(1).map(|&(v, n)| (v, pct(n))),
        limits,
    }
}
