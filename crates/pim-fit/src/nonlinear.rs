//! Evidence that is a smooth, nonlinear function of the twelve velocity components (an energy
//! loss, which is quadratic in them, scaled by factors that move with the impulse): fitted
//! with the exact fit inside a Gauss-Newton iteration.
//!
//! The cost is `Q(U) + u sum_j r_j(U)^2`, with `Q` the problem's own (linear) evidence, `r_j`
//! each term's residual in standard deviations and `u` the unit of the problem's
//! inverse-variance weights (1 for a cost without standard deviations: its velocity
//! residuals then count as if their standard deviation were 1 m/s). Each step replaces every
//! `r_j` by its linearisation at the current point (forward differences) as a
//! [`Combination`] row and solves that problem exactly with [`crate::fit`] (PIM's equations
//! and every admissibility condition hold at every step); a step that does not lower the true
//! cost is retried with Marquardt's damping rows. It starts from the optimum of each moment
//! branch without the terms and keeps the best end. When no end meets the lower bound below, it
//! starts again from the problem's optimum within each of [`E_SLICES`] slices of the e range:
//! the terms (an energy) need not be monotone along the solutions the problem alone leaves
//! open, and a descent from one of them can stop at a local minimum (at the edge of the e
//! range) while the evidence is met exactly elsewhere.
//!
//! **What is proven.** The terms only add to the cost, so the certified optimum without them
//! is a lower bound of the optimum with them. When the end's cost meets that bound (within
//! `1e-6` relative) the end is the global optimum; otherwise it is the best found, and the gap
//! to the bound is reported.

use crate::problem::{state_vector, Combination, FitProblem, Knowledge, MomentBranch, Vector12};
use crate::report::{FitReport, Solution, Status};
use crate::settings::ValidSettings;
use crate::Result;
use pim_core::damped::{self, Damped, Limit, Linearised, Lower, Progress, Rules, Step, Verdict};
use serde::Serialize;

/// A residual in standard deviations, `(observed - predicted) / sigma`, as a function of
/// `U = (initial, separation)`. `None` where it is not defined (e.g. no impulse).
pub trait NonlinearTerm: Sync {
    /// The residual at `u`.
    fn residual(&self, u: &Vector12) -> Option<f64>;
}

/// How the nonlinear fit ended.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct NonlinearFit {
    /// The moment branch of the best end.
    pub moment: MomentBranch,
    /// The fitted coefficients and velocities (its `cost` is that of the last linearised
    /// problem; [`NonlinearFit::cost`] is the true one).
    pub solution: Solution,
    /// The true cost at the end: the problem's own evidence plus `u r^2` of each term.
    pub cost: f64,
    /// The problem's own evidence alone at the end.
    pub linear_cost: f64,
    /// Each term's residual at the end, standard deviations.
    pub residuals: Vec<f64>,
    /// The certified optimum of the problem without the terms: a lower bound of `cost`'s
    /// optimum.
    pub lower_bound: f64,
    /// True when `cost` meets `lower_bound` (within 1e-6 relative): the end is the global
    /// optimum.
    pub proven: bool,
    /// Exact fits solved, over all starts.
    pub fits: usize,
    /// Gauss-Newton iterations of the best start.
    pub iterations: usize,
    /// Whether the best start's iteration met its convergence test.
    pub converged: bool,
}

/// Relative gap under which the end is taken as proven optimal.
pub const PROVEN_GAP: f64 = 1e-6;

/// The problem's own cost at `u` (what [`crate::fit`] minimises).
pub fn linear_cost(problem: &FitProblem, u: &Vector12) -> f64 {
    let mut q = 0.0;
    for (k, c) in problem.components.iter().enumerate() {
        if let Knowledge::Estimated { value, weight } = c {
            q += weight * (u[k] - value).powi(2);
        }
    }
    for o in &problem.observations {
        q += o.weight * (o.row(&problem.impact).dot(u) - o.value).powi(2);
    }
    for c in &problem.combinations {
        q += c.weight * (c.row.dot(u) - c.value).powi(2);
    }
    q
}

fn true_cost(
    problem: &FitProblem,
    unit: f64,
    terms: &[&dyn NonlinearTerm],
    u: &Vector12,
) -> Option<(f64, f64, Vec<f64>)> {
    let q = linear_cost(problem, u);
    let r: Option<Vec<f64>> = terms.iter().map(|t| t.residual(u)).collect();
    let r = r?;
    Some((q + unit * r.iter().map(|x| x * x).sum::<f64>(), q, r))
}

/// The free components of U: neither known nor held at 0 by a barrier.
fn free(problem: &FitProblem) -> Vec<usize> {
    (0..12)
        .filter(|&k| !matches!(problem.components[k], Knowledge::Known { .. }))
        .collect()
}

