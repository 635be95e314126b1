//! The linearly implicit integrator of a run-out's stiff last stretch: the Rosenbrock-W method
//! ROS34PW2 of Rang and Angermann (BIT 45, 2005), and its replay through given steps.
//!
//! **Why.** A rolling tyre's lateral force per unit of slip velocity grows as the car slows
//! (`mu Fz / (v alpha_sat)` in its linear range), so the lateral and yaw motions of a slow
//! rolling car decay with a time constant `tau = v alpha_sat / (mu g)` that goes to zero with
//! the speed. An explicit method is stable only for steps below about `3.3 tau`
//! (Dormand-Prince), however smooth the motion: from 1 m/s to rest that is a few hundred steps
//! whatever the tolerance. The stiff modes are decaying ones, so an L-stable method follows the
//! slow motion with steps set by its accuracy alone.
//!
//! **The method.** For `y' = f(y)` with the Jacobian `J = df/dy` (forward differences here), a
//! step of size `h` solves four linear systems with one matrix:
//! ```text
//! (I - h gamma J) k_i = h f(y + sum_{j<i} alpha_ij k_j) + h J sum_{j<i} gamma_ij k_j
//! y_new = y + sum_i b_i k_i,         error = sum_i (b_i - b^_i) k_i
//! ```
//! ROS34PW2 has order 3, an embedded solution of order 2, is stiffly accurate and L-stable, and
//! keeps its order with an approximate Jacobian of a W-method's kind. Of the state, only the
//! heading and the three velocities act on the rates (the position only through friction
//! zones, piecewise constant; the work and the distance not at all), so `J` has four columns
//! and the systems reduce to 4 x 4. A step costs eight evaluations: four for the columns, three
//! stages (the first is the rate at `y`, known) and the rate at `y_new` (the next step's
//! first stage and the dense output's slope).
//!
//! A run-out is replayed through the nominal's steps (internal numerical differentiation, as
//! for Dormand-Prince's: `dopri.rs`) with each step's Jacobian taken afresh at the replayed state. The
//! stiff components of a step follow its Jacobian, so a replay with the nominal's Jacobians
//! would differentiate another map: on a rolling car's rest at 1e-6 it is 10-23 % off the
//! true derivative where these replays, like Dormand-Prince's, are within 1-5 % (the
//! discretisation's own error). A Jacobian by differences moves by a little where a difference
//! straddles a kink of the tyre forces, so a replay from the nominal's own start reproduces it
//! to about 1e-10 (relative) rather than to rounding.

use crate::forces::State;
use nalgebra::{Matrix4, Vector4};

