//! A lower bound of one piece's optimal cost over a box of geometries, by weak duality.
//!
//! The piece is `min cost(U)` subject to `E(p) U = 0` (equations 1-3, and B = 0 in the zero
//! branch), `A(p) U >= b` (its rows), the known components and the velocity bounds
//! `|U_k| <= limit_k`, with the cost `U'HU - 2g'U + c0` (H diagonal, every free component
//! weighted). For any multipliers `lambda >= 0` and `nu`, the Lagrangian's minimum over the
//! free components within their bounds,
//!
//! ```text
//! phi(p) = c0 + lambda'b + sum_known (H_kk U_k^2 - 2 g_k U_k - r_k U_k)
//!          + sum_free min_{|u| <= limit} (H_ff u^2 - (2 g_f + r_f) u),
//!          r(p) = A(p)'lambda + E(p)'nu,
//! ```
//!
//! is below the piece's optimum at p (weak duality). The multipliers are the piece's own at the
//! box's centre (the dual active-set solver's over the null space of the equalities; clarabel
//! where that does not decide, and for a piece empty at the centre its certificate, scaled, or
//! the multipliers of the piece with its rows made elastic), so that phi equals the optimum
//! there. Over the box phi is bounded by the mean-value form `phi(u) >= phi(xi) + grad
//! phi(eta) . (u - xi)`, with `d phi / d p_j = -U(p)' dr/dp_j` (U(p) the Lagrangian's
//! minimiser, within the bounds) and `dp / du` from the box's interval enclosures, expanded at
//! the point xi of the box where each input whose derivative keeps its sign over the box sits
//! at the end that makes its term non-negative (the others at the centre, costing
//! `h_i max |d phi / d u_i|`). Near the optimum over the geometry the derivative is small, so the
//! bound's gap shrinks with the square of the box's size. Every quantity of the bound is
//! evaluated in interval arithmetic; the multipliers need not be exact (any choice gives a
//! valid bound). A piece is proven empty over the whole box when its certificate gives
//! `max over the bounds of r(p).U < lambda'b` at every p of the box.

// Dense linear algebra on index ranges reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

use super::interval::Iv;
use super::poly::{monomials, MonoBox, Poly};
use crate::convex::dual::{self, Outcome, Row, N};
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, SupportedConeT,
    ZeroConeT,
};
use nalgebra::{DMatrix, DVector};

/// The cost `U'HU - 2g'U + c0` with H diagonal, and the components known exactly.
#[derive(Debug)]
pub(crate) struct Cost {
    pub h: [f64; 12],
    pub g: [f64; 12],
    pub c0: f64,
    pub known: [Option<f64>; 12],
    /// The velocity bounds `|U_k| <= limit_k`: the domain of the Lagrangian's minimisation.
    pub limit: [f64; 12],
    /// Interior-point solves run (the proof's budget counts them).
    pub solves: std::sync::atomic::AtomicUsize,
}

/// The box: its centre's geometry, its enclosures and the half-widths of its inputs.
pub(crate) struct Around<'a> {
    /// The centre's geometry and its inputs (physical units).
    pub centre: [f64; 6],
    pub centre_u: &'a [f64],
    /// The geometry at a point of the inputs.
    pub p_at: &'a (dyn Fn(&[f64]) -> Option<[f64; 6]> + Sync),
    pub mono: &'a MonoBox,
    pub dp: &'a [[Iv; 6]],
    pub half: &'a [f64],
}

/// What the centre's solve gave.
enum Duals {
    Optimal(Vec<f64>, Vec<f64>),
    Empty(Vec<f64>, Vec<f64>),
    None,
}

/// A piece's problem at the centre with the equalities eliminated, `U = U0 + Z w`, for the
/// dual active-set solver (the fast path; clarabel decides what it does not).
pub(crate) struct Reduced {
    u0: [f64; 12],
    /// Basis vectors of the null space of the equalities over the free components.
    z: Vec<[f64; 12]>,
    objective: dual::Objective,
    /// The equalities over the free components, for their multipliers.
    eqs: Vec<[f64; 12]>,
}

