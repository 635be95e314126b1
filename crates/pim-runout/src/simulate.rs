//! The run-out from separation to rest.

use crate::chassis::{Chassis, Motion};
use crate::dopri::{integrate, Control, Failure};
use crate::error::{Result, RunoutError};
use crate::forces::{derivative, Dynamics, State};
use serde::{Deserialize, Serialize};

/// How a run-out is integrated.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Settings {
    /// Relative tolerance of the Dormand-Prince 5(4) step control.
    pub rtol: f64,
    /// Absolute tolerance of the step control (m, rad, m/s, rad/s, J).
    pub atol: f64,
    /// The motion is given up after this time, s: [`End::TimeLimit`].
    pub time_limit: f64,
    /// Below this speed at every contact patch, m/s, the vehicle is at its last few millimetres:
    /// the rest of the motion is taken at its current deceleration, in closed form (exact for a
    /// sliding translation, which decelerates uniformly to rest).
    pub rest_speed: f64,
}

impl Default for Settings {
    /// Tolerances 1e-10, 60 s, 2 cm/s.
    fn default() -> Self {
        Settings {
            rtol: 1e-10,
            atol: 1e-10,
            time_limit: 60.0,
            rest_speed: 0.02,
        }
    }
}

impl Settings {
    /// These settings with both tolerances at least `tolerance` (a quicker, coarser run-out;
    /// tolerances already coarser are kept).
    pub fn no_finer_than(&self, tolerance: f64) -> Settings {
        Settings {
            rtol: tolerance.max(self.rtol),
            atol: tolerance.max(self.atol),
            ..*self
        }
    }

    /// Checks the settings; the error names the field.
    pub fn check(&self) -> Result<()> {
        for (field, x) in [
            ("rtol", self.rtol),
            ("atol", self.atol),
            ("time_limit", self.time_limit),
            ("rest_speed", self.rest_speed),
        ] {
            if !(x.is_finite() && x > 0.0) {
                return Err(RunoutError::Input {
                    field,
                    reason: format!("{x}: must be a number above 0"),
                });
            }
        }
        Ok(())
    }
}

/// How a run-out ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum End {
    /// The vehicle came to rest.
    Rest,
    /// The time limit ended the motion before the vehicle came to rest (its last state is the
    /// `rest` of the run-out, still moving).
    TimeLimit,
}

/// One accepted step of the integration: the state and its rates, from which the path is
/// interpolated (cubic Hermite) between steps.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Step {
    /// Time since separation, s.
    pub time: f64,
    /// Position, heading and velocities.
    pub motion: Motion,
    /// CG acceleration (m/s^2, fixed frame) and yaw acceleration (rad/s^2).
    pub acceleration: [f64; 3],
    /// Distance travelled by the CG since separation, m.
    pub distance: f64,
    /// Work done by the tyre forces since separation, J (energy taken out).
    pub work: f64,
}

/// A run-out from separation to rest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Runout {
    /// The motion at separation.
    pub start: Motion,
    /// Where the vehicle stopped (velocities 0), or its state at the time limit.
    pub rest: Motion,
    /// How the motion ended.
    pub end: End,
    /// Time from separation to rest, s.
    pub time: f64,
    /// Distance along the CG's path, m.
    pub distance: f64,
    /// Rotation from separation to rest, rad (counter-clockwise positive; whole turns kept).
    pub rotation: f64,
    /// Kinetic energy at separation, J.
    pub initial_energy: f64,
    /// Work done by the tyre forces, J (energy taken out; equals the kinetic energy lost).
    pub tyre_work: f64,
    /// The accepted steps, the start and the rest included.
    pub steps: Vec<Step>,
    /// Right-hand side evaluations of the integration.
    pub evaluations: u32,
    /// How many of [`Runout::steps`] the integrator took (the start included; the closed-form
    /// last millimetres follow them), when the run-out can be replayed through them from another
    /// start ([`replay`]): not with inputs by distance, whose starts depend on the path.
    #[serde(skip)]
    #[schemars(skip)]
    pub(crate) integrated: Option<usize>,
}

