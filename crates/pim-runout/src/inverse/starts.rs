//! Starts of a candidate's search built from its first guess: turned off the line to the
//! rest, aimed at the nearest mark, and a scatter of single run-outs around it.

use super::evidence::Mark;
use super::problem::Problem;

/// `guess` with its CG velocity turned by `angle` (rad): a rotating vehicle's path curves off
/// the line from the start to the rest.
pub(super) fn turned(guess: &[f64], angle: f64) -> Vec<f64> {
    let (s, c) = angle.sin_cos();
    let mut t = guess.to_vec();
    t[0] = c * guess[0] - s * guess[1];
    t[1] = s * guess[0] + c * guess[1];
    t
}

/// `guess` with its CG speed aimed at the mark nearest the start, where there is a mark.
pub(super) fn toward_nearest_mark(p: &Problem, guess: &[f64]) -> Option<Vec<f64>> {
    p.evidence
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
            let mut t = guess.to_vec();
            t[0] = speed * dx / d;
            t[1] = speed * dy / d;
            t
        })
}

/// Single run-outs on `coarse` around `guess` (its direction turned by -0.5, 0 and 0.5 rad, its
/// speed times 0.8 and 1.25, its yaw rate times 0.5, 1 and 2), lowest cost first, the run-outs
/// counted in `runouts`.
pub(super) fn around(coarse: &Problem, guess: &[f64], runouts: &mut usize) -> Vec<Vec<f64>> {
    let mut scattered: Vec<(f64, Vec<f64>)> = Vec::new();
    for turn in [-0.5, 0.0, 0.5] {
        for speed in [0.8, 1.25] {
            for yaw in [0.5, 1.0, 2.0] {
                let mut t = turned(guess, turn);
                t[0] *= speed;
                t[1] *= speed;
                t[2] *= yaw;
                *runouts += 1;
                if let Ok((r, _)) = coarse.weighted(&t) {
                    scattered.push((r.norm_squared(), t));
                }
            }
        }
    }
    scattered.sort_by(|a, b| a.0.total_cmp(&b.0));
    scattered.into_iter().map(|(_, t)| t).collect()
}
