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
//! for every `k` of [`EstimateSettings::turns`], each minimised on its own. A rest position and
//! heading are three numbers for three unknowns: typically every count reaches them exactly and
//! only marks (or the impact) decide between the counts, so candidates whose costs agree within
//! [`CONSISTENT_COST`] are reported as equally consistent, never one chosen by round-off, and
//! those within [`PLAUSIBLE_COST`] as not excluded.
//!
//! ## The search of one candidate
//! Levenberg-Marquardt (Marquardt's scaling). Its Jacobians are forward differences by
//! internal numerical differentiation: each stepped run-out is integrated through the accepted
//! steps of the run-out it is compared with (no step control of its own), so that the
//! difference quotient differentiates one smooth map and the step can be 1e-6 of each
//! unknown's scale, not the square root of the run-outs' tolerance (where the stepped run-outs
//! would take steps of their own: inputs by distance, the square root as before). An exploring
//! search does not try a step whose predicted gain lies below what the run-outs' tolerance lets
//! the cost resolve (`rtol` times each residual's scale: the distance travelled for positions,
//! the rotation for headings); the polish of the answer goes on to the run-outs' precision.
//! The cost is not convex: the closest point of a path
//! to a mark jumps between parts of the path, and whether a vehicle sliding sideways ends nose
//! or tail first jumps with the yaw rate. So each candidate is explored from several starts on
//! run-outs of tolerance 1e-6 (12 iterations each), in turn until one ends within the
//! chi-square's expectation (the count of residuals): the first guess (a uniform deceleration
//! along the line to the rest, turning through the candidate's rotation, scaled by trial
//! run-outs until the distance or rotation matches); with marks, that guess fitted to the rest
//! alone; the guess with its yaw rate times 2.5, 0.4 and -1, turned 0.4 rad either way off the
//! line, and aimed at the mark nearest the start; then a scatter of 18 single run-outs (three
//! directions, two speeds, three yaw rates) searched from its two best. With
//! [`EstimateSettings::scatter`], the counts are also explored from one scatter of single
//! run-outs shared by every count (with a rest position, the separation states whose run-outs
//! end there, one per yaw rate from -10 to 10 rad/s on the branches through the first guess
//! and through faster states, and those a grid of each whole yaw rate finds, by the rest
//! position and, for a rolling car whose rest moves tens of metres with one per cent of speed,
//! by the rest heading; every state where a branch's rest heading passes a count's
//! heading explored for that count; without, a grid of yaw rates, directions and speeds; each
//! run-out counts for the count of turns it ends nearest): those and the lowest other points
//! over all counts (up to twelve in all), ranked and first searched on the evidence with its standard
//! deviations raised to 1 m and 10 deg and then to 0.2 m and 2 deg (smoother costs with the same
//! minimum for exact evidence), then on the evidence as given. The best explored point is
//! polished at full precision; the other distinct minima explored within a chi-square of 25 of
//! it are kept as the candidate's [`Candidate::alternatives`]. Counts that still end above the expectation start once more
//! from the answers of the counts that did not. Every state searched keeps within
//! [`MAX_SEARCH_SPEED`] and [`MAX_SEARCH_YAW_RATE`]. This is a local search from many starts, not a
//! proof: on 24 random run-outs with two marks each, every true count was found (to a cost of
//! 7e-10 and velocities to 6e-7; `tests/runout_inverse.rs`).
//!
//! ## What the evidence determines
//! At each candidate's minimum the weighted Jacobian `J` tells what the evidence determines:
//! its singular directions with a singular value below 1e-6 of the largest are *free* (the cost
//! does not change along them to first order; e.g. speed against friction when only the rest
//! position is known and the friction is estimated: the path of sliding wheels keeps its shape
//! when the friction scales by `s` and the velocities by `sqrt(s)`), and the standard errors of
//! the determined unknowns are the square roots of the diagonal of `(J^T J)^-1` (the
//! linearisation; exact for the evidence's sigmas in the limit of small ones). With the friction
//! estimated, the free directions are those of the scene's rows alone (the friction's own
//! standard deviation then decides along them).

mod evidence;
mod headings;
mod levenberg;
mod linear;
mod problem;
mod scatter;
mod search;
mod starts;

pub use evidence::{
    Alternative, Candidate, Estimate, EstimateSettings, Evidence, Mark, Quantity, Residual, Rest,
    ALTERNATIVE_COST, CONSISTENT_COST, MAX_ALTERNATIVES, MAX_HEADING, MAX_SCENE_DISTANCE,
    MAX_SEARCH_SPEED, MAX_SEARCH_YAW_RATE, MAX_TURNS, PLAUSIBLE_COST,
};
pub use linear::{
    differentiate, differentiate_zones, linearise, linearise_with_friction, Linearised,
};
pub use problem::residuals_of;

use crate::chassis::{Chassis, Motion};
use crate::error::Result;
use evidence::input;
use problem::Problem;
use rayon::prelude::*;
use search::solve;
use std::f64::consts::TAU;

