//! Separation velocities from the scene: weighted least squares through the run-out model.
//!
//! The unknowns are the CG velocity `(vx, vy)` and yaw rate `r` at separation, and the road
//! friction when the evidence gives it a standard deviation ([`Evidence::friction_sigma`]: the
//! friction is then an estimate, not a given). The position and heading at separation are known
//! (they are those at contact). The cost is the sum of the squared residuals in units of their
//! standard deviations:
//! - the rest position `x`, `y` and heading against those of the run-out's end;
//! - each mark: the signed distance of the mark from the CG's path (along the path's normal at
//!   the closest point; the full distance when the closest point is the start or the rest), and
//!   the heading there when the mark gives one;
//! - the friction against the value given, when it is estimated.
//!
//! A rest heading is known only modulo a full turn. The heading of candidate `k` is the rest
//! heading nearest the heading at separation plus `k` full turns (counter-clockwise positive),
//! for every `k` of [`EstimateSettings::turns`], each minimised on its own
//! (Levenberg-Marquardt with forward-difference Jacobians, from a start scaled by trial
//! run-outs until the distance or the rotation matches). A rest position and heading are three
//! numbers for three unknowns: typically every count reaches them exactly and only marks (or the
//! impact) decide between the counts, so candidates whose costs agree within
//! [`CONSISTENT_COST`] are reported as equally consistent, never one chosen by round-off.
//!
//! At each candidate's minimum the weighted Jacobian `J` tells what the evidence determines:
//! its singular directions with a singular value below 1e-6 of the largest are *free* (the cost
//! does not change along them to first order; e.g. speed against friction when only the rest
//! position is known and the friction is estimated), and the standard errors of the determined
//! unknowns are the square roots of the diagonal of `(J^T J)^-1` (the linearisation; exact for
//! the evidence's sigmas in the limit of small ones).

use crate::chassis::{Chassis, Motion, GRAVITY};
use crate::error::{Result, RunoutError};
use crate::forces::Dynamics;
use crate::simulate::{hermite, run, End, Runout, Settings};
use nalgebra::{DMatrix, DVector};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::f64::consts::{PI, TAU};

/// Candidates whose costs differ by less than this (in units of chi-square) are equally
/// consistent with the evidence.
pub const CONSISTENT_COST: f64 = 1e-6;

/// Candidates within this cost of the best (a likelihood ratio above e^-2, two standard
/// deviations of one parameter) are not excluded by the evidence: it favours the best without
/// deciding against them.
pub const PLAUSIBLE_COST: f64 = 4.0;

/// The rest position (and heading) of the vehicle, with standard deviations.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Rest {
    /// CG position, m.
    pub x: f64,
    /// CG position, m.
    pub y: f64,
    /// Heading at rest, rad (modulo a full turn), when known.
    pub heading: Option<f64>,
    /// Standard deviations of x and y, m.
    pub sigma_xy: [f64; 2],
    /// Standard deviation of the heading, rad.
    pub sigma_heading: f64,
}

/// A point the CG passed (a tyre mark or gouge placed at the CG's path), with a standard
/// deviation, optionally with the heading there.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Mark {
    /// Position, m.
    pub x: f64,
    /// Position, m.
    pub y: f64,
    /// Standard deviation of the distance from the path, m.
    pub sigma: f64,
    /// Heading of the vehicle there (rad, modulo a full turn) and its standard deviation (rad).
    pub heading: Option<(f64, f64)>,
}

/// The evidence of one vehicle's run-out.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
pub struct Evidence {
    /// The rest position and heading.
    pub rest: Option<Rest>,
    /// Points the CG passed, in any order.
    pub marks: Vec<Mark>,
    /// The count of full turns to rest, when the case states it (only that candidate is
    /// searched).
    pub turns: Option<i64>,
    /// Standard deviation of the road friction: with it the friction is estimated (its value in
    /// the chassis is the estimate's centre), without it the friction is taken as exact.
    pub friction_sigma: Option<f64>,
}

/// How the separation velocities are searched.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct EstimateSettings {
    /// The counts of full turns tried, from the first to the second inclusive.
    pub turns: (i64, i64),
    /// Iterations of the least-squares search per candidate.
    pub max_iterations: usize,
    /// How each run-out is integrated.
    pub runout: Settings,
}