/// Full turns of a rotation `r` (rad) beyond the shortest rotation between its ends, which lies
/// in (-pi, pi]: `r = shortest + 2 pi turns`.
pub fn full_turns(r: f64) -> i64 {
    use std::f64::consts::{PI, TAU};
    let mut short = r.rem_euclid(TAU);
    if short > PI {
        short -= TAU;
    }
    ((r - short) / TAU).round() as i64
}

impl Runout {
    /// Full turns from separation to rest beyond the shortest rotation between the two
    /// headings, the count of turns of the inverse's candidates and of a reconstruction (a
    /// rotation of -400 deg is the shortest -40 deg and -1 turn; -659.9 deg is 60.1 deg and -2
    /// turns). Counter-clockwise positive, as the rotation.
    pub fn turns(&self) -> i64 {
        full_turns(self.rotation)
    }

    /// The motion at time `t` since separation (cubic Hermite between accepted steps; the
    /// start before 0, the end after the end).
    pub fn at(&self, t: f64) -> Motion {
        let steps = &self.steps;
        let Some(first) = steps.first() else {
            return self.start;
        };
        if t <= first.time {
            return first.motion;
        }
        let last = steps[steps.len() - 1];
        if t >= last.time {
            return last.motion;
        }
        let k = steps
            .partition_point(|s| s.time <= t)
            .clamp(1, steps.len() - 1);
        hermite(&steps[k - 1], &steps[k], t)
    }

    /// The motion every `dt` seconds from separation, the rest included as the last sample.
    pub fn sample(&self, dt: f64) -> Vec<(f64, Motion)> {
        let mut out = Vec::new();
        if !(dt.is_finite() && dt > 0.0) {
            return out;
        }
        let n = (self.time / dt).floor() as usize;
        for i in 0..=n.min(1_000_000) {
            let t = i as f64 * dt;
            if t < self.time {
                out.push((t, self.at(t)));
            }
        }
        out.push((self.time, self.rest));
        out
    }
}

/// Cubic Hermite interpolation of the motion between two steps.
pub(crate) fn hermite(a: &Step, b: &Step, t: f64) -> Motion {
    let h = b.time - a.time;
    let s = ((t - a.time) / h).clamp(0.0, 1.0);
    let (s2, s3) = (s * s, s * s * s);
    let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
    let h10 = s3 - 2.0 * s2 + s;
    let h01 = -2.0 * s3 + 3.0 * s2;
    let h11 = s3 - s2;
    let f = |p0: f64, m0: f64, p1: f64, m1: f64| h00 * p0 + h10 * h * m0 + h01 * p1 + h11 * h * m1;
    let (ma, mb) = (&a.motion, &b.motion);
    Motion {
        x: f(ma.x, ma.vx, mb.x, mb.vx),
        y: f(ma.y, ma.vy, mb.y, mb.vy),
        heading: f(ma.heading, ma.yaw_rate, mb.heading, mb.yaw_rate),
        vx: f(ma.vx, a.acceleration[0], mb.vx, b.acceleration[0]),
        vy: f(ma.vy, a.acceleration[1], mb.vy, b.acceleration[1]),
        yaw_rate: f(
            ma.yaw_rate,
            a.acceleration[2],
            mb.yaw_rate,
            b.acceleration[2],
        ),
    }
}

fn step_of(t: f64, y: &State, dy: &State) -> Step {
    Step {
        time: t,
        motion: motion_of(y),
        acceleration: [dy[3], dy[4], dy[5]],
        distance: y[7],
        work: y[6],
    }
}

fn motion_of(y: &State) -> Motion {
    Motion {
        x: y[0],
        y: y[1],
        heading: y[2],
        vx: y[3],
        vy: y[4],
        yaw_rate: y[5],
    }
}

/// Kinks of the inputs closer than this to the current time (s) are where the run is already:
/// a piece ends at its end time to within rounding.
const KINK_GAP: f64 = 1e-9;

