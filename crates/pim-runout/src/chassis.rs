//! The vehicle of a run-out: mass, yaw inertia, where its wheels are and what each wheel does.

use crate::error::{Result, RunoutError};
use serde::{Deserialize, Serialize};

/// Standard gravity, m/s^2 (CGPM 1901; every distance of a sliding run-out scales with
/// `1 / (mu g)`).
pub const GRAVITY: f64 = 9.80665;

/// Road friction when a case gives none: 0.7, the middle of the range 0.55-0.80 that Fricke
/// (Traffic Accident Reconstruction, Northwestern University Traffic Institute, 1990) tabulates
/// for passenger-car tyres sliding on dry asphalt.
pub const DEFAULT_FRICTION: f64 = 0.7;

/// Rolling resistance of a free-rolling wheel when a case gives none: 0.015 of its load, the
/// figure Gillespie (Fundamentals of Vehicle Dynamics, SAE 1992, section 4) gives for passenger
/// car tyres on hard roads.
pub const DEFAULT_ROLLING_RESISTANCE: f64 = 0.015;

/// Slip angle at which a rolling wheel's lateral force reaches the friction limit when a case
/// gives none: 10 degrees (in radians). Not PC-Crash's "maximum slip angle" of 10 degrees,
/// whose force `min(alpha / 10 deg, mu)` saturates at `mu x 10` degrees (7.6 on a 0.76 road):
/// a case gives that one as `max_slip_angle`.
pub const DEFAULT_SATURATION_ANGLE: f64 = 10.0 * std::f64::consts::PI / 180.0;

pub use crate::zones::MAX_FRICTION;

/// What one wheel does during the run-out.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum WheelState {
    /// Locked or sliding (also a wheel the impact damaged so that it cannot turn): Coulomb
    /// friction `mu Fz` against the sliding velocity of its contact patch.
    Locked,
    /// Free-rolling: rolling resistance along the wheel, the linear tyre across it.
    Rolling,
    /// Braked: this share (0 to 1) of the friction circle is used along the wheel against its
    /// rolling direction, the rest `sqrt(1 - share^2) mu Fz` is available across it.
    Braked(f64),
}

/// The four wheels, in the order front left, front right, rear left, rear right.
pub const WHEEL_NAMES: [&str; 4] = ["front_left", "front_right", "rear_left", "rear_right"];

/// A vehicle on its four wheels (SI units, angles in radians).
///
/// The body frame has x forward along the centreline and y to the left, its origin at the
/// centre of gravity (CG). The front axle is `cg_to_front_axle` ahead of the CG, the rear axle
/// `wheelbase - cg_to_front_axle` behind it, each wheel `track / 2` to its side.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Chassis {
    /// Mass, kg.
    pub mass: f64,
    /// Yaw moment of inertia about the CG, kg m^2.
    pub yaw_inertia: f64,
    /// Front axle to rear axle, m.
    pub wheelbase: f64,
    /// CG to the front axle, m (0 to `wheelbase`).
    pub cg_to_front_axle: f64,
    /// Distance between the left and right wheels of an axle, m.
    pub track: f64,
    /// Height of the CG above the road, m: with it the normal loads follow the acceleration
    /// (load transfer); without it they keep their static split.
    pub cg_height: Option<f64>,
    /// Front left, front right, rear left, rear right.
    pub wheels: [WheelState; 4],
    /// Steer angles of the front left and front right wheels, rad, positive to the left
    /// (counter-clockwise); [`ackermann`] gives them from one steer angle.
    pub steer: [f64; 2],
    /// Road friction coefficient under this vehicle.
    pub friction: f64,
    /// Rolling resistance of a rolling or braked wheel, a fraction of its load (> 0).
    pub rolling_resistance: f64,
    /// Slip angle at which a rolling wheel's lateral force reaches its limit, rad (0 to pi/2).
    /// The cornering stiffness per unit load is `friction / saturation_angle` per rad.
    pub saturation_angle: f64,
    /// Overall length, m, when known: the wheels must lie inside it.
    pub length: Option<f64>,
    /// Overall width, m, when known: the wheels must lie inside it.
    pub width: Option<f64>,
    /// CG to the front face, m, when known (default half the length).
    pub cg_to_front: Option<f64>,
    /// The driver's inputs after separation, in the order of their times (none: the wheels and
    /// steer above throughout).
    #[serde(default)]
    pub inputs: Vec<Input>,
    /// Areas of the ground with a friction of their own (none: the road's `friction`
    /// everywhere); each wheel runs on the friction under it ([`crate::zones`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub zones: Vec<crate::zones::Zone>,
}

