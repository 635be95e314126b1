//! The least-squares search of one candidate: starts, Levenberg-Marquardt, what the evidence
//! determines at the answer.

use super::evidence::{
    Alternative, Candidate, Evidence, Quantity, Residual, ALTERNATIVE_COST, MAX_ALTERNATIVES,
    MAX_SEARCH_SPEED, MAX_SEARCH_YAW_RATE,
};
use super::levenberg::{jacobian, levenberg, Search};
use super::problem::Problem;
use super::starts::{around, toward_nearest_mark, turned};
use crate::chassis::{Motion, GRAVITY};
use crate::error::Result;
use crate::simulate::{End, Runout};
use nalgebra::DMatrix;

/// The first guess of a candidate: a uniform deceleration along the line from the start to
/// the rest (or the first mark), turning through the candidate's rotation in the same time;
/// then scaled by trial run-outs until the distance (or, for a vehicle that barely moves, the
/// rotation) matches.
pub(crate) fn first_guess(p: &Problem, runouts: &mut usize) -> Vec<f64> {
    let target = p
        .evidence
        .rest
        .map(|r| r.cg())
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
        bounded(&mut theta);
    }
    bounded(&mut theta);
    theta
}

/// Scales a start into the separation states a search tries (within 95 % of
/// [`MAX_SEARCH_SPEED`] and [`MAX_SEARCH_YAW_RATE`]).
pub(crate) fn bounded(theta: &mut [f64]) {
    let speed = theta[0].hypot(theta[1]);
    if speed > 0.95 * MAX_SEARCH_SPEED {
        let k = 0.95 * MAX_SEARCH_SPEED / speed;
        theta[0] *= k;
        theta[1] *= k;
    }
    theta[2] = theta[2].clamp(-0.95 * MAX_SEARCH_YAW_RATE, 0.95 * MAX_SEARCH_YAW_RATE);
}

/// `start` searched on each of the softened evidence `soft` in turn, then on `coarse` (the
/// evidence as given, exploring run-outs), counting run-outs and iterations.
fn softly(
    soft: &[Problem],
    coarse: &Problem,
    start: &[f64],
    (runouts, iterations): (&mut usize, &mut usize),
) -> Result<Search> {
    let mut theta = start.to_vec();
    bounded(&mut theta);
    for q in soft {
        let s = levenberg(q, theta, EXPLORE_ITERATIONS, runouts, false)?;
        *iterations += s.iterations;
        theta = s.theta;
    }
    let s = levenberg(coarse, theta, EXPLORE_ITERATIONS, runouts, false)?;
    *iterations += s.iterations;
    Ok(s)
}

