//! The inner problem: for fixed coefficients, friction sign and tangential mode, the best U.
//!
//! With `F X + G x = 0` and F regular, `X = R x` with `R = -F^-1 G`, so `U = (x, R x)` and the
//! cost `sum w (a.U - t)^2` is a convex quadratic in the six contact components x. Components held
//! fixed are linear equalities `E x = f`; writing `x = x_p + Z y` with Z a basis of the null space
//! of E leaves an unconstrained problem in y, solved in closed form. The linear inequalities
//! (velocity bounds, approach at C, sliding direction, friction admissibility or the mu bounds of
//! the sticking mode) are checked on that solution; when one is violated the problem is a convex
//! QP, solved by clarabel. The condition "no kinetic energy created", `E(x) = x' Qe x <= 0`, is
//! not convex; when the QP solution violates it, the Lagrangian `cost + lambda E` is minimised
//! for the lambda at which `E = 0`, found by bisection while the Lagrangian stays convex. By
//! weak duality that solution is then optimal for the energy-constrained problem.
//!
//! Two conditions are boundaries of other modes rather than constraints to push against. When
//! the optimum without the friction condition ("mu between 0 and mu_max") violates it, the
//! optimum with it has `Vt = 0` by convexity: a point of the sticking mode, which is searched
//! exactly on its own, so the sliding candidate is dropped as dominated. Likewise, when the optimum
//! without the sliding-direction condition violates it, the optimum with it has `vt = 0` at
//! contact, where the friction sign of equation 5 is undefined; such candidates are not counted
//! (the other friction sign is evaluated on its own).

use crate::determined::{Determined, Line, Pieces, Reduced3};
use crate::problem::{FitProblem, FitSettings, Knowledge, Vector12};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector, Matrix6, RowVector6, SMatrix, Vector6};
use pim_core::equations::{assemble, normal_velocity_row, tangential_velocity_row, LinearSystem};
use pim_core::{Coefficients, Impact, MomentForm, SolveOptions, TangentialCondition};

/// Tangential mode of a candidate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub(crate) enum Mode {
    /// Equation 5 with mu strictly inside [0, mu_max] (the boundary belongs to Sticking).
    Sliding,
    /// Equation 5a: mu = mu_max.
    Sticking,
}

/// Coefficients of a candidate (mu is ignored in the sticking mode).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Theta {
    pub e: f64,
    pub mu: f64,
    pub em: f64,
}

/// Why a candidate is not admissible.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) enum Violation {
    /// A velocity component exceeds its bound (index into U).
    Bound(usize),
    /// The vehicles do not approach at C at contact.
    NotApproaching,
    /// The contact state slides the other way than the friction sign assumes.
    SlidingDirection,
    /// mu is not between 0 and mu_max (the tangential impulse reverses the sliding).
    Friction,
    /// Sticking needs a friction ratio outside the mu bounds.
    MuBound,
    /// The solution creates kinetic energy.
    Energy,
    /// The equations are singular for these coefficients.
    Singular,
    /// The constraints together admit no solution (found by the QP).
    Infeasible,
    /// The energy-constrained problem could not be solved exactly (lambda left the convex range).
    EnergyUncertified,
    /// The known components contradict an equation that does not involve the unknown ones
    /// (for example sticking needs Vt = 0 of fixed separation velocities).
    Inconsistent,
}

/// A solved candidate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Candidate {
    pub cost: f64,
    pub x: Vector6<f64>,
    pub xf: Vector6<f64>,
    /// Friction ratio in the convention of equation 5 (mu itself, or mu_max when sticking).
    pub mu_eff: f64,
    /// True when the QP solver was needed.
    pub qp: bool,
    /// Lagrange multiplier of the energy constraint (0 when inactive).
    pub lambda: f64,
    /// The cost is flat along some direction of x at these coefficients: the data leave part
    /// of the velocities undetermined (x is then the smallest-norm choice).
    pub flat: bool,
}

/// Outcome of an evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Eval {
    Feasible(Candidate),
    /// Only from a relaxed evaluation: the equality-only optimum `lower_bound` violates a
    /// constraint; the exact value is at least that.
    Pending {
        lower_bound: f64,
        violation: Violation,
    },
    Infeasible(Violation),
}

/// Everything about a problem that does not depend on the coefficients.
pub(crate) struct Prepared {
    pub impact: Impact,
    pub form: MomentForm,
    /// Objective over U: `U' hu U - 2 gu' U + c0`.
    hu: SMatrix<f64, 12, 12>,
    gu: Vector12,
    c0: f64,
    /// Fixed components (index into U, value).
    pub fixed: Vec<(usize, f64)>,
    vb: f64,
    wb: f64,
    mu_bounds: [f64; 2],
    side: f64,
    nrow: RowVector6<f64>,
    trow: RowVector6<f64>,
    mass: Vector6<f64>,
    /// Friction sign when the contact state is fully known.
    pub known_sign: Option<f64>,
    /// Scale of velocities, for tolerances.
    scale: f64,
    fixed_kind: Fixed,
    /// The coefficient-independent pieces of the three-unknown reduction.
    pieces: Pieces,
    /// When the objective couples no two components (no observations): the square roots of
    /// the separation-state weights.
    hu_split: Option<Vector6<f64>>,
    /// The reduced three-unknown solve, when one whole state is known (Q1, Q2).
    determined: Option<Determined>,
    /// The objective over the unknown state of a determined problem: `u' h u - 2 g' u + c`.
    det_cost: (Matrix6<f64>, Vector6<f64>, f64),
}

/// Per-coefficient data: R, the objective in x and the null-space form of the fixed components.
struct Reduced {
    r: Matrix6<f64>,
    h: Matrix6<f64>,
    g: Vector6<f64>,
    /// `x = xp + Z y` spans the x that satisfy the fixed components.
    xp: Vector6<f64>,
    z: DMatrix<f64>,
}

impl Reduced {
    /// The reduced Hessian and gradient: `y' hy y - 2 gy' y + const`.
    fn reduced(&self) -> (DMatrix<f64>, DVector<f64>) {
        let hd = DMatrix::from_iterator(6, 6, self.h.iter().copied());
        let hy = self.z.transpose() * &hd * &self.z;
        let gy = self.z.transpose() * to_d(&(self.g - self.h * self.xp));
        (hy, gy)
    }
}

/// Where a profile line lies: the e range, mu and em, the tangential mode and the friction sign.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct LineAt {
    pub e_range: [f64; 2],
    pub mu: f64,
    pub em: f64,
    pub mode: Mode,
    pub sign: f64,
}

/// A profile line: states along t, the admissible pieces of t and the cost along t
/// (`cost[0] t^2 + cost[1] t + cost[2]`).
struct ProfileLine<'a> {
    det: &'a Determined,
    line: Line,
    pieces: [Option<(f64, f64)>; 2],
    cost: [f64; 3],
}

/// Result of [`Prepared::quick_check`].
struct Quick {
    /// First violated linear condition other than friction.
    linear: Option<Violation>,
    /// Friction condition violated (sliding mode).
    friction: bool,
    /// Kinetic energy created.
    energy: bool,
    /// The sliding direction is the only violated linear condition.
    only_direction: bool,
}

