//! The tyre forces and the equations of motion (see the crate docs for the model).

use crate::chassis::{Chassis, WheelState};

/// Below this sliding speed, m/s, the friction force of a patch grows linearly from zero
/// instead of jumping: Coulomb's law made continuous, so that a patch that passes through zero
/// sliding neither chatters nor stops the integrator. 1 cm/s is below every speed at which
/// the run-out's path is decided.
pub const SLIDING_DEADBAND: f64 = 1e-2;

/// The state integrated: x, y, heading, vx, vy, yaw rate, the work done by the tyre forces
/// (J, positive: energy taken out) and the distance travelled by the CG (m).
pub(crate) type State = nalgebra::SVector<f64, 8>;

/// One wheel at one instant of a run-out.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WheelAt {
    /// Normal load, N (0 when the wheel lifts).
    pub load: f64,
    /// Slip angle, rad: the direction of the contact patch's velocity from the wheel's axis,
    /// `atan2(u_s, |u_l|)`, positive when the patch slides to the wheel's left.
    pub slip_angle: f64,
    /// Tyre force on the vehicle, N, in the body frame (x forward, y left).
    pub force: [f64; 2],
}

/// Each wheel's normal load, slip angle and tyre force for `chassis` in the motion `m` at time
/// `t` after separation (front left, front right, rear left, rear right), as the run-out's
/// equations of motion use them (the driver's inputs at that time).
pub fn wheels_at(chassis: &Chassis, m: &crate::Motion, t: f64) -> [WheelAt; 4] {
    let y = State::from([m.x, m.y, m.heading, m.vx, m.vy, m.yaw_rate, 0.0, 0.0]);
    Dynamics::new(chassis).at_time(t).wheels_at(&y)
}

/// What one wheel does, in numbers per unit of normal load.
#[derive(Debug, Clone, Copy)]
enum Tyre {
    /// `-mu u / |u|`.
    Sliding { mu: f64 },
    /// Along the wheel `-along sgn(u_l)`, across it `-across min(alpha / sat, 1) sgn(u_s)`.
    Rolling { along: f64, across: f64 },
}

/// One wheel: position in the body frame, heading of the wheel in the body frame, behaviour.
#[derive(Debug, Clone, Copy)]
struct Wheel {
    r: [f64; 2],
    dir: [f64; 2],
    tyre: Tyre,
    /// Its braking share (0: free rolling), none when locked: the tyre again on another
    /// friction.
    share: Option<f64>,
    /// Static load, N.
    load: f64,
    /// Load change per unit of body-frame CG acceleration (ax, ay), N per m/s^2.
    transfer: [f64; 2],
}

/// The vehicle's equations of motion, prepared once from a checked [`Chassis`].
#[derive(Debug, Clone)]
pub(crate) struct Dynamics {
    mass: f64,
    inertia: f64,
    wheels: [Wheel; 4],
    saturation: f64,
    /// `tan(saturation)`: a slip whose tangent reaches it saturates the tyre, no arctangent
    /// needed.
    tan_saturation: f64,
    load_transfer: bool,
    /// The driver's inputs, when the chassis has any.
    schedule: Option<std::sync::Arc<Schedule>>,
    /// The ground, when it has friction zones: each wheel's tyre then follows the friction
    /// under it.
    ground: Option<std::sync::Arc<Ground>>,
}

/// The road friction with its zones, and the rolling resistance a tyre keeps on any of them.
#[derive(Debug)]
struct Ground {
    road: f64,
    zones: Vec<crate::zones::Zone>,
    rolling_resistance: f64,
}

/// The driver's inputs of a chassis, with what they change from.
#[derive(Debug, Clone)]
struct Schedule {
    inputs: Vec<crate::chassis::Input>,
    /// Each wheel's braking share at separation (none for a locked wheel, which stays locked).
    shares: [Option<f64>; 4],
    /// The front wheels' steer angles at separation, rad.
    steer: [f64; 2],
    friction: f64,
    rolling_resistance: f64,
}

