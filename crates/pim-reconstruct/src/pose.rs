//! The pose at contact fitted: where the vehicles met as unknowns of the whole reconstruction.
//!
//! See [`fit_pose`].

use crate::error::{ReconstructError, Result};
use crate::outcome::Found;
use crate::point::{linearised, velocity_of, Lin};
use crate::problem::{Reconstruction, Settings};
use crate::refine::refine_start;
use crate::work::Work;
use nalgebra::{DMatrix, DVector};
use pim_core::damped::{self, Damped, Limit, Linearised, Progress, Rules, Step, Verdict};
use rayon::prelude::*;
use serde::Serialize;

/// The most Levenberg-Marquardt iterations of a pose fit.
pub const MAX_ITERATIONS: usize = 20;

/// One unknown of the pose at contact.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PoseUnknown {
    /// Its name in tables (`vehicle2.impact_point.x`).
    pub name: String,
    /// The standard deviation of its prior about the stated pose, m or rad; it also scales
    /// the fit's steps and tolerances for this unknown.
    pub sigma: f64,
    /// Whether the prior weighs in the cost (false: the prior left out, the value still
    /// fitted, as a row of the consistency table leaves it out).
    pub prior: bool,
}

/// Where a pose fit starts: offsets (m and rad) and the answer there, or near there (a draw of
/// a study starts from the nominal answer); with a Jacobian of the residuals (that of a fit
/// before, [`PoseFit::jacobian`]) either held through the iterations rather than taken again
/// (a draw whose evidence moved a little from the nominal's) or taken as the first.
#[derive(Debug, Clone, Copy)]
pub struct PoseStart<'a> {
    /// The offsets, one per unknown.
    pub offsets: &'a [f64],
    /// The answer to refit from.
    pub found: &'a Found,
    /// A Jacobian at the start.
    pub jacobian: Option<&'a DMatrix<f64>>,
    /// Whether the Jacobian is held (else updated and differenced again as the fit goes).
    pub hold: bool,
}

/// The fitted pose at contact and the answer there.
#[derive(Debug, Clone, PartialEq)]
pub struct PoseFit {
    /// The offsets from the stated pose, one per unknown, m or rad.
    pub offsets: Vec<f64>,
    /// Their standard deviations at the answer (linearised), m or rad.
    pub sigmas: Vec<f64>,
    /// The priors' share of the cost: `sum (offset / sigma)^2`.
    pub prior_chi_square: f64,
    /// The reconstruction at the fitted pose (its chi-square without the priors).
    pub found: Found,
    /// Levenberg-Marquardt iterations.
    pub iterations: usize,
    /// Stopped by its tolerance (not by its limit or a step that could not be taken).
    pub converged: bool,
    /// Reconstructions refitted.
    pub refits: usize,
    /// The combination of counts of turns the fit held.
    pub counts: Vec<Option<i64>>,
    /// The Jacobian of the residuals (in standard deviations) with respect to the offsets at
    /// the answer, the data's alone (the priors' rows are `1 / sigma` on the diagonal).
    pub jacobian: DMatrix<f64>,
}

/// Every residual of a found reconstruction in standard deviations, in a fixed order: the
/// contact evidence, the fitted frictions, each scene's residuals. Their squares sum to its
/// chi-square.
pub fn residual_z(r: &Reconstruction, f: &Found) -> Vec<f64> {
    crate::outcome::evidence_z(r, f)
        .into_iter()
        .map(|(_, z)| z)
        .collect()
}

/// The reconstruction `r` refitted from the answer `from` of a neighbouring one: each scene's
/// count of turns and separation state, the frictions where it fits them.
///
/// # Errors
/// A run-out or fit that cannot start; [`ReconstructError::Input`] where no admissible impact
/// is found from there.
pub fn refit(r: &Reconstruction, settings: &Settings, from: &Found) -> Result<Found> {
    let mus = if from.frictions.len() == r.frictions.len() {
        from.frictions.clone()
    } else {
        crate::point::stated_frictions(r)
    };
    let start: Vec<Lin> = r
        .scene
        .iter()
        .enumerate()
        .map(|(v, s)| {
            let turns = from
                .scene
                .iter()
                .find(|f| f.vehicle == s.id)
                .and_then(|f| f.turns)
                .unwrap_or(0);
            let at = velocity_of(&from.solution.separation, s);
            linearised(r, settings, v, turns, at, true, &mus)
        })
        .collect::<Result<_>>()?;
    let work = Work::new(settings.refine_work);
    let contact = pim_fit::state_vector(&from.solution.initial, &from.solution.separation);
    let x = refine_start(r, settings, start, Some(contact), &work).map_err(|reason| {
        ReconstructError::Input {
            field: "pose",
            reason: reason.to_string(),
        }
    })?;
    Ok(Found::new(r, x.point, x.iterations, x.converged))
}