/// The linearised problem at `u`: each term as a row, and with `lambda > 0` Marquardt's rows
/// holding the free components near `u`. Its weights scaled into (0, 1] by one factor,
/// returned with it.
fn assemble(
    problem: &FitProblem,
    unit: f64,
    terms: &[&dyn NonlinearTerm],
    u: &Vector12,
    lambda: f64,
) -> Option<(FitProblem, f64)> {
    let mut p = problem.clone();
    let free = free(problem);
    let mut diag = [0.0_f64; 12];
    for t in terms {
        let r0 = t.residual(u)?;
        let mut g = Vector12::zeros();
        for &k in &free {
            let h = 1e-6 * (1.0 + u[k].abs());
            let mut v = *u;
            v[k] += h;
            g[k] = (t.residual(&v)? - r0) / h;
        }
        let norm = g.norm();
        if norm > 1e-300 {
            // r(U) ~ r0 + g.(U - u): the row (g/|g|) . U with target (g.u - r0)/|g|.
            p.combinations.push(Combination {
                row: g / norm,
                value: (g.dot(u) - r0) / norm,
                weight: unit * norm * norm,
            });
        }
        for k in 0..12 {
            diag[k] += unit * g[k] * g[k];
        }
    }
    if lambda > 0.0 {
        let largest = diag.iter().cloned().fold(0.0, f64::max).max(1e-12);
        for &k in &free {
            let mut row = Vector12::zeros();
            row[k] = 1.0;
            p.combinations.push(Combination {
                row,
                value: u[k],
                weight: lambda * diag[k].max(1e-6 * largest),
            });
        }
    }
    let largest = p.weights_mut().fold(0.0_f64, |m, w| m.max(*w));
    let scale = if largest > 1.0 { 1.0 / largest } else { 1.0 };
    for w in p.weights_mut() {
        *w = (*w * scale).max(f64::MIN_POSITIVE);
    }
    Some((p, scale))
}

/// The best optimal branch of a report, with its moment.
fn best(report: &FitReport, moment: Option<MomentBranch>) -> Option<(MomentBranch, Solution)> {
    report
        .branches
        .iter()
        .filter(|b| b.status == Status::Optimal && moment.is_none_or(|m| m == b.moment))
        .filter_map(|b| b.solution.clone().map(|s| (b.moment, s)))
        .min_by(|a, b| a.1.cost.total_cmp(&b.1.cost))
}

struct End {
    moment: MomentBranch,
    solution: Solution,
    cost: f64,
    linear: f64,
    residuals: Vec<f64>,
    iterations: usize,
    converged: bool,
}

/// Fits `problem` with the nonlinear `terms` added to its cost (see the module's text).
/// `base` is the certified fit of `problem` alone (its optimum is the lower bound and each
/// branch's optimum a start); `unit` the unit of the problem's inverse-variance weights.
/// `None` when no start has an admissible optimum or every term is undefined there.
///
/// # Errors
/// The errors of [`crate::fit`].
pub fn fit_nonlinear(
    problem: &FitProblem,
    base: &FitReport,
    unit: f64,
    terms: &[&dyn NonlinearTerm],
    settings: &ValidSettings,
) -> Result<Option<NonlinearFit>> {
    let Some((_, lowest)) = best(base, None) else {
        return Ok(None);
    };
    let lower_bound = lowest.cost;
    let meets = |cost: f64| cost - lower_bound <= PROVEN_GAP * (1.0 + lower_bound.abs());
    let mut fits = 0;
    let mut ends: Vec<End> = Vec::new();
    for (moment, start) in optima(base) {
        ends.extend(descend(
            problem, unit, terms, settings, moment, start, &mut fits,
        )?);
    }
    // An end above the bound may be a local minimum of the terms along the solutions the
    // problem alone leaves open (an energy that is not monotone along them): start again from
    // the problem's optimum within each slice of the e range, so that every part of that set
    // is reached from a start of its own.
    if !ends.iter().any(|e| meets(e.cost)) {
        let [lo, hi] = settings.0.e;
        for k in 0..E_SLICES {
            let mut slice = settings.clone();
            let w = (hi - lo) / E_SLICES as f64;
            slice.0.e = [lo + w * k as f64, lo + w * (k + 1) as f64];
            slice.0.ranges = false;
            fits += 1;
            let report = crate::fit(problem, &slice)?;
            for (moment, start) in optima(&report) {
                ends.extend(descend(
                    problem, unit, terms, settings, moment, start, &mut fits,
                )?);
            }
        }
    }
    let Some(end) = ends.into_iter().min_by(|a, b| a.cost.total_cmp(&b.cost)) else {
        return Ok(None);
    };
    Ok(Some(NonlinearFit {
        moment: end.moment,
        solution: end.solution,
        cost: end.cost,
        linear_cost: end.linear,
        residuals: end.residuals,
        lower_bound,
        proven: meets(end.cost),
        fits,
        iterations: end.iterations,
        converged: end.converged,
    }))
}