/// How the fixed components constrain x.
enum Fixed {
    /// Nothing fixed.
    None,
    /// Only contact components fixed: (indices, values) and the free indices.
    Initial(Vec<(usize, f64)>, Vec<usize>),
    /// All six separation components fixed.
    AllFinal(Vector6<f64>),
    /// Anything else.
    General,
}

impl Prepared {
    pub fn new(problem: &FitProblem, settings: &FitSettings) -> Self {
        let impact = problem.impact;
        let mut hu = SMatrix::<f64, 12, 12>::zeros();
        let mut gu = Vector12::zeros();
        let mut c0 = 0.0;
        let mut fixed = Vec::new();
        let mut scale: f64 = 1.0;
        for (k, c) in problem.components.iter().enumerate() {
            match *c {
                Knowledge::Known { value } => {
                    fixed.push((k, value));
                    scale = scale.max(value.abs());
                }
                Knowledge::Estimated { value, weight } => {
                    hu[(k, k)] += weight;
                    gu[k] += weight * value;
                    c0 += weight * value * value;
                    scale = scale.max(value.abs());
                }
                Knowledge::Unknown => {}
            }
        }
        for o in &problem.observations {
            let a = o.row(&impact);
            hu += a * a.transpose() * o.weight;
            gu += a * (o.weight * o.value);
            c0 += o.weight * o.value * o.value;
            scale = scale.max(o.value.abs());
        }
        let [m1, m2] = impact.masses();
        let [i1, i2] = impact.inertias();
        let known_sign = if fixed.iter().filter(|(k, _)| *k < 6).count() == 6 {
            let mut x = Vector6::zeros();
            for &(k, v) in &fixed {
                x[k] = v;
            }
            Some(impact.friction_sign(&pim_core::Velocities::from_vector(&x)))
        } else {
            None
        };
        let fixed_kind = classify(&fixed);
        let determined = match &fixed_kind {
            Fixed::Initial(known, free) if free.is_empty() => {
                let mut x = Vector6::zeros();
                for &(k, v) in known {
                    x[k] = v;
                }
                Some(Determined::new(&impact, settings.moment_form, x, true))
            }
            Fixed::AllFinal(xf) => Some(Determined::new(&impact, settings.moment_form, *xf, false)),
            _ => None,
        };
        let det_cost = match &determined {
            Some(d) => {
                // U = (k, u) or (u, k): the quadratic restricted to the unknown half.
                let (ku, uu) = if d.forward() { (0, 6) } else { (6, 0) };
                let k = d.known();
                let h = hu.fixed_view::<6, 6>(uu, uu).into_owned();
                let hk = hu.fixed_view::<6, 6>(uu, ku) * k;
                let g = gu.fixed_rows::<6>(uu) - hk;
                let c = c0 + (k.transpose() * hu.fixed_view::<6, 6>(ku, ku) * k)[0]
                    - 2.0 * gu.fixed_rows::<6>(ku).dot(k);
                (h, g, c)
            }
            None => (Matrix6::zeros(), Vector6::zeros(), 0.0),
        };
        let diagonal = (0..12).all(|i| (0..12).all(|j| i == j || hu[(i, j)] == 0.0));
        let hu_split =
            diagonal.then(|| Vector6::from_iterator((6..12).map(|k| hu[(k, k)].max(0.0).sqrt())));
        Prepared {
            pieces: Pieces::new(&impact, settings.moment_form),
            hu_split,
            determined,
            det_cost,
            impact,
            form: settings.moment_form,
            hu,
            gu,
            c0,
            vb: settings.velocity_bound,
            wb: settings.yaw_rate_bound,
            mu_bounds: settings.mu,
            side: if impact.side() == 0.0 {
                1.0
            } else {
                impact.side()
            },
            nrow: normal_velocity_row(&impact),
            trow: tangential_velocity_row(&impact),
            mass: Vector6::new(m1, m1, i1, m2, m2, i2),
            known_sign,
            scale,
            fixed_kind,
            fixed,
        }
    }

    /// Sum of weight x target^2 over the data.
    pub fn data_scale(&self) -> f64 {
        self.c0
    }

