//! One scatter of single run-outs shared by every count of turns: each run-out ends nearest one
//! count, and each count is explored from its lowest scatter points as well as from its own
//! first guess.
//!
//! A first guess and its variations (yaw rate scaled, direction turned) search near the state
//! a uniform deceleration suggests; a vehicle whose tyres turn it back (high yaw rate at
//! separation, little net rotation) or that spins through most of its run-out lies far from
//! it, in a basin of its own, often narrow in speed (a rolling car's rest moves metres with a
//! few per cent of speed). With a rest position the scatter follows the *rest curve*: the rest
//! position is two equations in the three unknowns, so the states that reach it form curves,
//! followed here by the yaw rate (-10 to 10 rad/s, the CG velocity by Newton's method at each,
//! continued from the last): the branch through the first guess in steps of 0.25, and in steps
//! of 0.5 the branches through faster states along the guess's line (2.5 and 4 times its
//! speed) and across it (turned 1.2 rad either way, 2.5 times): a car whose path is many times
//! the distance to its rest (rolling, turned back by its steered wheels or its spin) lies on a
//! branch of its own. Branches no seed lies near are found by mapping, at every whole yaw rate,
//! a polar grid of CG velocities (24 directions, 8 speeds from 0.5 to 5.6 times the first
//! guess's) to its rests: each cell whose image holds the rest gives a state on a branch, and
//! those on no branch followed so far are followed too (4,032 run-outs more, at a tolerance of
//! 1e-4: they only locate the cells). Where a rolling
//! car's rest is too sensitive for those cells to hold it, the same speed lines find the states
//! whose rest *heading* is a count's ([`super::headings`]): the one per count nearest its
//! count's heading once brought to the rest is that count's start besides the others. A
//! branch that
//! crosses no whole yaw rate can still be missed: some are closed loops (a rolling car looping
//! 98 m back to 8 m from its start reaches its rest only at yaw rates from -2.1 to -1.45
//! rad/s). About 6,000 to 9,000 run-outs per vehicle, each ending at the rest position, whose
//! heading and marks then rank it; where the rest heading passes a count's
//! heading between two points of a branch, the state between them is a solution of that
//! count's scene and is explored whatever the other counts' points cost (several per count:
//! the rest alone is three equations in three unknowns, met by every count, often by several
//! states of one count, which only the impact tells apart). Without a rest position, a grid: yaw
//! rates -8 to 8 rad/s in steps of 0.5, nine directions about the line to the first mark (±0.8
//! rad) and five speeds (0.7 to 1.5 times the first guess's), 1,485 run-outs. Either is run at
//! the exploring tolerance, once per vehicle, not once per count; of each count's six lowest
//! distinct points (by the softened cost) the twelve lowest over all counts are explored.

use super::headings;
use super::problem::{Problem, INTERNAL_STEP};
use super::search::{bounded, first_guess, EXPLORE_TOLERANCE};
use crate::simulate::Runout;
use rayon::prelude::*;

/// The scatter's yaw rates: -8 to 8 rad/s in steps of 0.5.
fn yaw_rates() -> impl Iterator<Item = f64> {
    (0..33).map(|i| -8.0 + 0.5 * f64::from(i))
}
/// Its directions about the first guess's: -0.8 to 0.8 rad in steps of 0.2.
fn directions() -> impl Iterator<Item = f64> {
    (0..9).map(|i| -0.8 + 0.2 * f64::from(i))
}
/// Its speeds as multiples of the first guess's.
const SPEEDS: [f64; 5] = [0.7, 0.9, 1.1, 1.3, 1.5];
/// Where a scatter point's run-out ends: the count it ends nearest, its cost there and its
/// count of residuals.
type End = (usize, f64, usize);

/// Distinct scatter points kept per count...
const PER_COUNT: usize = 6;
/// ... and explored in all, the lowest over every count.
const IN_ALL: usize = 12;

