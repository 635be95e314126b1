//! The six equations reduced to three unknowns.
//!
//! Equations 1-3 (linear and angular momentum) only involve the change `D = X - x` and do not
//! depend on the coefficients, so the changes that satisfy them form a fixed three-dimensional
//! space, `D = N p` with `p = (dV1x, dV1y, dW1)`; N is computed from the momentum rows of
//! [`crate::equations`]. Equations 4, 5 (or 5a) and 6 then become a 3x3 linear system in p.
//! Each of their rows is affine in its own coefficient (e, mu' = mu sgn(vn) sgn(vt), e_m), so
//! the rows are taken from [`crate::equations`] at the coefficient values 0 and 1, once per
//! impact, and combined for any coefficients without assembling the 6x6 system again.
//!
//! With x (or X) known the 3x3 system gives the other state ([`KnownState`]); along e at fixed
//! `(mu, e_m)` both states are affine in a parameter t ([`Line`]). With neither known it gives the
//! transfer matrix of `X = R x` ([`Reduction::transfer`]). The no-slip impulse of a contact state,
//! whose ratio is mu_max, is linear in that state ([`Reduction::critical_rows`]).

use crate::coefficients::{Coefficients, MomentForm, TangentialCondition};
use crate::equations::{
    angular_momentum, friction, impulse_rows, moment_restitution, momentum_x, momentum_y, no_slip,
    restitution, Row,
};
use crate::friction::{CriticalImpulse, FrictionSign};
use crate::model::Impact;
use nalgebra::{
    Matrix2x3, Matrix2x6, Matrix3, Matrix6, RowVector3, RowVector6, SMatrix, Vector3, Vector6,
};

/// Result of a reduced solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reduced {
    /// The contact and separation states.
    States(Vector6<f64>, Vector6<f64>),
    /// An equation has no terms in the unknown state and the known state violates it.
    Inconsistent,
    /// The reduced system is singular (or an equation without unknowns holds): the unknown
    /// state is not fixed by the equations.
    Singular,
}

/// One equation row `F(c) X + G(c) x = 0` whose coefficients are affine in one impact
/// coefficient c, with its pieces over p: `F(c) N = fp[0] + c fp[1]`, `G(c) N = gp[0] + c gp[1]`,
/// and `F(c) + G(c) = s[0] + c s[1]` (what multiplies the known state).
#[derive(Debug, Clone, Copy)]
struct AffineRow {
    fp: [RowVector3<f64>; 2],
    gp: [RowVector3<f64>; 2],
    s: [RowVector6<f64>; 2],
}

impl AffineRow {
    fn of(n: &SMatrix<f64, 6, 3>, row: impl Fn(f64) -> Row) -> Self {
        let (f0, g0) = row(0.0);
        let (f1, g1) = row(1.0);
        let (f1, g1) = (f1 - f0, g1 - g0);
        AffineRow {
            fp: [f0 * n, f1 * n],
            gp: [g0 * n, g1 * n],
            s: [f0 + g0, f1 + g1],
        }
    }

    /// The row over p (forwards: `F N`, backwards: `G N`) at coefficient c.
    fn over_p(&self, c: f64, forward: bool) -> RowVector3<f64> {
        let r = if forward { &self.fp } else { &self.gp };
        r[0] + r[1] * c
    }

    /// `F(c) + G(c)` at coefficient c.
    fn sum(&self, c: f64) -> RowVector6<f64> {
        self.s[0] + self.s[1] * c
    }
}

/// The coefficient-independent pieces of the reduced system of one impact.
#[derive(Debug, Clone)]
pub struct Reduction {
    /// `D = N p`.
    n: SMatrix<f64, 6, 3>,
    /// Equation 4, affine in e.
    restitution: AffineRow,
    /// Equation 5, affine in mu' = mu sign.
    friction: AffineRow,
    /// Equation 5a.
    no_slip: AffineRow,
    /// Equation 6, affine in e_m.
    moment: AffineRow,
    /// The impulse on vehicle 1 `(Pn, Pt)` over p.
    impulse: Matrix2x3<f64>,
}

