//! An independent reference search for the fit, written with pim-core only.
//!
//! Every point it accepts is checked by pim-core itself: a forward solve from the point's contact
//! state (sliding with mu, or no slip with mu = mu_max) must be admissible (mu between 0 and
//! mu_max, no kinetic energy created), approach at the impact centre, stay within the velocity
//! bounds, and (sticking) have mu_max within the mu bounds. The contact state of a point is:
//! - Q2: the known contact state;
//! - Q1: a backward solve from the known separation state, for each friction direction;
//! - Q3: the unconstrained least-squares contact state for `X = R x`, then a compass search over
//!   the coefficients and the six contact components together (nine dimensions), so that points
//!   on the energy or friction boundary are reached too.
//!
//! The search is a dense grid over the coefficient box, then a compass search from the best
//! grid points. It is slow and simple on purpose: the fit must never be worse than it.
#![allow(dead_code)]

use nalgebra::{Matrix6, Vector6};
use pim_core::*;
use pim_fit::{CostPreset, MomentBranch};

/// Bounds of the search, as in the fit's default settings.
#[derive(Debug, Clone, Copy)]
pub struct Box3 {
    /// e range.
    pub e: [f64; 2],
    /// mu range.
    pub mu: [f64; 2],
    /// |v| bound, m/s.
    pub vb: f64,
    /// |omega| bound, rad/s.
    pub wb: f64,
}

impl Default for Box3 {
    fn default() -> Self {
        Box3 {
            e: [0.0, 0.2],
            mu: [-1.2, 1.2],
            vb: 20.0,
            wb: 5.0,
        }
    }
}

/// A problem for the reference: the impact, the estimates and which cost function.
pub struct RefProblem<'a> {
    /// The impact.
    pub impact: &'a Impact,
    /// Cost function.
    pub preset: CostPreset,
    /// Contact-state estimate (known exactly for Q2).
    pub x: Velocities,
    /// Separation-state estimate (known exactly for Q1).
    pub xf: Velocities,
    /// Search box.
    pub bounds: Box3,
}

fn within(v: &Velocities, b: &Box3) -> bool {
    v.to_vector()
        .iter()
        .enumerate()
        .all(|(k, x)| x.abs() <= if k % 3 == 2 { b.wb } else { b.vb })
}

fn sq(a: &Velocities, b: &Velocities) -> f64 {
    (a.to_vector() - b.to_vector()).norm_squared()
}

fn options(stick: bool) -> SolveOptions {
    SolveOptions {
        tangential: if stick {
            TangentialCondition::NoSlip
        } else {
            TangentialCondition::Sliding
        },
        ..Default::default()
    }
}