/// For each count (one per heading of `headings`): its lowest scatter points by the softened
/// cost ([`Evidence::softened`](super::evidence::Evidence::softened); distinct yaw rates or directions) and the run-outs the scatter spent on
/// it.
pub(crate) fn scatter(
    base: &Problem,
    headings: &[Option<f64>],
    fine: bool,
) -> Vec<(Vec<Vec<f64>>, usize)> {
    let mut out: Vec<(Vec<Vec<f64>>, usize)> = vec![(Vec::new(), 0); headings.len()];
    if headings.is_empty() {
        return out;
    }
    let coarse = base.settings.no_finer_than(EXPLORE_TOLERANCE);
    let soft = base.evidence.softened(1.0);
    let problem = |heading: Option<f64>| Problem {
        chassis: base.chassis,
        start: base.start,
        evidence: &soft,
        heading,
        settings: &coarse,
        estimate_friction: base.estimate_friction,
        work: Default::default(),
    };
    let mut guess_runouts = 0;
    let guess = first_guess(base, &mut guess_runouts);
    let mut seeds = Vec::new();
    let branches = match base.evidence.rest {
        Some(rest) => {
            let path = Problem {
                evidence: base.evidence,
                ..problem(None)
            };
            let (x, y) = rest.cg();
            let (branches, spent, found) = rest_curve(&path, &guess, [x, y], (headings, fine));
            guess_runouts += spent;
            seeds = found;
            branches
        }
        None => vec![grid(&guess)],
    };
    let points: Vec<Vec<f64>> = branches.concat();
    let problems: Vec<Problem> = headings.iter().map(|&h| problem(h)).collect();
    let heading = |k: usize| problems[k].heading;
    // Each point's run-out once: its rest heading, the count it ends nearest, its cost there.
    let runs: Vec<Option<(f64, Option<End>)>> = points
        .par_iter()
        .map(|t| {
            let run = problems[0].runout(t).ok()?;
            let k = (0..headings.len()).min_by(|&a, &b| {
                let off = |i: usize| heading(i).map_or(0.0, |h| (run.rest.heading - h).abs());
                off(a).total_cmp(&off(b))
            });
            let end = k.and_then(|k| {
                let residuals = problems[k].residuals(t, &run);
                let cost: f64 = residuals.iter().map(|r| (r.value / r.sigma).powi(2)).sum();
                cost.is_finite().then_some((k, cost, residuals.len()))
            });
            Some((run.rest.heading, end))
        })
        .collect();
    let rests: Vec<Option<f64>> = runs.iter().map(|r| r.map(|r| r.0)).collect();
    let ends: Vec<Option<End>> = runs.iter().map(|r| r.and_then(|r| r.1)).collect();
    let mut by_count: Vec<Vec<(f64, &Vec<f64>, bool)>> = vec![Vec::new(); headings.len()];
    for (t, e) in points.iter().zip(&ends) {
        if let Some((k, cost, n)) = e {
            by_count[*k].push((*cost, t, *cost <= *n as f64));
        }
    }
    // The run-outs spent, each on the count it ended nearest (the failed ones on the first).
    out[0].1 += guess_runouts + ends.iter().filter(|e| e.is_none()).count();
    // Each count's distinct points, the lowest first (at most PER_COUNT)...
    let mut candidates: Vec<(f64, usize, &Vec<f64>)> = Vec::new();
    for (k, mut list) in by_count.into_iter().enumerate() {
        out[k].1 += list.len();
        list.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut chosen: Vec<&Vec<f64>> = Vec::new();
        for (cost, t, within) in list {
            if chosen.len() >= PER_COUNT {
                break;
            }
            let distinct = chosen.iter().all(|c| {
                (c[2] - t[2]).abs() > 0.4 || (c[1].atan2(c[0]) - t[1].atan2(t[0])).abs() > 0.2
            });
            if distinct {
                chosen.push(t);
                // A point within its expectation (a softened chi-square no larger than its
                // count of residuals) lies next to a state that meets the evidence: explored
                // whatever the other counts' points cost. A scene with a rest alone is three
                // equations in three unknowns, met exactly by every count, often by several
                // states of one count (a rolling car that spins one way at separation and
                // turns back under its steered wheels); the impact decides between them, so
                // each must be a start.
                if within {
                    out[k].0.push(t.clone());
                } else {
                    candidates.push((cost, k, t));
                }
            }
        }
    }
    if base.evidence.rest.is_some() {
        crossings(&branches, &rests, headings, &mut out);
    }
    // ... and of the others the lowest over every count, up to IN_ALL explored in all.
    let explored: usize = out.iter().map(|o| o.0.len()).sum();
    candidates.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (_, k, t) in candidates.into_iter().take(IN_ALL.saturating_sub(explored)) {
        out[k].0.push(t.clone());
    }
    // The states found through the rest heading (see `headings`) are each their count's start
    // besides those.
    for (k, t) in seeds {
        out[k].0.push(t);
    }
    out
}

