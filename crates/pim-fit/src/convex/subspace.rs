//! The QP of the convex route on the affine subspace left by the components known exactly.
//!
//! A component known exactly (Q1's separation state, Q2's contact state, any `[known]` entry)
//! is an equality `t_k . z = v_k` over `z = (x, q)`: `x_k` for a contact component,
//! `x_k + (D q)_k` for a separation one. The points that satisfy all of them are
//! `z = z0 + B w` (B an orthonormal basis of the null space of the equalities, z0 their
//! least-norm solution), and over w the cost is
//!
//! ```text
//! f(z0 + B w) = f(z0) + (B'(a + G z0))' w + w' (B'GB) w / 2,
//! ```
//!
//! strictly convex whenever every direction the equalities leave free is weighted: with one
//! whole state known the other state still moves with the impulse, and the estimates of that
//! state weigh every direction of it. Rows `n . z >= b` become `(B'n) . w >= b - n . z0`. The
//! solver, its bounds and its cutoff then work over w exactly as over z; answers are mapped
//! back, so callers see z and the cost's value, never w.

use super::dual::{self, Outcome, Row, N};
use super::form::dot;
use crate::certificate::Fallback;
use nalgebra::{DMatrix, DVector};

/// The convex route's objective over z, restricted to the subspace of the known components
/// when there are any.
pub(super) struct Qp {
    objective: dual::Objective,
    /// `z = z0 + B w`; `None` when nothing is known (w = z).
    map: Option<Map>,
    /// The unconstrained minimum's value, over z.
    pub f0: f64,
}

struct Map {
    /// Number of z and of w coordinates.
    n: usize,
    m: usize,
    z0: [f64; N],
    /// `basis[i][c]`: component i of basis vector c.
    basis: [[f64; N]; N],
    /// `f(z0)`: the value over z is the value over w plus this.
    offset: f64,
}

impl Qp {
    /// `a'z + z'Gz / 2` over the first `n` coordinates subject to `equalities` (`t . z = v`).
    /// Why not: the equalities contradict one another (no z satisfies them), or the cost is
    /// not strictly convex on what they leave free.
    pub fn new(
        n: usize,
        g: [[f64; N]; N],
        a: [f64; N],
        equalities: &[([f64; N], f64)],
    ) -> Result<Qp, Fallback> {
        if equalities.is_empty() {
            let objective = dual::Objective::new(n, g, a).ok_or(Fallback::DegenerateGeometry)?;
            let f0 = objective.f0;
            return Ok(Qp {
                objective,
                map: None,
                f0,
            });
        }
        // Padded with zero rows to at least n rows, so that the SVD gives all n right
        // singular vectors.
        let k = equalities.len();
        let rows = k.max(n);
        let e = DMatrix::from_fn(rows, n, |r, c| if r < k { equalities[r].0[c] } else { 0.0 });
        let v = DVector::from_fn(rows, |r, _| if r < k { equalities[r].1 } else { 0.0 });
        let svd = e.clone().svd(true, true);
        let Some(vt) = &svd.v_t else {
            return Err(Fallback::DegenerateGeometry);
        };
        let tol = 1e-10 * svd.singular_values.max().max(1.0);
        let z0v = svd
            .solve(&v, tol)
            .map_err(|_| Fallback::DegenerateGeometry)?;
        if (&e * &z0v - &v).amax() > 1e-9 * (1.0 + v.amax()) {
            return Err(Fallback::KnownInconsistent);
        }
        // The right singular vectors of (numerically) zero singular values span the null space.
        let free: Vec<usize> = (0..n).filter(|&i| svd.singular_values[i] <= tol).collect();
        let m = free.len();
        if m == 0 {
            return Err(Fallback::NotStrictlyConvex);
        }
        let mut basis = [[0.0; N]; N];
        for (c, &r) in free.iter().enumerate() {
            for i in 0..n {
                basis[i][c] = vt[(r, i)];
            }
        }
        let mut z0 = [0.0; N];
        for i in 0..n {
            z0[i] = z0v[i];
        }
        // Over w: G_w = B'GB, a_w = B'(a + G z0).
        let mut gz0 = [0.0; N];
        for i in 0..n {
            gz0[i] = dot(&g[i], &z0);
        }
        let offset = dot(&a, &z0) + 0.5 * dot(&z0, &gz0);
        let mut gw = [[0.0; N]; N];
        let mut aw = [0.0; N];
        for c in 0..m {
            for d in 0..m {
                let mut s = 0.0;
                for i in 0..n {
                    for j in 0..n {
                        s += basis[i][c] * g[i][j] * basis[j][d];
                    }
                }
                gw[c][d] = s;
            }
            aw[c] = (0..n).map(|i| basis[i][c] * (a[i] + gz0[i])).sum();
        }
        let objective = dual::Objective::new(m, gw, aw).ok_or(Fallback::NotStrictlyConvex)?;
        let f0 = objective.f0 + offset;
        Ok(Qp {
            objective,
            map: Some(Map {
                n,
                m,
                z0,
                basis,
                offset,
            }),
            f0,
        })
    }

    /// A row over w, or what it is when the subspace does not move it: `Ok(None)` for a row
    /// that every point of the subspace satisfies, `Err(())` for one that none does.
    fn row_over_w(map: &Map, row: &Row) -> Result<Option<Row>, ()> {
        let mut nw = [0.0; N];
        for c in 0..map.m {
            nw[c] = (0..map.n).map(|i| map.basis[i][c] * row.n[i]).sum();
        }
        let b = row.b - dot(&row.n, &map.z0);
        let size = nw.iter().fold(0.0f64, |s, v| s.max(v.abs()));
        if size <= 1e-12 {
            return if b <= 1e-9 * (1.0 + row.b.abs()) {
                Ok(None)
            } else {
                Err(())
            };
        }
        Ok(Row::new(nw, b))
    }

    /// A lower bound of the minimum subject to one row (over z).
    pub fn bound(&self, row: &Row) -> f64 {
        match &self.map {
            None => self.objective.bound(row),
            Some(map) => match Qp::row_over_w(map, row) {
                Ok(Some(r)) => self.objective.bound(&r) + map.offset,
                Ok(None) => self.f0,
                Err(()) => f64::INFINITY,
            },
        }
    }

    /// Minimises subject to `rows` (over z), stopping once the value reaches `cutoff`; the
    /// answer over z.
    pub fn solve(&self, rows: &[Row], cutoff: f64) -> Outcome {
        let Some(map) = &self.map else {
            return self.objective.solve(rows, cutoff);
        };
        let mut over_w = Vec::with_capacity(rows.len());
        for row in rows {
            match Qp::row_over_w(map, row) {
                Ok(Some(r)) => over_w.push(r),
                Ok(None) => {}
                Err(()) => return Outcome::Infeasible,
            }
        }
        match self.objective.solve(&over_w, cutoff - map.offset) {
            Outcome::Solved { z: w, f, active } => {
                let mut z = map.z0;
                for i in 0..map.n {
                    z[i] += (0..map.m).map(|c| map.basis[i][c] * w[c]).sum::<f64>();
                }
                Outcome::Solved {
                    z,
                    f: f + map.offset,
                    active,
                }
            }
            Outcome::Cutoff(f) => Outcome::Cutoff(f + map.offset),
            other => other,
        }
    }
}
