//! Linear algebra of the inner problem: the null space of the fixed components, a symmetric
//! solve that falls back to the pseudo-inverse, and the QP adaptor.
//!
//! The QPs here are tiny (at most six variables, about sixteen rows) and come in runs that
//! differ only slightly (the bisection on the energy multiplier, the two friction wedges), so
//! the adaptor first tries a dense active-set iteration started from the previous run's active
//! set. Its answer is returned only when it satisfies every Karush-Kuhn-Tucker condition
//! (stationarity by construction, primal feasibility, non-negative multipliers), which for a
//! convex QP makes it the exact optimum. Otherwise clarabel (an interior-point solver) decides,
//! including every infeasibility verdict.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, NonnegativeConeT, SolverStatus, SupportedConeT,
};
use nalgebra::{DMatrix, DVector, Matrix6, Vector6};

/// `x = xp + Z y` for the fixed components in general position (SVD of their rows).
pub(crate) fn general_null_space(
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

pub(crate) fn to6(v: &DVector<f64>) -> Vector6<f64> {
    Vector6::from_iterator(v.iter().copied())
}

pub(crate) fn to_d(v: &Vector6<f64>) -> DVector<f64> {
    DVector::from_iterator(6, v.iter().copied())
}

/// Iteration limit of the SVD and eigen decompositions (the plain nalgebra calls never stop on
/// NaN input).
pub(crate) const MAX_ITER: usize = 500;

/// True when a Cholesky factor's diagonal shows a (numerically) singular matrix.
pub(crate) fn nearly_singular<'a>(diag: impl Iterator<Item = &'a f64>, hmax: f64) -> bool {
    diag.map(|d| d * d).fold(f64::INFINITY, f64::min) <= 1e-10 * hmax.max(1e-300)
}

/// Solves `h y = g` for symmetric positive (semi)definite h: on a singular h, the smallest-norm
/// solution (pseudo-inverse).
pub(crate) fn solve_spd(h: &DMatrix<f64>, g: &DVector<f64>) -> Option<DVector<f64>> {
    if let Some(ch) = h.clone().cholesky() {
        if !nearly_singular(ch.l_dirty().diagonal().iter(), h.diagonal().amax()) {
            return Some(ch.solve(g));
        }
    }
    let svd = h.clone().try_svd(true, true, f64::EPSILON, MAX_ITER)?;
    let smax = svd.singular_values.max().max(1e-300);
    svd.solve(g, 1e-9 * smax).ok()
}

pub(crate) enum QpOutcome {
    Solved(DVector<f64>),
    Infeasible,
    Failed,
}

/// What a QP asks of its caller: a cheap certificate of an empty polyhedron, asked before
/// clarabel runs, and the counter of elementary operations it charges its work to.
pub(crate) struct QpHooks<'a> {
    pub proven_empty: &'a dyn Fn() -> bool,
    pub spend: &'a dyn Fn(u64),
}

/// min y' p y - 2 q' y  s.t. rows: a' y <= b + tol. `active` is the warm start: the rows
/// believed to hold with equality; it is updated with the active set of the answer.
/// `proven_empty` is asked before clarabel runs (a cheap certificate of an empty polyhedron).
pub(crate) fn qp(
    p: &DMatrix<f64>,
    q: &DVector<f64>,
    rows: &[(DVector<f64>, f64)],
    tol: f64,
    max_iter: u32,
    active: &mut Vec<usize>,
    hooks: QpHooks<'_>,
) -> QpOutcome {
    let QpHooks {
        proven_empty,
        spend,
    } = hooks;
    let mut steps = 0;
    let found = active_set(p, q, rows, tol, active, &mut steps);
    spend(steps);
    if let Some(y) = found {
        return QpOutcome::Solved(y);
    }
    if proven_empty() {
        return QpOutcome::Infeasible;
    }
    let (out, iterations) = clarabel_qp(p, q, rows, max_iter);
    spend(CLARABEL_ITERATION_OPERATIONS * u64::from(iterations));
    if let QpOutcome::Solved(y) = &out {
        active.clear();
        active.extend(
            rows.iter()
                .enumerate()
                .filter(|(_, (a, b))| a.dot(y) >= b - 1e-6 * (tol + b.abs()))
                .map(|(i, _)| i),
        );
    }
    out
}