/// Along the rest curve, where the rest heading passes a count's heading between two points
/// of a branch (`rests` the rest headings of the branches' points, in order), the state
/// between them (interpolated) nearly meets the rest: each such crossing is a solution of
/// that count's scene, pushed to its starts in `out` (the first PER_COUNT).
fn crossings(
    branches: &[Vec<Vec<f64>>],
    rests: &[Option<f64>],
    headings: &[Option<f64>],
    out: &mut [(Vec<Vec<f64>>, usize)],
) {
    let points: Vec<&Vec<f64>> = branches.iter().flatten().collect();
    let mut crossings = vec![0; headings.len()];
    let mut first = 0;
    for b in branches {
        for i in first..(first + b.len()).saturating_sub(1) {
            let (Some(ha), Some(hb)) = (rests[i], rests[i + 1]) else {
                continue;
            };
            for (k, h) in headings.iter().enumerate() {
                let Some(h) = h else { continue };
                if (ha - h) * (hb - h) >= 0.0 || crossings[k] >= PER_COUNT {
                    continue;
                }
                let f = (h - ha) / (hb - ha);
                let t: Vec<f64> = points[i]
                    .iter()
                    .zip(points[i + 1])
                    .map(|(a, b)| a + f * (b - a))
                    .collect();
                crossings[k] += 1;
                out[k].0.push(t);
            }
        }
        first += b.len();
    }
}

/// The grid of separation states about the first guess: every direction, speed and yaw rate of
/// the scatter.
fn grid(guess: &[f64]) -> Vec<Vec<f64>> {
    let mut points = Vec::new();
    for turn in directions() {
        for speed in SPEEDS {
            for yaw in yaw_rates() {
                let (s, c) = turn.sin_cos();
                let mut t = guess.to_vec();
                t[0] = speed * (c * guess[0] - s * guess[1]);
                t[1] = speed * (s * guess[0] + c * guess[1]);
                t[2] = yaw;
                bounded(&mut t);
                points.push(t);
            }
        }
    }
    points
}

/// Yaw rates along the rest curve: -10 to 10 rad/s in steps of 0.25.
const CURVE_STEP: f64 = 0.25;
/// See [`CURVE_STEP`].
const CURVE_LIMIT: f64 = 10.0;