/// Integrates one piece of a run-out from `t0` to `end` (or to rest, or to the path's distance
/// `target`), appending every accepted step to the log; returns the evaluations it took.
fn piece(
    dynamics: &Dynamics,
    settings: &Settings,
    (t0, end, y): (f64, f64, State),
    target: Option<f64>,
    (log, stopped, fired): (&mut Vec<(f64, State, State)>, &mut bool, &mut bool),
) -> Result<u32> {
    let control = Control {
        rtol: settings.rtol,
        atol: settings.atol,
        h_max: settings.time_limit,
        max_steps: 2_000_000,
    };
    let rest_speed = settings.rest_speed;
    let outcome = integrate(
        |t, y| derivative(&dynamics.at_time(t), y),
        (t0, end),
        y,
        &control,
        |t, y, dy| {
            // A piece after the first starts where the one before ended, already logged.
            if log.last().is_some_and(|l| l.0 >= t) {
                return *stopped;
            }
            log.push((t, *y, *dy));
            if dynamics.fastest_patch(y) < rest_speed {
                *stopped = true;
            } else if target.is_some_and(|d| y[7] >= d) {
                *fired = true;
            }
            *stopped || *fired
        },
    );
    match outcome {
        Ok(evaluations) => Ok(evaluations),
        Err(failure) => {
            let (time, reason) = match failure {
                Failure::MaxSteps { t, steps } => (t, format!("more than {steps} steps")),
                Failure::Underflow { t } => (t, "step size underflow".into()),
            };
            // Six evaluations per accepted step at least.
            let evaluations = 6 * log.len() as u64;
            Err(RunoutError::Integration {
                time,
                reason,
                evaluations,
            })
        }
    }
}