impl Default for EstimateSettings {
    /// Turns -3 to 3, 100 iterations, the default run-out settings.
    fn default() -> Self {
        EstimateSettings {
            turns: (-3, 3),
            max_iterations: 100,
            runout: Settings::default(),
        }
    }
}

/// One residual of a candidate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Residual {
    /// What it is: `rest.x`, `rest.y`, `rest.heading`, `mark 1`, `mark 1 heading`, `friction`.
    pub name: String,
    /// Fitted minus given, in its unit (m, rad, or the friction coefficient).
    pub value: f64,
    /// Its standard deviation, in the same unit.
    pub sigma: f64,
}

/// The best separation state for one count of turns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Candidate {
    /// Full turns beyond the rotation to the nearest rest heading (none when the rest heading
    /// is not given).
    pub turns: Option<i64>,
    /// The motion at separation (position and heading as given, velocities estimated).
    pub separation: Motion,
    /// The friction (estimated or as given).
    pub friction: f64,
    /// Sum of the squared residuals in units of their sigmas.
    pub cost: f64,
    /// Every piece of evidence against the fit.
    pub residuals: Vec<Residual>,
    /// Standard errors of the unknowns (`vx`, `vy`, `yaw_rate` and `friction` when estimated,
    /// in the order of [`Estimate::unknowns`]); `None` for an unknown the evidence leaves free.
    pub sigma: Vec<Option<f64>>,
    /// Directions in the unknowns (unit vectors, same order) that the scene's evidence does not
    /// determine (with the friction estimated: the evidence without the friction's own standard
    /// deviation, which then decides along them).
    pub free: Vec<Vec<f64>>,
    /// Equally consistent with the best candidate (cost within [`CONSISTENT_COST`]).
    pub consistent: bool,
    /// Not excluded by the evidence (cost within [`PLAUSIBLE_COST`] of the best).
    pub plausible: bool,
    /// The search converged (step or cost change below its tolerance).
    pub converged: bool,
    /// Least-squares iterations.
    pub iterations: usize,
    /// Run-outs simulated for this candidate.
    pub runouts: usize,
    /// Why this candidate does not reach the evidence, when it does not (a residual beyond
    /// 3 sigma, or a run-out that reaches its time limit).
    pub reason: Option<String>,
    /// The run-out from the estimated separation state.
    pub runout: Runout,
}

/// The separation velocities of one vehicle estimated from its run-out evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Estimate {
    /// The names of the unknowns, in the order of [`Candidate::sigma`].
    pub unknowns: Vec<String>,
    /// One candidate per count of turns, the lowest cost first.
    pub candidates: Vec<Candidate>,
}

impl Estimate {
    /// The candidates equally consistent with the evidence (the lowest cost and those within
    /// [`CONSISTENT_COST`] of it).
    pub fn consistent(&self) -> impl Iterator<Item = &Candidate> {
        self.candidates.iter().filter(|c| c.consistent)
    }

    /// The lowest-cost candidate (one of the consistent ones; check [`Estimate::consistent`]
    /// before calling it *the* answer).
    pub fn best(&self) -> Option<&Candidate> {
        self.candidates.first()
    }
}

fn input(field: &'static str, reason: String) -> RunoutError {
    RunoutError::Input { field, reason }
}

impl Evidence {
    /// Checks the evidence: finite numbers, sigmas above 0, something to fit.
    pub fn check(&self) -> Result<()> {
        let positive = |field: &'static str, s: f64| {
            if s.is_finite() && s > 0.0 {
                Ok(())
            } else {
                Err(input(
                    field,
                    format!("{s}: a standard deviation must be above 0"),
                ))
            }
        };
        let finite = |field: &'static str, x: f64| {
            if x.is_finite() {
                Ok(())
            } else {
                Err(input(field, format!("{x}: must be a finite number")))
            }
        };
        if let Some(r) = &self.rest {
            finite("rest.x", r.x)?;
            finite("rest.y", r.y)?;
            positive("rest_sigma.x", r.sigma_xy[0])?;
            positive("rest_sigma.y", r.sigma_xy[1])?;
            if let Some(h) = r.heading {
                finite("rest.heading", h)?;
                positive("rest_sigma.heading", r.sigma_heading)?;
            }
        }
        for m in &self.marks {
            finite("marks.x", m.x)?;
            finite("marks.y", m.y)?;
            positive("marks.sigma", m.sigma)?;
            if let Some((h, s)) = m.heading {
                finite("marks.heading", h)?;
                positive("marks.heading_sigma", s)?;
            }
        }
        if let Some(s) = self.friction_sigma {
            positive("friction_sigma", s)?;
        }
        if self.rest.is_none() && self.marks.is_empty() {
            return Err(input(
                "rest",
                "no evidence: give the rest position (and heading) or marks the CG passed".into(),
            ));
        }
        if self.turns.is_some() && self.rest.and_then(|r| r.heading).is_none() {
            return Err(input(
                "turns",
                "a count of turns needs the rest heading it counts to".into(),
            ));
        }
        Ok(())
    }
}