/// The no-slip impulse on vehicle 1 as a linear function of the contact state:
/// `(Pn, Pt) = (l0 + e l1) x` at restitution e (and the e_m it was built for).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CriticalRows {
    /// The part independent of e.
    pub l0: Matrix2x6<f64>,
    /// The part proportional to e.
    pub l1: Matrix2x6<f64>,
}

impl CriticalRows {
    /// The no-slip impulse of contact state `x` at restitution `e`.
    pub fn at(&self, e: f64, x: &Vector6<f64>) -> CriticalImpulse {
        let p = (self.l0 + self.l1 * e) * x;
        CriticalImpulse {
            normal: p[0],
            tangential: p[1],
        }
    }

    /// `(Pn, Pt)` rows over x at restitution e.
    pub fn rows(&self, e: f64) -> Matrix2x6<f64> {
        self.l0 + self.l1 * e
    }
}

impl Reduction {
    /// The pieces of an impact for a moment form.
    pub fn new(impact: &Impact, form: MomentForm) -> Self {
        // Momentum rows over D = (D_1, D_2) (vehicle 1's, vehicle 2's changes): M1 D_1 + M2 D_2 = 0,
        // so D_2 = -M2^-1 M1 D_1 and N = [I; -M2^-1 M1].
        let momentum = [
            momentum_x(impact),
            momentum_y(impact),
            angular_momentum(impact),
        ];
        let mut m1 = Matrix3::zeros();
        let mut m2 = Matrix3::zeros();
        for (i, (f, _)) in momentum.iter().enumerate() {
            m1.set_row(i, &f.fixed_columns::<3>(0));
            m2.set_row(i, &f.fixed_columns::<3>(3));
        }
        let lower = -m2.try_inverse().expect("positive masses and inertias") * m1;
        let mut n = SMatrix::<f64, 6, 3>::zeros();
        n.fixed_view_mut::<3, 3>(0, 0)
            .copy_from(&Matrix3::identity());
        n.fixed_view_mut::<3, 3>(3, 0).copy_from(&lower);
        let (pn, pt) = impulse_rows(impact);
        let mut impulse = Matrix2x3::zeros();
        impulse.set_row(0, &(pn * n));
        impulse.set_row(1, &(pt * n));
        Reduction {
            restitution: AffineRow::of(&n, |e| restitution(impact, e)),
            friction: AffineRow::of(&n, |m| friction(impact, m, FrictionSign::Positive)),
            no_slip: AffineRow::of(&n, |_| no_slip(impact)),
            moment: AffineRow::of(&n, |em| moment_restitution(impact, em, form)),
            impulse,
            n,
        }
    }

    /// Equations 4, 5 (or 5a) and 6 with their coefficient values.
    fn rows(
        &self,
        c: &Coefficients,
        tangential: TangentialCondition,
        sign: FrictionSign,
    ) -> [(&AffineRow, f64); 3] {
        let t = match tangential {
            TangentialCondition::Sliding => (&self.friction, c.mu * sign.value()),
            TangentialCondition::NoSlip => (&self.no_slip, 0.0),
        };
        [(&self.restitution, c.e), t, (&self.moment, c.em)]
    }

    /// The transfer matrix R of `X = R x` at coefficients c (mu unused under no slip) and
    /// friction sign: `R = I + N A^-1 K`, where `A p = K x` are equations 4, 5 (5a) and 6
    /// written for the change `D = N p`. `None` when A is (numerically) singular.
    pub fn transfer(
        &self,
        c: &Coefficients,
        tangential: TangentialCondition,
        sign: FrictionSign,
    ) -> Option<Matrix6<f64>> {
        let rows = self.rows(c, tangential, sign);
        let a = rows.map(|(r, v)| r.over_p(v, true));
        let (inv, scale) = inverse(&a, &[0.0; 3], 1.0).ok()??;
        let mut ks = SMatrix::<f64, 3, 6>::zeros();
        for (i, (r, v)) in rows.iter().enumerate() {
            ks.set_row(i, &(-r.sum(*v) / scale[i]));
        }
        Some(Matrix6::identity() + self.n * (inv * ks))
    }