/// A point of the pose fit: the offsets, the answer there, its residuals and its whole cost.
pub(crate) struct At {
    pub(crate) p: Vec<f64>,
    pub(crate) found: Found,
    z: Vec<f64>,
    pub(crate) cost: f64,
}

impl At {
    /// The point at offsets `p` of the reconstruction `r` there, refitted from `from`.
    pub(crate) fn refitted(
        (r, settings): (&Reconstruction, &Settings),
        unknowns: &[PoseUnknown],
        p: &[f64],
        from: &Found,
    ) -> Result<At> {
        let found = refit(r, settings, from)?;
        let z = residual_z(r, &found);
        Ok(At {
            cost: cost_of(&z, p, unknowns),
            p: p.to_vec(),
            found,
            z,
        })
    }
}

/// The reconstruction at a pose, refitted: `build` gives it at offsets, each refit counted.
struct Evaluator<'a, F> {
    build: &'a F,
    unknowns: &'a [PoseUnknown],
    settings: &'a Settings,
    refits: std::sync::atomic::AtomicUsize,
}

impl<'a, F> Evaluator<'a, F>
where
    F: Fn(&[f64]) -> Result<Reconstruction> + Sync,
{
    fn new(build: &'a F, unknowns: &'a [PoseUnknown], settings: &'a Settings) -> Self {
        Evaluator {
            build,
            unknowns,
            settings,
            refits: std::sync::atomic::AtomicUsize::new(0),
        }
    }

    /// The point at offsets `p`, refitted from `from`.
    fn eval(&self, p: &[f64], from: &Found) -> Result<At> {
        self.refits
            .fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let r = (self.build)(p)?;
        At::refitted((&r, self.settings), self.unknowns, p, from)
    }

    /// Refits so far.
    fn refits(&self) -> usize {
        self.refits.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// The priors' share of the cost at offsets `p`: `sum (p_j / s_j)^2`.
fn prior_cost(p: &[f64], unknowns: &[PoseUnknown]) -> f64 {
    p.iter()
        .zip(unknowns)
        .filter(|(_, u)| u.prior)
        .map(|(x, u)| (x / u.sigma).powi(2))
        .sum()
}

fn cost_of(z: &[f64], p: &[f64], unknowns: &[PoseUnknown]) -> f64 {
    z.iter().map(|x| x * x).sum::<f64>() + prior_cost(p, unknowns)
}

/// Fits the pose at contact: `build` gives the reconstruction at offsets `p` (one per unknown,
/// zeros: the stated pose), `start` is the answer at the stated pose.
///
/// The impact's geometry (each impact point, heading and the crush surface) and each run-out's
/// start are inputs of a [`Reconstruction`]. Where they are uncertain, each is an unknown `p_j`
/// (an offset from the stated pose, m or rad) with a prior of standard deviation `s_j`, and the
/// cost is
///
/// ```text
/// F(p) = chi2*(p) + sum_j (p_j / s_j)^2,    chi2*(p) = min over the rest of chi2(p, rest)
/// ```
///
/// with the rest (coefficients, both velocity states, fitted frictions) refitted at every `p`
/// from the answer at the point before (variable projection, Golub and Pereyra 1973: the
/// residuals `z*(p)` of the refitted reconstruction are a function of `p` alone, and their
/// Jacobian by central differences of refits is that of the reduced problem). `F` is minimised
/// by Levenberg-Marquardt (damping `lambda diag(A)`, `A = J^T J + diag(1/s^2)`; `lambda` from
/// 1e-3, times 4 after a failed step, divided by 3 after a success), with the count of turns of
/// each vehicle held at the starting answer's. The Jacobian is differenced at the start and
/// then updated by Broyden's rank-one rule after each accepted step (in the priors' metric),
/// differenced again before convergence is declared on an updated one or where an updated one
/// finds no lower cost: each difference is a refit, and the updates need none (on a realistic
/// crash with six unknowns, 48 refits in 14 iterations and 9.4 s against 82 refits in 6
/// iterations and 12.1 s differencing at every step, the refits of one Jacobian run in
/// parallel). It stops when a step's predicted gain is below 1e-4 `(1 + F)` (a chi-square far
/// below any that decides a question) or every step is below 1e-2 of its prior's deviation,
/// after `MAX_ITERATIONS` (20) otherwise.
///
/// The offsets' standard deviations are those of the linearised problem, `sqrt(diag(A^-1))` at
/// the answer: what the scene and the impact add to the prior (never more than the prior's).
/// The differences are taken with steps of a tenth of each prior's deviation.
///
/// # Errors
/// `build`'s errors; a refit that cannot start at the stated pose.
pub fn fit_pose<F>(
    build: F,
    unknowns: &[PoseUnknown],
    settings: &Settings,
    start: PoseStart<'_>,
) -> Result<PoseFit>
where
    F: Fn(&[f64]) -> Result<Reconstruction> + Sync,
{
    if let Some(u) = unknowns
        .iter()
        .find(|u| !(u.sigma.is_finite() && u.sigma > 0.0))
    {
        return Err(ReconstructError::Input {
            field: "pose",
            reason: format!("{}: a standard deviation above 0", u.name),
        });
    }
    let n = unknowns.len();
    let ev = Evaluator::new(&build, unknowns, settings);
    let eval = |p: &[f64], from: &Found| ev.eval(p, from);
    if start.offsets.len() != n {
        return Err(ReconstructError::Input {
            field: "pose",
            reason: format!("{} offsets for {n} unknowns", start.offsets.len()),
        });
    }
    let at = eval(start.offsets, start.found)?;
    let given = start
        .jacobian
        .filter(|j| j.nrows() == at.z.len() && j.ncols() == n);
    let held = given.filter(|_| start.hold);
    let rules = Rules {
        most: f64::INFINITY,
        tries: Some(12),
        ..Rules::classic(1e-9, Limit::Linearisations(MAX_ITERATIONS))
    }
    .checked()
    .expect("the pose fit's damping rules are in range");
    let mut descent = Descent {
        eval: &eval,
        unknowns,
        held: held.is_some(),
        next: given.cloned(),
        fresh: true,
        current: DMatrix::zeros(0, 0),
        normal: (DMatrix::zeros(0, 0), DVector::zeros(0)),
        last: None,
    };
    let end = match damped::minimise(&mut descent, at, &rules) {
        Ok(end) => end,
        Err(never) => match never {},
    };
    let (at, iterations, converged) = (end.point, end.linearisations, end.termination.converged());
    let last = descent.last;
    let a_last = last.as_ref().map(|j| normal_equations(j, &at, unknowns).0);
    let sigmas = match a_last.and_then(|a| a.try_inverse()) {
        Some(inv) => (0..n).map(|j| inv[(j, j)].max(0.0).sqrt()).collect(),
        None => unknowns.iter().map(|u| u.sigma).collect(),
    };
    let prior_chi_square = prior_cost(&at.p, unknowns);
    let jacobian = last.unwrap_or_else(|| DMatrix::zeros(at.z.len(), n));
    Ok(PoseFit {
        jacobian,
        offsets: at.p,
        sigmas,
        prior_chi_square,
        found: at.found,
        iterations,
        converged,
        refits: ev.refits(),
        counts: start.found.counts(),
    })
}

/// The normal equations of the data and the priors at `at` with the Jacobian `j`: `A = J^T J +
/// diag(1/s^2)`, `g = J^T z + p / s^2`.
fn normal_equations(
    j: &DMatrix<f64>,
    at: &At,
    unknowns: &[PoseUnknown],
) -> (DMatrix<f64>, DVector<f64>) {
    let mut a = j.transpose() * j;
    let mut g = j.transpose() * DVector::from_column_slice(&at.z);
    for (k, u) in unknowns.iter().enumerate().filter(|(_, u)| u.prior) {
        a[(k, k)] += 1.0 / (u.sigma * u.sigma);
        g[k] += at.p[k] / (u.sigma * u.sigma);
    }
    (a, g)
}

/// The pose fit as a damped least-squares problem: the Jacobian differenced (or held, or
/// given), updated by Broyden's rule after each accepted step, differenced again where an
/// updated one finds no step; Marquardt's damping `A_kk (1 + lambda)`.
struct Descent<'a, E> {
    eval: &'a E,
    unknowns: &'a [PoseUnknown],
    /// The Jacobian is held through the iterations.
    held: bool,
    /// The Jacobian for the next linearisation (given, held or updated), if any.
    next: Option<DMatrix<f64>>,
    /// The Jacobian in use was differenced (or given) at its point, not updated.
    fresh: bool,
    /// The Jacobian in use and its normal equations.
    current: DMatrix<f64>,
    normal: (DMatrix<f64>, DVector<f64>),
    /// The Jacobian of the answer (the one in use, updated after the last accepted step).
    last: Option<DMatrix<f64>>,
}

impl<E> Damped for Descent<'_, E>
where
    E: Fn(&[f64], &Found) -> Result<At> + Sync,
{
    type Point = At;
    type Reason = ();
    type Error = std::convert::Infallible;

    fn cost(&self, p: &At) -> f64 {
        p.cost
    }

    fn linearise(&mut self, at: &At, exact: bool) -> std::result::Result<Linearised, Self::Error> {
        if exact {
            self.next = None;
        }
        let j = match self.next.take() {
            Some(j) => j,
            None => {
                self.fresh = true;
                match jacobian(self.eval, at, self.unknowns) {
                    Some(j) => j,
                    None => return Ok(Linearised::Impossible),
                }
            }
        };
        self.normal = normal_equations(&j, at, self.unknowns);
        self.last = Some(j.clone());
        self.current = j;
        Ok(Linearised::Ready)
    }

    fn exact(&self) -> bool {
        self.fresh || self.held
    }

    fn step(&mut self, at: &At, lambda: f64) -> std::result::Result<Step<At>, Self::Error> {
        let (a, g) = &self.normal;
        let mut damped = a.clone();
        for k in 0..self.unknowns.len() {
            damped[(k, k)] *= 1.0 + lambda;
        }
        let Some(step) = damped.cholesky().map(|c| c.solve(&(-g))) else {
            return Ok(Step::Singular);
        };
        // The gain the linearised problem predicts.
        let predicted = -(2.0 * g.dot(&step) + (step.transpose() * a * &step)[(0, 0)]);
        let small = step
            .iter()
            .zip(self.unknowns)
            .all(|(s, u)| s.abs() < 1e-2 * u.sigma);
        if predicted < 1e-4 * (1.0 + at.cost) || small {
            return Ok(Step::Negligible);
        }
        let p: Vec<f64> = at.p.iter().zip(step.iter()).map(|(x, s)| x + s).collect();
        Ok(match (self.eval)(&p, &at.found) {
            Ok(trial) if trial.z.len() == at.z.len() => Step::Trial {
                point: trial,
                predicted: at.cost - predicted,
            },
            _ => Step::Failed,
        })
    }

    fn accepted(&mut self, from: &At, to: &At, _: &Progress) -> Verdict<()> {
        let mut j = std::mem::replace(&mut self.current, DMatrix::zeros(0, 0));
        if !self.held {
            broyden(&mut j, from, to, self.unknowns);
            self.fresh = false;
        }
        self.last = Some(j.clone());
        self.next = Some(j);
        Verdict::Continue
    }
}

/// Broyden's rank-one update of `j` from `from` to `to`, in the priors' metric: `J += (dz - J
/// dp) (dp / s^2)^T / sum (dp / s)^2`.
fn broyden(j: &mut DMatrix<f64>, from: &At, to: &At, unknowns: &[PoseUnknown]) {
    let dp = DVector::from_iterator(unknowns.len(), to.p.iter().zip(&from.p).map(|(a, b)| a - b));
    let w = DVector::from_iterator(
        unknowns.len(),
        dp.iter()
            .zip(unknowns)
            .map(|(d, u)| d / (u.sigma * u.sigma)),
    );
    let denom = dp.dot(&w);
    if denom <= 0.0 || !denom.is_finite() {
        return;
    }
    let dz = DVector::from_iterator(from.z.len(), to.z.iter().zip(&from.z).map(|(a, b)| a - b));
    let r = dz - &*j * &dp;
    *j += r * w.transpose() / denom;
}

/// The Jacobian of the residuals at `at` by central differences (one-sided where a side has no
/// answer), each refit from `at`'s answer; `None` where a column has neither side.
fn jacobian<E>(eval: &E, at: &At, unknowns: &[PoseUnknown]) -> Option<DMatrix<f64>>
where
    E: Fn(&[f64], &Found) -> Result<At> + Sync,
{
    let n = unknowns.len();
    let m = at.z.len();
    let sides: Vec<Option<Vec<f64>>> = (0..2 * n)
        .into_par_iter()
        .map(|k| {
            let (j, sign) = (k / 2, if k % 2 == 0 { 1.0 } else { -1.0 });
            let mut p = at.p.clone();
            p[j] += sign * 0.1 * unknowns[j].sigma;
            eval(&p, &at.found)
                .ok()
                .filter(|t| t.z.len() == m)
                .map(|t| t.z)
        })
        .collect();
    let mut jac = DMatrix::zeros(m, n);
    for j in 0..n {
        let h = 0.1 * unknowns[j].sigma;
        let column: Vec<f64> = match (&sides[2 * j], &sides[2 * j + 1]) {
            (Some(a), Some(b)) => a.iter().zip(b).map(|(x, y)| (x - y) / (2.0 * h)).collect(),
            (Some(a), None) => a.iter().zip(&at.z).map(|(x, y)| (x - y) / h).collect(),
            (None, Some(b)) => at.z.iter().zip(b).map(|(x, y)| (x - y) / h).collect(),
            (None, None) => return None,
        };
        jac.set_column(j, &DVector::from_vec(column));
    }
    Some(jac)
}
