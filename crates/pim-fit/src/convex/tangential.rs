//! The tangential model's fit as convex pieces over `z = (x, q)`.
//!
//! The model has no moment impulse, so its velocity changes are those of PIM's zero branch
//! (`d = D q`, q two-dimensional) and its impulse is `(Pn, Pt)` at C. At a fixed contact state
//! x and restitution e (`Vn = -e vn`, linear as in PIM) the impulses lie on a line along which
//! `Pn`, `Pt` and the final tangential velocity `Vt` are affine: `dPn = alpha dVt`,
//! `dPt = beta dVt` ([`Line`], constants of the geometry). The normal impulse must push the
//! vehicles apart: `sigma Pn > 0`, with `sigma` the sign of the frictionless impulse.
//!
//! - Sticking: `Vt = et vt` for an et of its range, i.e. `Vt` between `et_lo vt` and `et_hi vt`
//!   (for a sign of `vt`), and `|Pt| <= friction_max |Pn|`: linear.
//! - Sliding on the side s: `Pt = s f Pn` with f in the friction range (linear for the sign of
//!   Pn), where the sticking impulse at some et of the range, `P_s`, needs at least f on that
//!   side: `s Pt_s / Pn_s >= f` (the friction rule of pim-core's forward solve). `P_s` is the
//!   point of the line where `Vt = w = et vt`: with `Delta = w - Vt`,
//!   `Pn_s = Pn + alpha Delta`, `Pt_s = Pt + beta Delta`. Along the line the ratio `Pt / Pn` is
//!   monotone in Pt with the sign `sigma` on each side of its pole (`Pn = 0`), so:
//!   - where `P_s` is on the side of the pole of the actual impulse (`sigma Pn_s > 0`), the
//!     condition is `s sigma (Pt_s - Pt) >= 0`, i.e. `s sigma sgn(beta) Delta >= 0`;
//!   - beyond the pole (`sigma Pn_s < 0`) the ratio has the sign of `alpha beta` and a
//!     magnitude above `|beta / alpha|`, which exceeds every friction with `sigma Pn > 0` on
//!     that side: the condition holds for `s = sgn(alpha beta)` and never for the other side.
//!
//!   Each is linear in `(z, w)`, and `w` lies between `et_lo vt` and `et_hi vt`; a w exists
//!   when every lower bound of w is at most every upper bound (Fourier-Motzkin), which is
//!   linear in z.
//!
//! Every piece is a strictly convex QP (on the subspace of the known components), solved like
//! PIM's patterns; the best piece's optimum is checked by the fit's own constraint set and by
//! the model's forward solve (its energy condition is not convex here, as in PIM).

use super::dual::{Row, N};
use super::form::{add, dot, scaled, Form};
use super::modes::{Line, Mode};
use super::Formulation;
use crate::inner::{At, Candidate, Inner};
use pim_core::{Coefficients, FrictionSign, TangentialCondition};

/// A bound of `w = et vt`: `w >= form . z + c` (lower) or `w <= form . z + c` (upper).
#[derive(Debug, Clone, Copy)]
struct Bound {
    form: Form,
    c: f64,
}

impl Bound {
    fn at(&self, z: &[f64; N]) -> f64 {
        dot(&self.form, z) + self.c
    }
}

/// `form . z >= rhs` onto `rows`; `None` when the form vanishes and the row cannot hold.
fn push(rows: &mut Vec<Row>, form: Form, rhs: f64) -> Option<()> {
    match Row::new(form, rhs) {
        Some(row) => rows.push(row),
        None if rhs <= 0.0 => {}
        None => return None,
    }
    Some(())
}

impl Formulation {
    /// The line of impulses at fixed x and e (the zero branch's two q coordinates); `None`
    /// when the geometry leaves it degenerate.
    pub(super) fn line_of(&self) -> Option<Line> {
        if self.n != 8 {
            return None;
        }
        let part = |f: &Form| [f[6], f[7]];
        let dot2 = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
        let (pn, pt, vt) = (part(&self.pn), part(&self.pt), part(&self.big_vt));
        let dvn = part(&add(&self.big_vn, &self.vn, -1.0));
        // The normal velocity change per unit normal impulse without a tangential one.
        let frictionless = [-pt[1], pt[0]];
        let knn = dot2(dvn, frictionless) / dot2(pn, frictionless);
        // Along the line (Vn fixed).
        let along = [-dvn[1], dvn[0]];
        let dvt = dot2(vt, along);
        let line = Line {
            alpha: dot2(pn, along) / dvt,
            beta: dot2(pt, along) / dvt,
            sigma: self.side * knn.signum(),
        };
        (line.alpha.is_finite() && line.beta.is_finite() && line.beta != 0.0)
            .then_some(line)
            .filter(|_| knn.is_finite() && knn != 0.0)
    }

    /// The tangential model's pieces.
    pub(super) fn modes(&self) -> Vec<Mode> {
        let far_side = self.line.map(|l| l.alpha * l.beta);
        let mut out = Vec::with_capacity(8);
        for s_vt in [1.0, -1.0] {
            out.push(Mode::Stick { s_vt });
            for s in FrictionSign::BOTH {
                out.push(Mode::Slide {
                    s,
                    s_vt,
                    far: false,
                });
                if far_side.is_some_and(|p| p * s.value() > 0.0) {
                    out.push(Mode::Slide { s, s_vt, far: true });
                }
            }
        }
        out
    }

