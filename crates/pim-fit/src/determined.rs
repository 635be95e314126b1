//! The six equations reduced to three unknowns.
//!
//! Equations 1-3 (linear and angular momentum) and the sliding equation 5 only involve the
//! change `D = X - x`. Equations 1-3 do not depend on the coefficients, so the changes that
//! satisfy them form a fixed three-dimensional space:
//!
//! ```text
//! D = N p,  p = (dV1x, dV1y, dW1),
//! dV2x = -m1 dV1x / m2,  dV2y = -m1 dV1y / m2,
//! dW2 = -(I1 dW1 + m1 (D2 + D4) dV1y - m1 (D1 + D3) dV1x) / I2.
//! ```
//!
//! With x (or X) known, equations 4, 5 (or 5a) and 6 become a 3x3 linear system in p whose rows
//! are affine in e, mu and em; its pieces are computed once per problem. The result is the same
//! as a solve of the six equations, at a fraction of the cost: the fit evaluates thousands of
//! coefficient points per problem. With neither state known, the same reduction gives the
//! transfer matrix of `X = R x` ([`Pieces::transfer`]).

use crate::inner::Mode;
use nalgebra::{Matrix3, Matrix6, RowVector3, RowVector6, SMatrix, Vector3, Vector6};
use pim_core::equations::{moment_b_row, normal_velocity_row, tangential_velocity_row};
use pim_core::{Impact, MomentForm};

/// Result of a reduced solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Reduced3 {
    /// The contact and separation states.
    States(Vector6<f64>, Vector6<f64>),
    /// An equation has no terms in the unknown state and the known state violates it.
    Inconsistent,
    /// The reduced system is singular (or an equation without unknowns holds): the unknown
    /// state is not fixed by the equations.
    Singular,
}

/// The coefficient-independent pieces of the reduced system of one impact.
#[derive(Debug, Clone)]
pub(crate) struct Pieces {
    /// `D = N p`.
    n: SMatrix<f64, 6, 3>,
    /// `n . D` as a row over p (normal relative velocity change).
    nr: RowVector3<f64>,
    /// `t . D` as a row over p.
    tr: RowVector3<f64>,
    /// Equation 5 over p: `(fa + mu' fb) p = 0`.
    fa: RowVector3<f64>,
    fb: RowVector3<f64>,
    /// The yaw-rate row of equation 6 over p, and `b . D` over p.
    wr: RowVector3<f64>,
    br: RowVector3<f64>,
    /// vn, vt and the yaw-rate term of equation 6 as rows over a state.
    nrow: RowVector6<f64>,
    trow: RowVector6<f64>,
    w: RowVector6<f64>,
}

impl Pieces {
    /// The coefficient-independent pieces of an impact.
    pub fn new(impact: &Impact, form: MomentForm) -> Self {
        let [m1, m2] = impact.masses();
        let [i1, i2] = impact.inertias();
        let [d1, d2, d3, d4] = impact.levers();
        let q = m1 / m2;
        #[rustfmt::skip]
        let n = SMatrix::<f64, 6, 3>::from_row_slice(&[
            1.0, 0.0, 0.0,
            0.0, 1.0, 0.0,
            0.0, 0.0, 1.0,
            -q, 0.0, 0.0,
            0.0, -q, 0.0,
            m1 * (d1 + d3) / i2, -m1 * (d2 + d4) / i2, -i1 / i2,
        ]);
        let [c, s] = impact.normal();
        let nrow = normal_velocity_row(impact);
        let trow = tangential_velocity_row(impact);
        let fa = RowVector6::new(0.0, m1 * c, 0.0, m2 * s, 0.0, 0.0);
        let fb = RowVector6::new(0.0, -m1 * s, 0.0, m2 * c, 0.0, 0.0);
        let sign = match form {
            MomentForm::Corrected => 1.0,
            MomentForm::Brach1983 => -1.0,
        };
        let w = RowVector6::new(0.0, 0.0, -sign, 0.0, 0.0, sign);
        let b = moment_b_row(impact);
        // Rows over p are scaled by m1 (equation 5) so that all rows are velocities.
        Pieces {
            nr: nrow * n,
            tr: trow * n,
            fa: fa * n / m1,
            fb: fb * n / m1,
            wr: w * n,
            br: b * n,
            nrow,
            trow,
            w,
            n,
        }
    }

