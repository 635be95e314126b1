//! States of the rest curve found through the rest heading: where a vehicle rolls a long way
//! after its slide, its rest position is too sensitive to map by a grid, its rest heading is
//! not.
//!
//! A rolling car (free rolling, or steered) slides and spins until its tyres grip, then rolls
//! straight on at the deceleration of its rolling resistance (0.015 g: 0.15 m/s², so from
//! 4.5 m/s it rolls 70 m). Its rest lies on the line through the point where it gripped, along
//! its heading there, at a distance that grows with the square of its speed there: one per
//! cent of separation speed moves such a rest by tens of metres along that line and turns the
//! line by a few degrees. A grid cell of [`super::scatter`]'s preimages (15 degrees of
//! direction, 40 % of speed) then maps to rests hundreds of metres apart on a spiral, and a
//! rest it holds is found only by chance. The rest *heading* changes smoothly (about 6 degrees
//! per per cent of speed in such a run-out): along each speed line of the grid, where the rest
//! heading passes a count's heading between two speeds and changes by [`SMOOTH`] or more
//! between them (less, and the rest moves little: the grid finds it by its position), the
//! speed between them is bisected (at most [`DEPTH`] times, until the heading changes by less
//! than [`SMOOTH`] across it) and interpolated. There the rolling line has the count's
//! heading, and the rest lies on a line parallel to the evidence's. The states whose line
//! passes within [`ACROSS`] of the distance to the rest ([`TRIED`] at most, the nearest first)
//! are brought to the rest by Newton's method on the CG velocity, and of those that reach it
//! the one of each count whose rest heading lies nearest the count's is that count's start
//! ([`PER_COUNT`]).

use super::problem::Problem;
use rayon::prelude::*;

/// Halvings of a speed interval at most...
const DEPTH: u32 = 5;
/// ... until the rest heading changes by less than this across it, rad.
const SMOOTH: f64 = 0.3;
/// States kept per count of turns, those whose rest heading lies nearest the count's once
/// they are brought to the rest (on long rolling run-outs the nearest was the true basin's,
/// and three cost as much as one).
const PER_COUNT: usize = 1;
/// Crossing states brought to the rest: those whose rolling line passes within this fraction
/// of the distance from the start to the rest...
const ACROSS: f64 = 0.15;
/// ... at most this many, the nearest first.
const TRIED: usize = 60;

/// One speed line's interval where the rest heading passes a count's heading: the line's yaw
/// rate and direction, its ends and the count's index.
pub(super) struct Bracket {
    pub(super) yaw: f64,
    pub(super) direction: f64,
    pub(super) ends: [End; 2],
    pub(super) count: usize,
}

/// A state of a speed line: its speed factor and its run-out's rest `[x, y, heading]`.
pub(super) type End = (f64, [f64; 3]);

/// A state where the rest heading is a count's: the count's index, the distance of the rest
/// across its rolling line (m) and the state.
pub(super) type Crossing = (usize, f64, Vec<f64>);

/// A state brought to the rest: its rest heading's miss of its count's (rad) and the state;
/// `None` where the rest was not reached.
pub(super) type AtRest = Option<(f64, Vec<f64>)>;

/// The brackets of one speed line: consecutive speeds and their rests (`None` where the
/// run-out failed) between which the rest heading passes one of `headings` and changes by
/// [`SMOOTH`] or more.
pub(super) fn brackets_of(
    (yaw, direction): (f64, f64),
    line: &[(f64, Option<[f64; 3]>)],
    headings: &[Option<f64>],
    out: &mut Vec<Bracket>,
) {
    for pair in line.windows(2) {
        let [(s0, Some(e0)), (s1, Some(e1))] = [pair[0], pair[1]] else {
            continue;
        };
        let (h0, h1) = (e0[2], e1[2]);
        for (count, h) in headings.iter().enumerate() {
            let Some(h) = h else { continue };
            // Where the heading changes little across the interval, the rest does too and
            // the grid's cells find it by its position.
            if (h0 - h) * (h1 - h) < 0.0 && (h1 - h0).abs() >= SMOOTH {
                out.push(Bracket {
                    yaw,
                    direction,
                    ends: [(s0, e0), (s1, e1)],
                    count,
                });
            }
        }
    }
}