/// The problem of one candidate.
struct Problem<'a> {
    chassis: &'a Chassis,
    start: Motion,
    evidence: &'a Evidence,
    /// Target heading at rest (unwrapped for this candidate), rad.
    heading: Option<f64>,
    settings: &'a Settings,
    estimate_friction: bool,
}

impl Problem<'_> {
    fn n(&self) -> usize {
        if self.estimate_friction {
            4
        } else {
            3
        }
    }

    fn runout(&self, theta: &[f64]) -> Result<Runout> {
        let mut chassis = self.chassis.clone();
        if self.estimate_friction {
            // The friction stays inside the model's range while searched.
            chassis.friction = theta[3].clamp(0.02, crate::chassis::MAX_FRICTION);
            chassis.rolling_resistance = chassis.rolling_resistance.min(0.5 * chassis.friction);
        }
        let start = Motion {
            vx: theta[0],
            vy: theta[1],
            yaw_rate: theta[2],
            ..self.start
        };
        run(&Dynamics::new(&chassis), &start, self.settings)
    }

    /// The residuals (fitted minus given, and their sigmas) of a run-out.
    fn residuals(&self, theta: &[f64], r: &Runout) -> Vec<Residual> {
        let mut out = Vec::new();
        let res = |name: &str, value: f64, sigma: f64| Residual {
            name: name.to_string(),
            value,
            sigma,
        };
        if let Some(rest) = &self.evidence.rest {
            out.push(res("rest.x", r.rest.x - rest.x, rest.sigma_xy[0]));
            out.push(res("rest.y", r.rest.y - rest.y, rest.sigma_xy[1]));
            if let Some(h) = self.heading {
                out.push(res("rest.heading", r.rest.heading - h, rest.sigma_heading));
            }
        }
        for (i, m) in self.evidence.marks.iter().enumerate() {
            let (d, heading) = closest(r, m.x, m.y);
            out.push(res(&format!("mark {}", i + 1), d, m.sigma));
            if let Some((h, s)) = m.heading {
                let diff = wrap(heading - h);
                out.push(res(&format!("mark {} heading", i + 1), diff, s));
            }
        }
        if let (true, Some(s)) = (self.estimate_friction, self.evidence.friction_sigma) {
            out.push(res("friction", theta[3] - self.chassis.friction, s));
        }
        out
    }

    fn weighted(&self, theta: &[f64]) -> Result<(DVector<f64>, Runout)> {
        let r = self.runout(theta)?;
        let res = self.residuals(theta, &r);
        Ok((
            DVector::from_iterator(res.len(), res.iter().map(|x| x.value / x.sigma)),
            r,
        ))
    }
}

/// The residuals of `evidence` against a run-out computed elsewhere (from separation velocities
/// a solve or a fit gave): the rest heading is compared with the nearest of its full turns.
pub fn residuals_of(chassis: &Chassis, evidence: &Evidence, runout: &Runout) -> Vec<Residual> {
    let heading = evidence
        .rest
        .and_then(|r| r.heading)
        .map(|h| h + TAU * ((runout.rest.heading - h) / TAU).round());
    let settings = Settings::default();
    let p = Problem {
        chassis,
        start: runout.start,
        evidence,
        heading,
        settings: &settings,
        estimate_friction: false,
    };
    p.residuals(&[], runout)
}

/// Wraps an angle to (-pi, pi].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI {
        w - TAU
    } else {
        w
    }
}

