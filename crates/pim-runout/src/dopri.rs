//! Dormand-Prince 5(4): the adaptive integrator of the run-outs, and the replay of an accepted
//! step sequence through the same stages.
//!
//! The method, its step-size control and its first step are those of Hairer and Wanner's
//! DOPRI5 as the `ode_solvers` crate (0.6) implements them, operation for operation (the run-outs
//! of the two agree to the last bit): the 5th-order solution is propagated (local
//! extrapolation, first-same-as-last), the error is the root mean square of the embedded 4th-
//! order estimate scaled by `atol + rtol max(|y|, |y_new|)`, and a PI controller (exponents
//! 0.17 and 0.04, safety 0.9, factors 0.2 to 10) chooses the next step.
//!
//! Its own implementation is needed for [`replay`]: the derivatives of a run-out with respect to
//! its start are taken by *internal numerical differentiation* (Bock): the perturbed run-outs
//! are integrated through the nominal run-out's accepted steps, not with steps of their own, so
//! that the difference quotient differentiates one smooth discrete map (a perturbed run-out with
//! its own step control differs from the nominal by the two step sequences' errors, which the
//! difference step divides). A replayed step costs six evaluations and no error control.

use crate::forces::State;

/// The Butcher tableau of Dormand-Prince 5(4): row `i` of `A` gives stage `i + 2` (the last row
/// is the 5th-order solution's weights).
const A: [[f64; 6]; 6] = [
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const C: [f64; 7] = [0.0, 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0, 1.0, 1.0];
/// The error estimate's weights (5th minus 4th order).
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// How the step size is controlled.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Control {
    pub(crate) rtol: f64,
    pub(crate) atol: f64,
    /// The largest step, s.
    pub(crate) h_max: f64,
    /// The most steps (accepted or not) before the integration gives up.
    pub(crate) max_steps: u32,
}

/// Why an integration gave up, and where.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Failure {
    MaxSteps { t: f64, steps: u32 },
    Underflow { t: f64 },
}

/// One step of size `h` from `(t, y)` whose rate there is `k0`: the 5th-order solution and the
/// seven stages (the last one is the rate at the solution).
fn stages(
    f: &impl Fn(f64, &State) -> State,
    t: f64,
    y: &State,
    k0: &State,
    h: f64,
) -> (State, [State; 7]) {
    let mut k = [State::zeros(); 7];
    k[0] = *k0;
    let mut next = *y;
    for s in 1..7 {
        next = *y;
        for (j, kj) in k.iter().enumerate().take(s) {
            let a = A[s - 1][j];
            for i in 0..8 {
                next[i] += kj[i] * h * a;
            }
        }
        k[s] = f(t + h * C[s], &next);
    }
    (next, k)
}

/// The error of a step, scaled by the tolerances (accept at most 1).
fn error(y: &State, next: &State, k: &[State; 7], h: f64, c: &Control) -> f64 {
    let mut err = 0.0;
    for i in 0..8 {
        let e = (k[0][i] * E[0]
            + k[2][i] * E[2]
            + k[3][i] * E[3]
            + k[4][i] * E[4]
            + k[5][i] * E[5]
            + k[6][i] * E[6])
            * h;
        let sc = c.atol + y[i].abs().max(next[i].abs()) * c.rtol;
        err += (e / sc) * (e / sc);
    }
    (err / 8.0).sqrt()
}

/// The first step's size from the rate at the start and one explicit Euler step (two
/// evaluations).
fn first_step(f: &impl Fn(f64, &State) -> State, t: f64, y: &State, end: f64, c: &Control) -> f64 {
    let f0 = f(t, y);
    let (mut d0, mut d1) = (0.0, 0.0);
    for i in 0..8 {
        let sc = c.atol + y[i].abs() * c.rtol;
        d0 += (y[i] / sc) * (y[i] / sc);
        d1 += (f0[i] / sc) * (f0[i] / sc);
    }
    let posneg = (end - t).signum();
    let mut h0 = if d0 < 1e-10 || d1 < 1e-10 {
        1e-6
    } else {
        0.01 * (d0 / d1).sqrt()
    };
    h0 = h0.min(c.h_max).abs() * posneg;
    let mut y1 = *y;
    for i in 0..8 {
        y1[i] += f0[i] * h0;
    }
    let f1 = f(t + h0, &y1);
    let mut d2 = 0.0;
    for i in 0..8 {
        let sc = c.atol + y[i].abs() * c.rtol;
        d2 += ((f1[i] - f0[i]) / sc) * ((f1[i] - f0[i]) / sc);
    }
    d2 = d2.sqrt() / h0;
    let h1 = if d1.sqrt().max(d2.abs()) <= 1e-15 {
        1e-6_f64.max(h0.abs() * 1e-3)
    } else {
        (0.01 / d1.sqrt().max(d2)).powf(0.2)
    };
    (100.0 * h0.abs()).min(h1.min(c.h_max)).abs() * posneg
}