    /// The friction signs to try.
    pub fn signs(&self) -> &'static [f64] {
        match self.known_sign {
            Some(s) if s > 0.0 => &[1.0],
            Some(_) => &[-1.0],
            None => &[1.0, -1.0],
        }
    }

    /// The six equations `F X + G x = 0` of a candidate.
    fn system(&self, theta: &Theta, mode: Mode, sign: f64) -> LinearSystem {
        let opts = SolveOptions {
            moment_form: self.form,
            tangential: match mode {
                Mode::Sliding => TangentialCondition::Sliding,
                Mode::Sticking => TangentialCondition::NoSlip,
            },
        };
        let coef = Coefficients {
            e: theta.e,
            mu: theta.mu,
            em: theta.em,
        };
        assemble(&self.impact, &coef, sign, &opts)
    }

    fn reduce(&self, theta: &Theta, mode: Mode, sign: f64) -> Option<Reduced> {
        let r = self
            .pieces
            .transfer(theta.e, theta.mu, theta.em, mode, sign)?;
        // Objective in x: T = [I; R].
        let a = self.hu.fixed_view::<6, 6>(0, 0);
        let h = match &self.hu_split {
            // Weights on separate components only: R' C R = (S R)' (S R), S = sqrt(C).
            Some(sqrt_c) => {
                let sr = Matrix6::from_diagonal(sqrt_c) * r;
                a + sr.transpose() * sr
            }
            None => {
                let b = self.hu.fixed_view::<6, 6>(0, 6);
                let c = self.hu.fixed_view::<6, 6>(6, 6);
                let br = b * r;
                a + br + br.transpose() + r.transpose() * c * r
            }
        };
        let g = self.gu.fixed_rows::<6>(0) + r.transpose() * self.gu.fixed_rows::<6>(6);
        let (xp, z) = match &self.fixed_kind {
            Fixed::None => (Vector6::zeros(), DMatrix::identity(6, 6)),
            Fixed::Initial(known, free) => {
                let mut xp = Vector6::zeros();
                for &(k, v) in known {
                    xp[k] = v;
                }
                let mut z = DMatrix::zeros(6, free.len());
                for (c, &k) in free.iter().enumerate() {
                    z[(k, c)] = 1.0;
                }
                (xp, z)
            }
            Fixed::AllFinal(xf) => {
                // R x = X: solve G x = -F X on the row-equilibrated system. G is singular when
                // a row has no contact terms (no slip, e = 0, em = 0): then x is a family, found
                // by the general path (or none, when X does not satisfy that row).
                let sys = self.system(theta, mode, sign);
                let (mut f, mut gm) = (sys.f, sys.g);
                for i in 0..6 {
                    let s = f.row(i).amax();
                    if s == 0.0 {
                        return None;
                    }
                    f.row_mut(i).scale_mut(1.0 / s);
                    gm.row_mut(i).scale_mut(1.0 / s);
                }
                match gm.lu().solve(&-(f * xf)) {
                    Some(x) if (r * x - xf).amax() <= 1e-8 * (1.0 + xf.amax()) => {
                        (x, DMatrix::zeros(6, 0))
                    }
                    _ => general_null_space(&self.fixed, &r)?,
                }
            }
            Fixed::General => general_null_space(&self.fixed, &r)?,
        };
        Some(Reduced { r, h, g, xp, z })
    }

    /// Linear inequalities `rows x <= rhs` for a candidate.
    fn inequalities(
        &self,
        red: &Reduced,
        theta: &Theta,
        mode: Mode,
        sign: f64,
    ) -> Vec<(RowVector6<f64>, f64, Violation)> {
        let mut out = Vec::with_capacity(30);
        for k in 0..12 {
            let row: RowVector6<f64> = if k < 6 {
                let mut rr = RowVector6::zeros();
                rr[k] = 1.0;
                rr
            } else {
                red.r.row(k - 6).into_owned()
            };
            let bound = if k % 3 == 2 { self.wb } else { self.vb };
            out.push((row, bound, Violation::Bound(k)));
            out.push((-row, bound, Violation::Bound(k)));
        }
        // Approach: side * vn < 0, with at least 1 mm/s of closing speed.
        out.push((self.nrow * self.side, -1e-3, Violation::NotApproaching));
        // Sliding direction: sgn(vt) = sign * sgn(vn) = -sign * side.
        let sigma = -sign * self.side;
        out.push((-self.trow * sigma, 0.0, Violation::SlidingDirection));
        match mode {
            Mode::Sliding => {
                if theta.mu != 0.0 {
                    let vt_final = self.trow * red.r;
                    out.push((
                        -vt_final * (theta.mu.signum() * sigma),
                        0.0,
                        Violation::Friction,
                    ));
                }
            }
            Mode::Sticking => {
                let (pn, pt) = self.impulse_rows(&red.r);
                let spn = pn * self.side; // |Pn|
                let spt = pt * (sign * self.side);
                let [lo, hi] = self.mu_bounds;
                out.push((spn * lo - spt, 0.0, Violation::MuBound));
                out.push((spt - spn * hi, 0.0, Violation::MuBound));
            }
        }
        out
    }

    /// Normal and tangential impulse on vehicle 1 as rows over x.
    fn impulse_rows(&self, r: &Matrix6<f64>) -> (RowVector6<f64>, RowVector6<f64>) {
        let m1 = self.mass[0];
        let mut px = r.row(0).into_owned();
        px[0] -= 1.0;
        let mut py = r.row(1).into_owned();
        py[1] -= 1.0;
        let [nx, ny] = self.impact.normal();
        let [tx, ty] = self.impact.tangent();
        ((px * nx + py * ny) * m1, (px * tx + py * ty) * m1)
    }

    fn energy_matrix(&self, r: &Matrix6<f64>) -> Matrix6<f64> {
        let m = Matrix6::from_diagonal(&self.mass);
        (r.transpose() * m * r - m) * 0.5
    }

    fn cost(&self, red: &Reduced, x: &Vector6<f64>) -> f64 {
        ((x.transpose() * red.h * x)[0] - 2.0 * red.g.dot(x) + self.c0).max(0.0)
    }

    fn creates_energy(&self, qe: &Matrix6<f64>, x: &Vector6<f64>) -> bool {
        let t0 = 0.5 * x.component_mul(x).dot(&self.mass);
        (x.transpose() * qe * x)[0] > 1e-9 * t0.max(1.0)
    }

    /// Evaluates a candidate. `exact = false` stops at the equality-only optimum and returns
    /// [`Eval::Pending`] with its cost, a lower bound of the exact value, when a constraint is
    /// violated.
    ///
    /// Sliding mode: when the optimum without the friction condition violates it, the optimum
    /// with it has `Vt = 0` (convexity), a point of the sticking mode, which is searched
    /// exactly on its own; the sliding candidate is then dropped as dominated.
    ///
    /// `cutoff`: an exact solve is skipped (returning [`Eval::Pending`]) when the lower bound is
    /// already at least this value (the incumbent of the search).
    pub fn evaluate(&self, theta: &Theta, mode: Mode, sign: f64, exact: bool, cutoff: f64) -> Eval {
        if let Some(eval) = self.evaluate_determined(theta, mode, sign) {
            return eval;
        }
        let Some(red) = self.reduce(theta, mode, sign) else {
            return Eval::Infeasible(Violation::Singular);
        };
        let k = red.z.ncols();
        let (x, flat) = match self.equality_optimum(&red) {
            Some(v) => v,
            None => return Eval::Infeasible(Violation::Singular),
        };
        let quick = self.quick_check(&(red.r * x), theta, mode, sign, &x);
        let make = |x: Vector6<f64>, qp: bool, lambda: f64| Candidate {
            cost: self.cost(&red, &x),
            x,
            xf: red.r * x,
            mu_eff: match mode {
                Mode::Sliding => theta.mu,
                Mode::Sticking => self.sticking_ratio(&red.r, &x, sign),
            },
            qp,
            lambda,
            flat,
        };
        let (linear, friction, energy) = (quick.linear, quick.friction, quick.energy);
        match (linear, friction, energy) {
            (None, false, false) => return Eval::Feasible(make(x, false, 0.0)),
            (None, true, _) => return Eval::Infeasible(Violation::Friction),
            // Only the sliding direction fails: the optimum would have vt = 0 at contact, where
            // the friction sign assumed by equation 5 is undefined (see `direction_active`).
            (Some(Violation::SlidingDirection), _, _) if quick.only_direction => {
                return Eval::Infeasible(Violation::SlidingDirection)
            }
            _ => {}
        }
        let first = linear.unwrap_or(if friction {
            Violation::Friction
        } else {
            Violation::Energy
        });
        if k == 0 {
            return Eval::Infeasible(first);
        }
        let lower_bound = self.cost(&red, &x);
        if !exact || lower_bound >= cutoff {
            return Eval::Pending {
                lower_bound,
                violation: first,
            };
        }
        let ineq = self.inequalities(&red, theta, mode, sign);
        let qe = self.energy_matrix(&red.r);
        let (hy, gy) = red.reduced();
        let zq = red.z.transpose() * DMatrix::from_iterator(6, 6, qe.iter().copied()) * &red.z;
        let lq = red.z.transpose() * to_d(&(qe * red.xp));
        let rows: Vec<(DVector<f64>, f64)> = ineq
            .iter()
            .filter(|(_, _, v)| *v != Violation::Friction)
            .map(|(row, rhs, _)| {
                (
                    red.z.transpose() * to_d(&row.transpose()),
                    rhs - (row * red.xp)[0],
                )
            })
            .collect();
        // Minimiser of cost + lambda E over the linear constraints (not friction).
        let solve = |lambda: f64| -> Result<Vector6<f64>, Violation> {
            let p = &hy + &zq * lambda;
            let q = &gy - &lq * lambda;
            if let Some(y) = solve_spd(&p, &q) {
                let xl = red.xp + to6(&(&red.z * &y));
                if self.split_violations(&ineq, &xl).0.is_none() {
                    return Ok(xl);
                }
            }
            match qp(&p, &q, &rows) {
                QpOutcome::Solved(y) => Ok(red.xp + to6(&(&red.z * &y))),
                QpOutcome::Infeasible => Err(Violation::Infeasible),
                QpOutcome::Failed => Err(Violation::EnergyUncertified),
            }
        };
        let x0 = match solve(0.0) {
            Ok(x0) => x0,
            Err(Violation::Infeasible) => return Eval::Infeasible(first),
            Err(e) => return Eval::Infeasible(e),
        };
        if mode == Mode::Sliding && self.split_violations(&ineq, &x0).1 {
            return Eval::Infeasible(Violation::Friction);
        }
        if self.direction_active(&ineq, &x0) {
            return Eval::Infeasible(Violation::SlidingDirection);
        }
        let qp_used = linear.is_some();
        if !self.creates_energy(&qe, &x0) {
            return Eval::Feasible(make(x0, qp_used, 0.0));
        }
        // Energy condition active: bisection on lambda while the Lagrangian stays convex. Its
        // minimiser with E = 0 is optimal for the energy-constrained problem (weak duality).
        let energy_of = |x: &Vector6<f64>| (x.transpose() * qe * x)[0];
        let convex = |lambda: f64| (&hy + &zq * lambda).cholesky().is_some();
        let scale = hy.trace().abs() / zq.abs().max().max(1e-300);
        let mut lo = 0.0;
        let mut hi = 1e-6 * scale;
        let mut best = None;
        for _ in 0..60 {
            if !convex(hi) {
                return Eval::Infeasible(Violation::EnergyUncertified);
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
                Err(_) => return Eval::Infeasible(Violation::EnergyUncertified),
            }
        }
        let Some(mut best) = best else {
            return Eval::Infeasible(Violation::EnergyUncertified);
        };
        for _ in 0..40 {
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
        let (lin, fric) = self.split_violations(&ineq, &best);
        if lin.is_some() || (mode == Mode::Sliding && fric) {
            return Eval::Infeasible(Violation::EnergyUncertified);
        }
        Eval::Feasible(make(best, true, hi))
    }

    /// True when the contact state has vt = 0 (the sliding-direction constraint is active):
    /// such a candidate is not counted, since equation 5's friction sign is then undefined; the
    /// other sign is evaluated on its own.
    fn direction_active(
        &self,
        ineq: &[(RowVector6<f64>, f64, Violation)],
        x: &Vector6<f64>,
    ) -> bool {
        let tol = 1e-7 * self.scale.max(1.0);
        ineq.iter()
            .filter(|(_, _, v)| *v == Violation::SlidingDirection)
            .any(|(row, rhs, _)| ((row * x)[0] - rhs).abs() <= tol)
    }

    /// Every condition checked directly on x and X = R x, without building constraint rows.
    fn quick_check(
        &self,
        xf: &Vector6<f64>,
        theta: &Theta,
        mode: Mode,
        sign: f64,
        x: &Vector6<f64>,
    ) -> Quick {
        let tol = 1e-9 * self.scale.max(1.0);
        let mut linear = None;
        let note = |slot: &mut Option<Violation>, v: Violation, bad: bool| {
            if bad && slot.is_none() {
                *slot = Some(v);
            }
        };
        for k in 0..12 {
            let value = if k < 6 { x[k] } else { xf[k - 6] };
            let bound = if k % 3 == 2 { self.wb } else { self.vb };
            note(
                &mut linear,
                Violation::Bound(k),
                value.abs() > bound + tol * 2.0,
            );
        }
        let vn = (self.nrow * x)[0];
        note(
            &mut linear,
            Violation::NotApproaching,
            self.side * vn > -1e-3 + tol * 2.0,
        );
        let mut others_ok = linear.is_none();
        let sigma = -sign * self.side;
        let vt = (self.trow * x)[0];
        let direction_bad = -sigma * vt > tol * 2.0;
        let mut friction = false;
        match mode {
            Mode::Sliding => {
                if theta.mu != 0.0 {
                    let vt_final = (self.trow * xf)[0];
                    friction = -vt_final * theta.mu.signum() * sigma > 0.0;
                }
            }
            Mode::Sticking => {
                let m1 = self.mass[0];
                let [nx, ny] = self.impact.normal();
                let [tx, ty] = self.impact.tangent();
                let (dx, dy) = (xf[0] - x[0], xf[1] - x[1]);
                let pn = m1 * (dx * nx + dy * ny) * self.side;
                let pt = m1 * (dx * tx + dy * ty) * sign * self.side;
                let [lo, hi] = self.mu_bounds;
                let t = tol * 2.0 * m1;
                let bad = lo * pn - pt > t || pt - hi * pn > t;
                note(&mut linear, Violation::MuBound, bad);
                others_ok &= !bad;
            }
        }
        note(&mut linear, Violation::SlidingDirection, direction_bad);
        let t0 = 0.5 * x.component_mul(x).dot(&self.mass);
        let t1 = 0.5 * xf.component_mul(xf).dot(&self.mass);
        Quick {
            linear,
            friction,
            energy: t1 - t0 > 1e-9 * t0.max(1.0),
            only_direction: direction_bad && others_ok,
        }
    }

    /// Fast path when one whole state is known (Q1, Q2): U follows from one solve of the six
    /// equations, with no freedom left. `None` when the problem is not of that kind or the
    /// system is singular for these coefficients (the general path then decides).
    fn evaluate_determined(&self, theta: &Theta, mode: Mode, sign: f64) -> Option<Eval> {
        let det = self.determined.as_ref()?;
        let (x, xf) = match det.solve(theta.e, theta.mu, theta.em, mode, sign) {
            Reduced3::States(x, xf) => (x, xf),
            Reduced3::Inconsistent => return Some(Eval::Infeasible(Violation::Inconsistent)),
            Reduced3::Singular => return None,
        };
        Some(self.determined_candidate(det, theta, mode, sign, x, xf))
    }

    /// The candidate of a determined problem at solved states: checks, cost and friction ratio.
    fn determined_candidate(
        &self,
        det: &Determined,
        theta: &Theta,
        mode: Mode,
        sign: f64,
        x: Vector6<f64>,
        xf: Vector6<f64>,
    ) -> Eval {
        let quick = self.quick_check(&xf, theta, mode, sign, &x);
        if let Some(v) = quick.linear {
            return Eval::Infeasible(v);
        }
        if quick.friction {
            return Eval::Infeasible(Violation::Friction);
        }
        if quick.energy {
            return Eval::Infeasible(Violation::Energy);
        }
        let u = if det.forward() { &xf } else { &x };
        let (h, g, c) = &self.det_cost;
        let cost = ((u.transpose() * h * u)[0] - 2.0 * g.dot(u) + c).max(0.0);
        let mu_eff = match mode {
            Mode::Sliding => theta.mu,
            Mode::Sticking => {
                let m1 = self.mass[0];
                let [nx, ny] = self.impact.normal();
                let [tx, ty] = self.impact.tangent();
                let (dx, dy) = (xf[0] - x[0], xf[1] - x[1]);
                let pn = m1 * (dx * nx + dy * ny);
                let pt = m1 * (dx * tx + dy * ty);
                if pn == 0.0 {
                    0.0
                } else {
                    pt / pn * sign
                }
            }
        };
        Eval::Feasible(Candidate {
            cost,
            x,
            xf,
            mu_eff,
            qp: false,
            lambda: 0.0,
            flat: false,
        })
    }

    /// True when the search may profile e out (see [`Prepared::evaluate_profile`]).
    pub fn profiles(&self) -> bool {
        self.determined.as_ref().is_some_and(|d| d.profiles())
    }

    /// The line of e at fixed `(mu, em)`, mode and sign, with its admissible pieces of t and the
    /// cost along it; `Err` with the coefficients to report and why no e is admissible.
    fn profile_line(&self, at: &LineAt) -> Result<ProfileLine<'_>, Violation> {
        let LineAt {
            e_range,
            mu,
            em,
            mode,
            sign,
        } = *at;
        let det = self.determined.as_ref().expect("profiled problem");
        let forward = det.forward();
        let line = match det.line(mu, em, mode, sign) {
            Ok(l) => l,
            Err(Reduced3::Inconsistent) => return Err(Violation::Inconsistent),
            Err(_) => return Err(Violation::Singular),
        };
        if !forward && e_range[1] <= 0.0 {
            // e = 0 backwards asks Vn = 0 of the known separation state, which it is not
            // (otherwise e would not be profiled).
            return Err(Violation::Inconsistent);
        }
        // The t interval of the e range (e = 0 is t = infinity backwards).
        let (mut lo, mut hi) = if forward {
            (e_range[0], e_range[1])
        } else {
            let t = |e: f64| {
                if e > 0.0 {
                    Line::t_of_e(e, false)
                } else {
                    f64::INFINITY
                }
            };
            (t(e_range[1]), t(e_range[0]))
        };
        if lo.is_nan() || hi.is_nan() || lo > hi {
            return Err(Violation::Singular);
        }
        // Linear conditions g0 + t g1 <= limit, with half the tolerance of `quick_check` so
        // that the chosen point passes it.
        let tol = 1e-9 * self.scale.max(1.0);
        let mut first: Option<Violation> = None;
        let mut cut = |g0: f64, g1: f64, limit: f64, v: Violation| {
            if g1 > 0.0 {
                hi = hi.min((limit - g0) / g1);
            } else if g1 < 0.0 {
                lo = lo.max((limit - g0) / g1);
            } else if g0 > limit {
                lo = f64::INFINITY;
            }
            if lo > hi && first.is_none() {
                first = Some(v);
            }
        };
        for k in 0..12 {
            let (a, b) = if k < 6 {
                (line.x0[k], line.x1[k])
            } else {
                (line.xf0[k - 6], line.xf1[k - 6])
            };
            let bound = if k % 3 == 2 { self.wb } else { self.vb };
            cut(a, b, bound + tol, Violation::Bound(k));
            cut(-a, -b, bound + tol, Violation::Bound(k));
        }
        let dot = |row: &RowVector6<f64>, v: &Vector6<f64>| (row * v)[0];
        cut(
            self.side * dot(&self.nrow, &line.x0),
            self.side * dot(&self.nrow, &line.x1),
            -1e-3 + tol,
            Violation::NotApproaching,
        );
        let sigma = -sign * self.side;
        cut(
            -sigma * dot(&self.trow, &line.x0),
            -sigma * dot(&self.trow, &line.x1),
            tol,
            Violation::SlidingDirection,
        );
        match mode {
            Mode::Sliding => {
                if mu != 0.0 {
                    let f = -mu.signum() * sigma;
                    cut(
                        f * dot(&self.trow, &line.xf0),
                        f * dot(&self.trow, &line.xf1),
                        -tol,
                        Violation::Friction,
                    );
                }
            }
            Mode::Sticking => {
                let m1 = self.mass[0];
                let [nx, ny] = self.impact.normal();
                let [tx, ty] = self.impact.tangent();
                let imp = |a: &Vector6<f64>, b: &Vector6<f64>| {
                    let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
                    (
                        m1 * (dx * nx + dy * ny) * self.side,
                        m1 * (dx * tx + dy * ty) * sign * self.side,
                    )
                };
                let (pn0, pt0) = imp(&line.xf0, &line.x0);
                let (pn1, pt1) = imp(&line.xf1, &line.x1);
                let [mlo, mhi] = self.mu_bounds;
                let t = tol * m1;
                cut(mlo * pn0 - pt0, mlo * pn1 - pt1, t, Violation::MuBound);
                cut(pt0 - mhi * pn0, pt1 - mhi * pn1, t, Violation::MuBound);
            }
        }
        if lo > hi {
            return Err(first.unwrap_or(Violation::Singular));
        }
        // Energy: T1 - T0 = qa t^2 + qb t + qc <= 0.
        let quad = |a: &Vector6<f64>, b: &Vector6<f64>| {
            let m = &self.mass;
            (
                0.5 * b.component_mul(b).dot(m),
                a.component_mul(b).dot(m),
                0.5 * a.component_mul(a).dot(m),
            )
        };
        let (a1, b1, c1) = quad(&line.xf0, &line.xf1);
        let (a0, b0, c0) = quad(&line.x0, &line.x1);
        let pieces = quadratic_pieces(a1 - a0, b1 - b0, c1 - c0, lo, hi);
        if pieces.iter().all(Option::is_none) {
            return Err(Violation::Energy);
        }
        // Cost along t: ca t^2 + cb t + cc (u is the unknown state).
        let (h, g, c) = &self.det_cost;
        let (u0, u1) = if forward {
            (line.xf0, line.xf1)
        } else {
            (line.x0, line.x1)
        };
        let hu1 = h * u1;
        Ok(ProfileLine {
            det,
            line,
            pieces,
            cost: [
                u1.dot(&hu1),
                2.0 * (u0.dot(&hu1) - g.dot(&u1)),
                (u0.transpose() * h * u0)[0] - 2.0 * g.dot(&u0) + c,
            ],
        })
    }

    /// The best e in `e_range` for fixed `(mu, em)`, mode and friction sign, for a problem with
    /// one whole state known (only when [`Prepared::profiles`]).
    ///
    /// Along e both states are affine in a parameter t (t = e or 1 + 1/e, see [`Line`]), so the
    /// cost is a quadratic in t, every linear condition an interval of t and the energy
    /// condition `T1 - T0 <= 0` a quadratic inequality: the admissible t form at most two
    /// intervals, and the minimum over each is the clamped vertex of the quadratic. The chosen
    /// point then passes exactly the checks of any other evaluation.
    pub fn evaluate_profile(&self, at: &LineAt) -> (Theta, Eval) {
        let fallback = Theta {
            e: at.e_range[0],
            mu: at.mu,
            em: at.em,
        };
        let pl = match self.profile_line(at) {
            Ok(pl) => pl,
            Err(v) => return (fallback, Eval::Infeasible(v)),
        };
        let [ca, cb, _] = pl.cost;
        let value = |t: f64| ca * t * t + cb * t;
        let mut best: Option<(f64, f64)> = None;
        for &(plo, phi) in pl.pieces.iter().flatten() {
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
    fn profile_point(&self, pl: &ProfileLine<'_>, at: &LineAt, t: f64) -> (Theta, Eval) {
        let forward = pl.det.forward();
        let e = Line::e_of_t(t, forward).clamp(at.e_range[0], at.e_range[1]);
        let theta = Theta {
            e,
            mu: at.mu,
            em: at.em,
        };
        let (x, xf) = (pl.line.x0 + pl.line.x1 * t, pl.line.xf0 + pl.line.xf1 * t);
        (
            theta,
            self.determined_candidate(pl.det, &theta, at.mode, at.sign, x, xf),
        )
    }

    /// The admissible points at the ends of the e intervals, at fixed `(mu, em)`, where the cost
    /// is at most `limit` (profiled problems): the extremes of e and of the speeds over the
    /// near-optimal set along that line, exactly.
    pub fn profile_level_ends(&self, at: &LineAt, limit: f64) -> Vec<(Theta, Candidate)> {
        let Ok(pl) = self.profile_line(at) else {
            return Vec::new();
        };
        let [ca, cb, cc] = pl.cost;
        // cost(t) - limit = ca t^2 + cb t + (cc - limit) <= 0, inside each admissible piece.
        let mut out = Vec::new();
        for &(plo, phi) in pl.pieces.iter().flatten() {
            for (a, b) in quadratic_pieces(ca, cb, cc - limit, plo, phi)
                .into_iter()
                .flatten()
            {
                for t in [a, b] {
                    if !t.is_finite() {
                        continue;
                    }
                    if let (theta, Eval::Feasible(c)) = self.profile_point(&pl, at, t) {
                        out.push((theta, c));
                    }
                }
            }
        }
        out
    }

    /// The first violated linear constraint other than friction, and whether friction is violated.
    fn split_violations(
        &self,
        ineq: &[(RowVector6<f64>, f64, Violation)],
        x: &Vector6<f64>,
    ) -> (Option<Violation>, bool) {
        let tol = 1e-9 * self.scale.max(1.0);
        let mut first = None;
        let mut friction = false;
        for (row, rhs, v) in ineq {
            let value = (row * x)[0];
            if *v == Violation::Friction {
                // No tolerance: mu = mu_max belongs to the sticking mode.
                friction |= value > *rhs;
            } else if first.is_none() && value > rhs + tol * (1.0 + row.amax()) {
                first = Some(*v);
            }
        }
        (first, friction)
    }

    /// The optimum subject to the fixed components only, and whether the cost is flat along
    /// some direction there.
    fn equality_optimum(&self, red: &Reduced) -> Option<(Vector6<f64>, bool)> {
        match &self.fixed_kind {
            Fixed::None => match red.h.cholesky() {
                Some(ch)
                    if !nearly_singular(
                        ch.l_dirty().diagonal().iter(),
                        red.h.diagonal().amax(),
                    ) =>
                {
                    Some((ch.solve(&red.g), false))
                }
                _ => {
                    let (hy, gy) = red.reduced();
                    let y = solve_spd(&hy, &gy)?;
                    Some((red.xp + to6(&(&red.z * &y)), true))
                }
            },
            _ if red.z.ncols() == 0 => Some((red.xp, false)),
            _ => {
                let (hy, gy) = red.reduced();
                let flat = hy.clone().cholesky().is_none_or(|ch| {
                    nearly_singular(ch.l_dirty().diagonal().iter(), hy.diagonal().amax())
                });
                let y = solve_spd(&hy, &gy)?;
                Some((red.xp + to6(&(&red.z * &y)), flat))
            }
        }
    }

    /// Velocity components that the data leave undetermined at these coefficients: directions in
    /// which the reduced cost is flat (its Hessian is singular), as names of U's components.
    pub fn undetermined_components(
        &self,
        theta: &Theta,
        mode: Mode,
        sign: f64,
    ) -> Vec<&'static str> {
        let Some(red) = self.reduce(theta, mode, sign) else {
            return Vec::new();
        };
        if red.z.ncols() == 0 {
            return Vec::new();
        }
        let (hy, _) = red.reduced();
        let Some(eig) = hy.clone().try_symmetric_eigen(f64::EPSILON, MAX_ITER) else {
            return Vec::new();
        };
        let emax = eig.eigenvalues.amax().max(1e-300);
        let mut names = Vec::new();
        for i in 0..eig.eigenvalues.len() {
            if eig.eigenvalues[i].abs() > 1e-9 * emax {
                continue;
            }
            let dx = to6(&(&red.z * eig.eigenvectors.column(i)));
            let dxf = red.r * dx;
            let du: Vec<f64> = dx.iter().chain(dxf.iter()).copied().collect();
            let big = du.iter().fold(0.0_f64, |a, b| a.max(b.abs()));
            for (k, v) in du.iter().enumerate() {
                let name = crate::problem::COMPONENT_NAMES[k];
                if v.abs() > 0.05 * big && !names.contains(&name) {
                    names.push(name);
                }
            }
        }
        names
    }

    /// mu_max of a sticking solution: (Pt / Pn) * sign.
    fn sticking_ratio(&self, r: &Matrix6<f64>, x: &Vector6<f64>, sign: f64) -> f64 {
        let (pn, pt) = self.impulse_rows(r);
        let pn = (pn * x)[0];
        let pt = (pt * x)[0];
        if pn == 0.0 {
            0.0
        } else {
            pt / pn * sign
        }
    }

    /// The inequality constraints active at a candidate, in words.
    pub fn active_constraints(
        &self,
        theta: &Theta,
        mode: Mode,
        sign: f64,
        c: &Candidate,
    ) -> Vec<String> {
        let Some(red) = self.reduce(theta, mode, sign) else {
            return Vec::new();
        };
        let tol = 1e-6 * self.scale.max(1.0);
        let mut out = Vec::new();
        for (row, rhs, v) in self.inequalities(&red, theta, mode, sign) {
            if ((row * c.x)[0] - rhs).abs() <= tol * (1.0 + row.amax()) {
                let name = match v {
                    Violation::Bound(k) => {
                        format!("bound on {}", crate::problem::COMPONENT_NAMES[k])
                    }
                    Violation::NotApproaching => "minimum approach speed at C".to_string(),
                    Violation::SlidingDirection => "sliding direction at contact (vt = 0)".into(),
                    Violation::Friction => "mu = mu_max (sliding just stops)".into(),
                    Violation::MuBound => "mu bound".into(),
                    _ => continue,
                };
                if !out.contains(&name) {
                    out.push(name);
                }
            }
        }
        if c.lambda > 0.0 {
            out.push("no kinetic energy created (T1 = T0)".into());
        }
        out
    }
}