/// The diagonal of the method.
const GAMMA: f64 = 0.435_866_521_508_459;
/// `alpha_ij` (row `i`, columns `j < i`).
const ALPHA: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [0.871_733_043_016_918, 0.0, 0.0],
    [0.844_570_600_153_694_2, -0.112_990_642_364_841_85, 0.0],
    [0.0, 0.0, 1.0],
];
/// `gamma_ij` below the diagonal.
const GAMMAS: [[f64; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [-0.871_733_043_016_918, 0.0, 0.0],
    [-0.903_380_570_130_440_8, 0.054_180_672_388_095_326, 0.0],
    [
        0.242_123_807_060_953_46,
        -1.223_250_583_904_514_7,
        0.545_260_255_335_102_1,
    ],
];
/// The weights of the solution (order 3) and of the embedded one (order 2).
const B: [f64; 4] = [
    0.242_123_807_060_953_46,
    -1.223_250_583_904_514_7,
    1.545_260_255_335_102,
    GAMMA,
];
const B_HAT: [f64; 4] = [
    0.378_109_031_458_193_7,
    -0.096_042_292_212_423_18,
    0.5,
    0.217_933_260_754_229_5,
];
/// The components the rates depend on smoothly: heading, vx, vy, yaw rate.
const COUPLED: [usize; 4] = [2, 3, 4, 5];
/// The forward difference of the Jacobian's columns (rad, m/s, rad/s).
const DELTA: f64 = 1e-7;

/// The Jacobian's columns of the coupled components (heading, vx, vy, yaw rate).
pub(crate) type Columns = [State; 4];

/// The Jacobian's columns at `(t, y)`, whose rate is `f0`, by forward differences: four
/// evaluations.
pub(crate) fn columns(f: &impl Fn(f64, &State) -> State, t: f64, y: &State, f0: &State) -> Columns {
    std::array::from_fn(|c| {
        let mut yd = *y;
        yd[COUPLED[c]] += DELTA;
        (f(t, &yd) - f0) / DELTA
    })
}

/// One step of size `h` from `(t, y)` whose rate there is `f0`, with the Jacobian's columns
/// `cols`: the solution, the rate at it, and the error estimate (four evaluations).
pub(crate) fn step(
    f: &impl Fn(f64, &State) -> State,
    (t, y, f0): (f64, &State, &State),
    h: f64,
    cols: &Columns,
) -> (State, State, State) {
    let hg = h * GAMMA;
    let m = Matrix4::from_fn(|r, c| f64::from(u8::from(r == c)) - hg * cols[c][COUPLED[r]]);
    let lu = m.lu();
    // J v: only the coupled components of v act.
    let jv = |v: &State| -> State {
        let mut out = State::zeros();
        for (c, col) in cols.iter().enumerate() {
            out += col * v[COUPLED[c]];
        }
        out
    };
    let mut k = [State::zeros(); 4];
    for i in 0..4 {
        let (mut point, mut mix) = (*y, State::zeros());
        for j in 0..i {
            point += k[j] * ALPHA[i][j];
            mix += k[j] * GAMMAS[i][j];
        }
        let rate = if i == 0 { *f0 } else { f(t, &point) };
        let rhs = (rate + jv(&mix)) * h;
        // (I - h gamma J) k = rhs: the coupled block first, then the other rows.
        let coupled = Vector4::from_fn(|r, _| rhs[COUPLED[r]]);
        let kc = lu.solve(&coupled).unwrap_or(coupled);
        let mut ki = rhs;
        for (c, col) in cols.iter().enumerate() {
            for row in [0, 1, 6, 7] {
                ki[row] += hg * col[row] * kc[c];
            }
        }
        for (r, &comp) in COUPLED.iter().enumerate() {
            ki[comp] = kc[r];
        }
        k[i] = ki;
    }
    let (mut next, mut error) = (*y, State::zeros());
    for i in 0..4 {
        next += k[i] * B[i];
        error += k[i] * (B[i] - B_HAT[i]);
    }
    (next, f(t + h, &next), error)
}

/// Evaluations of one step, the Jacobian's columns aside.
pub(crate) const STEP_EVALUATIONS: u32 = 4;

#[cfg(test)]
mod tests {
    use super::*;

    /// The order conditions of a Rosenbrock method up to order 3 (Hairer and Wanner, Table
    /// IV.7.1), for the solution (and up to order 2 for the embedded one).
    #[test]
    fn the_coefficients_meet_the_order_conditions() {
        let alpha: [f64; 4] = std::array::from_fn(|i| ALPHA[i].iter().sum());
        // beta_ij = alpha_ij + gamma_ij; beta'_i = sum_j<i beta_ij.
        let beta: [f64; 4] =
            std::array::from_fn(|i| (0..i).map(|j| ALPHA[i][j] + GAMMAS[i][j]).sum());
        let g = GAMMA;
        for (w, order) in [(B, 3), (B_HAT, 2)] {
            let sum = |x: [f64; 4]| (0..4).map(|i| w[i] * x[i]).sum::<f64>();
            assert!((sum([1.0; 4]) - 1.0).abs() < 1e-14);
            assert!((sum(beta) - (0.5 - g)).abs() < 1e-14, "{}", sum(beta));
            if order == 3 {
                assert!((sum(alpha.map(|a| a * a)) - 1.0 / 3.0).abs() < 1e-14);
                let bb: [f64; 4] = std::array::from_fn(|i| {
                    (0..i).map(|j| (ALPHA[i][j] + GAMMAS[i][j]) * beta[j]).sum()
                });
                assert!((sum(bb) - (1.0 / 6.0 - g + g * g)).abs() < 1e-14);
            }
        }
        // Stiffly accurate: the last stage's row is the solution's weights.
        for j in 0..3 {
            assert!((ALPHA[3][j] + GAMMAS[3][j] - B[j]).abs() < 1e-14);
        }
        assert!((B[3] - GAMMA).abs() < 1e-16);
    }

    /// `y' = f(y)` from `y0` to t = 1 in steps of `h`: the state at the end.
    fn steps_to_one(f: &impl Fn(f64, &State) -> State, y0: State, h: f64) -> State {
        let (mut y, mut f0) = (y0, f(0.0, &y0));
        for i in 0..(1.0 / h).round() as usize {
            let t = i as f64 * h;
            let cols = columns(f, t, &y, &f0);
            let (next, rate, _) = step(f, (t, &y, &f0), h, &cols);
            (y, f0) = (next, rate);
        }
        y
    }

    /// A stiff linear system `x' = v, v' = -k (v - 1)` with `k = 1e4`, which an explicit method
    /// could only step below 3e-4 s: steps of 0.1 s stay stable and exact. On a smooth
    /// non-stiff one the error falls as the cube of the step (`(x, v)` in the heading and vx
    /// slots).
    #[test]
    fn third_order_on_a_stiff_problem_with_long_steps() {
        let k = 1e4;
        let stiff = |_t: f64, y: &State| {
            let mut d = State::zeros();
            d[2] = y[3];
            d[3] = -k * (y[3] - 1.0);
            d
        };
        let mut y0 = State::zeros();
        y0[3] = 2.0;
        // v relaxes to 1: x(t) = t + (1 - e^{-kt}) (v0 - 1) / k. The transient (worth 1e-4 of
        // x) is followed through its decay to 1e-10 in steps of a thousand time constants.
        for h in [0.1, 0.05] {
            let y = steps_to_one(&stiff, y0, h);
            let (ex, ev) = ((y[2] - (1.0 + 1.0 / k)).abs(), (y[3] - 1.0).abs());
            assert!(ex < 1e-10 && ev < 1e-12, "h {h}: x off by {ex}, v by {ev}");
        }
        // The harmonic oscillator x'' = -x from x = 0, v = 1: x(1) = sin 1.
        let smooth = |_t: f64, y: &State| {
            let mut d = State::zeros();
            d[2] = y[3];
            d[3] = -y[2];
            d
        };
        let mut y0 = State::zeros();
        y0[3] = 1.0;
        let err = |h: f64| (steps_to_one(&smooth, y0, h)[2] - 1f64.sin()).abs();
        let ratio = err(0.02) / err(0.01);
        assert!((6.5..10.0).contains(&ratio), "{ratio}");
    }
}
