//! Random vehicles and starts for the run-out tests, and an independent implementation of the
//! run-out model written from the equations in pim-runout's crate docs: fixed-step classical
//! Runge-Kutta (1 ms) instead of adaptive Dormand-Prince, the load transfer by fixed-point
//! iteration instead of the 2 x 2 solve, the stop checked at every fixed step.

use pim_runout::{Chassis, Motion, WheelState, GRAVITY};
use rand::rngs::StdRng;
use rand::Rng;

/// What kind of wheels a random vehicle gets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Locked,
    Rolling,
    Braked,
    /// Each wheel drawn from the three, and a steer angle.
    Mixed,
}

pub const KINDS: [Kind; 4] = [Kind::Locked, Kind::Rolling, Kind::Braked, Kind::Mixed];

/// A random passenger car with the wheels of `kind`, friction 0.1-1.0, a CG height half the
/// time.
pub fn random_chassis(rng: &mut StdRng, kind: Kind) -> Chassis {
    let mass = rng.random_range(800.0..2500.0);
    let wheelbase = rng.random_range(2.2..3.2);
    let mut c = Chassis::new(
        mass,
        mass * rng.random_range(1.1..1.9),
        wheelbase,
        wheelbase * rng.random_range(0.35..0.6),
        rng.random_range(1.3..1.7),
        WheelState::Locked,
    );
    c.friction = rng.random_range(0.1..1.0);
    c.rolling_resistance = rng.random_range(0.01..0.02_f64).min(0.5 * c.friction);
    c.saturation_angle = rng.random_range(5.0_f64..15.0).to_radians();
    if rng.random_bool(0.5) {
        c.cg_height = Some(rng.random_range(0.4..0.7));
    }
    let one = |rng: &mut StdRng, k: Kind| match k {
        Kind::Locked => WheelState::Locked,
        Kind::Rolling => WheelState::Rolling,
        Kind::Braked => WheelState::Braked(rng.random_range(0.1..1.0)),
        Kind::Mixed => unreachable!(),
    };
    c.wheels = match kind {
        Kind::Mixed => {
            let s = rng.random_range(-0.3..0.3);
            c.steer = [s, s];
            std::array::from_fn(|_| {
                let k = [Kind::Locked, Kind::Rolling, Kind::Braked][rng.random_range(0..3)];
                one(rng, k)
            })
        }
        k => {
            let w = one(rng, k);
            [w; 4]
        }
    };
    c
}

/// A random start: anywhere, any heading, 2 to `max_speed` m/s in any direction, a yaw rate of
/// either sense up to 4 rad/s.
pub fn random_start(rng: &mut StdRng, max_speed: f64) -> Motion {
    let speed = rng.random_range(2.0..max_speed);
    let dir = rng.random_range(-std::f64::consts::PI..std::f64::consts::PI);
    Motion {
        x: rng.random_range(-20.0..20.0),
        y: rng.random_range(-20.0..20.0),
        heading: rng.random_range(-std::f64::consts::PI..std::f64::consts::PI),
        vx: speed * dir.cos(),
        vy: speed * dir.sin(),
        yaw_rate: rng.random_range(-4.0..4.0),
    }
}

/// x, y, heading, vx, vy, yaw rate, and the distance along the path.
type State7 = nalgebra::SVector<f64, 7>;

struct Sys<'a, 'b> {
    model: &'a Reference<'b>,
    last: &'a mut (f64, State7),
    /// The accepted step before `last`.
    prev: &'a mut (f64, State7),
    stopped: &'a mut bool,
    /// Stop where the path reaches this distance (an input by distance starts).
    target: Option<f64>,
    reached: &'a mut bool,
}

impl ode_solvers::System<f64, State7> for Sys<'_, '_> {
    fn system(&self, t: f64, y: &State7, dy: &mut State7) {
        self.model.t.set(t);
        let s: [f64; 6] = std::array::from_fn(|i| y[i]);
        let d = self.model.deriv(&s);
        *dy = State7::from([d[0], d[1], d[2], d[3], d[4], d[5], y[3].hypot(y[4])]);
    }