fn classify(fixed: &[(usize, f64)]) -> Fixed {
    if fixed.is_empty() {
        Fixed::None
    } else if fixed.iter().all(|(k, _)| *k < 6) {
        let free = (0..6)
            .filter(|k| fixed.iter().all(|(f, _)| f != k))
            .collect();
        Fixed::Initial(fixed.to_vec(), free)
    } else if fixed.len() == 6 && fixed.iter().all(|(k, _)| *k >= 6) {
        let mut xf = Vector6::zeros();
        for &(k, v) in fixed {
            xf[k - 6] = v;
        }
        Fixed::AllFinal(xf)
    } else {
        Fixed::General
    }
}

/// `x = xp + Z y` for the fixed components in general position (SVD of their rows).
fn general_null_space(
    fixed: &[(usize, f64)],
    r: &Matrix6<f64>,
) -> Option<(Vector6<f64>, DMatrix<f64>)> {
    let n_eq = fixed.len();
    let mut e = DMatrix::zeros(n_eq, 6);
    let mut fv = DVector::zeros(n_eq);
    for (i, &(k, v)) in fixed.iter().enumerate() {
        if k < 6 {
            e[(i, k)] = 1.0;
        } else {
            for j in 0..6 {
                e[(i, j)] = r[(k - 6, j)];
            }
        }
        fv[i] = v;
    }
    let svd = e.clone().try_svd(true, true, f64::EPSILON, MAX_ITER)?;
    let smax = svd.singular_values.max().max(1e-300);
    let xp = svd.solve(&fv, 1e-10 * smax).ok()?;
    // Dependent rows must agree: otherwise no x meets the fixed components.
    if (&e * &xp - &fv).amax() > 1e-8 * (1.0 + fv.amax()) {
        return None;
    }
    let eig = (e.transpose() * &e).try_symmetric_eigen(f64::EPSILON, MAX_ITER)?;
    let emax = eig.eigenvalues.amax().max(1e-300);
    let cols: Vec<DVector<f64>> = (0..6)
        .filter(|&i| eig.eigenvalues[i].abs() <= 1e-14 * emax)
        .map(|i| eig.eigenvectors.column(i).into_owned())
        .collect();
    let z = if cols.is_empty() {
        DMatrix::zeros(6, 0)
    } else {
        DMatrix::from_columns(&cols)
    };
    Some((Vector6::from_iterator(xp.iter().copied()), z))
}

