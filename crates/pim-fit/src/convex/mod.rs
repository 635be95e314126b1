//! The fit as a union of convex QPs over the contact state and the impulse.
//!
//! Equations 1-3 (momentum) say that the velocity change `d = X - x` lies in a fixed
//! three-dimensional space (two-dimensional with no moment impulse, the zero branch): `d = D q`.
//! Over `z = (x, q)` every other condition is linear once a few signs are fixed:
//!
//! - restitution: `e = -Vn / vn` within `[e_min, e_max]` with the vehicles approaching
//!   (`side vn < 0`) is `e_min a <= b <= e_max a` for `a = -side vn`, `b = side Vn`;
//! - moment restitution: `e_m = W_f / W_lin`, the final relative yaw rate over the one the linear
//!   impulse alone would leave (`W_lin = W_f + B`, B the change caused by the moment impulse;
//!   equation 6 is `(1 - e_m) W_f = e_m B`), within `[-1, 0]`: for a sign `s_w` of `W_lin`,
//!   `s_w W_lin >= 0` and `W_f` between `e_lo W_lin` and `e_hi W_lin`;
//! - the mu bounds: `mu = s Pt / Pn` (s the friction sign) within `[mu_min, mu_max_bound]` is
//!   linear for a sign `s_n` of Pn;
//! - mu between 0 and mu_max: at fixed x, e and e_m the impulses of all mu lie on a line, on which
//!   Pt and the final tangential velocity Vt are affine, `Vt = k Pt + c`. mu = 0 is the point
//!   `Pt = 0`, mu = mu_max the point `Vt = 0`, and "mu between 0 and mu_max" (when the normal
//!   impulse keeps its sign between them, as it does wherever the ratio is defined on the way)
//!   is the segment between them: `Pt Vt / k <= 0`. The direction of the line depends on e_m
//!   alone, so the sign of k is a property of the geometry on each piece of the e_m interval;
//!   for a sign `s_t` of Pt the condition is `s_t Pt >= 0`, `sgn(k) s_t Vt <= 0`;
//! - velocity bounds, approach speed and the sliding direction of the friction sign are linear
//!   in x and X.
//!
//! With every weight of the cost positive (Q3 and custom costs that weigh each component) the
//! cost is strictly convex in z; with components known exactly (Q1, Q2) it is strictly convex
//! on the affine subspace they leave (every direction the known state leaves free moves the
//! other, estimated, state), over which [`subspace`] solves. Each sign pattern (friction sign,
//! `s_n`, `s_t`, and in the free branch the e_m piece and `s_w`) is a strictly convex QP,
//! solved exactly by a dual active-set method ([`dual`]) whose value only rises, so a pattern
//! stops as soon as it cannot beat the best one found. The minimum over the patterns is the
//! global optimum over the union; each pattern's optimum is checked against the search's own
//! constraint set (pim-core's friction classification and energy test).
//!
//! In the free branch [`bnb`] splits the e_m interval where a pattern's optimum fails the
//! friction ratio (its ratios relaxed over the interval) and closes an interval once its
//! lower bound is within 1e-7 of the best admissible cost (relative): the answer is proven
//! optimal to that gap. Where a pattern's optimum below the best creates energy (whose
//! condition is not convex here), or the normal impulse changes sign on the way to mu_max in
//! the zero branch, or a QP does not verify, or the best point's coefficients do not
//! reproduce its velocities through the forward model (next to a singular point of the six
//! equations), the general search decides instead. Where every pattern is empty the branch
//! is proven infeasible.
//!
//! The tangential model (no moment impulse: the zero branch's variables) has pieces of its own,
//! its sticking and sliding modes with the friction rule on the sticking impulse at some et of
//! the range written over the same variables ([`tangential`]); they are solved, bounded and
//! checked by the same code.

// Dense linear algebra on index ranges reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

pub(crate) mod bnb;
mod candidate;
pub(crate) mod dual;
mod form;
mod modes;
mod subspace;
mod tangential;
mod verdict;

use crate::certificate::Fallback;
use crate::family::Friction;
use crate::inner::{Inner, RowOf, RowU};
use crate::problem::MomentBranch;
use crate::report::Violation;
use crate::settings::FitSettings;
use dual::{Row, N};
use form::{add, scaled, Form};
use nalgebra::{Matrix6, RowVector6, SymmetricEigen};
use pim_core::equations::{
    angular_momentum, impulse_rows, moment_b_row, momentum_x, momentum_y, normal_velocity_row,
    relative_yaw_row, tangential_velocity_row,
};
use pim_core::FrictionSign;
pub(crate) use verdict::{Counts, Verdict};