/// A driver input from a time after separation on, as a PC-Crash sequence writes it: braking
/// shares per wheel (every wheel, an axle or one wheel; a locked wheel stays locked) and steer
/// angles for the front wheels, each reached linearly over `build_up` seconds from its value
/// when the input starts (a reaction time before the driver brakes is an input at that time).
/// A value the input does not give keeps what it was.
///
/// The inputs act in their order: each starts at its time `at`, or once the CG has travelled
/// `distance`, and never before the input before it. Each value is continuous in time and
/// piecewise linear; the run-out is integrated piece by piece between the times where its slope
/// changes (each input's start and the end of its build-up), so that the integrator never steps
/// across a kink of the inputs; the time a distance is reached is located within the step that
/// reaches it (on the cubic through the step's ends and their speeds), and the step integrated
/// again up to it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Input {
    /// When the input starts, s after separation (at least 0).
    pub at: f64,
    /// The braking share (0 to 1) of each wheel (front left, front right, rear left, rear
    /// right; none: that wheel keeps its share), as [`WheelState::Braked`]; a share 0 is a
    /// free-rolling wheel. A wheel locked at separation stays locked.
    pub braking: [Option<f64>; 4],
    /// The front left and front right wheels' steer angles, rad (as [`Chassis::steer`]).
    pub steer: Option<[f64; 2]>,
    /// Seconds over which the values move from where they were to the input's (0: at once).
    pub build_up: f64,
    /// Metres the CG has travelled along its path since separation when the input starts
    /// (PC-Crash's sequences by distance): the input then starts at the first time, from `at`
    /// and from the start of the input before it on, that the path's length reaches this.
    /// `None`: the input starts at `at` (or with the input before it, when that starts later).
    #[serde(default)]
    pub distance: Option<f64>,
}

impl Input {
    /// The same braking share on all four wheels (for [`Input::braking`]).
    pub const fn every_wheel(share: f64) -> [Option<f64>; 4] {
        [Some(share); 4]
    }

    /// Checks one input on its own (its order among the others is the chassis's check): the
    /// error names the key (`at`, `distance`, `build_up`, `braking`, `steer`) and says why.
    pub fn check(&self) -> std::result::Result<(), (&'static str, String)> {
        let half_pi = std::f64::consts::FRAC_PI_2;
        if !(self.at.is_finite() && self.at >= 0.0) {
            return Err(("at", format!("starts at {} s: must be at least 0", self.at)));
        }
        if let Some(d) = self.distance.filter(|d| !(d.is_finite() && *d >= 0.0)) {
            return Err((
                "distance",
                format!("starts after {d} m: must be at least 0"),
            ));
        }
        if !(self.build_up.is_finite() && self.build_up >= 0.0) {
            return Err((
                "build_up",
                format!("build-up {} s must be 0 or more", self.build_up),
            ));
        }
        if let Some(b) = self
            .braking
            .into_iter()
            .flatten()
            .find(|b| !(b.is_finite() && (0.0..=1.0).contains(b)))
        {
            return Err((
                "braking",
                format!("braking share {b} must lie between 0 and 1"),
            ));
        }
        if let Some(a) = self.steer.and_then(|s| {
            s.into_iter()
                .find(|a| !(a.is_finite() && a.abs() < half_pi))
        }) {
            return Err((
                "steer",
                format!(
                    "steer {} deg must lie between -90 and 90 deg",
                    a.to_degrees()
                ),
            ));
        }
        Ok(())
    }
}

impl Chassis {
    /// A vehicle with every wheel in `state`, the default road friction, rolling resistance and
    /// saturation angle, no CG height, no steer and no outline.
    pub fn new(
        mass: f64,
        yaw_inertia: f64,
        wheelbase: f64,
        cg_to_front_axle: f64,
        track: f64,
        state: WheelState,
    ) -> Self {
        Chassis {
            mass,
            yaw_inertia,
            wheelbase,
            cg_to_front_axle,
            track,
            cg_height: None,
            wheels: [state; 4],
            steer: [0.0; 2],
            friction: DEFAULT_FRICTION,
            rolling_resistance: DEFAULT_ROLLING_RESISTANCE,
            saturation_angle: DEFAULT_SATURATION_ANGLE,
            length: None,
            width: None,
            cg_to_front: None,
            inputs: Vec::new(),
            zones: Vec::new(),
        }
    }

    /// True when nothing stops the vehicle rolling straight on: a wheel rolls freely
    /// ([`WheelState::Rolling`]) and the rolling resistance is 0 (PC-Crash's free rolling). Its
    /// run-out is followed to the time limit, which is then its answer, not a failure.
    pub fn rolls_on(&self) -> bool {
        self.rolling_resistance <= 0.0 && self.wheels.contains(&WheelState::Rolling)
    }