impl RefProblem<'_> {
    /// pim-core's verdict on a contact state: the separation state when admissible.
    pub fn admissible_forward(
        &self,
        c: Coefficients,
        stick: bool,
        x: &Velocities,
    ) -> Option<Velocities> {
        if !within(x, &self.bounds) || self.impact.check_approach(x).is_err() {
            return None;
        }
        let r = solve_forward(self.impact, &c, x, &options(stick)).ok()?;
        let ok = r.admissibility.admissible
            && within(&r.separation, &self.bounds)
            && (!stick
                || r.mu_max
                    .is_some_and(|m| m >= self.bounds.mu[0] && m <= self.bounds.mu[1]))
            && (stick || (c.mu >= self.bounds.mu[0] && c.mu <= self.bounds.mu[1]));
        ok.then_some(r.separation)
    }

    fn cost_at(&self, c: Coefficients, stick: bool, x: &Velocities) -> f64 {
        match self.admissible_forward(c, stick, x) {
            Some(sep) => match self.preset {
                CostPreset::Q1 => sq(x, &self.x),
                CostPreset::Q2 => sq(&sep, &self.xf),
                CostPreset::Q3 => sq(x, &self.x) + sq(&sep, &self.xf),
            },
            None => f64::INFINITY,
        }
    }

    /// The best cost at fixed coefficients over the contact states this reference tries, and
    /// that state.
    fn coefficient_cost(&self, c: Coefficients, stick: bool) -> (f64, Option<Velocities>) {
        let candidates: Vec<Velocities> = match self.preset {
            CostPreset::Q2 => vec![self.x],
            CostPreset::Q1 => FrictionSign::BOTH
                .iter()
                .filter_map(|&s| {
                    solve_backward_with_sign(self.impact, &c, &self.xf, &options(stick), s)
                        .ok()
                        .map(|r| r.initial)
                })
                .collect(),
            CostPreset::Q3 => FrictionSign::BOTH
                .iter()
                .filter_map(|&s| {
                    let sys = equations::assemble(self.impact, &c, s, &options(stick));
                    let r: Matrix6<f64> = -sys.f.lu().solve(&sys.g)?;
                    let h = Matrix6::identity() + r.transpose() * r;
                    let g: Vector6<f64> = self.x.to_vector() + r.transpose() * self.xf.to_vector();
                    let x = Velocities::from_vector(&h.cholesky()?.solve(&g));
                    (contact_friction(self.impact, &c, &x, &options(stick)).0 == s).then_some(x)
                })
                .collect(),
        };
        let mut best = (f64::INFINITY, None);
        for x in candidates {
            // Q1: the contact state must reproduce the known separation state.
            let v = self.cost_at(c, stick, &x);
            if v < best.0 {
                best = (v, Some(x));
            }
        }
        best
    }

    /// The best cost found for a moment branch (infinite when no admissible point was found).
    pub fn search(&self, branch: MomentBranch) -> f64 {
        self.search_point(branch).0
    }

    /// The best cost found for a moment branch, its coefficients `[e, mu, em]` and whether it
    /// sticks.
    pub fn search_point(&self, branch: MomentBranch) -> (f64, [f64; 3], bool) {
        let axis = |lo: f64, hi: f64, n: usize| -> Vec<f64> {
            if hi <= lo {
                return vec![lo];
            }
            (0..n)
                .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
                .collect()
        };
        let b = &self.bounds;
        let ems = match branch {
            MomentBranch::Zero => vec![1.0],
            MomentBranch::Free => axis(-1.0, 0.0, 11),
        };
        // (cost, [e, mu, em], stick, contact state)
        let mut pts: Vec<(f64, [f64; 3], bool, Velocities)> = Vec::new();
        for stick in [false, true] {
            let mus = if stick {
                vec![0.0]
            } else {
                axis(b.mu[0], b.mu[1], 49)
            };
            for &e in &axis(b.e[0], b.e[1], 21) {
                for &mu in &mus {
                    for &em in &ems {
                        let (v, x) = self.coefficient_cost(Coefficients { e, mu, em }, stick);
                        if let Some(x) = x.filter(|_| v.is_finite()) {
                            pts.push((v, [e, mu, em], stick, x));
                        }
                    }
                }
            }
        }
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best = (f64::INFINITY, [0.0; 3], false);
        for &(v, p, stick, x) in pts.iter().take(4) {
            let (c, q) = self.polish(branch, v, p, stick, x);
            if c < best.0 {
                best = (c, q, stick);
            }
        }
        best
    }

    /// Compass search from a grid point: over the coefficients (Q1, Q2), and over the
    /// coefficients and the contact state together (Q3).
    fn polish(
        &self,
        branch: MomentBranch,
        cost: f64,
        p: [f64; 3],
        stick: bool,
        x: Velocities,
    ) -> (f64, [f64; 3]) {
        let b = &self.bounds;
        let q3 = self.preset == CostPreset::Q3;
        let mut z: Vec<f64> = p.to_vec();
        if q3 {
            z.extend(x.to_vector().iter());
        }
        let lo = [b.e[0], b.mu[0], -1.0];
        let hi = [b.e[1], b.mu[1], 0.0];
        let mut step: Vec<f64> = vec![0.005, 0.025, 0.05];
        if q3 {
            step.extend([0.2, 0.2, 0.05, 0.2, 0.2, 0.05]);
        }
        let active = |k: usize| {
            !((k == 1 && stick)
                || (k == 2 && branch == MomentBranch::Zero)
                || (k == 0 && b.e[1] <= b.e[0]))
        };
        let value = |z: &[f64]| {
            let c = Coefficients {
                e: z[0],
                mu: z[1],
                em: z[2],
            };
            if q3 {
                let x = Velocities::from_vector(&Vector6::from_column_slice(&z[3..9]));
                self.cost_at(c, stick, &x)
            } else {
                self.coefficient_cost(c, stick).0
            }
        };
        let mut cost = cost;
        let start: Vec<f64> = step.clone();
        for _ in 0..2000 {
            let mut improved = false;
            for k in 0..z.len() {
                if !active(k) {
                    continue;
                }
                for d in [-1.0, 1.0] {
                    let mut q = z.clone();
                    q[k] += d * step[k];
                    if k < 3 {
                        q[k] = q[k].clamp(lo[k], hi[k]);
                    }
                    let v = value(&q);
                    if v < cost {
                        cost = v;
                        z = q;
                        improved = true;
                    }
                }
            }
            if !improved {
                step.iter_mut().for_each(|s| *s *= 0.5);
                if step[0] < 1e-7 * start[0] {
                    break;
                }
            }
        }
        (cost, [z[0], z[1], z[2]])
    }
}
