//! A dense dual active-set QP solver (Goldfarb and Idnani, Math. Programming 27, 1983) for the
//! small strictly convex problems of [`super`]: at most [`N`] variables, inequality rows only,
//! nothing allocated per solve.
//!
//! `min f(z) = a'z + z'Gz / 2  subject to  n_i'z >= b_i`. The method starts at the unconstrained
//! minimum and adds violated rows one at a time, dropping rows whose multipliers would turn
//! negative. Every step raises f, so an iteration whose f reaches a cutoff (the best value
//! found elsewhere) can stop: the problem cannot beat it. An infeasible problem is recognised
//! when a violated row can be reached by neither a primal nor a dual step. The answer is
//! returned only after every Karush-Kuhn-Tucker condition has been checked (stationarity,
//! primal feasibility, non-negative multipliers), which for a convex problem proves it optimal.

// Dense linear algebra on index ranges reads best with explicit indices.
#![allow(clippy::needless_range_loop)]

/// Largest number of variables.
pub(crate) const N: usize = 9;

/// A row `n . z >= b` (n of unit length).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Row {
    pub n: [f64; N],
    pub b: f64,
}

impl Row {
    /// The row `n . z >= b`, scaled to unit length (`None` for a zero row).
    pub fn new(n: [f64; N], b: f64) -> Option<Row> {
        let norm = n.iter().map(|v| v * v).sum::<f64>().sqrt();
        (norm > 0.0 && norm.is_finite()).then(|| Row {
            n: n.map(|v| v / norm),
            b: b / norm,
        })
    }

    /// `n . z - b`: negative where the row is violated.
    pub fn slack(&self, z: &[f64; N]) -> f64 {
        dot(&self.n, z) - self.b
    }
}

/// The factorised objective, shared by every problem with the same G and a.
#[derive(Debug, Clone)]
pub(crate) struct Objective {
    n: usize,
    g: [[f64; N]; N],
    a: [f64; N],
    /// `J = L^-T` with `G = L L'` (so `J J' = G^-1`).
    j: [[f64; N]; N],
    /// The unconstrained minimum and its value.
    pub z0: [f64; N],
    pub f0: f64,
}

/// What a solve found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Outcome {
    /// The optimum, its value and the number of active rows.
    Solved { z: [f64; N], f: f64, active: usize },
    /// The value reached the cutoff: the optimum is at least that.
    Cutoff(f64),
    /// No point satisfies the rows.
    Infeasible,
    /// Round-off or the iteration limit stopped the method.
    Failed,
}