/// The signed distance of the point `(px, py)` from the CG's path (positive to the left of
/// the direction of travel; the full distance when the closest point is an end of the path)
/// and the heading at the closest point.
fn closest(r: &Runout, px: f64, py: f64) -> (f64, f64) {
    let steps = &r.steps;
    let dist2 = |m: &Motion| (m.x - px).powi(2) + (m.y - py).powi(2);
    if steps.len() < 2 {
        let m = r.rest;
        return (dist2(&m).sqrt(), m.heading);
    }
    // Coarse: eight points in every step; then Newton on (p(t) - q) . p'(t) = 0.
    let mut best = (f64::INFINITY, 0usize, 0.0);
    for k in 1..steps.len() {
        for j in 0..=8 {
            let s = j as f64 / 8.0;
            let t = steps[k - 1].time + s * (steps[k].time - steps[k - 1].time);
            let d = dist2(&hermite(&steps[k - 1], &steps[k], t));
            if d < best.0 {
                best = (d, k, t);
            }
        }
    }
    let (_, k, mut t) = best;
    let (a, b) = (&steps[k - 1], &steps[k]);
    let h = 1e-7 * (b.time - a.time).max(1e-9);
    for _ in 0..20 {
        let f = |t: f64| {
            let m = hermite(a, b, t);
            (m.x - px) * m.vx + (m.y - py) * m.vy
        };
        let (f0, f1) = (f(t), f(t + h));
        let df = (f1 - f0) / h;
        if df.abs() < 1e-300 {
            break;
        }
        let next = (t - f0 / df).clamp(a.time, b.time);
        let done = (next - t).abs() < 1e-13 * (1.0 + t.abs());
        t = next;
        if done {
            break;
        }
    }
    let m = hermite(a, b, t);
    let (dx, dy) = (px - m.x, py - m.y);
    let speed = m.vx.hypot(m.vy);
    let interior = t > steps[0].time && t < r.time;
    if interior && speed > 1e-9 {
        ((m.vx * dy - m.vy * dx) / speed, m.heading)
    } else {
        (dx.hypot(dy), m.heading)
    }
}

/// Estimates the separation velocities of a vehicle that starts at `start` (its position and
/// heading at separation; its velocities are ignored) from `evidence`, for every count of
/// turns in `settings.turns` (or the count the evidence states).
///
/// # Errors
/// [`RunoutError::Input`] for a vehicle, start, evidence or settings the model cannot use.
/// A candidate that does not reach the evidence is not an error: its cost, residuals and
/// [`Candidate::reason`] say so.
pub fn estimate(
    chassis: &Chassis,
    start: &Motion,
    evidence: &Evidence,
    settings: &EstimateSettings,
) -> Result<Estimate> {
    chassis.check()?;
    start.check()?;
    evidence.check()?;
    settings.runout.check()?;
    if settings.turns.0 > settings.turns.1 || settings.turns.1 - settings.turns.0 > 40 {
        return Err(input(
            "turns",
            format!(
                "{:?}: the range of counts must run upwards and span at most 40 turns",
                settings.turns
            ),
        ));
    }
    let estimate_friction = evidence.friction_sigma.is_some();
    let rest_heading = evidence.rest.and_then(|r| r.heading);
    // The rest heading nearest the heading at separation; candidate k adds k turns.
    let nearest = rest_heading.map(|h| h + TAU * ((start.heading - h) / TAU).round());
    let counts: Vec<Option<i64>> = match (nearest, evidence.turns) {
        (None, _) => vec![None],
        (Some(_), Some(k)) => vec![Some(k)],
        (Some(_), None) => (settings.turns.0..=settings.turns.1).map(Some).collect(),
    };
    let mut candidates = counts
        .par_iter()
        .map(|&k| {
            let problem = Problem {
                chassis,
                start: *start,
                evidence,
                heading: nearest.map(|h| h + TAU * k.unwrap_or(0) as f64),
                settings: &settings.runout,
                estimate_friction,
            };
            solve(&problem, k, settings.max_iterations, &[])
        })
        .collect::<Result<Vec<_>>>()?;
    // Counts that ended above the chi-square's expectation start again from the answers of the
    // counts that did not (neighbouring counts often have neighbouring answers).
    let good: Vec<(Option<i64>, Vec<f64>)> = candidates
        .iter()
        .filter(|c| c.cost <= c.residuals.len() as f64)
        .map(|c| {
            let s = &c.separation;
            let mut theta = vec![s.vx, s.vy, s.yaw_rate];
            if estimate_friction {
                theta.push(c.friction);
            }
            (c.turns, theta)
        })
        .collect();
    if !good.is_empty() {
        let rotation = |k: Option<i64>| {
            nearest.map_or(0.0, |h| h + TAU * k.unwrap_or(0) as f64 - start.heading)
        };
        let redone = candidates
            .par_iter()
            .map(|c| {
                if c.cost <= c.residuals.len() as f64 {
                    return Ok(None);
                }
                let starts: Vec<Vec<f64>> = good
                    .iter()
                    .map(|(k, theta)| {
                        let mut t = theta.clone();
                        let (from, to) = (rotation(*k), rotation(c.turns));
                        if from.abs() > 1e-3 {
                            t[2] *= to / from;
                        }
                        t
                    })
                    .collect();
                let problem = Problem {
                    chassis,
                    start: *start,
                    evidence,
                    heading: nearest.map(|h| h + TAU * c.turns.unwrap_or(0) as f64),
                    settings: &settings.runout,
                    estimate_friction,
                };
                solve(&problem, c.turns, settings.max_iterations, &starts).map(Some)
            })
            .collect::<Result<Vec<_>>>()?;
        for (c, r) in candidates.iter_mut().zip(redone) {
            if let Some(r) = r {
                if r.cost < c.cost {
                    let runouts = c.runouts + r.runouts;
                    *c = r;
                    c.runouts = runouts;
                }
            }
        }
    }
    candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let best = candidates.first().map_or(0.0, |c| c.cost);
    for c in &mut candidates {
        c.consistent = c.cost - best <= CONSISTENT_COST;
        c.plausible = c.cost - best < PLAUSIBLE_COST;
    }
    let mut unknowns: Vec<String> = ["vx", "vy", "yaw_rate"].map(String::from).to_vec();
    if estimate_friction {
        unknowns.push("friction".into());
    }
    Ok(Estimate {
        unknowns,
        candidates,
    })
}