    /// The wheel's position in the body frame (x forward, y left), m.
    pub fn wheel_position(&self, wheel: usize) -> [f64; 2] {
        let x = if wheel < 2 {
            self.cg_to_front_axle
        } else {
            self.cg_to_front_axle - self.wheelbase
        };
        let y = if wheel.is_multiple_of(2) {
            self.track / 2.0
        } else {
            -self.track / 2.0
        };
        [x, y]
    }

    /// The static normal loads, N: the axle loads from the moments about the CG, each split
    /// equally between its two wheels.
    pub fn static_loads(&self) -> [f64; 4] {
        let w = self.mass * GRAVITY;
        let front = w * (self.wheelbase - self.cg_to_front_axle) / self.wheelbase / 2.0;
        let rear = w * self.cg_to_front_axle / self.wheelbase / 2.0;
        [front, front, rear, rear]
    }

    /// Checks every field: finite, positive where it must be, of a road vehicle's size, the
    /// wheels inside the outline when the outline is known. The error names the field.
    pub fn check(&self) -> Result<()> {
        let positive = [
            ("mass", self.mass, 1e6),
            ("yaw_inertia", self.yaw_inertia, 2.5e8),
            ("wheelbase", self.wheelbase, 30.0),
            ("track", self.track, 5.0),
        ];
        for (field, x, max) in positive {
            if !(x.is_finite() && x > 0.0 && x <= max) {
                return bad(
                    field,
                    format!("{x}: must be a number above 0 and at most {max}"),
                );
            }
        }
        if !(self.cg_to_front_axle.is_finite()
            && self.cg_to_front_axle >= 0.0
            && self.cg_to_front_axle <= self.wheelbase)
        {
            return bad(
                "cg_to_front_axle",
                format!(
                    "{}: the CG must lie between the axles (0 to wheelbase = {} m)",
                    self.cg_to_front_axle, self.wheelbase
                ),
            );
        }
        if let Some(h) = self.cg_height {
            if !(h.is_finite() && h > 0.0 && h <= 5.0) {
                return bad("cg_height", format!("{h}: must be above 0 and at most 5 m"));
            }
        }
        if !(self.friction.is_finite() && self.friction > 0.0 && self.friction <= MAX_FRICTION) {
            return bad(
                "friction",
                format!(
                    "{}: must be above 0 and at most {MAX_FRICTION} (dry asphalt is about 0.7)",
                    self.friction
                ),
            );
        }
        if !(self.rolling_resistance.is_finite()
            && self.rolling_resistance >= 0.0
            && self.rolling_resistance < self.friction)
        {
            return bad(
                "rolling_resistance",
                format!(
                    "{}: must be at least 0 (free rolling) and below the friction {} (tyres roll \
                     at about 0.015)",
                    self.rolling_resistance, self.friction
                ),
            );
        }
        let half_pi = std::f64::consts::FRAC_PI_2;
        if !(self.saturation_angle.is_finite()
            && self.saturation_angle > 0.0
            && self.saturation_angle <= half_pi)
        {
            return bad(
                "saturation_angle",
                format!(
                    "{} deg: must be above 0 and at most 90 deg",
                    self.saturation_angle.to_degrees()
                ),
            );
        }
        for s in self.steer {
            if !(s.is_finite() && s.abs() < half_pi) {
                return bad(
                    "steer",
                    format!("{} deg: must lie between -90 and 90 deg", s.to_degrees()),
                );
            }
        }
        self.check_inputs()?;
        self.check_wheels_and_zones()?;
        self.check_outline()
    }

    /// The driver's inputs (each valid), their times in order unless some input starts by
    /// distance (each then starts no earlier than the one before it, whatever its time): the
    /// part of [`Chassis::check`] about the inputs.
    fn check_inputs(&self) -> Result<()> {
        let by_distance = self.inputs.iter().any(|i| i.distance.is_some());
        let mut last = 0.0;
        for (k, input) in self.inputs.iter().enumerate() {
            let order = input.at < last && !by_distance;
            if let Some((_, why)) = input.check().err().or_else(|| {
                order.then(|| {
                    (
                        "at",
                        format!("{} s: the inputs' times must be in order", input.at),
                    )
                })
            }) {
                return bad("inputs", format!("input {}: {why}", k + 1));
            }
            last = input.at;
        }
        Ok(())
    }