    /// The transfer matrix R of `X = R x` at coefficients `(e, mu, em)` (mu unused when
    /// sticking) and friction sign: `R = I + N A^-1 K`, where `A p = K x` are equations 4, 5 (5a)
    /// and 6 written for the change `D = N p`. `None` when A is (numerically) singular.
    pub fn transfer(
        &self,
        e: f64,
        mu: f64,
        em: f64,
        mode: Mode,
        sign: f64,
    ) -> Option<Matrix6<f64>> {
        let (tangential, kt) = match mode {
            Mode::Sliding => (self.fa + self.fb * (mu * sign), RowVector6::zeros()),
            Mode::Sticking => (self.tr, -self.trow),
        };
        let rows = [self.nr, tangential, self.wr * (1.0 - em) - self.br * em];
        let k = [self.nrow * -(1.0 + e), kt, self.w * -(1.0 - em)];
        let (inv, scale) = inverse(&rows, &[0.0; 3], 1.0).ok()??;
        let mut ks = SMatrix::<f64, 3, 6>::zeros();
        for i in 0..3 {
            ks.set_row(i, &(k[i] / scale[i]));
        }
        Some(Matrix6::identity() + self.n * (inv * ks))
    }
}

/// The precomputed pieces of the reduced system of one problem with one whole state known.
#[derive(Debug, Clone)]
pub(crate) struct Determined {
    p: Pieces,
    /// The known state.
    known: Vector6<f64>,
    /// True when the contact state x is known (solve forwards), false when X is.
    forward: bool,
    /// The rows of [`Pieces`] applied to the known state: vn (or Vn), vt (or Vt), the yaw-rate
    /// term.
    kn: f64,
    kt: f64,
    kw: f64,
}

impl Determined {
    /// Pieces for a problem whose contact state (`forward`) or separation state is `known`.
    pub fn new(impact: &Impact, form: MomentForm, known: Vector6<f64>, forward: bool) -> Self {
        let p = Pieces::new(impact, form);
        Determined {
            known,
            forward,
            kn: p.nrow.dot(&known.transpose()),
            kt: p.trow.dot(&known.transpose()),
            kw: p.w.dot(&known.transpose()),
            p,
        }
    }

    /// The known state.
    pub fn known(&self) -> &Vector6<f64> {
        &self.known
    }

    /// True when the contact state is the known one.
    pub fn forward(&self) -> bool {
        self.forward
    }

    /// Solves for the unknown state at coefficients `(e, mu, em)` (mu unused when sticking) and
    /// friction sign `sign`.
    pub fn solve(&self, e: f64, mu: f64, em: f64, mode: Mode, sign: f64) -> Reduced3 {
        // Rows a p = r of equations 4, 5 (5a) and 6.
        let (rows, rhs): ([RowVector3<f64>; 3], [f64; 3]) = if self.forward {
            // X = x + N p.
            let tangential = match mode {
                Mode::Sliding => (self.p.fa + self.p.fb * (mu * sign), 0.0),
                Mode::Sticking => (self.p.tr, -self.kt),
            };
            (
                [
                    self.p.nr,
                    tangential.0,
                    self.p.wr * (1.0 - em) - self.p.br * em,
                ],
                [-(1.0 + e) * self.kn, tangential.1, -(1.0 - em) * self.kw],
            )
        } else {
            // x = X - N p.
            let tangential = match mode {
                Mode::Sliding => (self.p.fa + self.p.fb * (mu * sign), 0.0),
                Mode::Sticking => (RowVector3::zeros(), self.kt),
            };
            (
                [self.p.nr * e, tangential.0, self.p.br * em],
                [(1.0 + e) * self.kn, tangential.1, (1.0 - em) * self.kw],
            )
        };
        let (inv, scale) = match inverse(&rows, &rhs, self.known.amax()) {
            Ok(Some(v)) => v,
            Ok(None) => return Reduced3::Singular,
            Err(r) => return r,
        };
        let p = inv * Vector3::from_iterator(rhs.iter().zip(&scale).map(|(r, s)| r / s));
        let d = self.p.n * p;
        if self.forward {
            Reduced3::States(self.known, self.known + d)
        } else {
            Reduced3::States(self.known - d, self.known)
        }
    }
}