/// The time within a step from `(ta, sa, va)` to `(tb, sb, vb)` (time, distance along the
/// path, speed) at which the distance reaches `d`, on the cubic Hermite curve through both
/// ends (increasing: the speed is never negative), by bisection to the last bit.
fn crossing((ta, sa, va): (f64, f64, f64), (tb, sb, vb): (f64, f64, f64), d: f64) -> f64 {
    let h = tb - ta;
    let at = |u: f64| {
        let (u2, u3) = (u * u, u * u * u);
        (2.0 * u3 - 3.0 * u2 + 1.0) * sa
            + (u3 - 2.0 * u2 + u) * h * va
            + (-2.0 * u3 + 3.0 * u2) * sb
            + (u3 - u2) * h * vb
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if at(mid) < d {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    ta + hi * h
}

/// The run-out of `chassis` from `start` to rest.
///
/// # Errors
/// [`RunoutError::Input`] for a vehicle, start or settings the model cannot use;
/// [`RunoutError::Integration`] when the integrator gives up. A motion that the time limit
/// ends is not an error: its [`Runout::end`] is [`End::TimeLimit`].
///
/// ```
/// use pim_runout::{simulate, Chassis, Motion, Settings, WheelState, GRAVITY};
/// let car = Chassis::new(1500.0, 2500.0, 2.7, 1.2, 1.5, WheelState::Locked);
/// let start = Motion { vx: 15.0, ..Motion::default() };
/// let r = simulate(&car, &start, &Settings::default()).unwrap();
/// let expected = 15.0_f64.powi(2) / (2.0 * car.friction * GRAVITY);
/// assert!((r.rest.x - expected).abs() < 1e-6);
/// ```
pub fn simulate(chassis: &Chassis, start: &Motion, settings: &Settings) -> Result<Runout> {
    chassis.check()?;
    start.check()?;
    settings.check()?;
    let dynamics = Dynamics::new(chassis);
    run(&dynamics, start, settings)
}

/// The run-out with prepared dynamics (the inverse calls it many times for one vehicle).
pub(crate) fn run(dynamics: &Dynamics, start: &Motion, settings: &Settings) -> Result<Runout> {
    let y0 = initial_state(start);
    let mut log = vec![(0.0, y0, State::zeros())];
    let mut stopped = dynamics.fastest_patch(&y0) < settings.rest_speed;
    let mut evaluations = 1;
    // Inputs by distance start when the path reaches their distance: their starts are found as
    // the run goes, and the dynamics hold the inputs started so far.
    let triggers = dynamics.distance_triggers();
    let mut starts: Vec<f64> = Vec::new();
    let mut current = match triggers {
        Some(_) => std::borrow::Cow::Owned(dynamics.with_starts(&starts)),
        None => std::borrow::Cow::Borrowed(dynamics),
    };
    // Piece by piece between the driver inputs' kinks (one piece without inputs).
    let limit = settings.time_limit;
    {
        // The start's rates under the inputs that start at once.
        let mut now = starts.clone();
        if let Some(tr) = &triggers {
            while let Some(&(at, distance)) = tr.get(now.len()) {
                if at > 0.0 || distance.is_some_and(|d| d > 0.0) {
                    break;
                }
                now.push(0.0);
            }
        }
        let at_start = match triggers {
            Some(_) => std::borrow::Cow::Owned(dynamics.with_starts(&now)),
            None => std::borrow::Cow::Borrowed(dynamics),
        };
        log[0].2 = derivative(&at_start.at_time(0.0), &y0);
    }
    while let Some(&(t0, y, _)) = log.last() {
        if stopped || t0 >= limit {
            break;
        }
        // The inputs that start now (their time and distance reached), the next one's time
        // when it is still ahead, or the distance it waits for.
        let mut end = limit;
        let mut target = None;
        if let Some(tr) = &triggers {
            while let Some(&(at, distance)) = tr.get(starts.len()) {
                let earliest = at.max(starts.last().copied().unwrap_or(0.0));
                if t0 < earliest - KINK_GAP {
                    end = earliest;
                    break;
                }
                if let Some(d) = distance.filter(|&d| y[7] < d) {
                    target = Some(d);
                    break;
                }
                starts.push(t0.max(earliest));
                current = std::borrow::Cow::Owned(dynamics.with_starts(&starts));
            }
        }
        if let Some(&k) = current.kinks(limit).iter().find(|&&k| k > t0 + KINK_GAP) {
            end = end.min(k);
        }
        let mut fired = false;
        evaluations += piece(
            &current,
            settings,
            (t0, end, y),
            target,
            (&mut log, &mut stopped, &mut fired),
        )?;
        if fired {
            // The distance was reached within the last step: where, on the cubic through the
            // step's ends (distance and speed); the step is then integrated again up to there.
            let d = target.expect("fired only with a target");
            let (tb, yb, db) = log.pop().expect("the step that reached it");
            let (ta, ya, da) = *log.last().expect("the step before it");
            let mut t = crossing((ta, ya[7], da[7]), (tb, yb[7], db[7]), d);
            let kept = log.len();
            // The cubic's time, then one Newton step on the distance integrated to it (the
            // cubic's error is that of one step; after the step it is its square).
            for newton in [false, true] {
                if newton {
                    let Some(&(te, ye, _)) = log.last() else {
                        break;
                    };
                    let speed = ye[3].hypot(ye[4]);
                    let next = (te + (d - ye[7]) / speed.max(f64::MIN_POSITIVE)).clamp(ta, tb);
                    if (next - te).abs() < KINK_GAP || stopped {
                        break;
                    }
                    log.truncate(kept);
                    t = next;
                }
                if t > ta {
                    let mut again = false;
                    evaluations += piece(
                        &current,
                        settings,
                        (ta, t, ya),
                        None,
                        (&mut log, &mut stopped, &mut again),
                    )?;
                }
            }
            let t_start = log.last().map_or(t, |l| l.0);
            starts.push(t_start);
            current = std::borrow::Cow::Owned(dynamics.with_starts(&starts));
        }
    }
    let integrated = triggers.is_none().then_some(log.len());
    Ok(finish(
        &current,
        start,
        settings,
        &log,
        stopped,
        evaluations,
        integrated,
    ))
}

/// The run-out from the logged steps: the last millimetres in closed form when the motion
/// `stopped` (else it ended at the time limit).
fn finish(
    current: &Dynamics,
    start: &Motion,
    settings: &Settings,
    log: &[(f64, State, State)],
    stopped: bool,
    evaluations: u32,
    integrated: Option<usize>,
) -> Runout {
    let initial_energy = current.kinetic_energy(&log[0].1);
    let mut steps: Vec<Step> = log.iter().map(|(t, y, dy)| step_of(*t, y, dy)).collect();
    let (t_last, y_last, _) = *log.last().expect("the start is logged");
    let (rest, end, time, distance, work) = if stopped {
        // The last millimetres at the current deceleration: the kinetic energy K goes at the
        // power P, so a uniform deceleration ends after tau = 2 K / P, with half the current
        // velocities' way covered.
        let k = current.kinetic_energy(&y_last);
        let p = current.at_time(t_last).rates(&y_last).power;
        let tau = if p > 0.0 { 2.0 * k / p } else { 0.0 };
        let tau = tau.min(settings.time_limit - t_last).max(0.0);
        let rest = Motion {
            x: y_last[0] + y_last[3] * tau / 2.0,
            y: y_last[1] + y_last[4] * tau / 2.0,
            heading: y_last[2] + y_last[5] * tau / 2.0,
            vx: 0.0,
            vy: 0.0,
            yaw_rate: 0.0,
        };
        let distance = y_last[7] + y_last[3].hypot(y_last[4]) * tau / 2.0;
        let work = y_last[6] + k;
        if tau > 0.0 {
            let decel = [-y_last[3] / tau, -y_last[4] / tau, -y_last[5] / tau];
            steps.push(Step {
                time: t_last + tau,
                motion: rest,
                acceleration: decel,
                distance,
                work,
            });
        }
        (rest, End::Rest, t_last + tau, distance, work)
    } else {
        (
            motion_of(&y_last),
            End::TimeLimit,
            t_last,
            y_last[7],
            y_last[6],
        )
    };
    Runout {
        start: *start,
        rotation: rest.heading - start.heading,
        rest,
        end,
        time,
        distance,
        initial_energy,
        tyre_work: work,
        steps,
        evaluations,
        integrated,
    }
}

/// The run-out of `dynamics` from `start` integrated through the accepted steps of `nominal`
/// (internal numerical differentiation: see [`crate::dopri`]); its last millimetres in closed
/// form when the nominal came to rest. `None` when `nominal` cannot be replayed (inputs by
/// distance) or `dynamics` starts inputs by distance.
pub(crate) fn replay(
    dynamics: &Dynamics,
    start: &Motion,
    settings: &Settings,
    nominal: &Runout,
) -> Option<Runout> {
    let n = nominal.integrated?;
    if dynamics.distance_triggers().is_some() || n == 0 || n > nominal.steps.len() {
        return None;
    }
    let times: Vec<f64> = nominal.steps[..n].iter().map(|s| s.time).collect();
    let kinks = dynamics.kinks(settings.time_limit);
    let mut log = Vec::with_capacity(n);
    let evaluations = crate::dopri::replay(
        |t, y| derivative(&dynamics.at_time(t), y),
        &times,
        initial_state(start),
        |t| kinks.iter().any(|&k| (k - t).abs() <= KINK_GAP),
        |t, y, dy| log.push((t, *y, *dy)),
    );
    Some(finish(
        dynamics,
        start,
        settings,
        &log,
        nominal.end == End::Rest,
        evaluations,
        Some(n),
    ))
}

/// The integrated state at separation: position, heading, velocities, no work, no distance.
fn initial_state(start: &Motion) -> State {
    State::from([
        start.x,
        start.y,
        start.heading,
        start.vx,
        start.vy,
        start.yaw_rate,
        0.0,
        0.0,
    ])
}

#[cfg(test)]
mod turn_tests {
    use super::full_turns;

    #[test]
    fn full_turns_beyond_the_shortest_rotation() {
        let t = |deg: f64| full_turns(deg.to_radians());
        // -400 deg: the shortest -40 deg and one turn the other way.
        assert_eq!(t(-400.0), -1);
        // -659.9 deg: the shortest +60.1 deg and two turns clockwise.
        assert_eq!(t(-659.9), -2);
        // 424 deg: 64 deg and one turn; 272.7 deg: -87.3 deg and one turn.
        assert_eq!(t(424.0), 1);
        assert_eq!(t(272.7), 1);
        assert_eq!(t(179.0), 0);
        assert_eq!(t(-179.0), 0);
        assert_eq!(t(0.0), 0);
        // Mirrored (the SAE frame counts clockwise): the count changes sign with the rotation.
        for deg in [-659.9, -400.0, 272.7, 424.0, 1000.0] {
            assert_eq!(t(-deg), -t(deg));
        }
    }
}

#[cfg(test)]
mod replay_tests {
    use super::{replay, run, Settings};
    use crate::chassis::{Chassis, Motion, WheelState};
    use crate::forces::{derivative, Dynamics, State};

    fn car() -> Chassis {
        let mut c = Chassis::new(1500.0, 2500.0, 2.7, 1.2, 1.5, WheelState::Braked(0.3));
        c.wheels[0] = WheelState::Locked;
        c
    }

    fn start(vx: f64) -> Motion {
        Motion {
            x: 1.0,
            y: -2.0,
            heading: 0.3,
            vx,
            vy: 4.0,
            yaw_rate: 2.5,
        }
    }

    /// The integrator is DOPRI5 as `ode_solvers` 0.6 computes it, to the last bit: the same
    /// accepted steps and states.
    #[test]
    fn the_integrator_is_ode_solvers_dopri5_to_the_bit() {
        let dynamics = Dynamics::new(&car());
        let settings = Settings::default();
        let ours = run(&dynamics, &start(14.0), &settings).unwrap();
        struct Sys<'a>(&'a Dynamics);
        impl ode_solvers::System<f64, State> for Sys<'_> {
            fn system(&self, _t: f64, y: &State, dy: &mut State) {
                *dy = derivative(self.0, y);
            }
        }
        let y0 = super::initial_state(&start(14.0));
        let n = ours.integrated.unwrap();
        let end = ours.steps[n - 1].time;
        let mut solver = ode_solvers::Dopri5::from_param(
            Sys(&dynamics),
            0.0,
            end,
            end,
            y0,
            settings.rtol,
            settings.atol,
            0.9,
            0.04,
            0.2,
            10.0,
            settings.time_limit,
            0.0,
            2_000_000,
            u32::MAX,
            ode_solvers::dop_shared::OutputType::Sparse,
        );
        solver.integrate().unwrap();
        let (times, states) = (solver.x_out(), solver.y_out());
        // The crate's last step is shortened to reach `end` exactly; every one before it is
        // the same step from the same state.
        for k in 0..n - 1 {
            let same = |a: f64, b: f64| assert_eq!(a.to_bits(), b.to_bits(), "step {k}: {a} {b}");
            same(times[k], ours.steps[k].time);
            same(states[k][0], ours.steps[k].motion.x);
            same(states[k][5], ours.steps[k].motion.yaw_rate);
        }
    }

    /// A run-out replayed from its own start through its own steps is itself (to rounding of
    /// the step times), at six evaluations a step.
    #[test]
    fn a_run_out_replayed_through_its_own_steps_is_itself() {
        let dynamics = Dynamics::new(&car());
        let settings = Settings::default();
        let nominal = run(&dynamics, &start(14.0), &settings).unwrap();
        let again = replay(&dynamics, &start(14.0), &settings, &nominal).unwrap();
        let n = nominal.integrated.unwrap();
        assert_eq!(again.evaluations as usize, 1 + 6 * (n - 1));
        for (a, b) in [
            (again.rest.x, nominal.rest.x),
            (again.rest.y, nominal.rest.y),
            (again.rest.heading, nominal.rest.heading),
            (again.distance, nominal.distance),
        ] {
            assert!((a - b).abs() < 1e-11 * (1.0 + b.abs()), "{a} against {b}");
        }
    }

    /// The derivative of the rest by internal numerical differentiation equals the central
    /// difference of run-outs with steps of their own at a tight tolerance.
    #[test]
    fn replayed_differences_are_the_derivative_of_the_run_out() {
        let dynamics = Dynamics::new(&car());
        let settings = Settings::default();
        let nominal = run(&dynamics, &start(14.0), &settings).unwrap();
        let h = 1e-6 * 15.0;
        let stepped = replay(&dynamics, &start(14.0 + h), &settings, &nominal).unwrap();
        let tight = Settings {
            rtol: 1e-12,
            atol: 1e-12,
            ..settings
        };
        let wide = 1e-2;
        let up = run(&dynamics, &start(14.0 + wide), &tight).unwrap();
        let down = run(&dynamics, &start(14.0 - wide), &tight).unwrap();
        for (ind, central) in [
            (
                (stepped.rest.x - nominal.rest.x) / h,
                (up.rest.x - down.rest.x) / (2.0 * wide),
            ),
            (
                (stepped.rest.y - nominal.rest.y) / h,
                (up.rest.y - down.rest.y) / (2.0 * wide),
            ),
            (
                (stepped.rest.heading - nominal.rest.heading) / h,
                (up.rest.heading - down.rest.heading) / (2.0 * wide),
            ),
        ] {
            assert!(
                (ind - central).abs() < 1e-3 * (1.0 + central.abs()),
                "{ind} against {central}"
            );
        }
    }
}