/// Tolerances of the run-outs that explore from each start before the best is polished.
pub(crate) const EXPLORE_TOLERANCE: f64 = 1e-6;

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
pub(crate) fn solve(
    p: &Problem,
    turns: Option<i64>,
    max_iterations: usize,
    others: &[Vec<f64>],
    (scattered, answers): (&[Vec<f64>], &[Vec<f64>]),
    quick: bool,
) -> Result<Candidate> {
    let mut runouts = 0;
    // A second pass (others given) tries only the others: the rest were tried in the first.
    let second_pass = !others.is_empty();
    let guess = first_guess(p, &mut runouts);
    let coarse_settings = p.settings.no_finer_than(EXPLORE_TOLERANCE);
    let coarse = p.on(&coarse_settings);
    let mut iterations = 0;
    let mut explored: Option<Search> = None;
    // Every explored end, for the alternatives.
    let ends = std::cell::RefCell::new(Vec::<Ended>::new());
    let consider = |s: Search, explored: &mut Option<Search>| {
        ends.borrow_mut().push((s.theta.clone(), s.cost));
        if explored.as_ref().is_none_or(|b| s.cost < b.cost) {
            *explored = Some(s);
        }
    };
    let good = |s: &Option<Search>| s.as_ref().is_some_and(|s| s.cost <= s.r.len() as f64);
    // 1. The first guess.
    if !second_pass {
        let s = levenberg(
            &coarse,
            guess.clone(),
            EXPLORE_ITERATIONS,
            &mut runouts,
            false,
        )?;
        iterations += s.iterations;
        consider(s, &mut explored);
    }
    // 1b. The lowest points of the shared scatter that end nearest this count, each searched
    //     on the softened evidence and then on the evidence as given (each whatever the first
    //     guess found: other basins are the alternatives).
    let soft_evidence = [1.0, 0.2].map(|f| p.evidence.softened(f));
    let soft = soft_evidence.each_ref().map(|e| Problem {
        evidence: e,
        work: Default::default(),
        ..coarse
    });
    for start in scattered {
        let s = softly(&soft, &coarse, start, (&mut runouts, &mut iterations))?;
        consider(s, &mut explored);
    }
    // 1c. Where an impact's answers ended (EstimateSettings::starts), searched as the
    //     scatter's states are and kept apart: alternatives of their own, never the candidate
    //     and never in place of the other alternatives.
    let mut from_answers = Vec::new();
    for start in answers {
        let s = softly(&soft, &coarse, start, (&mut runouts, &mut iterations))?;
        from_answers.push((s.theta, s.cost));
    }
    // 2. With marks, through the rest alone.
    if !second_pass && !good(&explored) && !p.evidence.marks.is_empty() && p.evidence.rest.is_some()
    {
        let s = through_rest_alone(&coarse, &guess, (&mut runouts, &mut iterations))?;
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
    } else if !quick {
        starts.extend([
            spun(2.5),
            spun(0.4),
            turned(&guess, 0.4),
            turned(&guess, -0.4),
            spun(-1.0),
        ]);
        starts.extend(toward_nearest_mark(p, &guess));
    }
    for start in starts {
        if good(&explored) {
            break;
        }
        let mut start = start;
        bounded(&mut start);
        let s = levenberg(&coarse, start, EXPLORE_ITERATIONS, &mut runouts, false)?;
        iterations += s.iterations;
        consider(s, &mut explored);
    }
    // 4. Still above the expectation: a scatter of single run-outs around the first guess
    //    (direction, speed, yaw rate), searched from the two lowest.
    if !second_pass && !quick && !good(&explored) {
        for start in around(&coarse, &guess, &mut runouts).into_iter().take(2) {
            if good(&explored) {
                break;
            }
            let mut start = start;
            bounded(&mut start);
            let s = levenberg(&coarse, start, EXPLORE_ITERATIONS, &mut runouts, false)?;
            iterations += s.iterations;
            consider(s, &mut explored);
        }
    }
    // 5. Polished ([`polished`]).
    let same_runouts = coarse_settings == *p.settings;
    polished(
        p,
        (turns, max_iterations, quick, same_runouts),
        (explored, guess),
        (ends.into_inner(), from_answers),
        (runouts, iterations),
    )
}

/// Where an exploring search ended: its unknowns and its cost.
type Ended = (Vec<f64>, f64);

/// Stage 2 of [`solve`]: `guess` fitted to the rest alone on `coarse` (the rest's exact
/// solutions are often the marks' basin), then to all of its evidence.
fn through_rest_alone(
    coarse: &Problem,
    guess: &[f64],
    (runouts, iterations): (&mut usize, &mut usize),
) -> Result<Search> {
    let rest_only = Evidence {
        marks: Vec::new(),
        ..coarse.evidence.clone()
    };
    let q = Problem {
        evidence: &rest_only,
        work: Default::default(),
        ..*coarse
    };
    let first = levenberg(&q, guess.to_vec(), EXPLORE_ITERATIONS, runouts, false)?;
    let s = levenberg(coarse, first.theta, EXPLORE_ITERATIONS, runouts, false)?;
    *iterations += first.iterations + s.iterations;
    Ok(s)
}