impl Cost {
    /// The centre's reduction, when the free components leave at most N directions.
    pub fn reduce(&self, eqs: &[Poly], centre: &[f64; 6]) -> Option<Reduced> {
        let m = monomials(centre);
        let free = self.free();
        let eqs_c: Vec<[f64; 12]> = eqs.iter().map(|e| e.at(&m)).collect();
        let (ne, nf) = (eqs_c.len(), free.len());
        let e = DMatrix::from_fn(
            ne.max(nf),
            nf,
            |i, j| if i < ne { eqs_c[i][free[j]] } else { 0.0 },
        );
        let rhs = DVector::from_fn(ne.max(nf), |i, _| {
            if i < ne {
                -(0..12)
                    .filter_map(|k| self.known[k].map(|v| eqs_c[i][k] * v))
                    .sum::<f64>()
            } else {
                0.0
            }
        });
        let svd = e.svd(true, true);
        let vt = svd.v_t.as_ref()?;
        let tol = 1e-10 * svd.singular_values.max().max(1e-300);
        let x = svd.solve(&rhs, tol).ok()?;
        let null: Vec<usize> = (0..nf).filter(|&i| svd.singular_values[i] <= tol).collect();
        if null.is_empty() || null.len() > N {
            return None;
        }
        let mut u0 = [0.0; 12];
        for k in 0..12 {
            if let Some(v) = self.known[k] {
                u0[k] = v;
            }
        }
        for (j, &k) in free.iter().enumerate() {
            u0[k] = x[j];
        }
        let z: Vec<[f64; 12]> = null
            .iter()
            .map(|&r| {
                let mut v = [0.0; 12];
                for (j, &k) in free.iter().enumerate() {
                    v[k] = vt[(r, j)];
                }
                v
            })
            .collect();
        // cost(U0 + Z w) = a'w + w'Gw/2 + const: G = 2 Z'HZ, a = Z'(2 H U0 - 2 g).
        let nw = z.len();
        let mut g = [[0.0; N]; N];
        let mut a = [0.0; N];
        for i in 0..nw {
            for j in 0..nw {
                g[i][j] = (0..12).map(|k| 2.0 * self.h[k] * z[i][k] * z[j][k]).sum();
            }
            a[i] = (0..12)
                .filter(|&k| self.known[k].is_none())
                .map(|k| z[i][k] * (2.0 * self.h[k] * u0[k] - 2.0 * self.g[k]))
                .sum();
        }
        let objective = dual::Objective::new(nw, g, a)?;
        Some(Reduced {
            u0,
            z,
            objective,
            eqs: eqs_c,
        })
    }

    /// The piece's multipliers at the centre by the dual active-set method, when it solves
    /// the piece (`None`: empty, or not decided; clarabel then decides).
    fn fast_duals(&self, red: &Reduced, rows: &[([f64; 12], f64)]) -> Option<(Vec<f64>, Vec<f64>)> {
        let nw = red.z.len();
        let mut over_w = Vec::with_capacity(rows.len());
        let mut index = Vec::with_capacity(rows.len());
        for (i, (r, b)) in rows.iter().enumerate() {
            let mut n = [0.0; N];
            for c in 0..nw {
                n[c] = (0..12).map(|k| red.z[c][k] * r[k]).sum();
            }
            let bw = b - (0..12).map(|k| r[k] * red.u0[k]).sum::<f64>();
            let norm = n.iter().map(|v| v * v).sum::<f64>().sqrt();
            match Row::new(n, bw) {
                Some(row) => {
                    over_w.push(row);
                    index.push((i, norm));
                }
                None if bw <= 1e-12 * (1.0 + b.abs()) => {}
                None => return None,
            }
        }
        let mut mult = Vec::new();
        let Outcome::Solved { z: w, .. } =
            red.objective
                .solve_with_multipliers(&over_w, f64::INFINITY, &mut mult)
        else {
            return None;
        };
        let mut lambda = vec![0.0; rows.len()];
        for &(j, u) in &mult {
            let (i, norm) = index[j];
            lambda[i] = u.max(0.0) / norm;
        }
        // nu from stationarity over the free components: grad cost - A'lambda = E'nu.
        let mut u = red.u0;
        for c in 0..nw {
            for k in 0..12 {
                u[k] += w[c] * red.z[c][k];
            }
        }
        let free = self.free();
        let ne = red.eqs.len();
        let lhs = DMatrix::from_fn(free.len(), ne, |j, i| red.eqs[i][free[j]]);
        let rhs = DVector::from_fn(free.len(), |j, _| {
            let k = free[j];
            2.0 * (self.h[k] * u[k] - self.g[k])
                - rows
                    .iter()
                    .zip(&lambda)
                    .map(|((r, _), l)| l * r[k])
                    .sum::<f64>()
        });
        let nu = lhs.svd(true, true).solve(&rhs, 1e-12).ok()?;
        Some((nu.iter().copied().collect(), lambda))
    }

    fn free(&self) -> Vec<usize> {
        (0..12).filter(|&k| self.known[k].is_none()).collect()
    }