/// The separation states whose run-out ends at the rest position `target`, one per yaw rate of
/// the scan, branch by branch: the rest position is two equations in the three unknowns, so
/// (the friction held) the states that reach it form curves, here followed by the yaw rate. At
/// each yaw rate the CG velocity is solved by Newton's method (forward differences) from the
/// last one's (continuation from 0 upwards and downwards, the seed's velocity at 0). A yaw
/// rate where it does not converge gives its best point and the next starts again from the
/// seed. The seeds: the first guess, [`SEEDS`], and then every state of [`preimages`] on no
/// branch already followed. With the points of each branch (in the order of the scan), the
/// run-outs spent.
fn rest_curve(
    p: &Problem,
    guess: &[f64],
    target: [f64; 2],
    (headings, fine): (&[Option<f64>], bool),
) -> (Vec<Vec<Vec<f64>>>, usize, Vec<Counted>) {
    // A branch of the guess's is followed over every yaw rate; another is given up after
    // GIVE_UP yaw rates in a row where Newton's method does not reach the rest (each such
    // costs up to 24 run-outs: the seed is on no branch there).
    let follow = |seed: &[f64], sign: f64, step: f64, persistent: bool| {
        let steps = (CURVE_LIMIT / step).round() as i32;
        let mut spent = 0;
        let mut points = Vec::new();
        let mut from = seed.to_vec();
        let mut failed = 0;
        for i in 0..=steps {
            if sign < 0.0 && i == 0 {
                continue;
            }
            let yaw = sign * step * f64::from(i);
            let mut t = from.clone();
            t[2] = yaw;
            let (end, ok) = to_rest(p, t, target, &mut spent);
            from = if ok { end.clone() } else { seed.to_vec() };
            failed = if ok { 0 } else { failed + 1 };
            points.push(end);
            if !persistent && failed >= GIVE_UP {
                break;
            }
        }
        (points, spent)
    };
    // The first guess's branch, and the branches through faster states along its line and
    // across it (a path many times the distance to the rest: a rolling car turned back by
    // its steered wheels or its spin), followed at twice the step.
    let mut seeds: Vec<(Vec<f64>, f64, bool)> = vec![(guess.to_vec(), CURVE_STEP, true)];
    for (turn, speed) in SEEDS {
        let (s, c) = f64::sin_cos(turn);
        let mut t = guess.to_vec();
        t[0] = speed * (c * guess[0] - s * guess[1]);
        t[1] = speed * (s * guess[0] + c * guess[1]);
        bounded(&mut t);
        seeds.push((t, 2.0 * CURVE_STEP, false));
    }
    let mut runs: Vec<(Vec<Vec<f64>>, usize)> = seeds
        .par_iter()
        .flat_map(|(seed, step, all)| [(seed, 1.0, *step, *all), (seed, -1.0, *step, *all)])
        .map(|(seed, sign, step, all)| follow(seed, sign, step, all))
        .collect();
    // Then the branches no seed lies on: every state of the planes' grids that reaches the
    // rest and lies on no branch followed so far, followed in turn.
    let (found, mut spent, seeds) = preimages(p, guess, target, (headings, fine));
    let on_a_branch = |t: &Vec<f64>| {
        runs.iter().flat_map(|r| &r.0).any(|q| {
            (q[2] - t[2]).abs() < 1e-9
                && (q[0] - t[0]).hypot(q[1] - t[1]) <= 0.5 + 0.03 * t[0].hypot(t[1])
        })
    };
    let fresh: Vec<Vec<f64>> = found.into_iter().filter(|t| !on_a_branch(t)).collect();
    runs.extend(
        fresh
            .par_iter()
            .flat_map(|seed| [(seed, 1.0), (seed, -1.0)])
            .map(|(seed, sign)| follow(seed, sign, 2.0 * CURVE_STEP, false))
            .collect::<Vec<_>>(),
    );
    spent += runs.iter().map(|r| r.1).sum::<usize>();
    (runs.into_iter().map(|r| r.0).collect(), spent, seeds)
}

/// The yaw rates (rad/s) at which the plane of CG velocities is mapped for [`preimages`]:
/// -10 to 10 (the rest curve's range) in steps of 1, or of 0.25 where `fine`
/// ([`super::EstimateSettings::fine`]).
fn planes(fine: bool) -> impl Iterator<Item = f64> {
    let per_unit: u32 = if fine { 4 } else { 1 };
    (0..=20 * per_unit).map(move |i| -CURVE_LIMIT + f64::from(i) / f64::from(per_unit))
}
/// The polar grid of each plane: directions all round, speeds as multiples of the first
/// guess's (geometric).
const GRID_DIRECTIONS: usize = 24;
const GRID_SPEEDS: [f64; 8] = [0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0, 5.6];
/// The relative and absolute tolerance of the grid's run-outs.
const GRID_TOLERANCE: f64 = 1e-4;