/// The first guess of a candidate: a uniform deceleration along the line from the start to
/// the rest (or the first mark), turning through the candidate's rotation in the same time;
/// then scaled by trial run-outs until the distance (or, for a vehicle that barely moves, the
/// rotation) matches.
fn first_guess(p: &Problem, runouts: &mut usize) -> Vec<f64> {
    let target = p
        .evidence
        .rest
        .map(|r| (r.x, r.y))
        .or_else(|| p.evidence.marks.last().map(|m| (m.x, m.y)))
        .unwrap_or((p.start.x, p.start.y));
    let (dx, dy) = (target.0 - p.start.x, target.1 - p.start.y);
    let dist = dx.hypot(dy);
    let rotation = p.heading.map_or(0.0, |h| h - p.start.heading);
    let decel = p.chassis.friction * GRAVITY;
    let radius = {
        let [x, y] = p.chassis.wheel_position(0);
        x.hypot(y)
    };
    // Spin decelerates at about mu m g rho / I.
    let spin_decel = decel * p.chassis.mass * radius / p.chassis.yaw_inertia;
    let (speed, time) = if dist > 0.05 {
        let v = (2.0 * decel * dist).sqrt();
        (v, 2.0 * dist / v)
    } else {
        let w = (2.0 * spin_decel * rotation.abs()).sqrt();
        (
            0.1,
            if w > 0.0 {
                2.0 * rotation.abs() / w
            } else {
                1.0
            },
        )
    };
    let (ux, uy) = if dist > 1e-9 {
        (dx / dist, dy / dist)
    } else {
        (p.start.heading.cos(), p.start.heading.sin())
    };
    let mut theta = vec![speed * ux, speed * uy, 2.0 * rotation / time.max(1e-3)];
    if p.estimate_friction {
        theta.push(p.chassis.friction);
    }
    for _ in 0..6 {
        *runouts += 1;
        let Ok(r) = p.runout(&theta) else { break };
        let factor = if dist > 0.05 {
            let reached = (r.rest.x - p.start.x).hypot(r.rest.y - p.start.y);
            if reached > 1e-6 {
                (dist / reached).sqrt()
            } else {
                3.0
            }
        } else if r.rotation.abs() > 1e-6 && rotation.abs() > 1e-6 {
            (rotation.abs() / r.rotation.abs()).sqrt()
        } else {
            1.0
        };
        let factor = factor.clamp(0.3, 3.0);
        if (factor - 1.0).abs() < 0.02 {
            break;
        }
        for x in theta.iter_mut().take(3) {
            *x *= factor;
        }
    }
    theta
}