impl Schedule {
    /// A value at time `t`: from `base`, each input that gives it (`pick`) moves it linearly
    /// from its value when the input starts to the input's over the input's build-up.
    fn value(
        &self,
        base: f64,
        pick: impl Fn(&crate::chassis::Input) -> Option<f64>,
        t: f64,
    ) -> f64 {
        // (start, from, to, build-up) of the ramp in force.
        let at = |r: (f64, f64, f64, f64), t: f64| {
            if r.3 <= 0.0 || t >= r.0 + r.3 {
                r.2
            } else {
                r.1 + (r.2 - r.1) * (t - r.0) / r.3
            }
        };
        let mut ramp = (0.0, base, base, 0.0);
        for input in self.inputs.iter().take_while(|i| i.at <= t) {
            if let Some(to) = pick(input) {
                ramp = (input.at, at(ramp, input.at), to, input.build_up);
            }
        }
        at(ramp, t)
    }
}

/// What the forces do at one state.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Rates {
    /// CG acceleration in the fixed frame, m/s^2.
    pub ax: f64,
    pub ay: f64,
    /// Yaw acceleration, rad/s^2.
    pub yaw: f64,
    /// Power taken out by the tyre forces, W (never negative).
    pub power: f64,
}

impl Dynamics {
    pub(crate) fn new(c: &Chassis) -> Self {
        let loads = c.static_loads();
        let b = c.wheelbase - c.cg_to_front_axle;
        let mu = c.friction;
        let wheels = std::array::from_fn(|i| {
            let r = c.wheel_position(i);
            let steer = if i < 2 { c.steer[i] } else { 0.0 };
            let share = match c.wheels[i] {
                WheelState::Locked => None,
                WheelState::Rolling => Some(0.0),
                WheelState::Braked(b) => Some(b),
            };
            let tyre = tyre_of(share, mu, c.rolling_resistance);
            // Load transfer of a CG acceleration (ax, ay) in the body frame at CG height h:
            // m ax h / L moves from the rear axle to the front one when ax < 0 (braking), and
            // m ay h / track from the left wheels to the right ones when ay > 0, shared by the
            // axles in their static proportion.
            let transfer = match c.cg_height {
                Some(h) => {
                    let axle_share = if i < 2 { b } else { c.cg_to_front_axle } / c.wheelbase;
                    let along = if i < 2 { -1.0 } else { 1.0 } * c.mass * h / c.wheelbase / 2.0;
                    let across =
                        if i % 2 == 0 { -1.0 } else { 1.0 } * c.mass * h / c.track * axle_share;
                    [along, across]
                }
                None => [0.0, 0.0],
            };
            Wheel {
                r,
                dir: [steer.cos(), steer.sin()],
                tyre,
                share,
                load: loads[i],
                transfer,
            }
        });
        let schedule = (!c.inputs.is_empty()).then(|| {
            std::sync::Arc::new(Schedule {
                inputs: c.inputs.clone(),
                shares: c.wheels.map(|w| match w {
                    WheelState::Locked => None,
                    WheelState::Rolling => Some(0.0),
                    WheelState::Braked(b) => Some(b),
                }),
                steer: c.steer,
                friction: mu,
                rolling_resistance: c.rolling_resistance,
            })
        });
        Dynamics {
            mass: c.mass,
            inertia: c.yaw_inertia,
            wheels,
            saturation: c.saturation_angle,
            tan_saturation: c.saturation_angle.tan(),
            load_transfer: c.cg_height.is_some(),
            schedule,
            ground: (!c.zones.is_empty()).then(|| {
                std::sync::Arc::new(Ground {
                    road: mu,
                    zones: c.zones.clone(),
                    rolling_resistance: c.rolling_resistance,
                })
            }),
        }
    }