    /// The piece at the centre by clarabel: multipliers of the equalities and the rows. With
    /// `elastic = Some(m)` every row may be violated at the price m per unit (so the piece is
    /// never empty, and its multipliers are the best of the dual's below m).
    fn duals(&self, eqs: &[[f64; 12]], rows: &[([f64; 12], f64)], elastic: Option<f64>) -> Duals {
        let free = self.free();
        let n = free.len();
        let sc = free.iter().map(|&k| self.h[k]).fold(0.0, f64::max);
        if n == 0 || sc <= 0.0 {
            return Duals::None;
        }
        self.solves
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let known = |a: &[f64; 12]| -> f64 {
            (0..12)
                .filter_map(|k| self.known[k].map(|v| a[k] * v))
                .sum()
        };
        // Variables: the free components, then (elastic) one slack per row.
        let m = if elastic.is_some() { rows.len() } else { 0 };
        let nv = n + m;
        let mut p = vec![vec![0.0; nv]; nv];
        for (i, &k) in free.iter().enumerate() {
            p[i][i] = 2.0 * self.h[k] / sc;
        }
        let mut q: Vec<f64> = free.iter().map(|&k| -2.0 * self.g[k] / sc).collect();
        q.extend(std::iter::repeat_n(elastic.unwrap_or(0.0) / sc, m));
        let mut a = Vec::with_capacity(eqs.len() + rows.len() + m + 2 * n);
        let mut b = Vec::with_capacity(eqs.len() + rows.len() + m + 2 * n);
        let wide = |v: Vec<f64>| {
            let mut v = v;
            v.resize(nv, 0.0);
            v
        };
        for e in eqs {
            a.push(wide(free.iter().map(|&k| e[k]).collect()));
            b.push(-known(e));
        }
        for (i, (r, rhs)) in rows.iter().enumerate() {
            let mut row = wide(free.iter().map(|&k| -r[k]).collect());
            if m > 0 {
                row[n + i] = -1.0;
            }
            a.push(row);
            b.push(-rhs + known(r));
        }
        for i in 0..m {
            let mut row = vec![0.0; nv];
            row[n + i] = -1.0;
            a.push(row);
            b.push(0.0);
        }
        // The velocity bounds of the free components (the domain; their multipliers are not
        // needed).
        for (i, &k) in free.iter().enumerate() {
            for sign in [1.0, -1.0] {
                let mut row = vec![0.0; nv];
                row[i] = sign;
                a.push(row);
                b.push(self.limit[k]);
            }
        }
        let cones: Vec<SupportedConeT<f64>> = vec![
            ZeroConeT(eqs.len()),
            NonnegativeConeT(rows.len() + m + 2 * n),
        ];
        let settings = DefaultSettings {
            verbose: false,
            max_iter: 200,
            ..DefaultSettings::default()
        };
        let Ok(mut solver) = DefaultSolver::new(
            &CscMatrix::from(&p),
            &q,
            &CscMatrix::from(&a),
            &b,
            &cones,
            settings,
        ) else {
            return Duals::None;
        };
        solver.solve();
        let z = &solver.solution.z;
        let split = |scale: f64| {
            let nu: Vec<f64> = z[..eqs.len()].iter().map(|v| -v * scale).collect();
            let lambda: Vec<f64> = z[eqs.len()..eqs.len() + rows.len()]
                .iter()
                .map(|v| v.max(0.0) * scale)
                .collect();
            (nu, lambda)
        };
        match solver.solution.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                let (nu, lambda) = split(sc);
                Duals::Optimal(nu, lambda)
            }
            SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
                let (nu, lambda) = split(1.0);
                Duals::Empty(nu, lambda)
            }
            _ => Duals::None,
        }
    }

    /// The unconstrained minimum: the bound of multipliers zero, at every geometry.
    pub fn unconstrained(&self) -> f64 {
        self.phi(&[Iv::point(0.0); 12], 0.0)
    }

    /// A lower bound of `min over |u| <= limit_k of (H_kk u^2 - (2 g_k + r) u)` at a point r.
    fn piece_at(&self, k: usize, r: f64) -> f64 {
        let (h, v) = (self.h[k], self.limit[k]);
        let m = Iv::point(2.0 * self.g[k]) + Iv::point(r);
        let u0 = m.mid() / (2.0 * h);
        let value = if u0 > v * (1.0 + 1e-9) {
            Iv::point(h * v).scale(v) - m.scale(v)
        } else if u0 < -v * (1.0 + 1e-9) {
            Iv::point(h * v).scale(v) + m.scale(v)
        } else {
            -m.sqr().div(Iv::point(4.0 * h))
        };
        value.lo
    }

    /// phi for r (over a point, as intervals) and `lambda'b`: the Lagrangian's minimum over
    /// the velocity bounds, bounded below.
    fn phi(&self, r: &[Iv; 12], lb: f64) -> f64 {
        let mut s = Iv::point(self.c0) + Iv::point(lb);
        for k in 0..12 {
            match self.known[k] {
                Some(v) => {
                    let c = self.h[k] * v * v - 2.0 * self.g[k] * v;
                    s = s + Iv::point(c) - r[k].scale(v);
                }
                // Concave in r: its least value over an interval is at an end.
                None => {
                    let low = self.piece_at(k, r[k].lo).min(self.piece_at(k, r[k].hi));
                    s = s + Iv::new(low, low);
                }
            }
        }
        s.lo
    }

    /// The Lagrangian's minimiser over a box of r: `U_f = clamp((g_f + r_f / 2) / H_ff)`.
    fn minimiser(&self, r: &[Iv; 12]) -> [Iv; 12] {
        std::array::from_fn(|k| match self.known[k] {
            Some(v) => Iv::point(v),
            None => {
                let u = (Iv::point(self.g[k]) + r[k].scale(0.5)).div(Iv::point(self.h[k]));
                let v = self.limit[k];
                Iv::new(u.lo.clamp(-v, v), u.hi.clamp(-v, v))
            }
        })
    }

    /// Whether multipliers `(nu, lambda)` of an empty piece (a certificate) prove it empty over
    /// the whole box: `max over the bounds of r(p).U < lambda'b` at every p of the box, while
    /// every admissible U has `r(p).U >= lambda'b`.
    fn empty_over(
        &self,
        eqs: &[Poly],
        rows: &[(Poly, f64)],
        nu: &[f64],
        lambda: &[f64],
        at: &Around<'_>,
    ) -> bool {
        let (r, lb, size) = combine(eqs, rows, nu, lambda);
        let rb = r.over(at.mono);
        let mut most = Iv::point(0.0);
        for k in 0..12 {
            most = most
                + match self.known[k] {
                    Some(v) => rb[k].scale(v),
                    None => Iv::point(rb[k].mag()).scale(self.limit[k]),
                };
        }
        most.hi < lb - 1e-12 * size
    }

    /// The bound of multipliers `(nu, lambda)` over the box.
    fn bound_of(
        &self,
        eqs: &[Poly],
        rows: &[(Poly, f64)],
        nu: &[f64],
        lambda: &[f64],
        at: &Around<'_>,
    ) -> f64 {
        // lambda'b is a sum of products: bounded below by its value less a relative margin
        // of their magnitudes for its rounding.
        let (r, lb, size) = combine(eqs, rows, nu, lambda);
        let lb_margin = 1e-14 * size;
        // U(p) over the box: U_f = (g_f + r_f / 2) / H_ff, U_k known.
        let u = self.minimiser(&r.over(at.mono));
        let dphi: [Iv; 6] = std::array::from_fn(|j| {
            let dr = r.derivative_over(at.mono, j);
            -(0..12).fold(Iv::point(0.0), |s, k| s + u[k] * dr[k])
        });
        // Expanded at the point of the box where the inputs whose derivative keeps its sign
        // are at their low end (rising) or high end (falling); the others at the centre.
        let mut xi = at.centre_u.to_vec();
        let mut loss = 0.0;
        for (i, dpi) in at.dp.iter().enumerate() {
            let di = (0..6).fold(Iv::point(0.0), |s, j| s + dphi[j] * dpi[j]);
            if at.half[i] == 0.0 {
                continue;
            }
            if di.lo >= 0.0 {
                xi[i] = at.centre_u[i] - at.half[i];
            } else if di.hi <= 0.0 {
                xi[i] = at.centre_u[i] + at.half[i];
            } else {
                loss += at.half[i] * di.mag();
            }
        }
        let Some(p_xi) = (at.p_at)(&xi) else {
            return f64::NEG_INFINITY;
        };
        let point = MonoBox::new(&p_xi.map(Iv::point));
        let phi_xi = self.phi(&r.over(&point), lb) - lb_margin;
        let v = phi_xi - loss * (1.0 + 1e-12);
        if v.is_nan() {
            f64::NEG_INFINITY
        } else {
            v
        }
    }

    /// A lower bound of the piece's optimum over the box (at least the unconstrained minimum),
    /// stopping early once it reaches `target`, and the multipliers that gave it. `hint`: the
    /// multipliers of the same piece over a box that contains this one, tried first.
    pub fn bound(
        &self,
        eqs: &[Poly],
        rows: &[(Poly, f64)],
        at: &Around<'_>,
        target: f64,
        hint: Option<&Multipliers>,
        reduced: Option<&Reduced>,
    ) -> (f64, Option<Multipliers>) {
        let floor = self.unconstrained();
        if let Some(h) = hint.filter(|h| h.lambda.len() == rows.len()) {
            if h.empty {
                if self.empty_over(eqs, rows, &h.nu, &h.lambda, at) {
                    return (f64::INFINITY, Some(h.clone()));
                }
            } else {
                let b = self.bound_of(eqs, rows, &h.nu, &h.lambda, at).max(floor);
                if b >= target {
                    return (b, Some(h.clone()));
                }
            }
        }
        let m = monomials(&at.centre);
        let rows_c: Vec<([f64; 12], f64)> = rows.iter().map(|(r, b)| (r.at(&m), *b)).collect();
        let keep =
            |nu: Vec<f64>, lambda: Vec<f64>, empty: bool| Some(Multipliers { nu, lambda, empty });
        if let Some((nu, lambda)) = reduced.and_then(|r| self.fast_duals(r, &rows_c)) {
            let b = self.bound_of(eqs, rows, &nu, &lambda, at).max(floor);
            return (b, keep(nu, lambda, false));
        }
        let eqs_c: Vec<[f64; 12]> = eqs.iter().map(|e| e.at(&m)).collect();
        match self.duals(&eqs_c, &rows_c, None) {
            Duals::Optimal(nu, lambda) => {
                let b = self.bound_of(eqs, rows, &nu, &lambda, at).max(floor);
                (b, keep(nu, lambda, false))
            }
            Duals::Empty(nu, lambda) => {
                if self.empty_over(eqs, rows, &nu, &lambda, at) {
                    return (f64::INFINITY, keep(nu, lambda, true));
                }
                if target == f64::INFINITY {
                    // Only a proof that the piece is empty closes the box.
                    return (floor, keep(nu, lambda, true));
                }
                // Along the certificate phi rises linearly at the centre while the derivative
                // term grows with the multipliers: the best of a geometric range of scales.
                let mut best = (floor, None);
                let at_centre = Around {
                    half: &vec![0.0; at.half.len()],
                    ..*at
                };
                let rise = self.bound_of(eqs, rows, &nu, &lambda, &at_centre) - floor;
                if rise > 0.0 {
                    let need = (target - floor).max(1e-9 * target.abs().max(1.0));
                    let t0 = need / rise;
                    for j in -10..=6 {
                        let t = t0 * 4f64.powi(j);
                        let scaled = |v: &Vec<f64>| v.iter().map(|x| x * t).collect::<Vec<f64>>();
                        let (n, l) = (scaled(&nu), scaled(&lambda));
                        let b = self.bound_of(eqs, rows, &n, &l, at);
                        if b > best.0 {
                            best = (b, keep(n, l, false));
                        }
                        if best.0 >= target {
                            return best;
                        }
                    }
                }
                // The elastic piece's multipliers (capped at a rising price) bound the cost
                // of the points nearby where the piece is not empty.
                let sc = self.h.iter().copied().fold(0.0, f64::max);
                for j in 0..8 {
                    if let Duals::Optimal(nu, lambda) =
                        self.duals(&eqs_c, &rows_c, Some(sc * 8f64.powi(j)))
                    {
                        let b = self.bound_of(eqs, rows, &nu, &lambda, at);
                        if b > best.0 {
                            best = (b, keep(nu, lambda, false));
                        }
                        if best.0 >= target {
                            break;
                        }
                    }
                }
                best
            }
            Duals::None => (floor, None),
        }
    }
}

/// Multipliers of a piece's rows (and equalities); `empty`: a certificate that the piece has
/// no point.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Multipliers {
    nu: Vec<f64>,
    lambda: Vec<f64>,
    empty: bool,
}

/// `r = E'nu + A'lambda` as a row, `lambda'b`, and `sum |lambda_i b_i|` (the scale of the
/// rounding of `lambda'b`).
fn combine(eqs: &[Poly], rows: &[(Poly, f64)], nu: &[f64], lambda: &[f64]) -> (Poly, f64, f64) {
    let mut r = Poly::zero();
    let (mut lb, mut size) = (0.0, 0.0);
    for (e, &v) in eqs.iter().zip(nu) {
        r.add_in(e, v);
    }
    for ((row, rhs), &l) in rows.iter().zip(lambda) {
        if l != 0.0 {
            r.add_in(row, l);
            lb += l * rhs;
            size += (l * rhs).abs();
        }
    }
    (r, lb, size)
}