fn dot(a: &[f64; N], b: &[f64; N]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Rotates columns `c` and `c + 1` of `j` so that a vector `(p, q)` in those coordinates of
/// `j' v` becomes `(h, 0)`.
fn rotate_columns(j: &mut [[f64; N]; N], n: usize, c: usize, cos: f64, sin: f64) {
    for row in j.iter_mut().take(n) {
        let (x, y) = (row[c], row[c + 1]);
        row[c] = cos * x + sin * y;
        row[c + 1] = -sin * x + cos * y;
    }
}

impl Objective {
    /// `a'z + z'Gz / 2` over the first `n` coordinates; `None` unless G is (numerically)
    /// positive definite.
    pub fn new(n: usize, g: [[f64; N]; N], a: [f64; N]) -> Option<Objective> {
        if n == 0 || n > N {
            return None;
        }
        // Cholesky G = L L'.
        let mut l = [[0.0; N]; N];
        let gmax = (0..n).map(|i| g[i][i].abs()).fold(0.0, f64::max);
        for i in 0..n {
            for k in 0..=i {
                let s: f64 = g[i][k] - (0..k).map(|m| l[i][m] * l[k][m]).sum::<f64>();
                if i == k {
                    if s.is_nan() || s <= 1e-12 * gmax {
                        return None;
                    }
                    l[i][i] = s.sqrt();
                } else {
                    l[i][k] = s / l[k][k];
                }
            }
        }
        // J = L^-T: solve L' J = I column by column (J upper triangular).
        let mut j = [[0.0; N]; N];
        for c in 0..n {
            for r in (0..=c).rev() {
                let mut s = if r == c { 1.0 } else { 0.0 };
                for m in r + 1..=c {
                    s -= l[m][r] * j[m][c];
                }
                j[r][c] = s / l[r][r];
            }
        }
        // z0 = -G^-1 a = -J J' a.
        let mut jta = [0.0; N];
        for (c, v) in jta.iter_mut().enumerate().take(n) {
            *v = (0..n).map(|r| j[r][c] * a[r]).sum();
        }
        let mut z0 = [0.0; N];
        for (r, v) in z0.iter_mut().enumerate().take(n) {
            *v = -(0..n).map(|c| j[r][c] * jta[c]).sum::<f64>();
        }
        let f0 = 0.5 * dot(&a, &z0);
        if !z0.iter().all(|v| v.is_finite()) {
            return None;
        }
        Some(Objective { n, g, a, j, z0, f0 })
    }

    /// The value at z.
    pub fn value(&self, z: &[f64; N]) -> f64 {
        let mut gz = [0.0; N];
        for (i, v) in gz.iter_mut().enumerate().take(self.n) {
            *v = dot(&self.g[i], z);
        }
        dot(&self.a, z) + 0.5 * dot(z, &gz)
    }

    /// A lower bound of the minimum subject to one row: `f0 + s^2 / (2 n'G^-1 n)` when the
    /// unconstrained minimum violates it by s, else f0.
    pub fn bound(&self, row: &Row) -> f64 {
        let s = row.slack(&self.z0);
        if s >= 0.0 {
            return self.f0;
        }
        let w: f64 = (0..self.n)
            .map(|c| {
                let v: f64 = (0..self.n).map(|r| self.j[r][c] * row.n[r]).sum();
                v * v
            })
            .sum();
        if w > 0.0 {
            self.f0 + 0.5 * s * s / w
        } else {
            f64::INFINITY
        }
    }

    /// Minimises subject to `rows`, stopping once the value reaches `cutoff`.
    pub fn solve(&self, rows: &[Row], cutoff: f64) -> Outcome {
        self.run(rows, cutoff, None)
    }

    /// As [`Objective::solve`], and at the optimum the multipliers of the active rows
    /// (`(index, multiplier)`, over the unit-length rows).
    pub fn solve_with_multipliers(
        &self,
        rows: &[Row],
        cutoff: f64,
        multipliers: &mut Vec<(usize, f64)>,
    ) -> Outcome {
        self.run(rows, cutoff, Some(multipliers))
    }

    fn run(
        &self,
        rows: &[Row],
        cutoff: f64,
        multipliers: Option<&mut Vec<(usize, f64)>>,
    ) -> Outcome {
        let n = self.n;
        let mut z = self.z0;
        let mut f = self.f0;
        let mut j = self.j;
        let mut r = [[0.0; N]; N];
        // Active rows and their multipliers; u[q] is the multiplier of the row being added.
        let mut act = [0usize; N];
        let mut u = [0.0; N + 1];
        let mut q = 0usize;
        let scale = 1.0 + self.z0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let eps = |row: &Row| 1e-11 * (scale + row.b.abs());
        if f >= cutoff {
            return Outcome::Cutoff(f);
        }
        let limit = 4 * rows.len() + 20;
        let mut steps = 0;
        loop {
            let Some(p) = most_violated(rows, &z, &act[..q], &eps) else {
                let out = self.verify(rows, &z, &act[..q], &u[..q], scale);
                if let (Some(m), Outcome::Solved { .. }) = (multipliers, &out) {
                    m.clear();
                    m.extend(act[..q].iter().copied().zip(u[..q].iter().copied()));
                }
                return out;
            };
            let np = rows[p].n;
            u[q] = 0.0;
            loop {
                steps += 1;
                if steps > limit {
                    return Outcome::Failed;
                }
                let (mut d, dir, rv) = directions((&j, &r), &np, q, n);
                // Partial step (a multiplier reaches zero) and full step (the row holds).
                let (t1, k) = partial_step(&u[..q], &rv[..q]);
                let dn = dot(&dir, &np);
                let dir_norm = dir.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                let t2 = if dir_norm <= 1e-14 * scale || dn <= 0.0 {
                    f64::INFINITY
                } else {
                    -rows[p].slack(&z) / dn
                };
                let t = t1.min(t2);
                if t.is_infinite() {
                    return Outcome::Infeasible;
                }
                if t2.is_infinite() {
                    // Dual step only, then the row whose multiplier vanished leaves.
                    for l in 0..q {
                        u[l] -= t * rv[l];
                    }
                    u[q] += t;
                    drop_row(&mut j, &mut r, &mut act, &mut u, &mut q, k, n);
                    continue;
                }
                for (zi, di) in z.iter_mut().zip(&dir) {
                    *zi += t * di;
                }
                f += t * dn * (0.5 * t + u[q]);
                for l in 0..q {
                    u[l] -= t * rv[l];
                }
                u[q] += t;
                if f >= cutoff {
                    return Outcome::Cutoff(f);
                }
                if t2 <= t1 {
                    // The row becomes active: rotate d2 onto its first coordinate.
                    for c in (q + 1..n).rev() {
                        let (x, y) = (d[c - 1], d[c]);
                        if y == 0.0 {
                            continue;
                        }
                        let h = x.hypot(y);
                        d[c - 1] = h;
                        d[c] = 0.0;
                        rotate_columns(&mut j, n, c - 1, x / h, y / h);
                    }
                    if d[q].abs() <= 1e-14 * scale {
                        return Outcome::Failed;
                    }
                    for (l, row) in r.iter_mut().enumerate().take(q + 1) {
                        row[q] = d[l];
                    }
                    act[q] = p;
                    q += 1;
                    break;
                }
                drop_row(&mut j, &mut r, &mut act, &mut u, &mut q, k, n);
            }
        }
    }

    /// The KKT conditions at a candidate: every row holds, the multipliers are non-negative and
    /// `G z + a = sum u_i n_i` over the active rows.
    fn verify(&self, rows: &[Row], z: &[f64; N], act: &[usize], u: &[f64], scale: f64) -> Outcome {
        let n = self.n;
        if !z.iter().all(|v| v.is_finite()) {
            return Outcome::Failed;
        }
        if rows
            .iter()
            .any(|row| row.slack(z) < -1e-9 * (scale + row.b.abs()))
        {
            return Outcome::Failed;
        }
        let umax = u.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        if u.iter().any(|&v| v < -1e-9 * (1.0 + umax)) {
            return Outcome::Failed;
        }
        let mut size: f64 = 0.0;
        let mut worst: f64 = 0.0;
        for i in 0..n {
            let gz = dot(&self.g[i], z);
            let mut res = gz + self.a[i];
            for (l, &k) in act.iter().enumerate() {
                res -= u[l] * rows[k].n[i];
            }
            size = size.max(gz.abs()).max(self.a[i].abs());
            worst = worst.max(res.abs());
        }
        if worst > 1e-8 * size.max(1e-300) {
            return Outcome::Failed;
        }
        Outcome::Solved {
            z: *z,
            f: self.value(z),
            active: act.len(),
        }
    }
}

/// Removes active row `k` and restores the triangular factor.
fn drop_row(
    j: &mut [[f64; N]; N],
    r: &mut [[f64; N]; N],
    act: &mut [usize; N],
    u: &mut [f64; N + 1],
    q: &mut usize,
    k: usize,
    n: usize,
) {
    let qq = *q;
    for c in k..qq - 1 {
        for row in r.iter_mut().take(qq) {
            row[c] = row[c + 1];
        }
        act[c] = act[c + 1];
        u[c] = u[c + 1];
    }
    // The multiplier of the row being added moves down with the others.
    u[qq - 1] = u[qq];
    for row in r.iter_mut().take(qq) {
        row[qq - 1] = 0.0;
    }
    for c in k..qq - 1 {
        let (x, y) = (r[c][c], r[c + 1][c]);
        if y == 0.0 {
            continue;
        }
        let h = x.hypot(y);
        r[c][c] = h;
        r[c + 1][c] = 0.0;
        let (cos, sin) = (x / h, y / h);
        for cc in c + 1..qq - 1 {
            let (a, b) = (r[c][cc], r[c + 1][cc]);
            r[c][cc] = cos * a + sin * b;
            r[c + 1][cc] = -sin * a + cos * b;
        }
        rotate_columns(j, n, c, cos, sin);
    }
    *q = qq - 1;
}

/// The most violated row not in `active` at `z` (beyond its tolerance `eps`), if any.
fn most_violated(
    rows: &[Row],
    z: &[f64; N],
    active: &[usize],
    eps: &dyn Fn(&Row) -> f64,
) -> Option<usize> {
    let mut p = None;
    let mut worst = 0.0;
    for (i, row) in rows.iter().enumerate() {
        if active.contains(&i) {
            continue;
        }
        let s = row.slack(z);
        if s < -eps(row) && s < worst {
            worst = s;
            p = Some(i);
        }
    }
    p
}

/// For the row of normal `np` being added with `q` rows active: `d = J' n+`, the primal
/// direction `J2 d2` and the dual direction `R^-1 d1`.
fn directions(
    (j, r): (&[[f64; N]; N], &[[f64; N]; N]),
    np: &[f64; N],
    q: usize,
    n: usize,
) -> ([f64; N], [f64; N], [f64; N]) {
    let mut d = [0.0; N];
    for (c, v) in d.iter_mut().enumerate().take(n) {
        *v = (0..n).map(|i| j[i][c] * np[i]).sum();
    }
    let mut dir = [0.0; N];
    for (i, v) in dir.iter_mut().enumerate().take(n) {
        *v = (q..n).map(|c| j[i][c] * d[c]).sum();
    }
    let mut rv = [0.0; N];
    for l in (0..q).rev() {
        let s: f64 = d[l] - (l + 1..q).map(|m| r[l][m] * rv[m]).sum::<f64>();
        rv[l] = s / r[l][l];
    }
    (d, dir, rv)
}

/// The partial step: the least `u_l / rv_l` over the active rows with `rv_l > 0` (a
/// multiplier reaches zero) and its row (infinite and none where no multiplier falls).
fn partial_step(u: &[f64], rv: &[f64]) -> (f64, usize) {
    let (mut t1, mut k) = (f64::INFINITY, usize::MAX);
    for (l, (&ul, &rl)) in u.iter().zip(rv).enumerate() {
        if rl > 0.0 {
            let t = ul / rl;
            if t < t1 {
                t1 = t;
                k = l;
            }
        }
    }
    (t1, k)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn obj(n: usize, diag: &[f64], a: &[f64]) -> Objective {
        let mut g = [[0.0; N]; N];
        let mut av = [0.0; N];
        for i in 0..n {
            g[i][i] = diag[i];
            av[i] = a[i];
        }
        // Couple the first two coordinates.
        g[0][1] = 0.5;
        g[1][0] = 0.5;
        Objective::new(n, g, av).unwrap()
    }

    fn row(n: &[f64], b: f64) -> Row {
        let mut v = [0.0; N];
        v[..n.len()].copy_from_slice(n);
        Row::new(v, b).unwrap()
    }

    #[test]
    fn unconstrained_minimum() {
        let o = obj(3, &[2.0, 2.0, 1.0], &[-2.0, 0.0, 1.0]);
        // G z = -a: [2 .5 0; .5 2 0; 0 0 1] z = (2, 0, -1).
        let z1 = 2.0 / (2.0 - 0.125);
        assert!((o.z0[0] - z1).abs() < 1e-12);
        assert!((o.z0[1] + 0.25 * z1).abs() < 1e-12);
        assert!((o.z0[2] + 1.0).abs() < 1e-12);
    }

    #[test]
    fn active_rows_are_found_and_dropped() {
        // min (z0 - 1)^2 + (z1 - 1)^2 + z0 z1 / 2 ... with rows z0 + z1 >= 3, z0 <= 1.
        let o = obj(2, &[2.0, 2.0], &[-2.0, -2.0]);
        let rows = [
            row(&[1.0, 1.0], 3.0),
            row(&[-1.0, 0.0], -1.0),
            row(&[0.0, 1.0], -5.0),
        ];
        let Outcome::Solved { z, active, .. } = o.solve(&rows, f64::INFINITY) else {
            panic!("not solved")
        };
        // On both rows: z0 = 1, z1 = 2 (the multipliers are positive there).
        assert!(
            (z[0] - 1.0).abs() < 1e-12 && (z[1] - 2.0).abs() < 1e-12,
            "{z:?}"
        );
        assert_eq!(active, 2);
        // A row that is first added and later dropped: z1 <= 0.2 then z0 + z1 >= 3 moves it.
        let rows = [row(&[0.0, -1.0], -4.0), row(&[1.0, 1.0], 6.0)];
        let Outcome::Solved { z, active, .. } = o.solve(&rows, f64::INFINITY) else {
            panic!("not solved")
        };
        assert!(
            (z[0] + z[1] - 6.0).abs() < 1e-12 && z[1] <= 4.0 + 1e-12,
            "{z:?}"
        );
        assert_eq!(active, 1);
    }

    #[test]
    fn infeasible_and_cutoff() {
        let o = obj(2, &[2.0, 2.0], &[0.0, 0.0]);
        let rows = [row(&[1.0, 0.0], 1.0), row(&[-1.0, 0.0], 0.0)];
        assert_eq!(o.solve(&rows, f64::INFINITY), Outcome::Infeasible);
        let rows = [row(&[1.0, 0.0], 10.0)];
        assert!(matches!(o.solve(&rows, 1.0), Outcome::Cutoff(f) if f >= 1.0));
    }

    /// Random strictly convex problems whose rows all hold at a known point: every one is
    /// solved (never called infeasible), its answer satisfies every row and is no worse than
    /// that point, and it does not move when solved again from its own rows.
    #[test]
    fn random_feasible_problems_are_solved() {
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        for _ in 0..300 {
            let n = 2 + (next().abs() * 7.99) as usize;
            let mut m = [[0.0; N]; N];
            for row in m.iter_mut().take(n) {
                for v in row.iter_mut().take(n) {
                    *v = next();
                }
            }
            let mut g = [[0.0; N]; N];
            for i in 0..n {
                for j in 0..n {
                    g[i][j] = (0..n).map(|k| m[k][i] * m[k][j]).sum::<f64>();
                }
                g[i][i] += 0.1;
            }
            let mut a = [0.0; N];
            for v in a.iter_mut().take(n) {
                *v = 5.0 * next();
            }
            let o = Objective::new(n, g, a).unwrap();
            let mut known = [0.0; N];
            for v in known.iter_mut().take(n) {
                *v = next();
            }
            let rows: Vec<Row> = (0..(3 * n))
                .filter_map(|_| {
                    let mut r = [0.0; N];
                    for v in r.iter_mut().take(n) {
                        *v = next();
                    }
                    let b = dot(&r, &known) - next().abs();
                    Row::new(r, b)
                })
                .collect();
            match o.solve(&rows, f64::INFINITY) {
                Outcome::Solved { z, f, .. } => {
                    assert!(rows.iter().all(|r| r.slack(&z) >= -1e-9));
                    assert!(f <= o.value(&known) + 1e-9 * (1.0 + f.abs()));
                }
                other => panic!("{other:?}"),
            }
        }
    }

    #[test]
    fn bound_is_below_the_optimum() {
        let o = obj(3, &[2.0, 3.0, 1.0], &[-1.0, 2.0, 0.5]);
        let rows = [row(&[1.0, 2.0, -1.0], 4.0), row(&[0.0, 1.0, 1.0], 1.0)];
        let Outcome::Solved { f, .. } = o.solve(&rows, f64::INFINITY) else {
            panic!()
        };
        for r in &rows {
            assert!(o.bound(r) <= f + 1e-12);
        }
    }
}