    /// The no-slip impulse on vehicle 1 as a linear function of the contact state, for moment
    /// restitution em: its ratio is mu_max ([`CriticalImpulse::mu_max`]). `None` when the
    /// no-slip system is singular for this em.
    pub fn critical_rows(&self, em: f64) -> Option<CriticalRows> {
        // Equation 4's row over p does not depend on e (only its contact-state part does).
        let c = Coefficients {
            e: 0.0,
            mu: 0.0,
            em,
        };
        let rows = self.rows(&c, TangentialCondition::NoSlip, FrictionSign::Positive);
        let a = rows.map(|(r, v)| r.over_p(v, true));
        let (inv, scale) = inverse(&a, &[0.0; 3], 1.0).ok()??;
        let mut k0 = SMatrix::<f64, 3, 6>::zeros();
        let mut k1 = SMatrix::<f64, 3, 6>::zeros();
        for (i, (r, v)) in rows.iter().enumerate() {
            k0.set_row(i, &(-r.sum(*v) / scale[i]));
        }
        k1.set_row(0, &(-self.restitution.s[1] / scale[0]));
        let m = self.impulse * inv;
        Some(CriticalRows {
            l0: m * k0,
            l1: m * k1,
        })
    }
}

/// The pieces of the reduced system of one problem with one whole state known.
#[derive(Debug, Clone)]
pub struct KnownState {
    red: Reduction,
    /// The known state.
    known: Vector6<f64>,
    /// True when the contact state x is known (solve forwards), false when X is.
    forward: bool,
}