/// The inverse of the row-equilibrated matrix of `rows` and the row scales. `Err` when a row has
/// no unknowns: [`Reduced3::Inconsistent`] when its right-hand side is not zero, else
/// [`Reduced3::Singular`]. `Ok(None)` when the matrix is (numerically) singular.
#[allow(clippy::type_complexity)]
fn inverse(
    rows: &[RowVector3<f64>; 3],
    rhs: &[f64; 3],
    size: f64,
) -> Result<Option<(Matrix3<f64>, [f64; 3])>, Reduced3> {
    let mut a = Matrix3::zeros();
    let mut scale = [1.0; 3];
    let mut without_unknowns = false;
    for i in 0..3 {
        let s = rows[i].amax();
        if s == 0.0 {
            // An equation without unknowns: the known state must satisfy it on its own.
            if rhs[i].abs() > 1e-9 * size.max(1e-300) {
                return Err(Reduced3::Inconsistent);
            }
            without_unknowns = true;
            continue;
        }
        a.set_row(i, &(rows[i] / s));
        scale[i] = s;
    }
    if without_unknowns {
        return Err(Reduced3::Singular);
    }
    // Rows have unit max-norm, so |det| is at most 6; below 1e-11 the system is singular.
    let det = a.determinant().abs();
    if det.is_nan() || det < 1e-11 {
        return Ok(None);
    }
    Ok(a.try_inverse().map(|inv| (inv, scale)))
}

/// The states along the coefficient e, for fixed mu, em, mode and friction sign:
/// `x = x0 + t x1`, `X = X0 + t X1`, with `t = e` when the contact state is known and
/// `t = 1 + 1/e` when the separation state is known (then the states are affine in t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Line {
    pub x0: Vector6<f64>,
    pub x1: Vector6<f64>,
    pub xf0: Vector6<f64>,
    pub xf1: Vector6<f64>,
}

impl Line {
    /// The parameter t of a restitution coefficient e (`forward`: t = e; else 1 + 1/e).
    pub fn t_of_e(e: f64, forward: bool) -> f64 {
        if forward {
            e
        } else {
            1.0 + 1.0 / e
        }
    }

    /// The restitution coefficient of a parameter t.
    pub fn e_of_t(t: f64, forward: bool) -> f64 {
        if forward {
            t
        } else {
            1.0 / (t - 1.0)
        }
    }
}

impl Determined {
    /// The states along e at fixed `(mu, em)`, mode and friction sign; `Err` with the reason
    /// when no e gives a regular system (then no e gives a solution: the caller must only ask
    /// when [`Determined::profiles`] is true).
    pub fn line(&self, mu: f64, em: f64, mode: Mode, sign: f64) -> Result<Line, Reduced3> {
        let tangential = match mode {
            Mode::Sliding => (self.p.fa + self.p.fb * (mu * sign), 0.0),
            Mode::Sticking if self.forward => (self.p.tr, -self.kt),
            Mode::Sticking => (RowVector3::zeros(), self.kt),
        };
        // rhs = r0 + t r1.
        let (rows, r0, r1) = if self.forward {
            (
                [
                    self.p.nr,
                    tangential.0,
                    self.p.wr * (1.0 - em) - self.p.br * em,
                ],
                [-self.kn, tangential.1, -(1.0 - em) * self.kw],
                [-self.kn, 0.0, 0.0],
            )
        } else {
            (
                [self.p.nr, tangential.0, self.p.br * em],
                [0.0, tangential.1, (1.0 - em) * self.kw],
                [self.kn, 0.0, 0.0],
            )
        };
        let (inv, scale) = match inverse(&rows, &r0, self.known.amax()) {
            Ok(Some(v)) => v,
            Ok(None) => return Err(Reduced3::Singular),
            Err(r) => return Err(r),
        };
        let scaled = |r: [f64; 3]| Vector3::new(r[0] / scale[0], r[1] / scale[1], r[2] / scale[2]);
        let d0 = self.p.n * (inv * scaled(r0));
        let d1 = self.p.n * (inv * scaled(r1));
        let z = Vector6::zeros();
        Ok(if self.forward {
            Line {
                x0: self.known,
                x1: z,
                xf0: self.known + d0,
                xf1: d1,
            }
        } else {
            Line {
                x0: self.known - d0,
                x1: -d1,
                xf0: self.known,
                xf1: z,
            }
        })
    }