/// The PI step-size controller.
struct Controller {
    fac_old: f64,
    reject: bool,
    h_max: f64,
}

/// The controller's constants: `alpha = 0.2 - 0.75 beta`, beta, the safety factor, and the
/// inverses of the least and largest step factors.
const BETA: f64 = 0.04;
const ALPHA: f64 = 0.2 - BETA * 0.75;
const SAFETY: f64 = 0.9;
const FACC1: f64 = 1.0 / 0.2;
const FACC2: f64 = 1.0 / 10.0;

impl Controller {
    /// Whether the step of error `err` is accepted, and the next step's size.
    fn accept(&mut self, err: f64, h: f64) -> (bool, f64) {
        let fac11 = err.powf(ALPHA);
        let fac = fac11 * self.fac_old.powf(-BETA);
        let fac = FACC2.max(FACC1.min(fac / SAFETY));
        let mut h_new = h / fac;
        if err <= 1.0 {
            self.fac_old = err.max(1e-4);
            if h_new.abs() > self.h_max {
                h_new = self.h_max;
            }
            if self.reject {
                h_new = h_new.abs().min(h.abs());
            }
            self.reject = false;
            (true, h_new)
        } else {
            self.reject = true;
            (false, h / FACC1.min(fac11 / SAFETY))
        }
    }
}

/// Integrates `y' = f(t, y)` from `(t0, y0)` towards `end` (forwards), calling `solout` at every
/// accepted step with its time, state and rate (the start is not reported); `solout` returning
/// `true` ends the integration there. Returns the evaluations of `f`.
pub(crate) fn integrate(
    f: impl Fn(f64, &State) -> State,
    (t0, end): (f64, f64),
    y0: State,
    c: &Control,
    mut solout: impl FnMut(f64, &State, &State) -> bool,
) -> Result<u32, Failure> {
    let mut evaluations = 2;
    let mut h = first_step(&f, t0, &y0, end, c);
    let mut k0 = f(t0, &y0);
    evaluations += 1;
    let (mut t, mut y) = (t0, y0);
    let mut control = Controller {
        fac_old: 1e-4,
        reject: false,
        h_max: c.h_max.abs(),
    };
    let mut steps = 0;
    let mut last = false;
    while !last {
        if steps > c.max_steps {
            return Err(Failure::MaxSteps { t, steps });
        }
        if 0.1 * h.abs() <= f64::EPSILON * t.abs() {
            return Err(Failure::Underflow { t });
        }
        if t + 1.01 * h - end > 0.0 {
            h = end - t;
            last = true;
        }
        steps += 1;
        let (next, k) = stages(&f, t, &y, &k0, h);
        evaluations += 6;
        let err = error(&y, &next, &k, h, c);
        let (ok, h_new) = control.accept(err, h);
        if ok {
            k0 = k[6];
            y = next;
            t += h;
            if solout(t, &y, &k0) {
                last = true;
            }
            if last {
                return Ok(evaluations);
            }
        } else {
            last = false;
        }
        h = h_new;
    }
    Ok(evaluations)
}

/// The steps of an integration replayed from `y0` through the accepted times `times` (the first
/// is the start), with `restart(t)` telling where the rate must be evaluated afresh (a piece of
/// the integration started there, after a kink of the inputs); `each` sees every step's time,
/// state and rate, the start's included. Returns the evaluations of `f`.
pub(crate) fn replay(
    f: impl Fn(f64, &State) -> State,
    times: &[f64],
    y0: State,
    restart: impl Fn(f64) -> bool,
    mut each: impl FnMut(f64, &State, &State),
) -> u32 {
    let Some(&t0) = times.first() else {
        return 0;
    };
    let mut k0 = f(t0, &y0);
    let mut evaluations = 1;
    let mut y = y0;
    each(t0, &y, &k0);
    for w in times.windows(2) {
        let (t, next_t) = (w[0], w[1]);
        if restart(t) && t > t0 {
            k0 = f(t, &y);
            evaluations += 1;
        }
        let (next, k) = stages(&f, t, &y, &k0, next_t - t);
        evaluations += 6;
        y = next;
        k0 = k[6];
        each(next_t, &y, &k0);
    }
    evaluations
}