impl KnownState {
    /// Pieces for a problem whose contact state (`forward`) or separation state is `known`.
    pub fn new(impact: &Impact, form: MomentForm, known: Vector6<f64>, forward: bool) -> Self {
        KnownState {
            red: Reduction::new(impact, form),
            known,
            forward,
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

    /// The reduction of the impact.
    pub fn reduction(&self) -> &Reduction {
        &self.red
    }

    /// `(F + G) . known` of a row at coefficient c, signed as the right-hand side over p.
    fn rhs(&self, row: &AffineRow, c: f64) -> f64 {
        let v = row.sum(c).dot(&self.known.transpose());
        if self.forward {
            -v
        } else {
            v
        }
    }

    /// The states from a solution p of the reduced system.
    fn states(&self, p: &Vector3<f64>) -> (Vector6<f64>, Vector6<f64>) {
        let d = self.red.n * p;
        if self.forward {
            (self.known, self.known + d)
        } else {
            (self.known - d, self.known)
        }
    }

    /// Solves for the unknown state at coefficients c (mu unused under no slip) and friction
    /// sign.
    pub fn solve(
        &self,
        c: &Coefficients,
        tangential: TangentialCondition,
        sign: FrictionSign,
    ) -> Reduced {
        let rows = self.red.rows(c, tangential, sign);
        let a = rows.map(|(r, v)| r.over_p(v, self.forward));
        let rhs = rows.map(|(r, v)| self.rhs(r, v));
        let (inv, scale) = match inverse(&a, &rhs, self.known.amax()) {
            Ok(Some(v)) => v,
            Ok(None) => return Reduced::Singular,
            Err(r) => return r,
        };
        let p = inv * Vector3::from_iterator(rhs.iter().zip(&scale).map(|(r, s)| r / s));
        let (x, xf) = self.states(&p);
        Reduced::States(x, xf)
    }

    /// The states along e at fixed `(mu, em)`, tangential condition and friction sign; `Err` with
    /// the reason when no e gives a regular system (then no e gives a solution: the caller must
    /// only ask when [`KnownState::profiles`] is true).
    ///
    /// Forwards, equation 4's row over p does not depend on e and its right-hand side is affine
    /// in e (t = e). Backwards its row over p is e times a fixed row and its right-hand side is
    /// affine in e; divided by e, the right-hand side is affine in t = 1 + 1/e.
    pub fn line(
        &self,
        mu: f64,
        em: f64,
        tangential: TangentialCondition,
        sign: FrictionSign,
    ) -> Result<Line, Reduced> {
        let c = Coefficients { e: 1.0, mu, em };
        let rows = self.red.rows(&c, tangential, sign);
        let mut a = rows.map(|(r, v)| r.over_p(v, self.forward));
        let mut r0 = rows.map(|(r, v)| self.rhs(r, v));
        let mut r1 = [0.0; 3];
        // Equation 4: rhs(e) = q0 + e q1 with q0, q1 the rhs at e = 0 and its slope.
        let rest = &self.red.restitution;
        let q0 = self.rhs(rest, 0.0);
        let q1 = self.rhs(rest, 1.0) - q0;
        if self.forward {
            a[0] = rest.over_p(0.0, true);
            (r0[0], r1[0]) = (q0, q1);
        } else {
            // e gp[1] p = q0 + e q1  =>  gp[1] p = q1 + (t - 1) q0.
            a[0] = rest.gp[1];
            (r0[0], r1[0]) = (q1 - q0, q0);
        }
        let (inv, scale) = match inverse(&a, &r0, self.known.amax()) {
            Ok(Some(v)) => v,
            Ok(None) => return Err(Reduced::Singular),
            Err(r) => return Err(r),
        };
        let scaled = |r: [f64; 3]| Vector3::new(r[0] / scale[0], r[1] / scale[1], r[2] / scale[2]);
        let d0 = self.red.n * (inv * scaled(r0));
        let d1 = self.red.n * (inv * scaled(r1));
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
        self.forward
            || self.singular_faces() == SingularFaces::default() && {
                let tiny = 1e-9 * self.known.amax().max(1e-300);
                self.rhs(&self.red.no_slip, 0.0).abs() > tiny
            }
    }

    /// The coefficient values at which the known separation state satisfies an equation on its
    /// own, so that the contact state there is a family rather than a point: e = 0 when its
    /// normal relative velocity at C is zero, e_m = 0 when its yaw rates are equal (corrected
    /// form). The cost can drop discontinuously onto such a face, so a search must visit it on
    /// its own. Always empty when the contact state is the known one.
    pub fn singular_faces(&self) -> SingularFaces {
        if self.forward {
            return SingularFaces::default();
        }
        let tiny = 1e-9 * self.known.amax().max(1e-300);
        SingularFaces {
            e_zero: self.rhs(&self.red.restitution, 0.0).abs() <= tiny,
            em_zero: self.rhs(&self.red.moment, 0.0).abs() <= tiny,
        }
    }
}

/// Faces of the coefficient box on which a known separation state leaves the contact state
/// undetermined ([`KnownState::singular_faces`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SingularFaces {
    /// e = 0 is such a face.
    pub e_zero: bool,
    /// e_m = 0 is such a face.
    pub em_zero: bool,
}

/// The inverse of the row-equilibrated matrix of `rows` and the row scales. `Err` when a row has
/// no unknowns: [`Reduced::Inconsistent`] when its right-hand side is not zero, else
/// [`Reduced::Singular`]. `Ok(None)` when the matrix is (numerically) singular.
#[allow(clippy::type_complexity)]
fn inverse(
    rows: &[RowVector3<f64>; 3],
    rhs: &[f64; 3],
    size: f64,
) -> Result<Option<(Matrix3<f64>, [f64; 3])>, Reduced> {
    let mut a = Matrix3::zeros();
    let mut scale = [1.0; 3];
    let mut without_unknowns = false;
    for i in 0..3 {
        let s = rows[i].amax();
        if s == 0.0 {
            // An equation without unknowns: the known state must satisfy it on its own.
            if rhs[i].abs() > 1e-9 * size.max(1e-300) {
                return Err(Reduced::Inconsistent);
            }
            without_unknowns = true;
            continue;
        }
        a.set_row(i, &(rows[i] / s));
        scale[i] = s;
    }
    if without_unknowns {
        return Err(Reduced::Singular);
    }
    // Rows have unit max-norm, so |det| is at most 6; below 1e-11 the system is singular.
    let det = a.determinant().abs();
    if det.is_nan() || det < 1e-11 {
        return Ok(None);
    }
    Ok(a.try_inverse().map(|inv| (inv, scale)))
}

/// The states along the coefficient e, for fixed mu, em, tangential condition and friction sign:
/// `x = x0 + t x1`, `X = X0 + t X1`, with `t = e` when the contact state is known and
/// `t = 1 + 1/e` when the separation state is known (then the states are affine in t).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Contact state at t = 0.
    pub x0: Vector6<f64>,
    /// Contact state per unit t.
    pub x1: Vector6<f64>,
    /// Separation state at t = 0.
    pub xf0: Vector6<f64>,
    /// Separation state per unit t.
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