    /// The bounds of `w = et vt` of a piece: the et range, and for sliding the friction rule
    /// on the sticking impulse at w.
    fn w_bounds(&self, inner: &Inner, m: &Mode, line: &Line) -> (Vec<Bound>, Vec<Bound>) {
        let [et_lo, et_hi] = inner.et_range;
        let (ea, eb) = if m.s_vt() > 0.0 {
            (et_lo, et_hi)
        } else {
            (et_hi, et_lo)
        };
        let mut lower = vec![Bound {
            form: scaled(&self.vt, ea),
            c: 0.0,
        }];
        let mut upper = vec![Bound {
            form: scaled(&self.vt, eb),
            c: 0.0,
        }];
        let Mode::Slide { s, far, .. } = *m else {
            return (lower, upper);
        };
        let sigma = line.sigma;
        let vt_final = Bound {
            form: self.big_vt,
            c: 0.0,
        };
        if !far {
            // s sigma sgn(beta) (w - Vt) >= 0.
            if s.value() * sigma * line.beta > 0.0 {
                lower.push(vt_final);
            } else {
                upper.push(vt_final);
            }
        }
        // The sign of Pn_s = Pn + alpha (w - Vt): sigma Pn_s >= floor near, <= -floor far,
        // i.e. k w >= (or <=) k Vt - sigma Pn +- floor with k = sigma alpha.
        let k = sigma * line.alpha;
        if k != 0.0 {
            let floor = inner.pn_floor();
            let form = add(&self.big_vt, &self.pn, -sigma / k);
            let (c, lower_bound) = if far {
                (-floor / k, k < 0.0)
            } else {
                (floor / k, k > 0.0)
            };
            let b = Bound { form, c };
            if lower_bound {
                lower.push(b);
            } else {
                upper.push(b);
            }
        }
        (lower, upper)
    }

    /// The rows of a piece beyond the common ones (`None`: the geometry is degenerate).
    pub(super) fn mode_rows(&self, inner: &Inner, m: &Mode) -> Option<Vec<Row>> {
        let line = self.line?;
        let sigma = line.sigma;
        let [f_lo, f_hi] = inner.friction;
        let mut rows = Vec::with_capacity(12);
        // The normal impulse pushes the vehicles apart; vt has the piece's sign.
        push(&mut rows, scaled(&self.pn, sigma), inner.pn_floor())?;
        push(&mut rows, scaled(&self.vt, m.s_vt()), 0.0)?;
        let (lower, upper) = self.w_bounds(inner, m, &line);
        match *m {
            Mode::Stick { .. } => {
                // |Pt| <= friction_max |Pn|, and Vt = w within the et range.
                for t in [1.0, -1.0] {
                    push(
                        &mut rows,
                        scaled(&add(&scaled(&self.pn, f_hi), &self.pt, -t), sigma),
                        0.0,
                    )?;
                }
                push(&mut rows, add(&self.big_vt, &lower[0].form, -1.0), 0.0)?;
                push(&mut rows, add(&upper[0].form, &self.big_vt, -1.0), 0.0)?;
            }
            Mode::Slide { s, .. } => {
                // s Pt / Pn within the friction range.
                let spt = scaled(&self.pt, s.value());
                push(&mut rows, scaled(&add(&spt, &self.pn, -f_lo), sigma), 0.0)?;
                push(&mut rows, scaled(&add(&spt, &self.pn, -f_hi), -sigma), 0.0)?;
                // Some w between every lower and every upper bound.
                for l in &lower {
                    for u in &upper {
                        push(&mut rows, add(&u.form, &l.form, -1.0), l.c - u.c)?;
                    }
                }
            }
        }
        Some(rows)
    }

    /// The candidate of a piece's optimum: e, the friction limit (sliding) or et (sticking)
    /// read from z; in sliding, the et in the middle of those whose sticking impulse exceeds
    /// the limit (the answer does not depend on it).
    pub(super) fn mode_candidate(&self, inner: &Inner, m: &Mode, z: &[f64; N]) -> (At, Candidate) {
        let (x, xf) = self.states(inner, z);
        let e = self.restitution(inner, z);
        let (pn, pt) = (dot(&self.pn, z), dot(&self.pt, z));
        let (vt, vt_final) = (dot(&self.vt, z), dot(&self.big_vt, z));
        let [et_lo, et_hi] = inner.et_range;
        let et_of = |w: f64| {
            if vt.abs() <= 1e-12 * inner.objective.scale {
                0.5 * (et_lo + et_hi)
            } else {
                (w / vt).clamp(et_lo, et_hi)
            }
        };
        let (at, mu_eff) = match *m {
            Mode::Stick { .. } => {
                // No friction sign enters the sticking mode.
                let sign = FrictionSign::Positive;
                let at = At {
                    c: Coefficients {
                        e,
                        mu: 0.0,
                        em: 1.0,
                    },
                    mode: TangentialCondition::NoSlip,
                    sign,
                    et: et_of(vt_final),
                };
                (at, sign.value() * pt / pn)
            }
            Mode::Slide { s, .. } => {
                let f = (s.value() * pt / pn).clamp(inner.friction[0], inner.friction[1]);
                let (lower, upper) = match self.line {
                    Some(line) => self.w_bounds(inner, m, &line),
                    None => (Vec::new(), Vec::new()),
                };
                let lo = lower.iter().map(|b| b.at(z)).fold(f64::MIN, f64::max);
                let hi = upper.iter().map(|b| b.at(z)).fold(f64::MAX, f64::min);
                let at = At {
                    c: Coefficients { e, mu: f, em: 1.0 },
                    mode: TangentialCondition::Sliding,
                    sign: s,
                    et: et_of(0.5 * (lo + hi)),
                };
                (at, f)
            }
        };
        let candidate = Candidate {
            cost: inner.objective.cost(&x, &xf),
            x,
            xf,
            mu_eff,
            qp: true,
            lambda: 0.0,
            flat: false,
        };
        (at, candidate)
    }
}