    /// True when e can be profiled out exactly: always when the contact state is known; when
    /// the separation state is known, only when no equation loses its unknowns at a point of
    /// the box (Vn, Vt and the final relative yaw rate all nonzero), since there the contact
    /// state would be a family rather than a point.
    pub fn profiles(&self) -> bool {
        let tiny = 1e-9 * self.known.amax().max(1e-300);
        self.forward || (self.kn.abs() > tiny && self.kt.abs() > tiny && self.kw.abs() > tiny)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use pim_core::equations::{assemble, LinearSystem};
    use pim_core::{Coefficients, SolveOptions, TangentialCondition};

    fn impact() -> Impact {
        let v = |mass, yaw_inertia, heading, d, phi| pim_core::Vehicle {
            mass,
            yaw_inertia,
            heading,
            d,
            phi,
        };
        Impact::new(pim_core::Collision {
            vehicle1: v(1500.0, 2500.0, 10.0, 1.9, 20.0),
            vehicle2: v(1200.0, 1900.0, 95.0, 1.2, -160.0),
            crush_angle: 15.0,
        })
        .expect("valid impact")
    }

    /// Every combination of moment form, mode, coefficients and friction sign, with the six
    /// assembled equations.
    fn cases(mut check: impl FnMut(MomentForm, Mode, [f64; 3], f64, LinearSystem)) {
        let imp = impact();
        for form in [MomentForm::Corrected, MomentForm::Brach1983] {
            for (mode, tc) in [
                (Mode::Sliding, TangentialCondition::Sliding),
                (Mode::Sticking, TangentialCondition::NoSlip),
            ] {
                for (e, mu, em) in [(0.1, 0.4, -0.5), (0.0, 0.9, 0.3), (0.2, -0.1, 1.0)] {
                    for sign in [1.0, -1.0] {
                        let opts = SolveOptions {
                            moment_form: form,
                            tangential: tc,
                        };
                        let sys = assemble(&imp, &Coefficients { e, mu, em }, sign, &opts);
                        check(form, mode, [e, mu, em], sign, sys);
                    }
                }
            }
        }
    }

    /// The reduced solve satisfies all six equations, forwards and backwards, in both modes and
    /// both moment forms.
    #[test]
    fn reduced_solve_satisfies_the_six_equations() {
        let x = Vector6::new(14.0, 1.0, 0.3, -2.0, 9.0, -0.2);
        let xf = Vector6::new(7.5, 4.0, -1.1, 5.8, 6.1, 0.9);
        cases(|form, mode, [e, mu, em], sign, sys| {
            for (known, forward) in [(x, true), (xf, false)] {
                let det = Determined::new(&impact(), form, known, forward);
                match det.solve(e, mu, em, mode, sign) {
                    Reduced3::States(a, b) => {
                        let res = sys.f * b + sys.g * a;
                        assert!(res.amax() < 1e-9 * 1e4, "{res}");
                    }
                    other => {
                        // Backwards with e = 0 or sticking: rows without unknowns.
                        assert!(!forward, "{other:?}");
                        assert!(e == 0.0 || mode == Mode::Sticking, "{other:?}");
                    }
                }
            }
        });
    }

    /// The transfer matrix equals `-F^-1 G` of the six assembled equations.
    #[test]
    fn transfer_matrix_is_the_six_equation_solution() {
        cases(|form, mode, [e, mu, em], sign, sys| {
            let expected = -sys.f.lu().solve(&sys.g).expect("regular F");
            let r = Pieces::new(&impact(), form)
                .transfer(e, mu, em, mode, sign)
                .expect("regular A");
            let diff = (r - expected).amax();
            assert!(diff < 1e-10 * (1.0 + expected.amax()), "{diff}");
        });
    }
}
