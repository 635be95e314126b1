//! The impact fit of the scenes linearised about their separation states: one step of a
//! combination's refinement ([`crate::refine`]) and the start of each combination.

use crate::error::NoPoint;
use crate::friction_step::FrictionStep;
use crate::point::Lin;
use crate::problem::{Reconstruction, Settings};
use crate::work::Work;
use pim_fit::{
    fit, state_vector, Combination, FitProblem, MomentBranch, Solution, Status as FitStatus,
    Vector12,
};

/// An impact fit's work in run-out evaluations (a run-out's right-hand side: 0.7 us): each
/// branch on the convex route [`CONVEX_FIT_EVALUATIONS`], on the grid route one per operation
/// of its search (cost evaluation, exact solve, QP solve, grid point), plus one per elementary
/// operation of its inner problems (pim-fit's `Certificate::operations`: linear solves,
/// active-set steps, interior-point iterations). Measured over 450 fits of ordinary and hostile
/// scenes, an operation so counted takes 0.36 to 1.3 us whatever the problem, so the count
/// bounds the time within a small factor on a given machine; it does not time it.
fn fit_work(report: &pim_fit::FitReport) -> u64 {
    let search: u64 = report
        .branches
        .iter()
        .map(|b| {
            let c = &b.certificate;
            match c.method.route {
                pim_fit::Route::Convex => CONVEX_FIT_EVALUATIONS,
                pim_fit::Route::Grid => {
                    (c.evaluations + c.exact_solves + c.qp_solves + c.grid_points) as u64
                }
            }
        })
        .sum();
    // The operations are counted once for the whole fit (every branch).
    search
        + report
            .branches
            .first()
            .map_or(0, |b| b.certificate.operations)
}

/// An impact fit on the convex route, in run-out evaluations.
pub(crate) const CONVEX_FIT_EVALUATIONS: u64 = 150;

/// The impact fit with each scene linearised (rows in chi-square units, weight 1 each) and,
/// with `damping`, Marquardt's rows that keep the separation state near the current one. Every
/// weight is scaled by one factor into (0, 1]; the fit's cost over that factor is the
/// chi-square of the linearised problem. With fitted frictions, the scenes' rows and the
/// frictions' own rows are projected onto the complement of the frictions' columns: the
/// linearised cost minimised over the frictions for every velocity state (exact for a linear
/// model), and the [`FrictionStep`] that gives those frictions back.
pub(crate) fn assemble(
    r: &Reconstruction,
    lins: &[Lin],
    damping: Option<(f64, &[Lin])>,
    at: Option<&Vector12>,
) -> (FitProblem, f64, Option<FrictionStep>) {
    let unit = r.unit.unwrap_or(1.0);
    let mut problem = r.contact.clone();
    // Chi-square weights first.
    for w in problem.weights_mut() {
        *w /= unit;
    }
    // The nonlinear evidence linearised at the current state (none before the first).
    if let Some(u) = at {
        problem.combinations.extend(nonlinear_rows(r, u));
    }
    let step = if r.frictions.is_empty() {
        for l in lins {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            let j = l.jacobian();
            for i in 0..j.nrows() {
                let mut row = Vector12::zeros();
                let mut target = -l.lin.weighted[i];
                for c in 0..3 {
                    row[base + c] = j[(i, c)];
                    target += j[(i, c)] * l.at[c];
                }
                push_row(&mut problem, row, target);
            }
        }
        None
    } else {
        let step = FrictionStep::new(r, lins);
        let projected = step.projected();
        for k in 0..projected.0.nrows() {
            let row = Vector12::from_iterator(projected.0.row(k).iter().copied());
            push_row(&mut problem, row, row.dot(&step.at) - projected.1[k]);
        }
        Some(step)
    };
    if let Some((lambda, around)) = damping {
        for l in around {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            let j = l.jacobian();
            let jtj = j.transpose() * j;
            let largest = (0..3).map(|c| jtj[(c, c)]).fold(0.0, f64::max).max(1e-12);
            for c in 0..3 {
                let mut row = Vector12::zeros();
                row[base + c] = 1.0;
                problem.combinations.push(Combination {
                    row,
                    value: l.at[c],
                    weight: lambda * jtj[(c, c)].max(1e-6 * largest),
                });
            }
        }
    }
    let largest = problem.weights_mut().fold(0.0_f64, |m, w| m.max(*w));
    let scale = if largest > 0.0 { 1.0 / largest } else { 1.0 };
    for w in problem.weights_mut() {
        *w = (*w * scale).max(f64::MIN_POSITIVE);
    }
    (problem, scale, step)
}