/// Every state of the rest curve found by mapping, at each yaw rate of [`planes`], a polar
/// grid of CG velocities to the run-outs' rest positions: wherever the rest `target` lies in
/// the image of a grid cell (two triangles), the state interpolated there is brought to the
/// rest by [`to_rest`]. The rest curve is a set of branches; each branch that crosses a plane
/// crosses it in a cell whose image holds the target (the map is continuous), so every such
/// branch is found whatever the first guess, to the grid's resolution. The distinct states
/// reached, and the run-outs spent.
fn preimages(
    p: &Problem,
    guess: &[f64],
    target: [f64; 2],
    (headings, fine): (&[Option<f64>], bool),
) -> (Vec<Vec<f64>>, usize, Vec<Counted>) {
    let speed = guess[0].hypot(guess[1]).max(1.0);
    let angle = guess[1].atan2(guess[0]);
    let state = |yaw: f64, i: f64, s: f64| {
        let a = angle + std::f64::consts::TAU * i / GRID_DIRECTIONS as f64;
        let mut t = guess.to_vec();
        t[0] = s * speed * a.cos();
        t[1] = s * speed * a.sin();
        t[2] = yaw;
        t
    };
    let cells: Vec<(f64, usize, usize)> = planes(fine)
        .flat_map(|w| {
            (0..GRID_DIRECTIONS).flat_map(move |i| (0..GRID_SPEEDS.len()).map(move |j| (w, i, j)))
        })
        .collect();
    // The grid only tells which cells hold the rest (their images are metres across): its
    // run-outs at GRID_TOLERANCE; the states found are then brought to the rest at the
    // search's own.
    let loose = p.settings.no_finer_than(GRID_TOLERANCE);
    let q = p.on(&loose);
    let ends: Vec<Option<[f64; 3]>> = cells
        .par_iter()
        .map(|&(w, i, j)| {
            let t = state(w, i as f64, GRID_SPEEDS[j]);
            q.runout(&t)
                .ok()
                .map(|r| [r.rest.x, r.rest.y, r.rest.heading])
        })
        .collect();
    let mut spent = cells.len();
    let n = GRID_SPEEDS.len();
    let end =
        |k: usize, i: usize, j: usize| ends[(k * GRID_DIRECTIONS + i % GRID_DIRECTIONS) * n + j];
    let at = |k: usize, i: usize, j: usize| end(k, i, j).map(|e| [e[0], e[1]]);
    let mut starts = Vec::new();
    let mut brackets = Vec::new();
    for (k, w) in planes(fine).enumerate() {
        for i in 0..GRID_DIRECTIONS {
            let line: Vec<(f64, Option<[f64; 3]>)> =
                (0..n).map(|j| (GRID_SPEEDS[j], end(k, i, j))).collect();
            // The heading brackets at the whole yaw rates only (the finer planes are for the
            // cells' images, where a closed branch shows).
            if w.fract() == 0.0 {
                headings::brackets_of((w, i as f64), &line, headings, &mut brackets);
            }
            for j in 0..n - 1 {
                let corners = [(0, 0), (1, 0), (1, 1), (0, 1)];
                let pts: Vec<Option<[f64; 2]>> =
                    corners.iter().map(|&(a, b)| at(k, i + a, j + b)).collect();
                for tri in [[0, 1, 2], [0, 2, 3]] {
                    let (Some(a), Some(b), Some(c)) = (pts[tri[0]], pts[tri[1]], pts[tri[2]])
                    else {
                        continue;
                    };
                    let Some((u, v)) = barycentric(a, b, c, target) else {
                        continue;
                    };
                    // The cell's corners in (direction index, log speed), interpolated.
                    let coord = |m: usize| {
                        let (da, db) = corners[tri[m]];
                        ((i + da) as f64, GRID_SPEEDS[j + db].ln())
                    };
                    let (a0, b0, c0) = (coord(0), coord(1), coord(2));
                    let di = a0.0 + u * (b0.0 - a0.0) + v * (c0.0 - a0.0);
                    let ls = a0.1 + u * (b0.1 - a0.1) + v * (c0.1 - a0.1);
                    starts.push(state(w, di, ls.exp()));
                }
            }
        }
    }
    let reached: Vec<(Option<Vec<f64>>, usize)> = starts
        .into_par_iter()
        .map(|t| {
            let mut used = 0;
            let (end, ok) = to_rest(p, t, target, &mut used);
            (ok.then_some(end), used)
        })
        .collect();
    // Where the rest heading passes a count's along a speed line: see `headings`.
    let (crossing, used) = headings::crossing_states(&q, &brackets, headings, target, &state);
    spent += used;
    let dist = (target[0] - p.start.x).hypot(target[1] - p.start.y);
    let near = headings::near_the_line(crossing, dist);
    let at_rest: Vec<(usize, headings::AtRest, usize)> = near
        .into_par_iter()
        .map(|(k, t)| {
            let mut used = 1;
            let (end, ok) = to_rest(p, t, target, &mut used);
            let miss =
                headings[k].and_then(|h| Some((p.runout(&end).ok()?.rest.heading - h).abs()));
            (k, miss.filter(|_| ok).map(|m| (m, end)), used)
        })
        .collect();
    spent += at_rest.iter().map(|r| r.2).sum::<usize>();
    let seeds = headings::best_per_count(at_rest.into_iter().map(|r| (r.0, r.1)), headings.len());
    let mut found: Vec<Vec<f64>> = Vec::new();
    for (t, used) in reached {
        spent += used;
        let Some(t) = t else { continue };
        // One state per branch crossing (cells next to each other can find the same).
        if found
            .iter()
            .all(|f| (f[2] - t[2]).abs() > 1e-9 || (f[0] - t[0]).hypot(f[1] - t[1]) > 0.05 * speed)
        {
            found.push(t);
        }
    }
    (found, spent, seeds)
}