/// The state of a least-squares search.
struct Search {
    theta: Vec<f64>,
    r: DVector<f64>,
    run: Runout,
    cost: f64,
    jac: DMatrix<f64>,
    converged: bool,
    iterations: usize,
}

/// Levenberg-Marquardt (Marquardt's scaling) from `theta`.
fn levenberg(
    p: &Problem,
    mut theta: Vec<f64>,
    max_iterations: usize,
    runouts: &mut usize,
) -> Result<Search> {
    let n = p.n();
    *runouts += 1;
    let (mut r, mut run_now) = p.weighted(&theta)?;
    let mut cost = r.norm_squared();
    let mut lambda = 1e-3;
    let mut converged = false;
    let mut iterations = 0;
    let mut jac = DMatrix::zeros(r.len(), n);
    while iterations < max_iterations {
        iterations += 1;
        jac = jacobian(p, &theta, &r, runouts)?;
        let a = jac.transpose() * &jac;
        let g = jac.transpose() * &r;
        if cost < 1e-24 || g.norm() < 1e-14 * (1.0 + cost) {
            converged = true;
            break;
        }
        let mut improved = false;
        while lambda < 1e12 {
            let mut m = a.clone();
            for i in 0..n {
                m[(i, i)] += lambda * a[(i, i)].max(1e-12);
            }
            let Some(step) = m.cholesky().map(|c| c.solve(&(-&g))) else {
                lambda *= 4.0;
                continue;
            };
            // The decrease the linear model predicts: below the run-outs' precision there is
            // nothing left to gain.
            let predicted = -(2.0 * g.dot(&step) + (&a * &step).dot(&step));
            if predicted < 1e-9 * cost + 1e-22 {
                break;
            }
            let trial: Vec<f64> = theta.iter().zip(step.iter()).map(|(t, s)| t + s).collect();
            *runouts += 1;
            match p.weighted(&trial) {
                Ok((rt, run_t)) if rt.norm_squared() < cost => {
                    let new_cost = rt.norm_squared();
                    let small_step = step.norm() < 1e-10 * (1.0 + norm(&theta));
                    let small_gain = cost - new_cost < 1e-9 * cost;
                    theta = trial;
                    r = rt;
                    run_now = run_t;
                    cost = new_cost;
                    lambda = (lambda / 3.0).max(1e-12);
                    improved = true;
                    converged = small_step || small_gain;
                    break;
                }
                _ => lambda *= 4.0,
            }
        }
        if !improved {
            // No step lowers the cost: a (local) minimum to the precision of the run-outs.
            converged = true;
            break;
        }
        if converged {
            break;
        }
    }
    Ok(Search {
        theta,
        r,
        run: run_now,
        cost,
        jac,
        converged,
        iterations,
    })
}

/// Tolerances of the run-outs that explore from each start before the best is polished.
const EXPLORE_TOLERANCE: f64 = 1e-6;

/// Iterations of an exploring search.
const EXPLORE_ITERATIONS: usize = 12;

