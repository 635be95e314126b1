//! Profiles along e for problems with one whole state known.
//!
//! At fixed `(mu, e_m)`, tangential condition and friction sign, both states are affine in a
//! parameter t (t = e forwards, t = 1 + 1/e backwards; pim-core's [`Line`]). The cost is then a
//! quadratic in t, every condition of the constraint set holds on a union of intervals of t
//! (found between the roots of its forms along the line, by the same point tests as any other
//! evaluation), and the energy condition `T1 - T0 <= 0` is a quadratic inequality. The minimum
//! over the admissible intervals is the clamped vertex of the cost on one of them.

use super::constraints::Intervals;
use super::{At, Candidate, Eval, Inner};
use crate::report::Violation;
use nalgebra::Vector6;
use pim_core::reduction::{Line, Reduced};
use pim_core::{Coefficients, FrictionSign, TangentialCondition};

/// Where a profile line lies: the e range, mu and em, the tangential condition and the sign.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LineAt {
    pub e_range: [f64; 2],
    pub mu: f64,
    pub em: f64,
    pub mode: TangentialCondition,
    pub sign: FrictionSign,
}

impl LineAt {
    fn at(&self, e: f64) -> At {
        At {
            c: Coefficients {
                e,
                mu: self.mu,
                em: self.em,
            },
            mode: self.mode,
            sign: self.sign,
            et: 0.0,
        }
    }
}

/// A profile line: states along t, the admissible intervals of t and the cost along t
/// (`cost[0] + cost[1] t + cost[2] t^2`).
struct ProfileLine {
    line: Line,
    forward: bool,
    admissible: Intervals,
    cost: [f64; 3],
}

impl Inner {
    /// The line of e at `at`, with its admissible intervals and cost; `Err` with why no e is
    /// admissible.
    fn profile_line(&self, at: &LineAt) -> Result<ProfileLine, Violation> {
        let known = self.known.as_ref().expect("profiled problem");
        let forward = known.forward();
        let line = match known.line(at.mu, at.em, at.mode, at.sign) {
            Ok(l) => l,
            Err(Reduced::Inconsistent) => return Err(Violation::Inconsistent),
            Err(_) => return Err(Violation::Singular),
        };
        if !forward && at.e_range[1] <= 0.0 {
            // e = 0 backwards asks Vn = 0 of the known separation state, which it is not
            // (otherwise e would not be profiled).
            return Err(Violation::Inconsistent);
        }
        // The t interval of the e range (e = 0 is t = infinity backwards).
        let (lo, hi) = if forward {
            (at.e_range[0], at.e_range[1])
        } else {
            let t = |e: f64| {
                if e > 0.0 {
                    Line::t_of_e(e, false)
                } else {
                    f64::INFINITY
                }
            };
            (t(at.e_range[1]), t(at.e_range[0]))
        };
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(Violation::Singular);
        }
        // Coefficients of the constraint set at the middle of the range: only the friction rows
        // depend on e, and the set reads them along the line itself.
        let cs = self.constraints(&at.at(at.e_range[0]));
        let (set, first) = cs.along(&line, forward, lo, hi);
        if let Some(v) = first {
            return Err(v);
        }
        // Energy: T1 - T0 along the line, a quadratic in t.
        let quad = |a: &Vector6<f64>, b: &Vector6<f64>| {
            let m = &cs.mass;
            [
                0.5 * a.component_mul(a).dot(m),
                a.component_mul(b).dot(m),
                0.5 * b.component_mul(b).dot(m),
            ]
        };
        let q1 = quad(&line.xf0, &line.xf1);
        let q0 = quad(&line.x0, &line.x1);
        let admissible = set.quadratic_nonpositive([q1[0] - q0[0], q1[1] - q0[1], q1[2] - q0[2]]);
        if admissible.is_empty() {
            return Err(Violation::Energy);
        }
        let cost = self
            .objective
            .along([&line.x0, &line.x1], [&line.xf0, &line.xf1]);
        Ok(ProfileLine {
            line,
            forward,
            admissible,
            cost,
        })
    }

    /// The best e in `e_range` for fixed `(mu, em)`, tangential condition and sign, for a
    /// problem with one whole state known (only when [`Inner::profiles`]). The chosen point
    /// then passes exactly the checks of any other evaluation.
    pub fn evaluate_profile(&self, at: &LineAt) -> (Coefficients, Eval) {
        let fallback = at.at(at.e_range[0]).c;
        let pl = match self.profile_line(at) {
            Ok(pl) => pl,
            Err(v) => return (fallback, Eval::Infeasible(v)),
        };
        let [_, cb, ca] = pl.cost;
        let value = |t: f64| ca * t * t + cb * t;
        let mut best: Option<(f64, f64)> = None;
        for &(plo, phi) in &pl.admissible.0 {
            let t = if ca > 0.0 {
                (-cb / (2.0 * ca)).clamp(plo, phi)
            } else if cb >= 0.0 || !phi.is_finite() {
                plo
            } else {
                phi
            };
            if !t.is_finite() {
                continue;
            }
            if best.is_none_or(|(_, v)| value(t) < v) {
                best = Some((t, value(t)));
            }
        }
        let Some((t, _)) = best else {
            return (fallback, Eval::Infeasible(Violation::Energy));
        };
        self.profile_point(&pl, at, t)
    }

    /// The candidate at parameter t of a profile line.
    fn profile_point(&self, pl: &ProfileLine, at: &LineAt, t: f64) -> (Coefficients, Eval) {
        let e = Line::e_of_t(t, pl.forward).clamp(at.e_range[0], at.e_range[1]);
        let point = at.at(e);
        let (x, xf) = pl.line.at(t);
        (point.c, self.checked(&point, x, xf))
    }

    /// The admissible points at the ends of the e intervals, at fixed `(mu, em)`, where the cost
    /// is at most `limit` (profiled problems): the extremes of e and of the speeds over the
    /// near-optimal set along that line, exactly.
    pub fn profile_level_ends(&self, at: &LineAt, limit: f64) -> Vec<(Coefficients, Candidate)> {
        let Ok(pl) = self.profile_line(at) else {
            return Vec::new();
        };
        let [c0, c1, c2] = pl.cost;
        let level = pl.admissible.quadratic_nonpositive([c0 - limit, c1, c2]);
        let mut out = Vec::new();
        for &(a, b) in &level.0 {
            for t in [a, b] {
                if !t.is_finite() {
                    continue;
                }
                if let (c, Eval::Feasible(cand)) = self.profile_point(&pl, at, t) {
                    out.push((c, cand));
                }
            }
        }
        out
    }
}