    /// The dynamics at time `t` after separation: the driver's inputs then (itself without
    /// inputs).
    pub(crate) fn at_time(&self, t: f64) -> std::borrow::Cow<'_, Dynamics> {
        let Some(s) = &self.schedule else {
            return std::borrow::Cow::Borrowed(self);
        };
        // The clone shares the schedule (no copy of the inputs at every evaluation).
        let mut d = self.clone();
        for (i, wheel) in d.wheels.iter_mut().enumerate() {
            if let Some(base) = s.shares[i] {
                let share = s.value(base, |x| x.braking[i], t);
                wheel.share = Some(share);
                wheel.tyre = tyre_of(wheel.share, s.friction, s.rolling_resistance);
            }
            if i < 2 {
                let steer = s.value(s.steer[i], |x| x.steer.map(|a| a[i]), t);
                wheel.dir = [steer.cos(), steer.sin()];
            }
        }
        std::borrow::Cow::Owned(d)
    }

    /// Each input's earliest time and distance when some input starts by distance (the run
    /// then resolves their starts as it goes), else `None`.
    pub(crate) fn distance_triggers(&self) -> Option<Vec<(f64, Option<f64>)>> {
        let s = self.schedule.as_ref()?;
        s.inputs
            .iter()
            .any(|i| i.distance.is_some())
            .then(|| s.inputs.iter().map(|i| (i.at, i.distance)).collect())
    }

    /// These dynamics with the first `starts.len()` inputs only, starting at `starts` (the
    /// inputs started so far of a run with inputs by distance).
    pub(crate) fn with_starts(&self, starts: &[f64]) -> Dynamics {
        let mut d = self.clone();
        if let Some(s) = &self.schedule {
            let mut resolved = Schedule::clone(s);
            resolved.inputs.truncate(starts.len());
            for (input, &t) in resolved.inputs.iter_mut().zip(starts) {
                input.at = t;
            }
            d.schedule = Some(std::sync::Arc::new(resolved));
        }
        d
    }

    /// The times before `limit` where an input's value changes its slope (each input's start and
    /// the end of its build-up), in order: the run-out is integrated piece by piece between
    /// them.
    pub(crate) fn kinks(&self, limit: f64) -> Vec<f64> {
        let Some(s) = &self.schedule else {
            return Vec::new();
        };
        let mut out: Vec<f64> = s
            .inputs
            .iter()
            .flat_map(|i| [i.at, i.at + i.build_up])
            .filter(|&t| t > 0.0 && t < limit)
            .collect();
        out.sort_by(f64::total_cmp);
        out.dedup();
        out
    }

    /// Velocity of each contact patch in the body frame, m/s.
    pub(crate) fn patch_velocities(&self, y: &State) -> [[f64; 2]; 4] {
        self.patch_velocities_turned(y, y[2].sin_cos())
    }

    /// [`Dynamics::patch_velocities`] with the heading's sine and cosine already known.
    fn patch_velocities_turned(&self, y: &State, (s, c): (f64, f64)) -> [[f64; 2]; 4] {
        let (vx, vy, w) = (c * y[3] + s * y[4], -s * y[3] + c * y[4], y[5]);
        self.wheels.map(|wh| [vx - w * wh.r[1], vy + w * wh.r[0]])
    }

    /// The fastest contact patch, m/s.
    pub(crate) fn fastest_patch(&self, y: &State) -> f64 {
        self.patch_velocities(y)
            .iter()
            .map(|u| speed(u[0], u[1]))
            .fold(0.0, f64::max)
    }

    /// Kinetic energy, J.
    pub(crate) fn kinetic_energy(&self, y: &State) -> f64 {
        0.5 * (self.mass * (y[3] * y[3] + y[4] * y[4]) + self.inertia * y[5] * y[5])
    }

    /// The accelerations and the power of the tyre forces at `y`.
    pub(crate) fn rates(&self, y: &State) -> Rates {
        let (s, c) = y[2].sin_cos();
        let u = self.patch_velocities_turned(y, (s, c));
        let tyres = self.tyres(y, (s, c));
        // Force per unit normal load of each wheel, body frame.
        let g: [[f64; 2]; 4] = std::array::from_fn(|i| self.unit_force(i, u[i], tyres[i]));
        let loads = self.loads(&g);
        let (mut fx, mut fy, mut mz, mut power) = (0.0, 0.0, 0.0, 0.0);
        for i in 0..4 {
            let f = [loads[i] * g[i][0], loads[i] * g[i][1]];
            let r = self.wheels[i].r;
            fx += f[0];
            fy += f[1];
            mz += r[0] * f[1] - r[1] * f[0];
            power -= f[0] * u[i][0] + f[1] * u[i][1];
        }
        Rates {
            ax: (c * fx - s * fy) / self.mass,
            ay: (s * fx + c * fy) / self.mass,
            yaw: mz / self.inertia,
            power: power.max(0.0),
        }
    }

    /// Each wheel's normal load, slip angle and tyre force at `y`: what [`Dynamics::rates`]
    /// sums, wheel by wheel.
    pub(crate) fn wheels_at(&self, y: &State) -> [WheelAt; 4] {
        let u = self.patch_velocities(y);
        let tyres = self.tyres(y, y[2].sin_cos());
        let g: [[f64; 2]; 4] = std::array::from_fn(|i| self.unit_force(i, u[i], tyres[i]));
        let loads = self.loads(&g);
        std::array::from_fn(|i| {
            let [c, s] = self.wheels[i].dir;
            let (ul, us) = (c * u[i][0] + s * u[i][1], -s * u[i][0] + c * u[i][1]);
            WheelAt {
                load: loads[i],
                slip_angle: us.atan2(ul.abs()),
                force: [loads[i] * g[i][0], loads[i] * g[i][1]],
            }
        })
    }

    /// The normal loads, N. Without a CG height the static ones. With it each load is affine in
    /// the CG acceleration and every force is its load times a factor of the kinematics, so the
    /// acceleration solves a 2 x 2 linear system; a wheel whose load would turn negative lifts
    /// (its load is 0) and the system is solved again without it.
    fn loads(&self, g: &[[f64; 2]; 4]) -> [f64; 4] {
        let mut loads = self.wheels.map(|w| w.load);
        if !self.load_transfer {
            return loads;
        }
        let mut lifted = [false; 4];
        for _ in 0..4 {
            let mut a = [[self.mass, 0.0], [0.0, self.mass]];
            let mut rhs = [0.0; 2];
            for i in (0..4).filter(|&i| !lifted[i]) {
                let w = &self.wheels[i];
                for (row, gi) in g[i].iter().enumerate() {
                    rhs[row] += w.load * gi;
                    a[row][0] -= gi * w.transfer[0];
                    a[row][1] -= gi * w.transfer[1];
                }
            }
            let Some(acc) = solve2(a, rhs) else {
                return loads;
            };
            let mut again = false;
            for i in 0..4 {
                let w = &self.wheels[i];
                loads[i] = if lifted[i] {
                    0.0
                } else {
                    w.load + w.transfer[0] * acc[0] + w.transfer[1] * acc[1]
                };
                if loads[i] < 0.0 {
                    lifted[i] = true;
                    loads[i] = 0.0;
                    again = true;
                }
            }
            if !again {
                break;
            }
        }
        loads
    }

    /// Each wheel's tyre at `y` (the heading's sine and cosine given): its own, or on ground
    /// with zones the same tyre on the friction under the wheel.
    fn tyres(&self, y: &State, (s, c): (f64, f64)) -> [Tyre; 4] {
        let Some(g) = &self.ground else {
            return self.wheels.map(|w| w.tyre);
        };
        self.wheels.map(|w| {
            let p = [
                y[0] + c * w.r[0] - s * w.r[1],
                y[1] + s * w.r[0] + c * w.r[1],
            ];
            let mu = crate::zones::friction_at(g.road, &g.zones, p);
            tyre_of(w.share, mu, g.rolling_resistance)
        })
    }

    /// The force of wheel `i` with `tyre` per unit normal load for the patch velocity `u`
    /// (body frame).
    fn unit_force(&self, i: usize, u: [f64; 2], tyre: Tyre) -> [f64; 2] {
        let w = &self.wheels[i];
        match tyre {
            Tyre::Sliding { mu } => {
                let k = mu / speed(u[0], u[1]).max(SLIDING_DEADBAND);
                [-k * u[0], -k * u[1]]
            }
            Tyre::Rolling { along, across } => {
                let [c, s] = w.dir;
                let ul = c * u[0] + s * u[1];
                let us = -s * u[0] + c * u[1];
                let fl = -along * ul / ul.abs().max(SLIDING_DEADBAND);
                let along_speed = ul.abs().max(SLIDING_DEADBAND);
                // min(alpha / saturation, 1) with alpha = atan(|u_s| / |u_l|) (the speed
                // along the wheel is at least the band, so the quotient is finite): at or
                // beyond the saturation angle 1 (the tangent decides, without the arctangent).
                let share = if us.abs() >= self.tan_saturation * along_speed {
                    1.0
                } else {
                    ((us.abs() / along_speed).atan() / self.saturation).min(1.0)
                };
                let fs = -across * share * us.signum();
                [c * fl - s * fs, s * fl + c * fs]
            }
        }
    }
}