fn to6(v: &DVector<f64>) -> Vector6<f64> {
    Vector6::from_iterator(v.iter().copied())
}

fn to_d(v: &Vector6<f64>) -> DVector<f64> {
    DVector::from_iterator(6, v.iter().copied())
}

/// Iteration limit of the SVD and eigen decompositions (the plain nalgebra calls never stop on
/// NaN input).
const MAX_ITER: usize = 500;

/// True when a Cholesky factor's diagonal shows a (numerically) singular matrix.
fn nearly_singular<'a>(diag: impl Iterator<Item = &'a f64>, hmax: f64) -> bool {
    diag.map(|d| d * d).fold(f64::INFINITY, f64::min) <= 1e-10 * hmax.max(1e-300)
}

/// Solves `h y = g` for symmetric positive (semi)definite h: on a singular h, the smallest-norm
/// solution (pseudo-inverse).
fn solve_spd(h: &DMatrix<f64>, g: &DVector<f64>) -> Option<DVector<f64>> {
    if let Some(ch) = h.clone().cholesky() {
        if !nearly_singular(ch.l_dirty().diagonal().iter(), h.diagonal().amax()) {
            return Some(ch.solve(g));
        }
    }
    let svd = h.clone().try_svd(true, true, f64::EPSILON, MAX_ITER)?;
    let smax = svd.singular_values.max().max(1e-300);
    svd.solve(g, 1e-9 * smax).ok()
}