/// The state of each bracket where its rest heading is its count's (none where the heading
/// jumps across the bracket however far it is halved: the slide ends one way or the other),
/// with the count's index and the distance of the rest position `target` across the rolling
/// line of its run-out, m; `state` the grid's state of a yaw rate, direction and
/// speed factor; `q` its problem at the grid's tolerance. The run-outs spent.
pub(super) fn crossing_states(
    q: &Problem,
    brackets: &[Bracket],
    headings: &[Option<f64>],
    target: [f64; 2],
    state: &(dyn Fn(f64, f64, f64) -> Vec<f64> + Sync),
) -> (Vec<Crossing>, usize) {
    let done: Vec<(Option<Crossing>, usize)> = brackets
        .par_iter()
        .map(|b| {
            let Some(h) = headings[b.count] else {
                return (None, 0);
            };
            let mut spent = 0;
            let [(mut s0, mut e0), (mut s1, mut e1)] = b.ends;
            for _ in 0..DEPTH {
                if (e1[2] - e0[2]).abs() < SMOOTH {
                    break;
                }
                let s = (s0 * s1).sqrt();
                spent += 1;
                let Ok(r) = q.runout(&state(b.yaw, b.direction, s)) else {
                    return (None, spent);
                };
                let em = [r.rest.x, r.rest.y, r.rest.heading];
                if (e0[2] - h) * (em[2] - h) < 0.0 {
                    (s1, e1) = (s, em);
                } else {
                    (s0, e0) = (s, em);
                }
            }
            let (h0, h1) = (e0[2], e1[2]);
            if (h1 - h0).abs() >= SMOOTH {
                return (None, spent);
            }
            let f = (h - h0) / (h1 - h0);
            let s = (s0.ln() + f * (s1.ln() - s0.ln())).exp();
            let t = state(b.yaw, b.direction, s);
            spent += 1;
            let Ok(r) = q.runout(&t) else {
                return (None, spent);
            };
            let rest = [r.rest.x, r.rest.y, r.rest.heading];
            (Some((b.count, across(rest, target), t)), spent)
        })
        .collect();
    let spent = done.iter().map(|d| d.1).sum();
    (done.into_iter().filter_map(|d| d.0).collect(), spent)
}

/// The distance of `target` from the line through a rest `[x, y, heading]` along its heading,
/// m.
fn across(rest: [f64; 3], target: [f64; 2]) -> f64 {
    let (s, c) = rest[2].sin_cos();
    (c * (target[1] - rest[1]) - s * (target[0] - rest[0])).abs()
}

/// Crossing states (count, distance across, state) whose rolling line passes within
/// [`ACROSS`] of the distance `dist` from the start to the rest (and 1 m) of the rest, the
/// nearest first, at most [`TRIED`]: those worth bringing to the rest.
pub(super) fn near_the_line(mut states: Vec<Crossing>, dist: f64) -> Vec<(usize, Vec<f64>)> {
    states.retain(|s| s.1 <= (ACROSS * dist).max(1.0));
    states.sort_by(|a, b| a.1.total_cmp(&b.1));
    states.into_iter().take(TRIED).map(|s| (s.0, s.2)).collect()
}

/// Of the states brought to the rest (count, and the heading miss and state where the rest was
/// reached), the [`PER_COUNT`] of each count whose rest heading lies nearest its count's.
pub(super) fn best_per_count(
    states: impl Iterator<Item = (usize, AtRest)>,
    counts: usize,
) -> Vec<(usize, Vec<f64>)> {
    let mut reached: Vec<Crossing> = states
        .filter_map(|(k, r)| r.map(|(miss, t)| (k, miss, t)))
        .collect();
    reached.sort_by(|a, b| a.1.total_cmp(&b.1));
    let mut kept = vec![0; counts];
    let mut out = Vec::new();
    for (k, _, t) in reached {
        if kept[k] < PER_COUNT {
            kept[k] += 1;
            out.push((k, t));
        }
    }
    out
}