    /// Contact and separation states at t.
    pub fn at(&self, t: f64) -> (Vector6<f64>, Vector6<f64>) {
        (self.x0 + self.x1 * t, self.xf0 + self.xf1 * t)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::equations::{assemble, LinearSystem};
    use crate::SolveOptions;

    fn impact() -> Impact {
        let v = |mass, yaw_inertia, heading, d, phi| crate::Vehicle {
            mass,
            yaw_inertia,
            heading,
            d,
            phi,
        };
        Impact::new(crate::Collision {
            vehicle1: v(1500.0, 2500.0, 10.0, 1.9, 20.0),
            vehicle2: v(1200.0, 1900.0, 95.0, 1.2, -160.0),
            crush_angle: 15.0,
        })
        .expect("valid impact")
    }

    /// Every combination of moment form, mode, coefficients and friction sign, with the six
    /// assembled equations.
    fn cases(
        mut check: impl FnMut(MomentForm, TangentialCondition, [f64; 3], FrictionSign, LinearSystem),
    ) {
        let imp = impact();
        for form in [MomentForm::Corrected, MomentForm::Brach1983] {
            for tc in [TangentialCondition::Sliding, TangentialCondition::NoSlip] {
                for (e, mu, em) in [(0.1, 0.4, -0.5), (0.0, 0.9, 0.3), (0.2, -0.1, 1.0)] {
                    for sign in FrictionSign::BOTH {
                        let opts = SolveOptions {
                            moment_form: form,
                            tangential: tc,
                        };
                        let sys = assemble(&imp, &Coefficients { e, mu, em }, sign, &opts);
                        check(form, tc, [e, mu, em], sign, sys);
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
                let det = KnownState::new(&impact(), form, known, forward);
                match det.solve(&Coefficients { e, mu, em }, mode, sign) {
                    Reduced::States(a, b) => {
                        let res = sys.f * b + sys.g * a;
                        assert!(res.amax() < 1e-9 * 1e4, "{res}");
                    }
                    other => {
                        // Backwards with e = 0 or sticking: rows without unknowns.
                        assert!(!forward, "{other:?}");
                        assert!(e == 0.0 || mode == TangentialCondition::NoSlip, "{other:?}");
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
            let r = Reduction::new(&impact(), form)
                .transfer(&Coefficients { e, mu, em }, mode, sign)
                .expect("regular A");
            let diff = (r - expected).amax();
            assert!(diff < 1e-10 * (1.0 + expected.amax()), "{diff}");
        });
    }

    /// The critical rows give the no-slip impulse of a forward no-slip solve of the six
    /// assembled equations.
    #[test]
    fn critical_rows_are_the_no_slip_impulse() {
        let x = Vector6::new(14.0, 1.0, 0.3, -2.0, 9.0, -0.2);
        let imp = impact();
        for form in [MomentForm::Corrected, MomentForm::Brach1983] {
            let red = Reduction::new(&imp, form);
            for (e, em) in [(0.1, -0.5), (0.0, 0.3), (0.2, 1.0)] {
                let c = Coefficients { e, mu: 0.0, em };
                let opts = SolveOptions {
                    moment_form: form,
                    tangential: TangentialCondition::NoSlip,
                };
                let sys = assemble(&imp, &c, FrictionSign::Positive, &opts);
                let xf = -sys.f.lu().solve(&(sys.g * x)).expect("regular");
                let (pn, pt) = impulse_rows(&imp);
                let want = [(pn * (xf - x))[0], (pt * (xf - x))[0]];
                let got = red.critical_rows(em).expect("regular").at(e, &x);
                assert!((got.normal - want[0]).abs() < 1e-8 * want[0].abs().max(1.0));
                assert!((got.tangential - want[1]).abs() < 1e-8 * want[1].abs().max(1.0));
            }
        }
    }
}