/// A clarabel iteration in elementary operations (an active-set step or a 6 x 6 solve): its
/// sparse factorisation and cone steps take about ten times as long.
const CLARABEL_ITERATION_OPERATIONS: u64 = 10;

/// Active-set iterations allowed per row before giving the problem to clarabel.
const ACTIVE_SET_STEPS_PER_ROW: usize = 2;

/// A dense active-set iteration from the working set `w`: solve the equality-constrained
/// problem on `w`, drop the row with the most negative multiplier, else add the most violated
/// row, until the KKT conditions hold (`Some`, with `w` the final active set) or the step limit
/// or a degenerate working set ends it (`None`).
fn active_set(
    p: &DMatrix<f64>,
    q: &DVector<f64>,
    rows: &[(DVector<f64>, f64)],
    tol: f64,
    w: &mut Vec<usize>,
    steps: &mut u64,
) -> Option<DVector<f64>> {
    let n = p.nrows();
    if n == 0 {
        return None;
    }
    w.retain(|&i| i < rows.len());
    let pmax = p.amax().max(1e-300);
    for _ in 0..ACTIVE_SET_STEPS_PER_ROW * rows.len() + 4 {
        *steps += 1;
        let k = w.len();
        if k > n {
            return None;
        }
        // [p a_w'; a_w 0] [y; nu] = [q; b_w]; nu is half the multiplier of y'py - 2q'y.
        let mut kkt = DMatrix::zeros(n + k, n + k);
        let mut rhs = DVector::zeros(n + k);
        kkt.view_mut((0, 0), (n, n)).copy_from(p);
        rhs.rows_mut(0, n).copy_from(q);
        for (j, &i) in w.iter().enumerate() {
            let (a, b) = &rows[i];
            let scale = a.amax().max(1e-300);
            for c in 0..n {
                kkt[(n + j, c)] = a[c] / scale * pmax;
                kkt[(c, n + j)] = a[c] / scale * pmax;
            }
            rhs[n + j] = b / scale * pmax;
        }
        // Stationarity and the active rows hold by construction, when the solve succeeds: with
        // dependent active rows (singular KKT matrix) by the smallest-norm solution.
        let residual_ok = |sol: &DVector<f64>| {
            let y = sol.rows(0, n);
            sol.iter().all(|v| v.is_finite())
                && (&kkt * sol - &rhs).amax() <= 1e-9 * (rhs.amax() + pmax * y.amax()).max(1e-300)
        };
        let sol = match kkt.clone().lu().solve(&rhs) {
            Some(sol) if residual_ok(&sol) => sol,
            _ => {
                let svd = kkt.clone().try_svd(true, true, f64::EPSILON, MAX_ITER)?;
                let smax = svd.singular_values.max().max(1e-300);
                let sol = svd.solve(&rhs, 1e-12 * smax).ok()?;
                if !residual_ok(&sol) {
                    return None;
                }
                sol
            }
        };
        let y = sol.rows(0, n).into_owned();
        let nu = sol.rows(n, k);
        let numax = nu.amax();
        if let Some((j, _)) = nu
            .iter()
            .enumerate()
            .filter(|(_, v)| **v < -1e-12 * numax.max(1e-300))
            .min_by(|a, b| a.1.total_cmp(b.1))
        {
            w.remove(j);
            continue;
        }
        let worst = rows
            .iter()
            .enumerate()
            .filter(|(i, _)| !w.contains(i))
            .map(|(i, (a, b))| (i, a.dot(&y) - b))
            .filter(|(_, excess)| *excess > 0.5 * tol)
            .max_by(|a, b| a.1.total_cmp(&b.1));
        let Some((i, _)) = worst else {
            return Some(y);
        };
        // A violated row in the span of the working set, a_i = sum c_j a_j, would make the
        // working set dependent: as in Goldfarb and Idnani's dual method, the row j with
        // c_j > 0 whose multiplier runs out first (least nu_j / c_j) leaves for it. With no
        // c_j > 0 the rows cannot all hold: clarabel decides.
        if k > 0 {
            let aw = DMatrix::from_fn(n, k, |r, c| rows[w[c]].0[r]);
            let a = &rows[i].0;
            if let Some(c) = aw
                .clone()
                .svd(true, true)
                .solve(a, 1e-12 * a.norm())
                .ok()
                .filter(|c| (&aw * c - a).norm() <= 1e-9 * a.norm())
            {
                // The multiplier of row j itself (the KKT rows are scaled by pmax / amax(a_j)).
                let mult = |j: usize| nu[j] * pmax / rows[w[j]].0.amax().max(1e-300);
                let leave = (0..k)
                    .filter(|&j| c[j] > 1e-12 * c.amax())
                    .min_by(|&x, &z| (mult(x) / c[x]).total_cmp(&(mult(z) / c[z])));
                match leave {
                    Some(j) => w[j] = i,
                    None => return None,
                }
                continue;
            }
        }
        w.push(i);
    }
    None
}

