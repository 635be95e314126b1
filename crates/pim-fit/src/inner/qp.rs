//! Linear algebra of the inner problem: the null space of the fixed components, a symmetric
//! solve that falls back to the pseudo-inverse, and the QP adaptor (clarabel stays behind it).

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

/// min y' p y - 2 q' y  s.t. rows: a' y <= b, by clarabel (private adaptor).
pub(crate) fn qp(
    p: &DMatrix<f64>,
    q: &DVector<f64>,
    rows: &[(DVector<f64>, f64)],
    max_iter: u32,
) -> QpOutcome {
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
        max_iter,
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