enum QpOutcome {
    Solved(DVector<f64>),
    Infeasible,
    Failed,
}

/// min y' p y - 2 q' y  s.t. rows: a' y <= b, by clarabel (private adaptor).
fn qp(p: &DMatrix<f64>, q: &DVector<f64>, rows: &[(DVector<f64>, f64)]) -> QpOutcome {
    let n = p.nrows();
    if n == 0 {
        return if rows.iter().all(|(_, b)| *b >= -1e-9) {
            QpOutcome::Solved(DVector::zeros(0))
        } else {
            QpOutcome::Infeasible
        };
    }
    // Scale the objective so that clarabel's tolerances are meaningful.
    let s = p.amax().max(1e-300);
    let mut pd: Vec<Vec<f64>> = vec![vec![0.0; n]; n];
    for i in 0..n {
        for j in i..n {
            pd[i][j] = 2.0 * p[(i, j)] / s;
        }
    }
    let pm = CscMatrix::from(&pd);
    let qv: Vec<f64> = q.iter().map(|v| -2.0 * v / s).collect();
    let ad: Vec<Vec<f64>> = rows
        .iter()
        .map(|(a, _)| a.iter().copied().collect())
        .collect();
    let am = CscMatrix::from(&ad);
    let b: Vec<f64> = rows.iter().map(|(_, b)| *b).collect();
    let cones: Vec<SupportedConeT<f64>> = vec![NonnegativeConeT(rows.len())];
    let settings = DefaultSettings {
        verbose: false,
        max_iter: 200,
        ..DefaultSettings::default()
    };
    let Ok(mut solver) = DefaultSolver::new(&pm, &qv, &am, &b, &cones, settings) else {
        return QpOutcome::Failed;
    };
    solver.solve();
    match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            QpOutcome::Solved(DVector::from_vec(solver.solution.x.clone()))
        }
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            QpOutcome::Infeasible
        }
        _ => QpOutcome::Failed,
    }
}