/// True when a Farkas certificate proves that no y with `|y| <= radius` satisfies
/// `a' y <= b + tol` for the rows `subset` (at most six are looked at): weights `u >= 0` with
/// `sum u (b + tol) < -|sum u a| radius`, the weights taken from the near-null vector of each
/// small group of rows. A `false` proves nothing.
pub(crate) fn certainly_infeasible(
    rows: &[(DVector<f64>, f64)],
    subset: &[usize],
    tol: f64,
    radius: f64,
) -> bool {
    if !radius.is_finite() {
        return false;
    }
    let rows: Vec<(DVector<f64>, f64)> = subset
        .iter()
        .take(6)
        .filter_map(|&i| {
            let (a, b) = &rows[i];
            let norm = a.norm();
            (norm > 0.0).then(|| (a / norm, (b + tol) / norm))
        })
        .collect();
    let k = rows.len();
    let n = rows.first().map_or(0, |r| r.0.len());
    // Gram matrix of the unit rows: a group's certificate is a near-null vector of its block.
    let gram = DMatrix::from_fn(k, k, |i, j| rows[i].0.dot(&rows[j].0));
    for mask in 1usize..(1 << k) {
        let size = mask.count_ones() as usize;
        if size < 2 || size > n + 1 {
            continue;
        }
        let idx: Vec<usize> = (0..k).filter(|i| mask >> i & 1 == 1).collect();
        let block = DMatrix::from_fn(size, size, |i, j| gram[(idx[i], idx[j])]);
        let Some(eig) = block.try_symmetric_eigen(f64::EPSILON, MAX_ITER) else {
            continue;
        };
        let j = eig.eigenvalues.imin();
        let mut u = eig.eigenvectors.column(j).into_owned();
        if u.sum() < 0.0 {
            u = -u;
        }
        if u.iter().any(|&w| w < 0.0) {
            continue;
        }
        let slack: f64 = idx.iter().zip(u.iter()).map(|(&i, w)| w * rows[i].1).sum();
        // |sum u a|^2 = u' G u (clamped at round-off below zero).
        let residual = eig.eigenvalues[j].max(0.0).sqrt() * u.norm();
        if slack + residual * radius < 0.0 {
            return true;
        }
    }
    false
}