/// One convex piece of a branch: PIM's signs over an e_m interval, or a contact mode of the
/// tangential model with its signs.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Pattern {
    Pim(Signs),
    Tangential(modes::Mode),
}

/// PIM's sign pattern over an e_m interval.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Signs {
    sign: FrictionSign,
    /// Signs of Pn, Pt, Vt, of the frictionless normal impulse Pn0 and of the no-slip one Pn*.
    s_n: f64,
    s_t: f64,
    s_v: f64,
    s_a: f64,
    s_b: f64,
    /// The ranges of `Pn0 = Pn - rho_a Pt` and `Pn* = Pn - rho_b Vt` over the interval.
    rho_a: [f64; 2],
    rho_b: [f64; 2],
    /// The e_m interval and the sign of W_lin (free branch).
    em: [f64; 2],
    s_w: f64,
}

/// The problem over z for one branch.
struct Formulation {
    /// Number of variables: 6 + the dimension of the velocity-change space.
    n: usize,
    /// Basis of the velocity-change space (columns 0..n-6).
    d: [[f64; 3]; 6],
    objective: subspace::Qp,
    /// The constant of the cost: cost = f + c0.
    c0: f64,
    /// Rows every pattern shares, and the largest of their single-row lower bounds.
    common: Vec<Row>,
    common_bound: f64,
    /// The sliding-direction rows of each friction sign (positive, negative).
    sliding: [Vec<Row>; 2],
    vn: Form,
    /// The tangential relative velocity at C at contact.
    vt: Form,
    big_vn: Form,
    pn: Form,
    pt: Form,
    big_vt: Form,
    w_final: Form,
    w_lin: Form,
    side: f64,
    /// The tangential model's line of impulses (`None` for PIM).
    line: Option<modes::Line>,
}

impl Formulation {
    /// Why not, when the problem is not one this path solves (something held fixed, a weight
    /// missing so that the cost is not strictly convex, a barrier, a degenerate geometry).
    fn new(
        inner: &Inner,
        settings: &FitSettings,
        branch: MomentBranch,
    ) -> Result<Formulation, Fallback> {
        let impact = &inner.impact;
        if impact.is_barrier() {
            return Err(Fallback::Barrier);
        }
        let equivalent = inner.family.friction() == Friction::Equivalent;
        if equivalent && !settings.mu_max_condition {
            return Err(Fallback::NoMuMaxCondition);
        }
        let b_row = moment_b_row(impact);
        let (d, r) = velocity_basis(impact, &b_row, branch)?;
        let n = 6 + r;
        // Forms of x, of X = x + D q, and of rows over x or over d.
        let over_x = |row: &RowVector6<f64>| {
            let mut f = [0.0; N];
            f[..6].copy_from_slice(row.as_slice());
            f
        };
        let over_d = |row: &RowVector6<f64>| {
            let mut f = [0.0; N];
            for c in 0..r {
                f[6 + c] = (0..6).map(|k| row[k] * d[k][c]).sum();
            }
            f
        };
        let over_final = |row: &RowVector6<f64>| add(&over_x(row), &over_d(row), 1.0);
        let (t, g, a, c0) = cost_over_z(inner, &d, r);
        // Components known exactly are equalities over z (x_k, or x_k + (D q)_k).
        let equalities: Vec<([f64; N], f64)> = inner
            .objective
            .fixed
            .iter()
            .map(|&(k, v)| (t[k], v))
            .collect();
        let objective = subspace::Qp::new(n, g, a, &equalities)?;
        // The inner problem's rows `row . U <= rhs` over U = T z (as `-row T z >= -rhs`).
        let over_z = |(row, rhs, _): &RowU| {
            let f = match *row {
                RowOf::Component { k, sign } => scaled(&t[k], -sign),
                RowOf::Contact(row) => scaled(&over_x(&row), -1.0),
            };
            Row::new(f, -rhs).ok_or(Fallback::DegenerateGeometry)
        };
        let mut common = inner
            .linear_rows(None)
            .iter()
            .map(over_z)
            .collect::<Result<Vec<Row>, Fallback>>()?;
        let sliding = |sign: FrictionSign| {
            inner
                .linear_rows(Some(sign))
                .iter()
                .filter(|r| r.2 == Violation::SlidingDirection)
                .map(over_z)
                .collect::<Result<Vec<Row>, Fallback>>()
        };
        let sliding = [
            sliding(FrictionSign::Positive)?,
            sliding(FrictionSign::Negative)?,
        ];
        let side = if impact.side() == 0.0 {
            1.0
        } else {
            impact.side()
        };
        let nrow = normal_velocity_row(impact);
        let trow = tangential_velocity_row(impact);
        let vn = over_x(&nrow);
        let big_vn = over_final(&nrow);
        // Restitution within [e_min, e_max]: a = -side vn, b = side Vn.
        let (fa, fb) = (scaled(&vn, -side), scaled(&big_vn, side));
        common.push(
            Row::new(add(&fb, &fa, -settings.e[0]), 0.0).ok_or(Fallback::DegenerateGeometry)?,
        );
        common.push(
            Row::new(add(&scaled(&fa, settings.e[1]), &fb, -1.0), 0.0)
                .ok_or(Fallback::DegenerateGeometry)?,
        );
        let (pn_row, pt_row) = impulse_rows(impact);
        let w = relative_yaw_row(settings.moment_form);
        let w_final = over_final(&w);
        let w_lin = add(&w_final, &over_d(&b_row), 1.0);
        let common_bound = common
            .iter()
            .map(|r| objective.bound(r))
            .fold(objective.f0, f64::max);
        let mut form = Formulation {
            n,
            d,
            objective,
            c0,
            common,
            common_bound,
            vn,
            vt: over_x(&trow),
            big_vn,
            pn: over_d(&pn_row),
            pt: over_d(&pt_row),
            sliding,
            big_vt: over_final(&trow),
            w_final,
            w_lin,
            side,
            line: None,
        };
        if !equivalent {
            form.line = Some(form.line_of().ok_or(Fallback::DegenerateGeometry)?);
        }
        Ok(form)
    }