    /// The wheels inside the outline where it is known: the part of [`Chassis::check`] about
    /// the outline.
    fn check_outline(&self) -> Result<()> {
        if let Some(l) = self.length {
            let front = self.cg_to_front.unwrap_or(l / 2.0);
            if self.cg_to_front_axle > front || self.wheelbase - self.cg_to_front_axle > l - front {
                return bad(
                    "wheelbase",
                    format!(
                        "the wheels (front axle {:.3} m ahead of the CG, rear axle {:.3} m \
                         behind) lie outside the outline ({:.3} m ahead, {:.3} m behind): the \
                         wheelbase is longer than the vehicle",
                        self.cg_to_front_axle,
                        self.wheelbase - self.cg_to_front_axle,
                        front,
                        l - front
                    ),
                );
            }
        }
        if let Some(w) = self.width {
            if self.track > w {
                return bad(
                    "track",
                    format!(
                        "{} m is wider than the vehicle ({w} m): the wheels lie outside the \
                         outline",
                        self.track
                    ),
                );
            }
        }
        Ok(())
    }

    /// The wheels' braking shares (0 to 1) and the friction zones (each valid, its friction
    /// above the rolling resistance): the part of [`Chassis::check`] about the wheels' grip.
    fn check_wheels_and_zones(&self) -> Result<()> {
        for (k, z) in self.zones.iter().enumerate() {
            let why = z.check().err().or_else(|| {
                (z.friction <= self.rolling_resistance).then(|| {
                    let r = self.rolling_resistance;
                    (
                        "friction",
                        format!("{}: must be above the rolling resistance {r}", z.friction),
                    )
                })
            });
            if let Some((field, why)) = why {
                return bad("zones", format!("zone {}, {field}: {why}", k + 1));
            }
        }
        for (i, w) in self.wheels.iter().enumerate() {
            if let WheelState::Braked(b) = w {
                if !(b.is_finite() && (0.0..=1.0).contains(b)) {
                    return bad(
                        WHEEL_NAMES[i],
                        format!("braking share {b}: must lie between 0 and 1"),
                    );
                }
            }
        }
        Ok(())
    }
}

/// Where a vehicle is and how it moves, in a fixed (road) frame: x, y in m, heading in rad
/// counter-clockwise from +x (where the nose points; not wrapped, so that a run-out's turns
/// add up), velocities of the CG in m/s and the yaw rate in rad/s (counter-clockwise).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Motion {
    /// CG position along x, m.
    pub x: f64,
    /// CG position along y, m.
    pub y: f64,
    /// Heading, rad counter-clockwise from +x.
    pub heading: f64,
    /// CG velocity along x, m/s.
    pub vx: f64,
    /// CG velocity along y, m/s.
    pub vy: f64,
    /// Yaw rate, rad/s counter-clockwise.
    pub yaw_rate: f64,
}

impl Motion {
    /// Where the vehicle's point `at` (metres ahead of the CG and to its left: a tyre's contact
    /// point, say) lies in the fixed frame, m.
    pub fn point(&self, at: [f64; 2]) -> (f64, f64) {
        let (s, c) = self.heading.sin_cos();
        (
            self.x + c * at[0] - s * at[1],
            self.y + s * at[0] + c * at[1],
        )
    }

    /// Checks that every number is finite; the error names the field.
    pub fn check(&self) -> Result<()> {
        for (field, x) in [
            ("x", self.x),
            ("y", self.y),
            ("heading", self.heading),
            ("vx", self.vx),
            ("vy", self.vy),
            ("yaw_rate", self.yaw_rate),
        ] {
            if !x.is_finite() {
                return Err(RunoutError::Input {
                    field,
                    reason: format!("{x}: must be a finite number"),
                });
            }
        }
        Ok(())
    }
}

/// The front wheels' steer angles (left, right; rad, positive to the left) of Ackermann
/// geometry for the steer angle `delta` of a single wheel at the middle of the front axle (the
/// bicycle model: a steering-wheel angle over the steer ratio). Every wheel then rolls about
/// one centre on the rear axle's line, `R = wheelbase / tan delta` to the left of the middle:
/// `tan delta_left = wheelbase / (R - track / 2)`, `tan delta_right = wheelbase / (R + track /
/// 2)`, that is `tan delta_w = tan delta / (1 -+ tan delta x track / (2 wheelbase))`. The inner
/// wheel turns more. `None` when the inner wheel would turn 90 degrees or more (the centre
/// inside the track).
pub fn ackermann(delta: f64, wheelbase: f64, track: f64) -> Option<[f64; 2]> {
    let t = delta.tan();
    let k = t * track / (2.0 * wheelbase);
    let (left, right) = (1.0 - k, 1.0 + k);
    (left > 0.0 && right > 0.0 && t.is_finite()).then(|| [(t / left).atan(), (t / right).atan()])
}

/// A field of a chassis refused, with why.
fn bad(field: &'static str, reason: String) -> Result<()> {
    Err(RunoutError::Input { field, reason })
}