/// min y' p y - 2 q' y  s.t. rows: a' y <= b, by clarabel.
fn clarabel_qp(
    p: &DMatrix<f64>,
    q: &DVector<f64>,
    rows: &[(DVector<f64>, f64)],
    max_iter: u32,
) -> (QpOutcome, u32) {
    let n = p.nrows();
    if n == 0 {
        let out = if rows.iter().all(|(_, b)| *b >= -1e-9) {
            QpOutcome::Solved(DVector::zeros(0))
        } else {
            QpOutcome::Infeasible
        };
        return (out, 0);
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
        max_iter,
        ..DefaultSettings::default()
    };
    let Ok(mut solver) = DefaultSolver::new(&pm, &qv, &am, &b, &cones, settings) else {
        return (QpOutcome::Failed, 0);
    };
    solver.solve();
    let out = match solver.solution.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {
            QpOutcome::Solved(DVector::from_vec(solver.solution.x.clone()))
        }
        SolverStatus::PrimalInfeasible | SolverStatus::AlmostPrimalInfeasible => {
            QpOutcome::Infeasible
        }
        _ => QpOutcome::Failed,
    };
    (out, solver.info.iterations)
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// Rows `a' y <= b`.
    type Rows = Vec<(DVector<f64>, f64)>;

    /// A strictly convex QP in n variables with m rows, from flat random numbers.
    fn problem(n: usize, m: usize, raw: &[f64]) -> (DMatrix<f64>, DVector<f64>, Rows) {
        let mut it = raw.iter().copied().cycle();
        let l = DMatrix::from_fn(n, n, |_, _| it.next().unwrap_or(0.0));
        let p = &l * l.transpose() + DMatrix::identity(n, n) * 0.5;
        let q = DVector::from_fn(n, |_, _| 4.0 * it.next().unwrap_or(0.0));
        let rows = (0..m)
            .map(|_| {
                let a = DVector::from_fn(n, |_, _| it.next().unwrap_or(0.0));
                (a, 0.5 + it.next().unwrap_or(0.0))
            })
            .collect();
        (p, q, rows)
    }

    /// Relative residual of the stationarity condition `2 P y - 2 q + A' lambda = 0` over the
    /// rows active at `y`, with `lambda >= 0` found by projected gradient (nonnegative least
    /// squares): close to 0 exactly when `y` is optimal.
    fn kkt_residual(p: &DMatrix<f64>, q: &DVector<f64>, rows: &Rows, y: &DVector<f64>) -> f64 {
        let g = p * y * 2.0 - q * 2.0;
        let active: Vec<&DVector<f64>> = rows
            .iter()
            .filter(|(a, b)| (a.dot(y) - b).abs() <= 1e-7 * (1.0 + b.abs()))
            .map(|(a, _)| a)
            .collect();
        let mut lambda = vec![0.0; active.len()];
        let lip: f64 = active
            .iter()
            .map(|a| a.norm_squared())
            .sum::<f64>()
            .max(1e-12);
        // The stationarity residual g + A' lambda.
        let residual = |lambda: &[f64]| {
            let mut r = g.clone();
            for (l, a) in lambda.iter().zip(&active) {
                r += *a * *l;
            }
            r
        };
        for _ in 0..20_000 {
            let r = residual(&lambda);
            for (l, a) in lambda.iter_mut().zip(&active) {
                *l = (*l - a.dot(&r) / lip).max(0.0);
            }
        }
        residual(&lambda).norm() / (1.0 + g.norm())
    }

    fn objective(p: &DMatrix<f64>, q: &DVector<f64>, y: &DVector<f64>) -> f64 {
        (y.transpose() * p * y)[0] - 2.0 * q.dot(y)
    }

    /// A degenerate QP (five parallel rows) on which clarabel stops at its iteration limit: the
    /// active set's answer is optimal by its KKT conditions.
    #[test]
    fn degenerate_parallel_rows() {
        // n = 2, m = 9 reads the first 2 x 2 + 2 + 9 x 3 = 33 numbers.
        let raw = [
            0.7964611719908197,
            0.16682786557918028,
            0.4819033729831247,
            -0.7108763538035591,
            -0.3418533686459183,
            0.0,
            0.61079754766398,
            -0.13982040907044438,
            -0.9516624240970072,
            -0.09028970236444211,
            -0.9128247839842484,
            -0.9832785122526998,
            0.0,
            -0.9485237237061783,
            0.3703042068628044,
            0.0,
            -0.7534191839753257,
            0.0,
            0.0,
            -0.8919216581310738,
            0.0,
            -0.45935857082998605,
            0.46390650545339973,
            0.32833910991695975,
            0.0,
            -0.7461782833398346,
            0.8365752077851931,
            0.0,
            -0.7439406636939014,
            0.8188296296837099,
            0.9194901559528216,
            0.0,
            0.0,
        ];
        let (p, q, rows) = problem(2, 9, &raw);
        let mut w = Vec::new();
        let y = active_set(&p, &q, &rows, 1e-9, &mut w, &mut 0).expect("answered");
        for (a, b) in &rows {
            assert!(a.dot(&y) <= b + 1e-9);
        }
        assert!(kkt_residual(&p, &q, &rows, &y) <= 1e-6);
    }

    proptest! {
        // Seeded: the suite gives the same verdict on every run.
        #![proptest_config(ProptestConfig {
            cases: 300,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed_0f9e),
            failure_persistence: None,
            ..ProptestConfig::default()
        })]

        /// Whenever the active-set path answers, its answer is feasible and no worse than
        /// clarabel's (both solve the same convex QP; clarabel stops at its tolerance).
        #[test]
        fn active_set_agrees_with_clarabel(
            n in 1usize..=6,
            m in 1usize..=12,
            raw in prop::collection::vec(-1.0f64..1.0, 120),
        ) {
            let (p, q, rows) = problem(n, m, &raw);
            let tol = 1e-9;
            let mut w = Vec::new();
            if let Some(y) = active_set(&p, &q, &rows, tol, &mut w, &mut 0) {
                for (a, b) in &rows {
                    prop_assert!(a.dot(&y) <= b + tol);
                }
                match clarabel_qp(&p, &q, &rows, 200).0 {
                    QpOutcome::Solved(z) => {
                        let (fy, fz) = (objective(&p, &q, &y), objective(&p, &q, &z));
                        prop_assert!(fy <= fz + 1e-6 * (1.0 + fz.abs()), "{fy} > {fz}");
                    }
                    QpOutcome::Infeasible => {
                        prop_assert!(false, "clarabel calls infeasible a QP the active set solved")
                    }
                    // clarabel stops without converging on some degenerate problems (many
                    // parallel rows through the optimum): check the answer's KKT conditions.
                    QpOutcome::Failed => prop_assert!(
                        kkt_residual(&p, &q, &rows, &y) <= 1e-6,
                        "clarabel did not converge and the answer fails KKT"
                    ),
                }
            }
        }

        /// The Farkas test never calls a polyhedron with a known interior point empty.
        #[test]
        fn certificate_never_rejects_a_feasible_polyhedron(
            n in 1usize..=6,
            m in 1usize..=6,
            raw in prop::collection::vec(-1.0f64..1.0, 60),
            point in prop::collection::vec(-1.0f64..1.0, 6),
        ) {
            let mut it = raw.iter().copied().cycle();
            let y0 = DVector::from_fn(n, |i, _| point[i]);
            let rows: Vec<(DVector<f64>, f64)> = (0..m)
                .map(|_| {
                    let a = DVector::from_fn(n, |_, _| it.next().unwrap_or(0.0));
                    let b = a.dot(&y0) + it.next().unwrap_or(0.0).abs();
                    (a, b)
                })
                .collect();
            let all: Vec<usize> = (0..m).collect();
            prop_assert!(!certainly_infeasible(&rows, &all, 0.0, 10.0));
        }
    }

    /// The active-set path answers most small problems (so that the property above is not
    /// vacuous) and matches clarabel's optimum on each.
    #[test]
    fn active_set_answers_most_problems() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        };
        let (mut answered, total) = (0, 200);
        for k in 0..total {
            let raw: Vec<f64> = (0..120).map(|_| next()).collect();
            let (p, q, rows) = problem(1 + k % 6, 1 + k % 12, &raw);
            let mut w = Vec::new();
            if let Some(y) = active_set(&p, &q, &rows, 1e-9, &mut w, &mut 0) {
                answered += 1;
                let QpOutcome::Solved(z) = clarabel_qp(&p, &q, &rows, 200).0 else {
                    panic!("clarabel disagrees on feasibility");
                };
                let (fy, fz) = (objective(&p, &q, &y), objective(&p, &q, &z));
                assert!((fy - fz).abs() <= 1e-6 * (1.0 + fz.abs()), "{fy} vs {fz}");
            }
        }
        assert!(answered >= total * 3 / 4, "answered {answered} of {total}");
    }

    /// Rows that contradict each other are proven empty: y <= -1 and -y <= -1 (y >= 1).
    #[test]
    fn certificate_proves_contradictory_rows_empty() {
        let a = DVector::from_vec(vec![1.0, 0.0]);
        let rows = vec![(a.clone(), -1.0), (-a, -1.0)];
        assert!(certainly_infeasible(&rows, &[0, 1], 1e-9, 100.0));
        // Relaxed enough to overlap: no certificate.
        let b = DVector::from_vec(vec![1.0, 0.0]);
        let rows = vec![(b.clone(), 1.0), (-b, -0.5)];
        assert!(!certainly_infeasible(&rows, &[0, 1], 1e-9, 100.0));
    }
}