/// Slices of the e range a second round of starts is taken from (see [`fit_nonlinear`]).
pub const E_SLICES: usize = 5;

/// Each optimal branch's solution of a report, with its moment.
fn optima(report: &FitReport) -> Vec<(MomentBranch, Solution)> {
    report
        .branches
        .iter()
        .filter(|b| b.status == Status::Optimal)
        .filter_map(|b| b.solution.clone().map(|s| (b.moment, s)))
        .collect()
}

/// A point of the Gauss-Newton iteration: the exact fit's solution and its true cost, the
/// problem's own evidence's share and each term's residual.
struct At {
    solution: Solution,
    cost: f64,
    linear: f64,
    residuals: Vec<f64>,
}

/// The iteration on one moment branch as a damped least-squares problem: each step is the
/// exact fit of the problem with the terms linearised at the current point (Marquardt's rows
/// added with `lambda > 0`).
struct Descent<'a> {
    problem: &'a FitProblem,
    unit: f64,
    terms: &'a [&'a dyn NonlinearTerm],
    one: ValidSettings,
    moment: MomentBranch,
    fits: &'a mut usize,
}

impl Damped for Descent<'_> {
    type Point = At;
    type Reason = ();
    type Error = crate::FitError;

    fn cost(&self, p: &At) -> f64 {
        p.cost
    }

    fn linearise(&mut self, _: &At, _: bool) -> Result<Linearised> {
        // Each step linearises the terms itself, with its damping rows.
        Ok(Linearised::Ready)
    }

    fn step(&mut self, at: &At, lambda: f64) -> Result<Step<At>> {
        let u = state_vector(&at.solution.initial, &at.solution.separation);
        let Some((p, _)) = assemble(self.problem, self.unit, self.terms, &u, lambda) else {
            return Ok(Step::Unavailable);
        };
        *self.fits += 1;
        let trial = crate::fit(&p, &self.one)?;
        let next = best(&trial, Some(self.moment)).and_then(|(_, t)| {
            let v = state_vector(&t.initial, &t.separation);
            true_cost(self.problem, self.unit, self.terms, &v).map(|c| (t, c))
        });
        Ok(match next {
            Some((solution, (cost, linear, residuals))) => Step::Trial {
                point: At {
                    solution,
                    cost,
                    linear,
                    residuals,
                },
                predicted: f64::NAN,
            },
            None => Step::Failed,
        })
    }

    fn accepted(&mut self, from: &At, to: &At, _: &Progress) -> Verdict<()> {
        let gain = from.cost - to.cost;
        let u = state_vector(&from.solution.initial, &from.solution.separation);
        let step = (state_vector(&to.solution.initial, &to.solution.separation) - u).amax();
        if gain <= 1e-10 * (1.0 + to.cost) || step < 1e-10 {
            Verdict::Converged
        } else {
            Verdict::Continue
        }
    }
}

/// The Gauss-Newton iteration from `start` on the `moment` branch (see the module's text):
/// undamped until a step fails to lower the true cost, then damped from `lambda` 1e-4, ten
/// times more after each failure (a minimum above 1e6), undamped again after a success; at
/// most 60 steps. `None` when a term is undefined at the start.
fn descend(
    problem: &FitProblem,
    unit: f64,
    terms: &[&dyn NonlinearTerm],
    settings: &ValidSettings,
    moment: MomentBranch,
    start: Solution,
    fits: &mut usize,
) -> Result<Option<End>> {
    let u0 = state_vector(&start.initial, &start.separation);
    let Some((cost, linear, residuals)) = true_cost(problem, unit, terms, &u0) else {
        return Ok(None);
    };
    let mut one = settings.clone();
    one.0.branches = vec![moment];
    let rules = Rules {
        start: 0.0,
        first: 1e-4,
        raise: 10.0,
        lower: Lower::Reset,
        most: 1e6,
        tries: None,
        limit: Limit::Trials(60),
    }
    .checked()
    .expect("the nonlinear fit's damping rules are in range");
    let mut descent = Descent {
        problem,
        unit,
        terms,
        one,
        moment,
        fits,
    };
    let at = At {
        solution: start,
        cost,
        linear,
        residuals,
    };
    let end = damped::minimise(&mut descent, at, &rules)?;
    Ok(Some(End {
        moment,
        solution: end.point.solution,
        cost: end.point.cost,
        linear: end.point.linear,
        residuals: end.point.residuals,
        iterations: end.trials,
        converged: end.termination.converged(),
    }))
}