/// `a x = b` for a 2 x 2 `a` (rows), by Gaussian elimination with partial pivoting: the
/// operations of nalgebra's `LU::new(a).solve(b)` one for one (the same results to the bit),
/// without its general matrices (the run-outs solve this system at every evaluation of their
/// forces). `None` where `a` is singular.
fn solve2(a: [[f64; 2]; 2], b: [f64; 2]) -> Option<[f64; 2]> {
    // The pivot: the larger of the first column (the first where they tie).
    let ([u0, mut u1], [mut b0, mut b1]) = if a[1][0].abs() > a[0][0].abs() {
        ([a[1], a[0]], [b[1], b[0]])
    } else {
        ([a[0], a[1]], b)
    };
    if u0[0] == 0.0 {
        return None;
    }
    let l = u1[0] * (1.0 / u0[0]);
    u1[1] -= u0[1] * l;
    b1 -= b0 * l;
    if u1[1] == 0.0 {
        return None;
    }
    let x1 = b1 / u1[1];
    b0 -= x1 * u0[1];
    Some([b0 / u0[0], x1])
}

/// The tyre of a wheel with braking share `share` (none: locked) on the friction `mu`.
fn tyre_of(share: Option<f64>, mu: f64, rolling_resistance: f64) -> Tyre {
    match share {
        None => Tyre::Sliding { mu },
        Some(b) => rolling(mu, (b * mu).max(rolling_resistance)),
    }
}

