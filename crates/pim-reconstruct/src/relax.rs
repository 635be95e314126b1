//! A lower bound of an impact fit that needs no search: the same cost with only the momentum
//! balance as constraints.
//!
//! Whatever the coefficients, an impulse at the impact centre C (and, in PIM's free branch, a
//! moment impulse equal and opposite on the two vehicles) conserves the linear momentum and the
//! total angular momentum about C:
//!
//! ```text
//! m1 (V1 - v1) + m2 (V2 - v2) = 0                                  (two rows)
//! sum_i I_i (W_i - w_i) + m_i rho_i x (V_i - v_i) = 0,   rho_i = CG_i - C
//! ```
//!
//! Every solution of the six equations satisfies these three rows, so the least-squares cost
//! under them alone (an equality-constrained quadratic, one linear solve) is a lower bound of
//! the fit's optimal cost.

use nalgebra::{DMatrix, DVector};
use pim_fit::{FitProblem, Knowledge};

/// The minimum of the problem's cost under the momentum balance (and its known components).
pub(crate) fn momentum_bound(problem: &FitProblem) -> f64 {
    let impact = &problem.impact;
    if impact.is_barrier() {
        // A barrier takes up momentum: no balance to bound with.
        return 0.0;
    }
    let [m1, m2] = impact.masses();
    let [i1, i2] = impact.inertias();
    let rho = impact.cg_positions();
    // The cost sum w (a . U - t)^2 as U' H U - 2 g' U + c.
    let mut h = DMatrix::<f64>::zeros(12, 12);
    let mut g = DVector::<f64>::zeros(12);
    let mut c = 0.0;
    let mut add = |a: &[f64; 12], t: f64, w: f64| {
        for i in 0..12 {
            if a[i] == 0.0 {
                continue;
            }
            g[i] += w * a[i] * t;
            for j in 0..12 {
                h[(i, j)] += w * a[i] * a[j];
            }
        }
        c += w * t * t;
    };
    let mut rows: Vec<([f64; 12], f64)> = Vec::new();
    for (k, kn) in problem.components.iter().enumerate() {
        let mut a = [0.0; 12];
        a[k] = 1.0;
        match *kn {
            Knowledge::Estimated { value, weight } => add(&a, value, weight),
            Knowledge::Known { value } => rows.push((a, value)),
            Knowledge::Unknown => {}
        }
    }
    for o in &problem.observations {
        let r = o.row(impact);
        add(&std::array::from_fn(|k| r[k]), o.value, o.weight);
    }
    for cb in &problem.combinations {
        add(&std::array::from_fn(|k| cb.row[k]), cb.value, cb.weight);
    }
    // The momentum rows over U = (x, X).
    let mut px = [0.0; 12];
    let mut py = [0.0; 12];
    let mut l = [0.0; 12];
    for (i, (m, inertia)) in [(m1, i1), (m2, i2)].into_iter().enumerate() {
        let b = 3 * i;
        for (sign, off) in [(-1.0, 0), (1.0, 6)] {
            px[off + b] = sign * m;
            py[off + b + 1] = sign * m;
            // rho x v = rho_x vy - rho_y vx
            l[off + b] = -sign * m * rho[i][1];
            l[off + b + 1] = sign * m * rho[i][0];
            l[off + b + 2] = sign * inertia;
        }
    }
    for a in [px, py, l] {
        let scale = a.iter().fold(0.0_f64, |s, x| s.max(x.abs()));
        rows.push((a.map(|x| x / scale), 0.0));
    }
    // KKT: [H E'; E 0] [U; lambda] = [g; f].
    let n = 12 + rows.len();
    let mut k = DMatrix::<f64>::zeros(n, n);
    let mut rhs = DVector::<f64>::zeros(n);
    k.view_mut((0, 0), (12, 12)).copy_from(&h);
    for i in 0..12 {
        rhs[i] = g[i];
    }
    for (r, (a, f)) in rows.iter().enumerate() {
        for j in 0..12 {
            k[(12 + r, j)] = a[j];
            k[(j, 12 + r)] = a[j];
        }
        rhs[12 + r] = *f;
    }
    let svd = k.svd(true, true);
    let tol = 1e-12 * svd.singular_values.max();
    let Ok(sol) = svd.solve(&rhs, tol) else {
        return 0.0;
    };
    let u = sol.rows(0, 12).into_owned();
    let value = (u.transpose() * &h * &u)[(0, 0)] - 2.0 * g.dot(&u) + c;
    value.max(0.0)
}
