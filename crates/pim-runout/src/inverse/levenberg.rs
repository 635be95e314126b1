//! The run-out inverse's Levenberg-Marquardt: the separation state (and the friction where it
//! is estimated) fitted to the evidence by `pim_core::damped`, Marquardt's scaling, the
//! Jacobian by forward differences at every accepted point.

use super::problem::Problem;
use crate::error::{Result, RunoutError};
use crate::simulate::Runout;
use nalgebra::{DMatrix, DVector};
use pim_core::damped::{self, Damped, Limit, Linearised, Progress, Rules, Step, Verdict};

/// One point of the search: the unknowns, their weighted residuals and run-out, the cost and
/// the precision the run-outs' tolerance gives it.
pub(crate) struct At {
    theta: Vec<f64>,
    r: DVector<f64>,
    run: Runout,
    cost: f64,
    noise: f64,
    /// The length of the step that reached this point (0 at the start).
    step: f64,
}

/// The end of a search.
pub(crate) struct Search {
    pub(crate) theta: Vec<f64>,
    pub(crate) r: DVector<f64>,
    pub(crate) run: Runout,
    pub(crate) cost: f64,
    /// The Jacobian last differenced (at the last point but one where the limit ended it).
    pub(crate) jac: DMatrix<f64>,
    pub(crate) converged: bool,
    /// Jacobians differenced.
    pub(crate) iterations: usize,
}

/// The search as a damped least-squares problem.
struct Levenberg<'a> {
    p: &'a Problem<'a>,
    runouts: &'a mut usize,
    precise: bool,
    jac: DMatrix<f64>,
    a: DMatrix<f64>,
    g: DVector<f64>,
}

impl Levenberg<'_> {
    /// The least gain worth a step, and the least predicted gain worth a run-out; an exploring
    /// search never goes below what the run-outs' tolerance lets the cost resolve
    /// (`Problem::noise`), a precise one goes on to the run-outs' own precision (the answer).
    fn least(&self, at: &At) -> (f64, f64) {
        let cost = at.cost;
        if self.precise {
            (1e-7 * cost + 1e-14, 1e-9 * cost + 1e-22)
        } else {
            let (step, trial) = (GAIN * (1.0 + cost), 0.1 * GAIN * (1.0 + cost));
            (step.max(at.noise), trial.max(at.noise))
        }
    }
}