/// The parts of `[lo, hi]` where `a t^2 + b t + c <= 0` (the energy condition, or a cost level),
/// each shrunk by a relative 1e-12 at a root so that round-off cannot put a chosen point outside.
fn quadratic_pieces(a: f64, b: f64, c: f64, lo: f64, hi: f64) -> [Option<(f64, f64)>; 2] {
    let f = |t: f64| a * t * t + b * t + c;
    let inward = |r: f64, up: bool| {
        let d = 1e-12 * (1.0 + r.abs());
        if up {
            r + d
        } else {
            r - d
        }
    };
    let keep = |(p, q): (f64, f64)| {
        (p <= q && (f(p) <= 0.0 || f(q) <= 0.0 || f(0.5 * (p + q)) <= 0.0)).then_some((p, q))
    };
    let size = a.abs().max(b.abs()).max(c.abs());
    if a.abs() <= 1e-14 * size {
        // Linear (or constant).
        if b == 0.0 {
            return [(c <= 0.0).then_some((lo, hi)), None];
        }
        let r = -c / b;
        let piece = if b > 0.0 {
            (lo, hi.min(inward(r, false)))
        } else {
            (lo.max(inward(r, true)), hi)
        };
        return [(piece.0 <= piece.1).then_some(piece), None];
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        // No root: the sign of a everywhere.
        return [(a < 0.0).then_some((lo, hi)), None];
    }
    // Stable roots.
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (mut r1, mut r2) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
    if r1 > r2 {
        std::mem::swap(&mut r1, &mut r2);
    }
    if a > 0.0 {
        [
            keep((lo.max(inward(r1, true)), hi.min(inward(r2, false)))),
            None,
        ]
    } else {
        [
            keep((lo, hi.min(inward(r1, false)))),
            keep((lo.max(inward(r2, true)), hi)),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::problem::CostPreset;
    use pim_core::{Collision, Vehicle, Velocities};

    fn problem(preset: CostPreset) -> FitProblem {
        let v = |mass, yaw_inertia, heading, d, phi| Vehicle {
            mass,
            yaw_inertia,
            heading,
            d,
            phi,
        };
        let impact = Impact::new(Collision {
            vehicle1: v(1500.0, 2500.0, 0.0, 1.6, 10.0),
            vehicle2: v(1200.0, 1900.0, 80.0, 1.3, -150.0),
            crush_angle: 10.0,
        })
        .expect("valid impact");
        // Separation states of the model, disturbed so that no coefficients reproduce them.
        let initial = Velocities::from_vector(&Vector6::new(-12.0, 1.0, 0.2, 0.5, 8.0, -0.1));
        let truth = pim_core::Coefficients {
            e: 0.1,
            mu: 0.3,
            em: -0.5,
        };
        let sep = pim_core::solve_forward(&impact, &truth, &initial, &SolveOptions::default())
            .expect("forward solve")
            .separation
            .to_vector()
            + Vector6::new(0.3, -0.2, 0.1, -0.25, 0.15, -0.05);
        let separation = Velocities::from_vector(&sep);
        FitProblem::from_preset(impact, preset, &initial, &separation, None)
    }

    fn quadratic_roots_ok(a: f64, b: f64, c: f64, lo: f64, hi: f64) {
        let pieces = quadratic_pieces(a, b, c, lo, hi);
        let n = 20_000;
        for i in 0..=n {
            let t = lo + (hi - lo) * i as f64 / n as f64;
            let inside = pieces.iter().flatten().any(|(p, q)| t >= *p && t <= *q);
            let value = a * t * t + b * t + c;
            if inside {
                assert!(value <= 1e-9, "t = {t}: {value} in {pieces:?}");
            } else {
                // Outside the pieces only where the condition fails or within the margin.
                let near = pieces
                    .iter()
                    .flatten()
                    .any(|(p, q)| (t - p).abs() < 1e-9 || (t - q).abs() < 1e-9);
                assert!(value > 0.0 || near, "t = {t}: {value} outside {pieces:?}");
            }
        }
    }

    /// The pieces of a quadratic condition: convex, concave, linear, no root.
    #[test]
    fn quadratic_pieces_are_the_admissible_set() {
        quadratic_roots_ok(1.0, 0.0, -0.25, -1.0, 1.0); // [-0.5, 0.5]
        quadratic_roots_ok(-1.0, 0.0, 0.25, -1.0, 1.0); // two rays
        quadratic_roots_ok(0.0, 2.0, -1.0, -1.0, 1.0); // t <= 0.5
        quadratic_roots_ok(0.0, -2.0, -1.0, -1.0, 1.0); // t >= -0.5
        quadratic_roots_ok(1.0, 0.0, 1.0, -1.0, 1.0); // never
        quadratic_roots_ok(-1.0, 0.0, -1.0, -1.0, 1.0); // always
        assert_eq!(
            quadratic_pieces(-1.0, 0.0, 0.25, -1.0, 1.0)
                .iter()
                .flatten()
                .count(),
            2
        );
        assert!(quadratic_pieces(1.0, 0.0, 1.0, -1.0, 1.0)
            .iter()
            .all(Option::is_none));
    }

    /// With e fixed at 0, separation velocities that still approach at C admit no contact state:
    /// the profile says so instead of reporting a bound.
    #[test]
    fn profile_with_e_zero_backwards_is_inconsistent() {
        let settings = FitSettings {
            e: [0.0, 0.0],
            ..FitSettings::default()
        };
        let prep = Prepared::new(&problem(CostPreset::Q1), &settings);
        for &sign in prep.signs() {
            let at = LineAt {
                e_range: settings.e,
                mu: 0.3,
                em: -0.5,
                mode: Mode::Sliding,
                sign,
            };
            let (_, eval) = prep.evaluate_profile(&at);
            assert_eq!(eval, Eval::Infeasible(Violation::Inconsistent));
        }
    }

    /// The level-set ends along e bracket every point of a dense scan whose cost is within the
    /// limit, and lie within it themselves.
    #[test]
    fn level_ends_bracket_the_near_optimal_e() {
        let settings = FitSettings {
            e: [0.0, 0.4],
            ..FitSettings::default()
        };
        let mut checked = 0;
        for preset in [CostPreset::Q1, CostPreset::Q2] {
            let prep = Prepared::new(&problem(preset), &settings);
            for &sign in prep.signs() {
                for (mu, em) in [(0.2, -0.6), (0.5, -0.2), (0.3, 1.0)] {
                    let at = LineAt {
                        e_range: settings.e,
                        mu,
                        em,
                        mode: Mode::Sliding,
                        sign,
                    };
                    let Eval::Feasible(best) = prep.evaluate_profile(&at).1 else {
                        continue;
                    };
                    let limit = best.cost * 1.05 + 1e-6;
                    let ends = prep.profile_level_ends(&at, limit);
                    assert!(!ends.is_empty());
                    let lo = ends.iter().map(|(t, _)| t.e).fold(f64::INFINITY, f64::min);
                    let hi = ends
                        .iter()
                        .map(|(t, _)| t.e)
                        .fold(f64::NEG_INFINITY, f64::max);
                    for (_, c) in &ends {
                        assert!(c.cost <= limit * (1.0 + 1e-9), "{} > {limit}", c.cost);
                    }
                    for i in 0..=4000 {
                        let e = 0.4 * i as f64 / 4000.0;
                        let th = Theta { e, mu, em };
                        if let Eval::Feasible(c) =
                            prep.evaluate(&th, Mode::Sliding, sign, true, f64::INFINITY)
                        {
                            if c.cost <= limit {
                                assert!(
                                    e >= lo - 1e-4 && e <= hi + 1e-4,
                                    "{e} outside [{lo}, {hi}]"
                                );
                            }
                        }
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked >= 3, "only {checked} lines checked");
    }

    /// For fixed (mu, em), the profiled e is the best e: no point of a dense scan over e with
    /// the plain evaluation is lower, and the scan's best is within its spacing of it.
    #[test]
    fn profile_is_the_minimum_over_e() {
        let settings = FitSettings {
            e: [0.0, 0.4],
            ..FitSettings::default()
        };
        let mut compared = 0;
        for preset in [CostPreset::Q1, CostPreset::Q2] {
            let prep = Prepared::new(&problem(preset), &settings);
            assert!(prep.profiles());
            for mode in [Mode::Sliding, Mode::Sticking] {
                for &sign in prep.signs() {
                    for mu in [0.0, 0.2, 0.5, 0.9] {
                        for em in [-1.0, -0.6, -0.2, 0.0, 1.0] {
                            let at = LineAt {
                                e_range: settings.e,
                                mu,
                                em,
                                mode,
                                sign,
                            };
                            let (theta, eval) = prep.evaluate_profile(&at);
                            let profiled = match eval {
                                Eval::Feasible(c) => Some(c.cost),
                                _ => None,
                            };
                            let mut scan: Option<f64> = None;
                            for i in 0..=4000 {
                                let e = 0.4 * i as f64 / 4000.0;
                                let th = Theta { e, mu, em };
                                if let Eval::Feasible(c) =
                                    prep.evaluate(&th, mode, sign, true, f64::INFINITY)
                                {
                                    scan = Some(scan.map_or(c.cost, |s: f64| s.min(c.cost)));
                                }
                            }
                            match (profiled, scan) {
                                (Some(p), Some(s)) => {
                                    compared += 1;
                                    assert!(p <= s + 1e-9 * (1.0 + s), "{theta:?} {p} > {s}");
                                    assert!(s - p <= 1e-4 * (1.0 + p), "{theta:?} {p} vs {s}");
                                    // The profiled point is an ordinary feasible point.
                                    let again =
                                        prep.evaluate(&theta, mode, sign, true, f64::INFINITY);
                                    assert!(
                                        matches!(again, Eval::Feasible(c) if (c.cost - p).abs() <= 1e-9 * (1.0 + p))
                                    );
                                }
                                (None, Some(s)) => {
                                    panic!("{preset:?} {mode:?} {sign} mu {mu} em {em}: scan finds {s}, profile none")
                                }
                                _ => {}
                            }
                        }
                    }
                }
            }
        }
        assert!(compared >= 30, "only {compared} feasible lines compared");
    }
}