/// Estimates the separation velocities of a vehicle that starts at `start` (its position and
/// heading at separation; its velocities are ignored) from `evidence`, for every count of
/// turns in `settings.turns` (or the count the evidence states).
///
/// # Errors
/// [`RunoutError::Input`](crate::RunoutError::Input) for a vehicle, start, evidence or settings the model cannot use.
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
    let problem_of = |k: Option<i64>| Problem {
        chassis,
        start: *start,
        evidence,
        heading: nearest.map(|h| h + TAU * k.unwrap_or(0) as f64),
        settings: &settings.runout,
        estimate_friction,
        work: Default::default(),
    };
    // The count with no turns added (or the one stated) gives the scatter's direction and
    // speed.
    let middle = counts
        .iter()
        .copied()
        .find(|k| k.unwrap_or(0) == 0)
        .unwrap_or(counts[0]);
    let headings: Vec<Option<f64>> = counts
        .iter()
        .map(|k| nearest.map(|h| h + TAU * k.unwrap_or(0) as f64))
        .collect();
    let scatter = if settings.scatter {
        scatter::scatter(&problem_of(middle), &headings, settings.fine)
    } else {
        vec![(Vec::new(), 0); counts.len()]
    };
    let rotation =
        |k: Option<i64>| nearest.map_or(0.0, |h| h + TAU * k.unwrap_or(0) as f64 - start.heading);
    let answers = answers_per_count(
        (&counts, &rotation),
        settings,
        (chassis.friction, estimate_friction),
    );
    let mut candidates = counts
        .par_iter()
        .zip(scatter.par_iter().zip(&answers))
        .map(|(&k, ((starts, spent), answers))| {
            let problem = problem_of(k);
            let mut c = solve(
                &problem,
                k,
                settings.max_iterations,
                &[],
                (starts, answers),
                settings.quick,
            )?;
            c.runouts += spent;
            Ok(c)
        })
        .collect::<Result<Vec<_>>>()?;
    restart_poor(
        &mut candidates,
        (&problem_of, &rotation),
        settings,
        estimate_friction,
    )?;
    ranked(&mut candidates);
    let mut unknowns: Vec<String> = ["vx", "vy", "yaw_rate"].map(String::from).to_vec();
    if estimate_friction {
        unknowns.push("friction".into());
    }
    Ok(Estimate {
        unknowns,
        candidates,
    })
}

/// Counts that ended above the chi-square's expectation start again from the answers of the
/// counts that did not (neighbouring counts often have neighbouring answers), the lower kept.
fn restart_poor<'a, P, R>(
    candidates: &mut [Candidate],
    (problem_of, rotation): (&P, &R),
    settings: &EstimateSettings,
    estimate_friction: bool,
) -> Result<()>
where
    P: Fn(Option<i64>) -> Problem<'a> + Sync,
    R: Fn(Option<i64>) -> f64 + Sync,
{
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
    if good.is_empty() {
        return Ok(());
    }
    let redone = candidates
        .par_iter()
        .map(|c| {
            if c.cost <= c.residuals.len() as f64 {
                return Ok(None);
            }
            // A quick search starts only from the neighbouring counts' answers.
            let starts: Vec<Vec<f64>> = good
                .iter()
                .filter(|(k, _)| {
                    !settings.quick
                        || matches!((k, c.turns), (Some(a), Some(b)) if (a - b).abs() <= 1)
                })
                .map(|(k, theta)| {
                    let mut t = theta.clone();
                    let (from, to) = (rotation(*k), rotation(c.turns));
                    if from.abs() > 1e-3 {
                        t[2] *= to / from;
                    }
                    t
                })
                .collect();
            if starts.is_empty() {
                return Ok(None);
            }
            let problem = problem_of(c.turns);
            solve(
                &problem,
                c.turns,
                settings.max_iterations,
                &starts,
                (&[], &[]),
                settings.quick,
            )
            .map(Some)
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
    Ok(())
}

/// A count's rotation from the heading at separation to its rest heading, rad.
type Rotation<'a> = dyn Fn(Option<i64>) -> f64 + 'a;

/// Each count's starts from [`EstimateSettings::starts`]: every answer found for a count
/// within one turn of it, its yaw rate scaled to the count's rotation (`rotation` of a count),
/// the friction appended where it is estimated.
fn answers_per_count(
    (counts, rotation): (&[Option<i64>], &Rotation<'_>),
    settings: &EstimateSettings,
    (friction, estimate_friction): (f64, bool),
) -> Vec<Vec<Vec<f64>>> {
    counts
        .iter()
        .map(|&k| {
            settings
                .starts
                .iter()
                .filter(|(from, _)| !matches!((from, k), (Some(a), Some(b)) if (a - b).abs() > 1))
                .map(|(from, at)| {
                    let mut t = at.to_vec();
                    let (r0, r1) = (rotation(*from), rotation(k));
                    if r0.abs() > 1e-3 {
                        t[2] *= r1 / r0;
                    }
                    if estimate_friction {
                        t.push(friction);
                    }
                    t
                })
                .collect()
        })
        .collect()
}

/// The candidates from the lowest cost, each marked consistent or plausible against the best.
fn ranked(candidates: &mut [evidence::Candidate]) {
    candidates.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    let best = candidates.first().map_or(0.0, |c| c.cost);
    for c in candidates {
        c.consistent = c.cost - best <= CONSISTENT_COST;
        c.plausible = c.cost - best < PLAUSIBLE_COST;
    }
}