impl Damped for Levenberg<'_> {
    type Point = At;
    type Reason = ();
    type Error = RunoutError;

    fn cost(&self, p: &At) -> f64 {
        p.cost
    }

    fn linearise(&mut self, at: &At, _exact: bool) -> Result<Linearised> {
        self.jac = jacobian(self.p, &at.theta, &at.r, &at.run, self.runouts)?;
        self.a = self.jac.transpose() * &self.jac;
        self.g = self.jac.transpose() * &at.r;
        if at.cost < 1e-24 || self.g.norm() < 1e-14 * (1.0 + at.cost) {
            return Ok(Linearised::Stationary);
        }
        Ok(Linearised::Ready)
    }

    fn step(&mut self, at: &At, lambda: f64) -> Result<Step<At>> {
        let mut m = self.a.clone();
        for i in 0..self.p.n() {
            m[(i, i)] += lambda * self.a[(i, i)].max(1e-12);
        }
        let Some(step) = m.cholesky().map(|c| c.solve(&(-&self.g))) else {
            return Ok(Step::Singular);
        };
        // The decrease the linear model predicts: below the least worth a run-out there is
        // nothing left to gain.
        let predicted = -(2.0 * self.g.dot(&step) + (&self.a * &step).dot(&step));
        if predicted < self.least(at).1 {
            return Ok(Step::Negligible);
        }
        let length = step.norm();
        let theta: Vec<f64> = at
            .theta
            .iter()
            .zip(step.iter())
            .map(|(t, s)| t + s)
            .collect();
        *self.runouts += 1;
        Ok(match self.p.weighted(&theta) {
            Ok((r, run)) => {
                let cost = r.norm_squared();
                let noise = self.p.noise(&r, &run);
                Step::Trial {
                    point: At {
                        theta,
                        r,
                        run,
                        cost,
                        noise,
                        step: length,
                    },
                    predicted: at.cost - predicted,
                }
            }
            Err(_) => Step::Failed,
        })
    }

    fn accepted(&mut self, from: &At, to: &At, _: &Progress) -> Verdict<()> {
        let small_step = to.step < 1e-10 * (1.0 + norm(&from.theta));
        let small_gain = from.cost - to.cost < self.least(from).0;
        if small_step || small_gain {
            Verdict::Converged
        } else {
            Verdict::Continue
        }
    }
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Levenberg-Marquardt (Marquardt's scaling) from `theta`, the Jacobian by forward
/// differences at every accepted point, at most `max_iterations` of them; `precise`: converged
/// only at the run-outs' precision (a gain below 1e-7 of the cost), else at a gain of
/// [`GAIN`]. `lambda` from 1e-3, times 4 after a failed step, divided by 3 (down to 1e-12)
/// after a success; no step is tried above 1e12.
pub(crate) fn levenberg(
    p: &Problem,
    theta: Vec<f64>,
    max_iterations: usize,
    runouts: &mut usize,
    precise: bool,
) -> Result<Search> {
    *runouts += 1;
    let (r, run) = p.weighted(&theta)?;
    let cost = r.norm_squared();
    let noise = p.noise(&r, &run);
    let m = r.len();
    let start = At {
        theta,
        r,
        run,
        cost,
        noise,
        step: 0.0,
    };
    if max_iterations == 0 {
        let At {
            theta,
            r,
            run,
            cost,
            ..
        } = start;
        return Ok(Search {
            jac: DMatrix::zeros(m, p.n()),
            theta,
            r,
            run,
            cost,
            converged: false,
            iterations: 0,
        });
    }
    let rules = Rules::classic(1e-12, Limit::Linearisations(max_iterations))
        .checked()
        .expect("the run-out search's damping rules are in range");
    let mut problem = Levenberg {
        p,
        runouts,
        precise,
        jac: DMatrix::zeros(m, p.n()),
        a: DMatrix::zeros(0, 0),
        g: DVector::zeros(0),
    };
    let end = damped::minimise(&mut problem, start, &rules)?;
    let At {
        theta,
        r,
        run,
        cost,
        ..
    } = end.point;
    Ok(Search {
        theta,
        r,
        run,
        cost,
        jac: problem.jac,
        converged: end.termination.converged(),
        iterations: end.linearisations,
    })
}

/// An exploring search (and a quick candidate's polish) has converged when a step gains less
/// than this times (1 + its chi-square): a change of a millionth in a chi-square is far below
/// any statistical meaning (the whole reconstruction's refinement stops at the same gain). A
/// precise polish goes on to the run-outs' own precision.
pub(crate) const GAIN: f64 = 1e-6;

/// The Jacobian of the weighted residuals at `theta`, whose run-out is `nominal` and weighted
/// residuals `r0`: forward differences of run-outs integrated through the nominal's accepted
/// steps (internal numerical differentiation, the step [`INTERNAL_STEP`](super::problem::INTERNAL_STEP) of `1 + |theta_j|`);
/// where the nominal cannot be replayed (inputs by distance), of run-outs with steps of their
/// own, the step the square root of the run-outs' relative tolerance (which keeps their noise
/// and the truncation error alike small). At the edge of the searched states, the backward
/// difference.
pub(crate) fn jacobian(
    p: &Problem,
    theta: &[f64],
    r0: &DVector<f64>,
    nominal: &Runout,
    runouts: &mut usize,
) -> Result<DMatrix<f64>> {
    let n = p.n();
    let mut jac = DMatrix::zeros(r0.len(), n);
    let relative = p.difference_step(nominal);
    for j in 0..n {
        let h = relative * (1.0 + theta[j].abs());
        let mut t = theta.to_vec();
        t[j] += h;
        *runouts += 1;
        let (r1, h) = match p.stepped(&t, nominal) {
            Ok(r1) => (r1, h),
            Err(_) => {
                t[j] = theta[j] - h;
                *runouts += 1;
                (p.stepped(&t, nominal)?, -h)
            }
        };
        for i in 0..r0.len() {
            jac[(i, j)] = (r1[i] - r0[i]) / h;
        }
    }
    Ok(jac)
}