    /// `(Pn, Pt, Vt)` along the direction of the line of impulses at fixed x, e and e_m (its
    /// length and sign arbitrary, but affine in e_m; e_m ignored in the zero branch).
    fn slopes(&self, em: f64) -> [f64; 3] {
        let r = self.n - 6;
        let part = |f: &Form| [f[6], f[7], if r == 3 { f[8] } else { 0.0 }];
        let u1 = part(&add(&self.big_vn, &self.vn, -1.0));
        let delta = if r == 2 {
            [-u1[1], u1[0], 0.0]
        } else {
            // Equation 6 along d: (1 - em) W_f - em B, with B = W_lin - W_f.
            let wf = part(&self.w_final);
            let b = part(&add(&self.w_lin, &self.w_final, -1.0));
            let u2 = [
                (1.0 - em) * wf[0] - em * b[0],
                (1.0 - em) * wf[1] - em * b[1],
                (1.0 - em) * wf[2] - em * b[2],
            ];
            [
                u1[1] * u2[2] - u1[2] * u2[1],
                u1[2] * u2[0] - u1[0] * u2[2],
                u1[0] * u2[1] - u1[1] * u2[0],
            ]
        };
        let along = |f: &Form| {
            let p = part(f);
            p[0] * delta[0] + p[1] * delta[1] + p[2] * delta[2]
        };
        [along(&self.pn), along(&self.pt), along(&self.big_vt)]
    }

    /// The e_m pieces of a branch: between the roots of the line's Pt and Vt slopes (affine in
    /// e_m), so that the sign of `k = dVt / dPt` and the ratios below have no pole inside.
    fn pieces(&self, branch: MomentBranch) -> Vec<[f64; 2]> {
        if branch == MomentBranch::Zero {
            return vec![[1.0, 1.0]];
        }
        let (lo, hi) = (-1.0, 0.0);
        let (s0, s1) = (self.slopes(0.0), self.slopes(1.0));
        let mut cuts = vec![lo, hi];
        for i in 1..3 {
            let slope = s1[i] - s0[i];
            if slope != 0.0 {
                let root = -s0[i] / slope;
                if root > lo && root < hi {
                    cuts.push(root);
                }
            }
        }
        cuts.sort_by(f64::total_cmp);
        cuts.dedup();
        cuts.windows(2).map(|w| [w[0], w[1]]).collect()
    }

    /// The convex pieces of an e_m interval (within one piece of the free branch; the whole
    /// zero branch).
    fn patterns(&self, inner: &Inner, branch: MomentBranch, em: [f64; 2]) -> Vec<Pattern> {
        match inner.family.friction() {
            Friction::Equivalent => self
                .signs(inner, branch, em)
                .into_iter()
                .map(Pattern::Pim)
                .collect(),
            Friction::Limit => self.modes().into_iter().map(Pattern::Tangential).collect(),
        }
    }