/// A state with the index of the count of turns it was found for.
type Counted = (usize, Vec<f64>);

/// The barycentric coordinates `(u, v)` of `x` in the triangle `a b c` (`x = a + u (b - a) +
/// v (c - a)`) when `x` lies in it.
fn barycentric(a: [f64; 2], b: [f64; 2], c: [f64; 2], x: [f64; 2]) -> Option<(f64, f64)> {
    let (e1, e2, d) = (
        [b[0] - a[0], b[1] - a[1]],
        [c[0] - a[0], c[1] - a[1]],
        [x[0] - a[0], x[1] - a[1]],
    );
    let det = e1[0] * e2[1] - e1[1] * e2[0];
    if det.abs() < 1e-12 {
        return None;
    }
    let u = (d[0] * e2[1] - d[1] * e2[0]) / det;
    let v = (e1[0] * d[1] - e1[1] * d[0]) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0).then_some((u, v))
}

/// Yaw rates in a row without the rest after which a seed's branch is given up.
const GIVE_UP: i32 = 3;

/// The other seeds of the rest curve: (turn off the first guess's direction, rad; its speed
/// times).
const SEEDS: [(f64, f64); 4] = [(0.0, 2.5), (0.0, 4.0), (1.2, 2.5), (-1.2, 2.5)];

