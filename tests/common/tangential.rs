//! An independent reference for the tangential model's fit under Q2 (contact state known),
//! written with pim-core's forward solver only: a dense grid over (e, et, friction), then a
//! compass search from its best point.

use pim_core::{solve_tangential, Impact, TangentialCoefficients, Velocities};

/// The Q2 cost (unit weights) of the forward solve from `x` against `xf`, when the answer is
/// admissible and within the fit's default velocity bounds (20 m/s, 5 rad/s).
pub fn q2_cost(
    impact: &Impact,
    c: &TangentialCoefficients,
    x: &Velocities,
    xf: &Velocities,
) -> f64 {
    let Ok(t) = solve_tangential(impact, c, x) else {
        return f64::INFINITY;
    };
    let sep = t.report.separation.to_vector();
    let within = sep
        .iter()
        .enumerate()
        .all(|(k, v)| v.abs() <= if k % 3 == 2 { 5.0 } else { 20.0 });
    if !t.report.admissibility.admissible || !within {
        return f64::INFINITY;
    }
    (sep - xf.to_vector()).norm_squared()
}

/// The smallest Q2 cost found over the box `[e, et, friction]` (each `[lo, hi]`): 21 x 41 x 25
/// grid points, then a compass search down to steps of 1e-9 of the e range.
pub fn q2_reference(impact: &Impact, x: &Velocities, xf: &Velocities, bx: [[f64; 2]; 3]) -> f64 {
    let cost = |p: [f64; 3]| {
        let c = TangentialCoefficients {
            e: p[0].clamp(bx[0][0], bx[0][1]),
            et: p[1].clamp(bx[1][0], bx[1][1]),
            friction: p[2].clamp(bx[2][0], bx[2][1]),
        };
        q2_cost(impact, &c, x, xf)
    };
    let n = [20usize, 40, 24];
    let at = |d: usize, i: usize| bx[d][0] + (bx[d][1] - bx[d][0]) * i as f64 / n[d] as f64;
    let mut best = ([0.0; 3], f64::INFINITY);
    for i in 0..=n[0] {
        for j in 0..=n[1] {
            for k in 0..=n[2] {
                let p = [at(0, i), at(1, j), at(2, k)];
                let v = cost(p);
                if v < best.1 {
                    best = (p, v);
                }
            }
        }
    }
    let mut step = [0, 1, 2].map(|d| 0.5 * (bx[d][1] - bx[d][0]) / n[d] as f64);
    let stop = 1e-9 * (bx[0][1] - bx[0][0]).max(1e-3);
    while step[0].max(step[1]).max(step[2]) > stop && best.1.is_finite() {
        let mut moved = false;
        for d in 0..3 {
            for s in [-1.0, 1.0] {
                let mut p = best.0;
                p[d] += s * step[d];
                let v = cost(p);
                if v < best.1 {
                    best = (p, v);
                    moved = true;
                }
            }
        }
        if !moved {
            step.iter_mut().for_each(|s| *s *= 0.5);
        }
    }
    best.1
}