/// Stage 5 of [`solve`]: the best explored point polished at the settings' precision (a polish
/// on coarser run-outs would answer a slightly different model: a long free-rolling run-out
/// moves by millimetres between tolerances 1e-9 and 1e-10), or, in a quick look whose
/// exploring run-outs already have the settings' precision (`same_runouts`), a converged
/// explored point kept as it is (polishing it again on the same run-outs would only confirm
/// it); from the first guess where nothing was explored. The candidate, with its alternatives
/// among `ends` and `from_answers`, what the evidence determines and the run-outs and
/// iterations spent.
fn polished(
    p: &Problem,
    (turns, max_iterations, quick, same_runouts): (Option<i64>, usize, bool, bool),
    (explored, guess): (Option<Search>, Vec<f64>),
    (ends, from_answers): (Vec<Ended>, Vec<Ended>),
    (mut runouts, mut iterations): (usize, usize),
) -> Result<Candidate> {
    let best = match explored {
        Some(s) if quick && same_runouts && s.converged => s,
        explored => {
            let from = explored.map_or(guess, |s| s.theta);
            let best = levenberg(p, from, max_iterations, &mut runouts, !quick)?;
            iterations += best.iterations;
            best
        }
    };
    let Search {
        theta,
        r,
        run: run_now,
        cost,
        jac,
        converged,
        ..
    } = best;
    // The standard errors from the Jacobian at the answer itself (the search's last one was
    // taken before its last step); a quick candidate keeps the last one.
    let jac = if quick {
        jac
    } else {
        jacobian(p, &theta, &r, &run_now, &mut runouts)?
    };
    let residuals = p.residuals(&theta, &run_now);
    let alternatives = alternatives_of(
        (&theta, cost, residuals.len()),
        p.chassis.friction,
        ends,
        from_answers,
    );
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
        alternatives,
    })
}

/// The distinct explored minima other than the answer `theta` (cost `cost`, over `data`
/// residuals): within [`ALTERNATIVE_COST`] of it, the lowest first, at most
/// [`MAX_ALTERNATIVES`] beyond those that meet the scene as well as its own data expect (a cost
/// no larger than `data`): the scene alone cannot tell those from its candidate, so none is
/// dropped (a car steered 50 m without marks has its rest as three equations in its three
/// unknowns, and five exact solutions for one count; the truth's was the fourth). Two states
/// are the same minimum when their speeds differ by less than 5 % (and 0.2 m/s) and their yaw
/// rates by less than 0.3 rad/s.
fn alternatives_of(
    (theta, cost, data): (&[f64], f64, usize),
    friction: f64,
    mut ends: Vec<Ended>,
    answers: Vec<Ended>,
) -> Vec<Alternative> {
    let same = |a: &[f64], b: &[f64]| {
        let scale = 0.05 * a[0].hypot(a[1]).max(b[0].hypot(b[1])) + 0.2;
        (a[0] - b[0]).hypot(a[1] - b[1]) < scale && (a[2] - b[2]).abs() < 0.3
    };
    ends.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut kept: Vec<Vec<f64>> = vec![theta.to_vec()];
    let mut out = Vec::new();
    // Those beyond the data's expectation kept so far (the ends are in order of cost).
    let mut beyond = 0;
    for (t, c) in ends {
        if c > cost + ALTERNATIVE_COST {
            break;
        }
        if !c.is_finite() || kept.iter().any(|k| same(k, &t)) {
            continue;
        }
        if c > data as f64 {
            if beyond >= MAX_ALTERNATIVES {
                break;
            }
            beyond += 1;
        }
        out.push(Alternative {
            velocity: [t[0], t[1], t[2]],
            friction: t.get(3).copied().unwrap_or(friction),
            cost: c,
        });
        kept.push(t);
    }
    // The answers' ends beyond the others (the answers are few).
    for (t, c) in answers {
        if !c.is_finite() || c > cost + ALTERNATIVE_COST || kept.iter().any(|k| same(k, &t)) {
            continue;
        }
        out.push(Alternative {
            velocity: [t[0], t[1], t[2]],
            friction: t.get(3).copied().unwrap_or(friction),
            cost: c,
        });
        kept.push(t);
    }
    out
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
    let (value, unit) = match worst.what {
        w if w.is_angle() => (worst.value.to_degrees(), "deg"),
        Quantity::Friction => (worst.value, ""),
        _ => (worst.value, "m"),
    };
    Some(format!(
        "the best run-out found for this count misses {} by {:.3} {unit} ({z:.1} sigma) with \
         friction {:.3}: it does not reach the evidence",
        worst.name, value, p.chassis.friction
    ))
}