/// A linearised row `(row . U - target)^2` as a combination of the problem (a row that no
/// velocity moves adds only a constant and is left out).
fn push_row(problem: &mut FitProblem, row: Vector12, target: f64) {
    let norm = row.norm();
    if norm > 1e-12 {
        problem.combinations.push(Combination {
            row: row / norm,
            value: target / norm,
            weight: norm * norm,
        });
    }
}

/// Each piece of nonlinear evidence linearised at `u`, `z(U) ~ z(u) + g (U - u)` with `z` the
/// residual in standard deviations and `g` by forward differences over the free components:
/// a combination row in chi-square units.
fn nonlinear_rows(r: &Reconstruction, u: &Vector12) -> Vec<Combination> {
    let z = |v: &Vector12, t: &dyn crate::StateEvidence| t.residual(v).map(|(x, s)| x / s);
    let free: Vec<usize> = (0..12)
        .filter(|&k| !matches!(r.contact.components[k], pim_fit::Knowledge::Known { .. }))
        .collect();
    let mut rows = Vec::new();
    for t in &r.nonlinear.0 {
        let Some(z0) = z(u, t.as_ref()) else { continue };
        let mut g = Vector12::zeros();
        for &k in &free {
            let h = 1e-6 * (1.0 + u[k].abs());
            let mut v = *u;
            v[k] += h;
            if let Some(z1) = z(&v, t.as_ref()) {
                g[k] = (z1 - z0) / h;
            }
        }
        let norm = g.norm();
        if norm > 1e-300 {
            rows.push(Combination {
                row: g / norm,
                value: (g.dot(u) - z0) / norm,
                weight: norm * norm,
            });
        }
    }
    rows
}

/// An impact fit's answer: its branch, solution and certificate, and the frictions that go
/// with its velocities.
pub(crate) struct Fitted {
    pub(crate) branch: MomentBranch,
    pub(crate) solution: Solution,
    pub(crate) certificate: pim_fit::Certificate,
    pub(crate) mus: Vec<f64>,
    /// The linearised problem's chi-square at the fit (damping rows included).
    pub(crate) predicted: f64,
}

/// How an impact fit of the linearised problem may move the separation state.
#[derive(Clone, Copy)]
pub(crate) enum Step<'a> {
    /// Freely (Gauss-Newton's step).
    Free,
    /// Kept near the scenes' linearisation points by Marquardt's damping `lambda`.
    Damped(f64, &'a [Lin]),
    /// Not at all: held at the scenes' linearisation points (the impact fitted to them).
    Held,
}

impl<'a> Step<'a> {
    /// Marquardt's damping `lambda` about `around` (none at 0).
    pub(crate) fn marquardt(lambda: f64, around: &'a [Lin]) -> Step<'a> {
        if lambda > 0.0 {
            Step::Damped(lambda, around)
        } else {
            Step::Free
        }
    }
}

/// One impact fit of the linearised problem: the best optimal branch, or why there is none.
pub(crate) fn fit_once(
    r: &Reconstruction,
    settings: &Settings,
    lins: &[Lin],
    step: Step<'_>,
    at: Option<&Vector12>,
    work: &Work,
) -> std::result::Result<Fitted, NoPoint> {
    let damping = match step {
        Step::Damped(lambda, around) => Some((lambda, around)),
        Step::Free | Step::Held => None,
    };
    let (mut problem, scale, frictions) = assemble(r, lins, damping, at);
    if matches!(step, Step::Held) {
        for l in lins {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            for c in 0..3 {
                problem.components[base + c] = pim_fit::Knowledge::Known { value: l.at[c] };
            }
        }
    }
    let report = fit(&problem, &settings.fit)?;
    work.add(fit_work(&report));
    let best = report.best_branch().ok_or_else(|| {
        NoPoint::NoImpact(
            report
                .branches
                .iter()
                .find_map(|b| b.reason.as_ref().map(|x| x.to_string()))
                .unwrap_or_else(|| "no admissible impact".into()),
        )
    })?;
    match (&best.status, &best.solution) {
        (FitStatus::Optimal, Some(s)) => {
            let mus = frictions.map_or_else(Vec::new, |st| {
                st.frictions_at(&state_vector(&s.initial, &s.separation))
            });
            Ok(Fitted {
                branch: best.moment,
                solution: s.clone(),
                certificate: best.certificate.clone(),
                mus,
                predicted: s.cost / scale,
            })
        }
        _ => Err(NoPoint::Ended(best.status)),
    }
}