/// A rolling wheel whose force along it is `along` (per unit load): the rest of the friction
/// circle is available across it.
fn rolling(mu: f64, along: f64) -> Tyre {
    let along = along.min(mu);
    Tyre::Rolling {
        along,
        across: (mu * mu - along * along).max(0.0).sqrt(),
    }
}

/// The time derivative of the state.
pub(crate) fn derivative(d: &Dynamics, y: &State) -> State {
    let r = d.rates(y);
    State::from([
        y[3],
        y[4],
        y[5],
        r.ax,
        r.ay,
        r.yaw,
        r.power,
        speed(y[3], y[4]),
    ])
}

/// The magnitude of a velocity `(x, y)`, m/s: `sqrt(x^2 + y^2)` without `hypot`'s guard
/// against overflow, which velocities of a vehicle (at most a few hundred m/s) never need,
/// at a fraction of its cost in the equations of motion.
#[inline]
fn speed(x: f64, y: f64) -> f64 {
    (x * x + y * y).sqrt()
}

#[cfg(test)]
mod tests {
    use super::solve2;
    use proptest::prelude::*;

    /// nalgebra's LU solve, the operations `solve2` repeats.
    fn lu(a: [[f64; 2]; 2], b: [f64; 2]) -> Option<[f64; 2]> {
        let m = nalgebra::Matrix2::new(a[0][0], a[0][1], a[1][0], a[1][1]);
        m.lu()
            .solve(&nalgebra::Vector2::new(b[0], b[1]))
            .map(|x| [x[0], x[1]])
    }

    fn bits(x: Option<[f64; 2]>) -> Option<[u64; 2]> {
        x.map(|x| x.map(f64::to_bits))
    }

    proptest! {
        #[test]
        fn the_2x2_solve_is_nalgebras_lu_to_the_bit(
            a in prop::array::uniform4(-1e4..1e4f64),
            b in prop::array::uniform2(-1e4..1e4f64),
        ) {
            let a = [[a[0], a[1]], [a[2], a[3]]];
            prop_assert_eq!(bits(solve2(a, b)), bits(lu(a, b)));
        }
    }

    #[test]
    fn ties_and_singular_matrices_as_nalgebra() {
        for a in [
            [[2.0, 1.0], [-2.0, 3.0]],
            [[0.0, 1.0], [0.0, 3.0]],
            [[1.0, 2.0], [2.0, 4.0]],
            [[0.0, 1.0], [1.0, 0.0]],
            [[1500.0, -0.0], [0.0, 1500.0]],
        ] {
            let b = [3.0, -7.0];
            assert_eq!(bits(solve2(a, b)), bits(lu(a, b)), "{a:?}");
        }
        assert!(solve2([[1.0, 2.0], [2.0, 4.0]], [1.0, 1.0]).is_none());
    }
}