/// Newton's method on the CG velocity (the yaw rate held) to bring the run-out's rest to
/// `target`: the state reached and whether it is within 1 % of the distance (and 0.5 m).
fn to_rest(p: &Problem, mut t: Vec<f64>, target: [f64; 2], spent: &mut usize) -> (Vec<f64>, bool) {
    let dist = (target[0] - p.start.x).hypot(target[1] - p.start.y);
    let tolerance = (0.01 * dist).max(0.5);
    let miss_of = |r: &Runout| [r.rest.x - target[0], r.rest.y - target[1]];
    let simulated = |t: &[f64], spent: &mut usize| -> Option<Runout> {
        *spent += 1;
        p.runout(t).ok()
    };
    let miss = |t: &[f64], spent: &mut usize| simulated(t, spent).map(|r| (miss_of(&r), r));
    bounded(&mut t);
    let Some((mut r, mut now)) = miss(&t, spent) else {
        return (t, false);
    };
    for _ in 0..8 {
        if r[0].hypot(r[1]) < tolerance {
            return (t, true);
        }
        // The 2 x 2 Jacobian of the rest position in (vx, vy): through the current run-out's
        // steps where it can be replayed (see `jacobian`), else from run-outs of their own.
        let mut j = [[0.0; 2]; 2];
        let replayable = p.can_replay(&now);
        for c in 0..2 {
            let relative = if replayable { INTERNAL_STEP } else { 1e-3 };
            let h = relative * (1.0 + t[c].abs());
            let mut u = t.clone();
            u[c] += h;
            let column = if replayable {
                *spent += 1;
                p.runout_through(&u, Some(&now))
                    .and_then(|r| r.ok())
                    .map(|r| miss_of(&r))
            } else {
                simulated(&u, spent).map(|r| miss_of(&r))
            };
            let Some(rc) = column else {
                return (t, false);
            };
            j[0][c] = (rc[0] - r[0]) / h;
            j[1][c] = (rc[1] - r[1]) / h;
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if det.is_nan() || det.abs() <= 1e-12 {
            return (t, false);
        }
        let mut dx = -(j[1][1] * r[0] - j[0][1] * r[1]) / det;
        let mut dy = -(-j[1][0] * r[0] + j[0][0] * r[1]) / det;
        // A step of at most 30 % of the speed (and 1 m/s).
        let limit = (0.3 * t[0].hypot(t[1])).max(1.0);
        let len = dx.hypot(dy);
        if len > limit {
            dx *= limit / len;
            dy *= limit / len;
        }
        let mut u = t.clone();
        u[0] += dx;
        u[1] += dy;
        bounded(&mut u);
        let Some((ru, run_u)) = miss(&u, spent) else {
            return (t, false);
        };
        if ru[0].hypot(ru[1]) >= r[0].hypot(r[1]) {
            // Halved once; a second failure ends the search at this yaw rate.
            u = t.clone();
            u[0] += 0.5 * dx;
            u[1] += 0.5 * dy;
            bounded(&mut u);
            let Some((rh, run_h)) = miss(&u, spent) else {
                return (t, false);
            };
            if rh[0].hypot(rh[1]) >= r[0].hypot(r[1]) {
                return (t, false);
            }
            t = u;
            r = rh;
            now = run_h;
        } else {
            t = u;
            r = ru;
            now = run_u;
        }
    }
    let ok = r[0].hypot(r[1]) < tolerance;
    (t, ok)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::chassis::{Chassis, Motion, WheelState};
    use crate::inverse::evidence::{Evidence, Rest};
    use crate::simulate::Settings;

    /// A run-out from a state at a whole yaw rate: the grid at that yaw rate finds a state
    /// whose run-out ends at its rest (within `to_rest`'s tolerance), wherever the first guess
    /// points: the grid covers every direction.
    #[test]
    fn the_grid_finds_the_states_that_reach_a_rest() {
        for (state, t) in [
            (WheelState::Locked, [9.0, 4.0, 2.0]),
            (WheelState::Rolling, [6.0, -3.0, -3.0]),
        ] {
            let mut chassis = Chassis::new(1500.0, 2500.0, 2.7, 1.2, 1.5, state);
            chassis.rolling_resistance = 0.3;
            let start = Motion {
                x: 0.0,
                y: 0.0,
                heading: 0.3,
                vx: t[0],
                vy: t[1],
                yaw_rate: t[2],
            };
            let settings = Settings::default();
            let truth = crate::simulate(&chassis, &start, &settings).unwrap();
            let evidence = Evidence {
                rest: Some(Rest {
                    x: truth.rest.x,
                    y: truth.rest.y,
                    heading: None,
                    sigma_xy: [0.1, 0.1],
                    sigma_heading: 0.1,
                    point: [0.0, 0.0],
                }),
                ..Evidence::default()
            };
            let p = Problem {
                chassis: &chassis,
                start,
                evidence: &evidence,
                heading: None,
                settings: &settings,
                estimate_friction: false,
                work: Default::default(),
            };
            // A first guess pointing the other way, at half the speed.
            let guess = [-0.5 * t[0], -0.5 * t[1], 0.0];
            let (found, spent, _) =
                preimages(&p, &guess, [truth.rest.x, truth.rest.y], (&[], false));
            assert!(spent >= 21 * GRID_DIRECTIONS * GRID_SPEEDS.len());
            let near = found
                .iter()
                .filter(|f| (f[2] - t[2]).abs() < 1e-9)
                .map(|f| (f[0] - t[0]).hypot(f[1] - t[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(near < 0.5, "{state:?}: nearest {near} m/s of {found:?}");
        }
    }

    #[test]
    fn barycentric_coordinates_hold_inside_only() {
        let (a, b, c) = ([0.0, 0.0], [2.0, 0.0], [0.0, 2.0]);
        assert_eq!(barycentric(a, b, c, [0.5, 0.5]), Some((0.25, 0.25)));
        assert_eq!(barycentric(a, b, c, [1.5, 1.5]), None);
        assert_eq!(barycentric(a, b, [4.0, 0.0], [1.0, 0.0]), None);
    }
}