/// One candidate. Each start is explored by a short Levenberg-Marquardt search on coarser
/// run-outs, in turn, until one ends within the chi-square's expectation (the count of
/// residuals); the best explored point is polished at full precision. The starts: the first
/// guess; with marks, the first guess fitted to the rest alone (the rest's exact solutions are
/// often the marks' basin); the first guess with its yaw rate scaled (2.5, 0.4, -1: whether a
/// vehicle sliding sideways ends nose or tail first jumps with it), turned off the line to the
/// rest (a rotating vehicle's path curves) and aimed at the mark nearest the start; and
/// `others` (the answers of other counts of turns).
fn solve(
    p: &Problem,
    turns: Option<i64>,
    max_iterations: usize,
    others: &[Vec<f64>],
) -> Result<Candidate> {
    let mut runouts = 0;
    // A second pass (others given) tries only the others: the rest were tried in the first.
    let second_pass = !others.is_empty();
    let guess = first_guess(p, &mut runouts);
    let coarse_settings = Settings {
        rtol: EXPLORE_TOLERANCE.max(p.settings.rtol),
        atol: EXPLORE_TOLERANCE.max(p.settings.atol),
        ..*p.settings
    };
    let coarse = Problem {
        settings: &coarse_settings,
        ..*p
    };
    let rest_only = Evidence {
        marks: Vec::new(),
        ..p.evidence.clone()
    };
    let turned = |angle: f64| -> Vec<f64> {
        let (s, c) = angle.sin_cos();
        let mut t = guess.clone();
        t[0] = c * guess[0] - s * guess[1];
        t[1] = s * guess[0] + c * guess[1];
        t
    };
    let toward_mark = p
        .evidence
        .marks
        .iter()
        .min_by(|a, b| {
            let d = |m: &Mark| (m.x - p.start.x).hypot(m.y - p.start.y);
            d(a).total_cmp(&d(b))
        })
        .map(|m| {
            let speed = guess[0].hypot(guess[1]);
            let (dx, dy) = (m.x - p.start.x, m.y - p.start.y);
            let d = dx.hypot(dy).max(1e-9);
            let mut t = guess.clone();
            t[0] = speed * dx / d;
            t[1] = speed * dy / d;
            t
        });
    let mut iterations = 0;
    let mut explored: Option<Search> = None;
    let consider = |s: Search, explored: &mut Option<Search>| {
        if explored.as_ref().is_none_or(|b| s.cost < b.cost) {
            *explored = Some(s);
        }
    };
    let good = |s: &Option<Search>| s.as_ref().is_some_and(|s| s.cost <= s.r.len() as f64);
    // 1. The first guess.
    if !second_pass {
        let s = levenberg(&coarse, guess.clone(), EXPLORE_ITERATIONS, &mut runouts)?;
        iterations += s.iterations;
        consider(s, &mut explored);
    }
    // 2. With marks, through the rest alone.
    if !second_pass && !good(&explored) && !p.evidence.marks.is_empty() && p.evidence.rest.is_some()
    {
        let q = Problem {
            evidence: &rest_only,
            ..coarse
        };
        let first = levenberg(&q, guess.clone(), EXPLORE_ITERATIONS, &mut runouts)?;
        let s = levenberg(&coarse, first.theta, EXPLORE_ITERATIONS, &mut runouts)?;
        iterations += first.iterations + s.iterations;
        consider(s, &mut explored);
    }
    // 3. The other starts.
    // The yaw rate decides whether a vehicle that slides sideways ends up nose first or tail
    // first: the rotation jumps across that divide, which a local search cannot cross.
    let spun = |factor: f64| -> Vec<f64> {
        let mut t = guess.clone();
        t[2] *= factor;
        t
    };
    let mut starts = Vec::new();
    if second_pass {
        starts.extend(others.iter().cloned());
    } else {
        starts.extend([spun(2.5), spun(0.4), turned(0.4), turned(-0.4), spun(-1.0)]);
        starts.extend(toward_mark);
    }
    for start in starts {
        if good(&explored) {
            break;
        }
        let s = levenberg(&coarse, start, EXPLORE_ITERATIONS, &mut runouts)?;
        iterations += s.iterations;
        consider(s, &mut explored);
    }
    // 4. Still above the expectation: a scatter of single run-outs around the first guess
    //    (direction, speed, yaw rate), searched from the two lowest.
    if !second_pass && !good(&explored) {
        let mut scattered: Vec<(f64, Vec<f64>)> = Vec::new();
        for turn in [-0.5, 0.0, 0.5] {
            for speed in [0.8, 1.25] {
                for yaw in [0.5, 1.0, 2.0] {
                    let mut t = turned(turn);
                    t[0] *= speed;
                    t[1] *= speed;
                    t[2] *= yaw;
                    runouts += 1;
                    if let Ok((r, _)) = coarse.weighted(&t) {
                        scattered.push((r.norm_squared(), t));
                    }
                }
            }
        }
        scattered.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (_, start) in scattered.into_iter().take(2) {
            if good(&explored) {
                break;
            }
            let s = levenberg(&coarse, start, EXPLORE_ITERATIONS, &mut runouts)?;
            iterations += s.iterations;
            consider(s, &mut explored);
        }
    }
    // 5. Polished at full precision.
    let from = explored.map_or(guess, |s| s.theta);
    let best = levenberg(p, from, max_iterations, &mut runouts)?;
    iterations += best.iterations;
    let Search {
        theta,
        run: run_now,
        cost,
        jac,
        converged,
        ..
    } = best;
    let residuals = p.residuals(&theta, &run_now);
    let (sigma, mut free) = determinacy(&jac);
    if p.estimate_friction {
        // What the scene alone leaves free (the friction's own standard deviation then
        // decides along it): the rows of the evidence, without the friction's.
        let scene = jac.rows(0, jac.nrows() - 1).into_owned();
        free = determinacy(&scene).1;
    }
    let reason = reason_of(p, &residuals, &run_now);
    let friction = if p.estimate_friction {
        theta[3]
    } else {
        p.chassis.friction
    };
    Ok(Candidate {
        turns,
        separation: Motion {
            vx: theta[0],
            vy: theta[1],
            yaw_rate: theta[2],
            ..p.start
        },
        friction,
        cost,
        residuals,
        sigma,
        free,
        consistent: false,
        plausible: false,
        converged,
        iterations,
        runouts,
        reason,
        runout: run_now,
    })
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

/// Forward-difference Jacobian of the weighted residuals, the step the square root of the
/// run-outs' relative tolerance.
fn jacobian(
    p: &Problem,
    theta: &[f64],
    r0: &DVector<f64>,
    runouts: &mut usize,
) -> Result<DMatrix<f64>> {
    let n = p.n();
    let mut jac = DMatrix::zeros(r0.len(), n);
    for j in 0..n {
        // The run-outs carry their tolerance's noise: a difference step of its square root
        // keeps the noise and the truncation error alike small.
        let h = p.settings.rtol.sqrt() * (1.0 + theta[j].abs());
        let mut t = theta.to_vec();
        t[j] += h;
        *runouts += 1;
        let (r1, _) = p.weighted(&t)?;
        for i in 0..r0.len() {
            jac[(i, j)] = (r1[i] - r0[i]) / h;
        }
    }
    Ok(jac)
}

/// Standard errors of the unknowns and the directions the evidence does not determine, from
/// the singular values of the weighted Jacobian.
fn determinacy(jac: &DMatrix<f64>) -> (Vec<Option<f64>>, Vec<Vec<f64>>) {
    let n = jac.ncols();
    // J^T J = V S^2 V^T: its eigen-decomposition gives V and the squared singular values, also
    // when J has fewer rows than columns.
    let a = jac.transpose() * jac;
    let eig = nalgebra::SymmetricEigen::new(a);
    let largest = eig.eigenvalues.iter().cloned().fold(0.0, f64::max);
    let mut free = Vec::new();
    let mut cov = DMatrix::zeros(n, n);
    for k in 0..n {
        let v = eig.eigenvectors.column(k);
        let s2 = eig.eigenvalues[k];
        if !(s2 > 1e-12 * largest && largest > 0.0) {
            let mut dir: Vec<f64> = v.iter().cloned().collect();
            // A sign that reads the same on every run: the largest component positive.
            let big = dir
                .iter()
                .cloned()
                .fold(0.0_f64, |m, x| if x.abs() > m.abs() { x } else { m });
            if big < 0.0 {
                dir.iter_mut().for_each(|x| *x = -*x);
            }
            free.push(dir);
        } else {
            cov += v * v.transpose() / s2;
        }
    }
    let sigma = (0..n)
        .map(|j| {
            let touched = free.iter().any(|d| d[j].abs() > 1e-3);
            (!touched).then(|| cov[(j, j)].sqrt())
        })
        .collect();
    (sigma, free)
}

/// Why a candidate does not reach the evidence, if it does not.
fn reason_of(p: &Problem, residuals: &[Residual], r: &Runout) -> Option<String> {
    if r.end == End::TimeLimit {
        return Some(format!(
            "the run-out from the best separation state is still moving at the time limit \
             ({} s)",
            p.settings.time_limit
        ));
    }
    let worst = residuals.iter().max_by(|a, b| {
        (a.value / a.sigma)
            .abs()
            .total_cmp(&(b.value / b.sigma).abs())
    })?;
    let z = (worst.value / worst.sigma).abs();
    if z <= 3.0 {
        return None;
    }
    let (value, unit) = if worst.name.contains("heading") {
        (worst.value.to_degrees(), "deg")
    } else if worst.name == "friction" {
        (worst.value, "")
    } else {
        (worst.value, "m")
    };
    Some(format!(
        "the run-out closest to the evidence misses {} by {:.3} {unit} ({z:.1} sigma): no \
         motion from this separation position and heading reaches it with friction {:.3}",
        worst.name, value, p.chassis.friction
    ))
}