    /// The rows of a pattern beyond the common ones.
    fn pattern_rows(&self, inner: &Inner, p: &Pattern, branch: MomentBranch) -> Option<Vec<Row>> {
        match p {
            Pattern::Pim(p) => self.sign_rows(inner, p, branch),
            Pattern::Tangential(m) => self.mode_rows(inner, m),
        }
    }

    /// PIM's sign patterns of an e_m interval (within one piece).
    fn signs(&self, inner: &Inner, branch: MomentBranch, em: [f64; 2]) -> Vec<Signs> {
        let ends = [self.slopes(em[0]), self.slopes(em[1])];
        let mid = self.slopes(0.5 * (em[0] + em[1]));
        let kappa = if mid[1] * mid[2] < 0.0 { -1.0 } else { 1.0 };
        // Pn0 = Pn - rho_a Pt, Pn* = Pn - rho_b Vt, with the ratios over the interval. A ratio
        // is monotone between its poles, which are the ends of the pieces: there its value is
        // infinite, with the sign it has just inside.
        let size = |i: usize| ends[0][i].abs().max(ends[1][i].abs()).max(mid[i].abs());
        let ratio = |end: &[f64; 3], i: usize| {
            if end[i].abs() <= 1e-9 * size(i) {
                let inside = mid[0] / mid[i];
                if inside >= 0.0 {
                    f64::INFINITY
                } else {
                    f64::NEG_INFINITY
                }
            } else {
                end[0] / end[i]
            }
        };
        let range = |i: usize| {
            let v = [ratio(&ends[0], i), ratio(&ends[1], i)];
            [v[0].min(v[1]), v[0].max(v[1])]
        };
        let (rho_a, rho_b) = (range(1), range(2));
        let s_ws: &[f64] = match branch {
            MomentBranch::Zero => &[1.0],
            MomentBranch::Free => &[1.0, -1.0],
        };
        let mut out = Vec::new();
        for &sign in inner.signs() {
            for &s_w in s_ws {
                for s_a in [1.0, -1.0] {
                    for s_b in [s_a, -s_a] {
                        // Pn lies between Pn0 and Pn* on the segment (case A), beyond one of
                        // them on the rays (case B).
                        let s_ns: &[f64] = if s_a * s_b > 0.0 {
                            &[1.0]
                        } else {
                            &[1.0, -1.0]
                        };
                        for &s_n_rel in s_ns {
                            let s_n = s_a * s_n_rel;
                            for s_t in [1.0, -1.0] {
                                // mu between 0 and mu_max: kappa s_a s_b s_t s_v <= 0.
                                let s_v = -kappa * s_a * s_b * s_t;
                                out.push(Signs {
                                    sign,
                                    s_n,
                                    s_t,
                                    s_v,
                                    s_a,
                                    s_b,
                                    rho_a,
                                    rho_b,
                                    em,
                                    s_w,
                                });
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// The rows of PIM's sign pattern beyond the common ones.
    fn sign_rows(&self, inner: &Inner, p: &Signs, branch: MomentBranch) -> Option<Vec<Row>> {
        let mut rows = Vec::with_capacity(12);
        let s = p.sign.value();
        // Sliding direction of this sign, closed (vt = 0: the no-slip impulse's side decides).
        rows.extend_from_slice(&self.sliding[usize::from(p.sign == FrictionSign::Negative)]);
        // mu = s Pt / Pn within the bounds, for the sign s_n of Pn.
        let [mlo, mhi] = inner.mu_bounds;
        let spt = scaled(&self.pt, s);
        // Signs of normal impulses are held strictly (by the floor of the other solve paths):
        // where one vanishes mu_max is undefined, and an optimum approached there is reached
        // from inside.
        let floor = inner.pn_floor();
        rows.push(Row::new(scaled(&self.pn, p.s_n), floor)?);
        if let Some(r) = Row::new(scaled(&add(&spt, &self.pn, -mlo), p.s_n), 0.0) {
            rows.push(r);
        }
        if let Some(r) = Row::new(scaled(&add(&spt, &self.pn, -mhi), -p.s_n), 0.0) {
            rows.push(r);
        }
        // The signs of Pt and Vt, and of Pn0 = Pn - rho_a Pt and Pn* = Pn - rho_b Vt for some
        // ratio of the interval (exact when e_m is fixed).
        rows.push(Row::new(scaled(&self.pt, p.s_t), 0.0)?);
        rows.push(Row::new(scaled(&self.big_vt, p.s_v), 0.0)?);
        for (form, sf, sign, rho) in [
            (&self.pt, p.s_t, p.s_a, p.rho_a),
            (&self.big_vt, p.s_v, p.s_b, p.rho_b),
        ] {
            // max over rho of sign (Pn - rho F) with sgn F = sf: at the low end when
            // sign sf > 0.
            let r = if sign * sf > 0.0 { rho[0] } else { rho[1] };
            if r.is_finite() {
                if let Some(row) = Row::new(scaled(&add(&self.pn, form, -r), sign), floor) {
                    rows.push(row);
                }
            }
        }
        if branch == MomentBranch::Free {
            // e_m = W_f / W_lin within the interval, for the sign s_w of W_lin.
            let [lo, hi] = p.em;
            rows.push(Row::new(scaled(&self.w_lin, p.s_w), 0.0)?);
            if let Some(r) = Row::new(scaled(&add(&self.w_final, &self.w_lin, -lo), p.s_w), 0.0) {
                rows.push(r);
            }
            if let Some(r) = Row::new(scaled(&add(&self.w_final, &self.w_lin, -hi), -p.s_w), 0.0) {
                rows.push(r);
            }
        }
        Some(rows)
    }
}

/// The basis `D` (6 x r, r = 3 or 2 columns used) of the velocity changes equations 1-3 allow
/// (and B = 0, row `b_row`, in the zero branch), and r.
fn velocity_basis(
    impact: &pim_core::Impact,
    b_row: &RowVector6<f64>,
    branch: MomentBranch,
) -> Result<([[f64; 3]; 6], usize), Fallback> {
    // Basis of the velocity changes allowed by equations 1-3 (and B = 0 in the zero branch).
    let mut rows: Vec<RowVector6<f64>> = vec![
        momentum_x(impact).0,
        momentum_y(impact).0,
        angular_momentum(impact).0,
    ];
    if branch == MomentBranch::Zero {
        rows.push(*b_row);
    }
    let mut cc = Matrix6::zeros();
    for r in &rows {
        let unit = r / r.norm();
        cc += unit.transpose() * unit;
    }
    let eig = SymmetricEigen::try_new(cc, f64::EPSILON, 500).ok_or(Fallback::DegenerateGeometry)?;
    let null: Vec<usize> = (0..6)
        .filter(|&i| eig.eigenvalues[i].abs() <= 1e-10)
        .collect();
    if null.len() != 6 - rows.len() {
        return Err(Fallback::DegenerateGeometry);
    }
    let r = null.len();
    let mut d = [[0.0; 3]; 6];
    for (c, &i) in null.iter().enumerate() {
        for (k, row) in d.iter_mut().enumerate() {
            row[c] = eig.eigenvectors[(k, i)];
        }
    }
    Ok((d, r))
}

/// The cost `U'HU - 2g'U + c0` over `z` with `U = T z` (T the 12 x n map of `z = (x, q)`,
/// `X = x + D q`): `T`, `G = 2 T'HT`, `a = -2 T'g` and `c0`.
fn cost_over_z(inner: &Inner, d: &[[f64; 3]; 6], r: usize) -> CostOverZ {
    let n = 6 + r;
    let (hu, gu, c0) = inner.objective.quadratic();
    let mut t = [[0.0; N]; 12];
    for k in 0..6 {
        t[k][k] = 1.0;
        t[6 + k][k] = 1.0;
        for c in 0..r {
            t[6 + k][6 + c] = d[k][c];
        }
    }
    let mut g = [[0.0; N]; N];
    let mut a = [0.0; N];
    for i in 0..n {
        for j in 0..n {
            let mut s = 0.0;
            for p in 0..12 {
                if t[p][i] == 0.0 {
                    continue;
                }
                for q in 0..12 {
                    s += t[p][i] * hu[(p, q)] * t[q][j];
                }
            }
            g[i][j] = 2.0 * s;
        }
        a[i] = -2.0 * (0..12).map(|p| t[p][i] * gu[p]).sum::<f64>();
    }
    (t, g, a, c0)
}

/// See [`cost_over_z`].
type CostOverZ = ([[f64; N]; 12], [[f64; N]; N], [f64; N], f64);

#[cfg(test)]
mod tests;