    fn solout(&mut self, t: f64, y: &State7, _dy: &State7) -> bool {
        self.model.t.set(t);
        if self.last.0 < t {
            *self.prev = *self.last;
        }
        *self.last = (t, *y);
        let s: [f64; 6] = std::array::from_fn(|i| y[i]);
        *self.stopped = self.model.slow(&s);
        *self.reached = !*self.stopped && self.target.is_some_and(|d| y[6] >= d);
        *self.stopped || *self.reached
    }
}

/// Where a stretch of the reference's integration ended.
#[derive(Clone, Copy)]
struct Stretch {
    last: (f64, State7),
    prev: (f64, State7),
    stopped: bool,
    reached: bool,
}

/// A start as the reference's state: pose, velocities, and no distance yet.
fn initial(start: &Motion) -> State7 {
    State7::from([
        start.x,
        start.y,
        start.heading,
        start.vx,
        start.vy,
        start.yaw_rate,
        0.0,
    ])
}

/// The reference's run-out: where it ended, whether at rest (within 60 s), when, and the
/// path's length (m).
pub struct RefRun {
    pub rest: [f64; 3],
    pub stopped: bool,
    pub time: f64,
    pub distance: f64,
}

pub struct Reference<'a> {
    pub c: &'a Chassis,
    /// The time of the state being evaluated (for the driver's inputs).
    pub t: std::cell::Cell<f64>,
}

impl<'a> Reference<'a> {
    pub fn new(c: &'a Chassis) -> Self {
        Reference {
            c,
            t: std::cell::Cell::new(0.0),
        }
    }

    /// A value of the driver's inputs at time `t`, written as a list of breakpoints (time,
    /// value) joined by straight lines: each input cuts the list at its start (the value there
    /// read off the list) and adds its own ramp.
    fn input_value(&self, base: f64, pick: impl Fn(&pim_runout::Input) -> Option<f64>) -> f64 {
        let t = self.t.get();
        let read = |points: &[(f64, f64)], t: f64| -> f64 {
            let mut v = points[0].1;
            for w in points.windows(2) {
                let ((t0, v0), (t1, v1)) = (w[0], w[1]);
                if t >= t1 {
                    v = v1;
                } else if t > t0 {
                    v = v0 + (v1 - v0) * (t - t0) / (t1 - t0);
                }
            }
            v
        };
        let mut points = vec![(0.0, base)];
        for i in &self.c.inputs {
            if let Some(target) = pick(i) {
                let now = read(&points, i.at);
                points.retain(|p| p.0 < i.at);
                points.push((i.at, now));
                // A step (no build-up) rises over the smallest time after its start.
                let rise = i.build_up.max(f64::MIN_POSITIVE.max(i.at * f64::EPSILON));
                points.push((i.at + rise, target));
            }
        }
        if points.iter().any(|p| p.0 <= t) {
            read(&points, t)
        } else {
            base
        }
    }
}

const DEADBAND: f64 = 0.01;
const REST_SPEED: f64 = 0.02;

impl Reference<'_> {
    fn wheel(&self, i: usize) -> ([f64; 2], f64) {
        let c = self.c;
        let x = if i < 2 {
            c.cg_to_front_axle
        } else {
            c.cg_to_front_axle - c.wheelbase
        };
        let y = if i.is_multiple_of(2) {
            c.track / 2.0
        } else {
            -c.track / 2.0
        };
        let steer = if i < 2 {
            self.input_value(c.steer[i], |input| input.steer.map(|a| a[i]))
        } else {
            0.0
        };
        ([x, y], steer)
    }

    fn patches(&self, s: &[f64; 6]) -> [[f64; 2]; 4] {
        let (sn, cs) = s[2].sin_cos();
        let vb = [cs * s[3] + sn * s[4], -sn * s[3] + cs * s[4]];
        std::array::from_fn(|i| {
            let (p, _) = self.wheel(i);
            [vb[0] - s[5] * p[1], vb[1] + s[5] * p[0]]
        })
    }

    /// The friction under wheel `i` at the state `s`: the road's, moved toward each zone's in
    /// turn by the share of a 0.2 m contact patch on the zone (inside by the winding number,
    /// the distance to the nearest edge).
    fn friction_under(&self, i: usize, s: &[f64; 6]) -> f64 {
        let (r, _) = self.wheel(i);
        let (sn, cs) = s[2].sin_cos();
        let p = [s[0] + cs * r[0] - sn * r[1], s[1] + sn * r[0] + cs * r[1]];
        let mut mu = self.c.friction;
        for z in &self.c.zones {
            let n = z.corners.len();
            let (mut winding, mut nearest) = (0.0, f64::INFINITY);
            for k in 0..n {
                let a = [z.corners[k][0] - p[0], z.corners[k][1] - p[1]];
                let b = [
                    z.corners[(k + 1) % n][0] - p[0],
                    z.corners[(k + 1) % n][1] - p[1],
                ];
                winding += (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1]);
                let e = [b[0] - a[0], b[1] - a[1]];
                let t =
                    (-(a[0] * e[0] + a[1] * e[1]) / (e[0] * e[0] + e[1] * e[1])).clamp(0.0, 1.0);
                nearest = nearest.min((a[0] + t * e[0]).hypot(a[1] + t * e[1]));
            }
            let inside = winding.abs() > std::f64::consts::PI;
            let d = if inside { nearest } else { -nearest };
            mu += (0.5 + d / 0.2).clamp(0.0, 1.0) * (z.friction - mu);
        }
        mu
    }

    /// Force per unit load of wheel `i` at patch velocity `u` (body frame) on the friction
    /// `mu`.
    fn per_load(&self, i: usize, u: [f64; 2], mu: f64) -> [f64; 2] {
        let c = self.c;
        let along = match c.wheels[i] {
            WheelState::Locked => {
                let n = (u[0] * u[0] + u[1] * u[1]).sqrt().max(DEADBAND);
                return [-mu * u[0] / n, -mu * u[1] / n];
            }
            WheelState::Rolling => {
                (self.input_value(0.0, |input| input.braking[i]) * mu).max(c.rolling_resistance)
            }
            WheelState::Braked(b) => {
                (self.input_value(b, |input| input.braking[i]) * mu).max(c.rolling_resistance)
            }
        }
        .min(mu);
        let across = (mu * mu - along * along).sqrt();
        let (_, steer) = self.wheel(i);
        let (sn, cs) = steer.sin_cos();
        let ul = cs * u[0] + sn * u[1];
        let us = -sn * u[0] + cs * u[1];
        let fl = -along * ul / ul.abs().max(DEADBAND);
        let alpha = (us.abs() / ul.abs().max(DEADBAND)).atan();
        let fs = -across * (alpha / c.saturation_angle).min(1.0) * us.signum();
        [cs * fl - sn * fs, sn * fl + cs * fs]
    }

    fn static_load(&self, i: usize) -> f64 {
        let c = self.c;
        let w = c.mass * GRAVITY;
        if i < 2 {
            w * (c.wheelbase - c.cg_to_front_axle) / c.wheelbase / 2.0
        } else {
            w * c.cg_to_front_axle / c.wheelbase / 2.0
        }
    }

    /// `(ax, ay, r_dot, power)` in the fixed frame.
    pub fn rates(&self, s: &[f64; 6]) -> [f64; 4] {
        let c = self.c;
        let u = self.patches(s);
        let g: [[f64; 2]; 4] =
            std::array::from_fn(|i| self.per_load(i, u[i], self.friction_under(i, s)));
        let mut load: [f64; 4] = std::array::from_fn(|i| self.static_load(i));
        if let Some(h) = c.cg_height {
            // Fixed point: acceleration from the loads, loads from the acceleration.
            for _ in 0..500 {
                let ax = (0..4).map(|i| load[i] * g[i][0]).sum::<f64>() / c.mass;
                let ay = (0..4).map(|i| load[i] * g[i][1]).sum::<f64>() / c.mass;
                let next: [f64; 4] = std::array::from_fn(|i| {
                    let front = i < 2;
                    let left = i % 2 == 0;
                    let share = if front {
                        (c.wheelbase - c.cg_to_front_axle) / c.wheelbase
                    } else {
                        c.cg_to_front_axle / c.wheelbase
                    };
                    let long =
                        if front { -1.0 } else { 1.0 } * c.mass * h * ax / (2.0 * c.wheelbase);
                    let lat = if left { -1.0 } else { 1.0 } * c.mass * h * ay / c.track * share;
                    (self.static_load(i) + long + lat).max(0.0)
                });
                let change = (0..4)
                    .map(|i| (next[i] - load[i]).abs())
                    .fold(0.0, f64::max);
                load = next;
                if change < 1e-10 {
                    break;
                }
            }
        }
        let (mut fx, mut fy, mut mz, mut p) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..4 {
            let f = [load[i] * g[i][0], load[i] * g[i][1]];
            let (r, _) = self.wheel(i);
            fx += f[0];
            fy += f[1];
            mz += r[0] * f[1] - r[1] * f[0];
            p -= f[0] * u[i][0] + f[1] * u[i][1];
        }
        let (sn, cs) = s[2].sin_cos();
        [
            (cs * fx - sn * fy) / c.mass,
            (sn * fx + cs * fy) / c.mass,
            mz / c.yaw_inertia,
            p,
        ]
    }

    fn deriv(&self, s: &[f64; 6]) -> [f64; 6] {
        let r = self.rates(s);
        [s[3], s[4], s[5], r[0], r[1], r[2]]
    }

    /// One Dormand-Prince 8(5,3) integration from `from` to `end`, or to rest, or to the path's
    /// distance `target`.
    fn integrate(&self, from: (f64, State7), end: f64, target: Option<f64>) -> Stretch {
        let (mut last, mut prev) = (from, from);
        let (mut stopped, mut reached) = (false, false);
        let sys = Sys {
            model: self,
            last: &mut last,
            prev: &mut prev,
            stopped: &mut stopped,
            target,
            reached: &mut reached,
        };
        // Stiffness detection off: a patch inside the 1 cm/s band is stiff, by design.
        let mut solver = ode_solvers::Dop853::from_param(
            sys,
            from.0,
            end,
            end - from.0,
            from.1,
            1e-11,
            1e-11,
            0.9,
            0.0,
            0.333,
            6.0,
            60.0,
            0.0,
            10_000_000,
            u32::MAX,
            ode_solvers::OutputType::Sparse,
        );
        solver.integrate().expect("the reference integrates");
        Stretch {
            last,
            prev,
            stopped,
            reached,
        }
    }

    /// From `from` to `until` (or to rest, or to the distance `target`), piece by piece between
    /// the kinks of this reference's inputs: across a kink the 8th-order method loses its order.
    fn pieces(&self, from: (f64, State7), until: f64, target: Option<f64>) -> Stretch {
        let mut kinks: Vec<f64> = self
            .c
            .inputs
            .iter()
            .flat_map(|i| [i.at, i.at + i.build_up])
            .filter(|t| *t > from.0 && *t < until)
            .chain([until])
            .collect();
        kinks.sort_by(f64::total_cmp);
        let mut out = Stretch {
            last: from,
            prev: from,
            stopped: false,
            reached: false,
        };
        for end in kinks {
            if out.stopped || out.reached || end <= out.last.0 {
                continue;
            }
            out = self.integrate(out.last, end, target);
        }
        out
    }

    /// The rest `(x, y, heading)` and whether it came to rest within 60 s: Dormand and
    /// Prince's 8(5,3) method (`ode_solvers::Dop853`, not the 5(4) pair pim-runout uses) at
    /// tolerances 1e-11, the stop checked after every accepted step. Inputs by distance are
    /// started one after the other: the reference runs with the inputs started so far to the
    /// input's earliest time, then to its distance, and finds the time the distance is reached
    /// by bisection over integrations from the step before it (not from a cubic through the
    /// step, as pim-runout does).
    pub fn run(&self, start: &Motion) -> ([f64; 3], bool) {
        let r = self.run_out(start);
        (r.rest, r.stopped)
    }

    /// The pose `(x, y, heading)` at time `t` after `start` (the rest's, once stopped): for a
    /// chassis without inputs by distance.
    pub fn pose_at(&self, start: &Motion, t: f64) -> [f64; 3] {
        assert!(self.c.inputs.iter().all(|i| i.distance.is_none()));
        let y0 = initial(start);
        let s = self.pieces((0.0, y0), t, None).last.1;
        [s[0], s[1], s[2]]
    }

    /// As [`Reference::run`], with the time and the path's length to rest.
    pub fn run_out(&self, start: &Motion) -> RefRun {
        let y0 = initial(start);
        let by_distance = self.c.inputs.iter().any(|i| i.distance.is_some());
        let mut chassis = self.c.clone();
        let mut state = (0.0, y0);
        let mut stopped = false;
        if by_distance {
            chassis.inputs.clear();
            let mut started = 0.0_f64;
            for input in &self.c.inputs {
                let stage = Reference::new(&chassis);
                let earliest = input.at.max(started);
                let r = stage.pieces(state, earliest, None);
                state = r.last;
                if r.stopped || state.0 < earliest {
                    stopped = r.stopped;
                    break;
                }
                if let Some(d) = input.distance.filter(|&d| state.1[6] < d) {
                    let r = stage.pieces(state, 60.0, Some(d));
                    if !r.reached {
                        state = r.last;
                        stopped = r.stopped;
                        break;
                    }
                    let (mut lo, mut hi) = (r.prev.0, r.last.0);
                    for _ in 0..60 {
                        let mid = 0.5 * (lo + hi);
                        if stage.pieces(r.prev, mid, None).last.1[6] < d {
                            lo = mid;
                        } else {
                            hi = mid;
                        }
                    }
                    state = stage.pieces(r.prev, hi, None).last;
                }
                started = state.0;
                chassis.inputs.push(pim_runout::Input {
                    at: started,
                    distance: None,
                    ..*input
                });
            }
        }
        let model = Reference::new(&chassis);
        if !stopped && state.0 < 60.0 {
            let r = model.pieces(state, 60.0, None);
            state = r.last;
            stopped = r.stopped;
        }
        model.t.set(state.0);
        let s: [f64; 6] = std::array::from_fn(|i| state.1[i]);
        let (time, distance) = (state.0, state.1[6]);
        if !stopped {
            return RefRun {
                rest: [s[0], s[1], s[2]],
                stopped: false,
                time,
                distance,
            };
        }
        let k =
            0.5 * (model.c.mass * (s[3] * s[3] + s[4] * s[4]) + model.c.yaw_inertia * s[5] * s[5]);
        let p = model.rates(&s)[3];
        let tau = if p > 0.0 { 2.0 * k / p } else { 0.0 };
        RefRun {
            rest: [
                s[0] + s[3] * tau / 2.0,
                s[1] + s[4] * tau / 2.0,
                s[2] + s[5] * tau / 2.0,
            ],
            stopped: true,
            time,
            distance,
        }
    }

    fn slow(&self, s: &[f64; 6]) -> bool {
        self.patches(s)
            .iter()
            .all(|u| (u[0] * u[0] + u[1] * u[1]).sqrt() < REST_SPEED)
    }
}
