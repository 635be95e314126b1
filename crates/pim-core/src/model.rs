//! The inputs of the model: vehicles, collision geometry, coefficients and velocity states.

use crate::error::{PimError, Result, VehicleId};
use crate::friction::FrictionSign;
use nalgebra::Vector6;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// One vehicle: its inertial properties and where the impact centre C sits on it.
///
/// Vehicle 2 may be a fixed rigid barrier ([`Vehicle::barrier`]): infinite mass and yaw inertia,
/// at rest before and after the impact. The equations then take their limits as vehicle 2's
/// mass and inertia grow without bound (see [`crate::equations`]): vehicle 2 does not move, the
/// impulse acts on vehicle 1 alone, and momentum is not conserved (the ground takes it).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Vehicle {
    /// Mass m, kg (> 0; infinite for a barrier).
    pub mass: f64,
    /// Yaw moment of inertia I about the vertical axis through the CG, kg m^2 (> 0; infinite
    /// for a barrier).
    pub yaw_inertia: f64,
    /// Heading angle theta of the vehicle's length axis to the fixed x axis, degrees.
    pub heading: f64,
    /// Distance d from the CG to the impact centre C, m (>= 0).
    pub d: f64,
    /// Angle phi between the length axis and the line from the CG to C, degrees.
    pub phi: f64,
}

/// A two-vehicle impact configuration: both vehicles and the crush surface.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, JsonSchema)]
pub struct Collision {
    /// Vehicle 1 (the papers' vehicle A).
    pub vehicle1: Vehicle,
    /// Vehicle 2 (the papers' vehicle B).
    pub vehicle2: Vehicle,
    /// Angle Gamma of the crush surface to the fixed y axis, degrees.
    pub crush_angle: f64,
}

/// A checked [`Collision`] with the geometric quantities of the equations precomputed.
///
/// Names follow the 1983 BASIC listing: `D1 = d2 sin(theta2 + phi2)`, `D2 = d2 cos(theta2 + phi2)`,
/// `D3 = d1 sin(theta1 + phi1)`, `D4 = d1 cos(theta1 + phi1)`. The impact centre C sits at
/// `r1 = -(D4, D3)` from the CG of vehicle 1 and at `r2 = (D2, D1)` from the CG of vehicle 2.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impact {
    collision: Collision,
    /// `[D1, D2, D3, D4]`, m.
    d: [f64; 4],
    /// Unit normal of the crush surface, `(cos Gamma, sin Gamma)`.
    n: [f64; 2],
    /// Unit tangent of the crush surface, `(-sin Gamma, cos Gamma)`.
    t: [f64; 2],
    /// +1 when vehicle 1's CG lies on the +n side of vehicle 2's CG, -1 on the -n side, 0 if undecided.
    pub(crate) side: f64,
    /// What the side rests on.
    pub(crate) side_basis: SideBasis,
    /// Heights of the two CGs above the crush plane through C, along n, m.
    heights: [f64; 2],
    /// Unit forward (nose) axes of vehicle 1 and 2 in the fixed frame.
    axes: [[f64; 2]; 2],
}

/// What the side of the crush surface each vehicle is on ([`Impact::side`]) rests on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum SideBasis {
    /// The two CGs lie on opposite sides of the crush plane: the geometry decides.
    Geometry,
    /// Both CGs lie on one side of the crush plane (or one on it): the side is read from their
    /// heights weighted by mobility, `sgn(m2 h1 - m1 h2)`, a choice rather than a fact.
    Mobility,
    /// The case states it ([`Impact::with_side`]).
    Case,
    /// Both CGs lie on one side of the crush plane, and the side is the one under which the
    /// case's contact-velocity estimates approach at C (under the other they would separate):
    /// [`Impact::with_side_from_velocities`].
    Velocities,
}

impl Vehicle {
    /// A fixed rigid barrier as vehicle 2: infinite mass and yaw inertia, its "centre" at the
    /// impact centre (`d = 0`), heading 0. Only the crush-surface angle orients it.
    pub fn barrier() -> Self {
        Vehicle {
            mass: f64::INFINITY,
            yaw_inertia: f64::INFINITY,
            heading: 0.0,
            d: 0.0,
            phi: 0.0,
        }
    }

    /// True for a barrier (infinite mass).
    pub fn is_barrier(&self) -> bool {
        self.mass == f64::INFINITY
    }
}

fn check_vehicle(v: &Vehicle, id: VehicleId) -> Result<()> {
    if id == VehicleId::Two && (v.mass == f64::INFINITY || v.yaw_inertia == f64::INFINITY) {
        if !(v.mass.is_infinite() && v.yaw_inertia.is_infinite()) {
            return Err(PimError::Barrier(
                "a barrier (vehicle 2) needs both mass and yaw inertia infinite".into(),
            ));
        }
        let finite = Vehicle {
            mass: 1.0,
            yaw_inertia: 1.0,
            ..*v
        };
        return check_vehicle(&finite, id);
    }
    for (field, value) in [
        ("mass", v.mass),
        ("yaw_inertia", v.yaw_inertia),
        ("heading", v.heading),
        ("d", v.d),
        ("phi", v.phi),
    ] {
        if !value.is_finite() {
            return Err(PimError::NonFinite {
                vehicle: id,
                field,
                value,
            });
        }
    }
    for (field, value) in [("mass", v.mass), ("yaw_inertia", v.yaw_inertia)] {
        if value <= 0.0 {
            return Err(PimError::NotPositive {
                vehicle: id,
                field,
                value,
            });
        }
    }
    if v.d < 0.0 {
        return Err(PimError::NegativeDistance {
            vehicle: id,
            value: v.d,
        });
    }
    for (field, value, limit, unit) in [
        ("mass", v.mass, MAX_MASS, "kg"),
        ("yaw_inertia", v.yaw_inertia, MAX_INERTIA, "kg m^2"),
        ("d", v.d, MAX_DISTANCE, "m"),
        ("heading", v.heading.abs(), MAX_ANGLE, "deg"),
        ("phi", v.phi.abs(), MAX_ANGLE, "deg"),
    ] {
        if value > limit {
            return Err(PimError::Implausible {
                what: format!("{id}.{field}"),
                value,
                limit,
                unit,
            });
        }
    }
    Ok(())
}

/// An angle in degrees brought into (-180, 180].
pub fn wrap_degrees(a: f64) -> f64 {
    let r = a.rem_euclid(360.0);
    if r > 180.0 {
        r - 360.0
    } else {
        r
    }
}

/// How a case gives the vehicles' headings.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Convention {
    /// Both headings are the direction the nose points (counter-clockwise from +x, degrees),
    /// as in scene diagrams and simulation programs. The default.
    #[default]
    Natural,
    /// The papers' form (Brach 1983, 1984; the RICSAC tables): vehicle 1's heading theta1 is the
    /// direction of its tail, its nose points along theta1 + 180 deg; vehicle 2's heading is its
    /// nose.
    Brach,
    /// SAE J670, the frame of US reconstruction and of EDR data: x forward, y to the right,
    /// angles and yaw rates clockwise (seen from above). A case written so is mirrored into the
    /// natural form when it is read (`y`, headings, angles and yaw rates change sign); its
    /// headings are where the noses point.
    Sae,
}

impl Convention {
    /// The heading theta of [`Vehicle::heading`] (the papers' form) for a heading written in
    /// this convention.
    pub fn theta(self, id: VehicleId, heading: f64) -> f64 {
        match (self, id) {
            (Convention::Natural, VehicleId::One) => wrap_degrees(heading + 180.0),
            (Convention::Sae, VehicleId::One) => wrap_degrees(180.0 - heading),
            (Convention::Sae, VehicleId::Two) => wrap_degrees(-heading),
            _ => heading,
        }
    }

    /// The direction a vehicle's nose points, degrees in the case's own frame, for a heading
    /// written in this convention (the papers' form gives vehicle 1's tail).
    pub fn nose(self, id: VehicleId, heading: f64) -> f64 {
        match (self, id) {
            (Convention::Brach, VehicleId::One) => wrap_degrees(heading + 180.0),
            _ => heading,
        }
    }

    /// The other reading of vehicle 1's heading (nose or tail): natural and SAE read the nose,
    /// the papers' form the tail.
    pub fn other(self) -> Self {
        match self {
            Convention::Natural | Convention::Sae => Convention::Brach,
            Convention::Brach => Convention::Natural,
        }
    }

    /// The name used in case files: `natural`, `brach` or `sae`.
    pub fn name(self) -> &'static str {
        match self {
            Convention::Natural => "natural",
            Convention::Brach => "brach",
            Convention::Sae => "sae",
        }
    }
}

/// The polar form `(d, phi)` (m, degrees) of an impact centre given in the vehicle's own frame
/// (`x` forward, `y` to the left, m from the CG).
pub fn impact_point_polar(x: f64, y: f64) -> (f64, f64) {
    (x.hypot(y), y.atan2(x).to_degrees())
}

/// The impact centre `(x, y)` in the vehicle's own frame (m, `x` forward, `y` to the left) of
/// its polar form `(d, phi)` (m, degrees from the nose): the inverse of [`impact_point_polar`].
///
/// ```
/// use pim_core::{impact_point_cartesian, impact_point_polar};
/// let (x, y) = impact_point_cartesian(2.0, 30.0);
/// assert!((x - 3f64.sqrt()).abs() < 1e-12 && (y - 1.0).abs() < 1e-12);
/// let (d, phi) = impact_point_polar(x, y);
/// assert!((d - 2.0).abs() < 1e-12 && (phi - 30.0).abs() < 1e-12);
/// ```
pub fn impact_point_cartesian(d: f64, phi: f64) -> (f64, f64) {
    let (s, c) = phi.to_radians().sin_cos();
    (d * c, d * s)
}

/// Relative size of the tangential relative velocity at contact below which the vehicles are
/// taken not to slide (round-off of the contact-point speeds, e.g. `cos 90 deg` = 6e-17).
pub const NO_SLIDING_TOL: f64 = 1e-9;

/// Largest mass accepted, kg (far above any road vehicle; keeps the arithmetic finite).
pub const MAX_MASS: f64 = 1e7;
/// Largest yaw inertia accepted, kg m^2.
pub const MAX_INERTIA: f64 = 1e10;
/// Largest distance from the CG to the impact centre accepted, m.
pub const MAX_DISTANCE: f64 = 1e3;
/// Largest |angle| accepted, degrees.
pub const MAX_ANGLE: f64 = 1e6;
/// Largest |velocity component| accepted, m/s.
pub const MAX_SPEED: f64 = 1e4;
/// Largest |yaw rate| accepted, rad/s.
pub const MAX_YAW_RATE: f64 = 1e4;

impl Impact {
    /// Checks a collision (finite numbers, positive mass and inertia, non-negative d) and
    /// precomputes its geometry.
    pub fn new(collision: Collision) -> Result<Self> {
        check_vehicle(&collision.vehicle1, VehicleId::One)?;
        check_vehicle(&collision.vehicle2, VehicleId::Two)?;
        if !collision.crush_angle.is_finite() {
            return Err(PimError::NonFiniteValue {
                field: "impact.crush_angle",
                value: collision.crush_angle,
            });
        }
        if collision.crush_angle.abs() > MAX_ANGLE {
            return Err(PimError::Implausible {
                what: "impact.crush_angle".to_string(),
                value: collision.crush_angle,
                limit: MAX_ANGLE,
                unit: "deg",
            });
        }
        let v1 = &collision.vehicle1;
        let v2 = &collision.vehicle2;
        let a1 = (v1.heading + v1.phi).to_radians();
        let a2 = (v2.heading + v2.phi).to_radians();
        let d = [
            v2.d * a2.sin(),
            v2.d * a2.cos(),
            v1.d * a1.sin(),
            v1.d * a1.cos(),
        ];
        let g = collision.crush_angle.to_radians();
        let (sg, cg) = g.sin_cos();
        let n = [cg, sg];
        let t = [-sg, cg];
        // CG of vehicle 1 relative to C is -r1 = (D4, D3); CG of vehicle 2 is -r2 = -(D2, D1).
        // Each CG's distance from the crush plane votes for the side, weighted by the vehicle's
        // mobility 1/m: equal masses compare the two CGs, and a barrier (infinite mass, no CG)
        // is the limit of an ever heavier vehicle 2, so both read the same.
        let [m1, m2] = [v1.mass, v2.mass];
        let h1 = d[3] * n[0] + d[2] * n[1];
        let h2 = -(d[1] * n[0] + d[0] * n[1]);
        let (w1, w2) = if m2.is_infinite() {
            (1.0, 0.0)
        } else {
            (m2 / (m1 + m2), m1 / (m1 + m2))
        };
        let sep = w1 * h1 - w2 * h2;
        let scale = w1 * v1.d + w2 * v2.d;
        let side = if scale > 0.0 && sep.abs() > 1e-9 * scale {
            sep.signum()
        } else {
            0.0
        };
        // Opposite sides (vehicle 2's height has the other sign) decide by geometry alone; a
        // barrier has no CG, its face is the plane.
        let tiny = 1e-9 * (v1.d + if m2.is_infinite() { 0.0 } else { v2.d }).max(1e-9);
        let opposite = if m2.is_infinite() {
            h1.abs() > tiny
        } else {
            h1 * h2 < 0.0 && h1.abs() > tiny && h2.abs() > tiny
        };
        let side_basis = if opposite {
            SideBasis::Geometry
        } else {
            SideBasis::Mobility
        };
        let (s1, c1) = v1.heading.to_radians().sin_cos();
        let (s2, c2) = v2.heading.to_radians().sin_cos();
        Ok(Impact {
            collision,
            d,
            n,
            t,
            side,
            side_basis,
            heights: [h1, if m2.is_infinite() { 0.0 } else { h2 }],
            axes: [[-c1, -s1], [c2, s2]],
        })
    }

    /// The collision this geometry was built from.
    pub fn collision(&self) -> &Collision {
        &self.collision
    }

    /// True when vehicle 2 is a fixed rigid barrier ([`Vehicle::barrier`]).
    pub fn is_barrier(&self) -> bool {
        self.collision.vehicle2.is_barrier()
    }

    /// Checks that a barrier's velocities are zero in a state (always true without a barrier).
    pub fn check_barrier_state(&self, v: &Velocities) -> Result<()> {
        let b = &v.vehicle2;
        if self.is_barrier() && (b.vx != 0.0 || b.vy != 0.0 || b.omega != 0.0) {
            return Err(PimError::Barrier(format!(
                "vehicle 2 is a fixed barrier: its velocities must be 0 (got vx = {}, vy = {}, \
                 omega = {})",
                b.vx, b.vy, b.omega
            )));
        }
        Ok(())
    }

    /// Masses `[m1, m2]`, kg.
    pub fn masses(&self) -> [f64; 2] {
        [self.collision.vehicle1.mass, self.collision.vehicle2.mass]
    }

    /// Yaw inertias `[I1, I2]`, kg m^2.
    pub fn inertias(&self) -> [f64; 2] {
        [
            self.collision.vehicle1.yaw_inertia,
            self.collision.vehicle2.yaw_inertia,
        ]
    }

    /// The lever terms `[D1, D2, D3, D4]` of the 1983 listing, m.
    pub fn levers(&self) -> [f64; 4] {
        self.d
    }

    /// Unit normal n = (cos Gamma, sin Gamma) of the crush surface.
    pub fn normal(&self) -> [f64; 2] {
        self.n
    }

    /// Unit tangent t = (-sin Gamma, cos Gamma) of the crush surface.
    pub fn tangent(&self) -> [f64; 2] {
        self.t
    }

    /// Position of the impact centre relative to each vehicle's CG, m: `[r1, r2]`.
    pub fn lever_arms(&self) -> [[f64; 2]; 2] {
        let [d1, d2, d3, d4] = self.d;
        [[-d4, -d3], [d2, d1]]
    }

    /// The direction the vehicle's nose points, degrees counter-clockwise from the fixed x axis,
    /// in (-180, 180]. In the papers' convention of [`Vehicle::heading`] vehicle 2's nose points
    /// along theta2 and vehicle 1's along theta1 + 180 deg (theta1 is the direction of its tail).
    pub fn nose_heading(&self, id: VehicleId) -> f64 {
        let c = &self.collision;
        match id {
            VehicleId::One => wrap_degrees(c.vehicle1.heading + 180.0),
            VehicleId::Two => wrap_degrees(c.vehicle2.heading),
        }
    }

    /// Unit vector of the vehicle's forward (nose) direction in the fixed frame.
    pub fn forward_axis(&self, id: VehicleId) -> [f64; 2] {
        self.axes[id.index()]
    }

    /// A fixed-frame vector in the vehicle's own axes: `(forward, left)` components.
    pub fn to_body(&self, id: VehicleId, v: [f64; 2]) -> [f64; 2] {
        let f = self.forward_axis(id);
        [v[0] * f[0] + v[1] * f[1], -v[0] * f[1] + v[1] * f[0]]
    }

    /// Positions of the two CGs in the fixed frame with the impact centre C at the origin, m:
    /// `[-r1, -r2]`.
    pub fn cg_positions(&self) -> [[f64; 2]; 2] {
        let [r1, r2] = self.lever_arms();
        [[-r1[0], -r1[1]], [-r2[0], -r2[1]]]
    }

    /// Which side of the crush surface vehicle 1 is on: +1 on the +n side, -1 on the -n side, 0
    /// when the geometry does not say. Decided by the heights `h1`, `h2` of the two CGs above the
    /// crush plane through C (along n), weighted by each vehicle's mobility:
    /// `sgn(m2 h1 - m1 h2)`. With equal masses that is "vehicle 1's CG on the +n side of vehicle
    /// 2's"; against a barrier (infinite mass) it is `sgn(h1)`, the limit of an ever heavier
    /// vehicle 2, so a barrier and a very heavy vehicle read the same.
    ///
    /// The vehicles approach at C when the normal relative velocity `vn` has the opposite sign.
    pub fn side(&self) -> f64 {
        self.side
    }

    /// What [`Impact::side`] rests on: the geometry (the CGs on opposite sides of the crush
    /// plane), the mobility-weighted reading (both on one side), or the case.
    pub fn side_basis(&self) -> SideBasis {
        self.side_basis
    }

    /// Heights of vehicle 1's and vehicle 2's CG above the crush plane through C, along n, m
    /// (0 for a barrier).
    pub fn cg_heights(&self) -> [f64; 2] {
        self.heights
    }

    /// Velocity of each vehicle's material point at C, m/s: `[(x, y) of vehicle 1, of vehicle 2]`.
    pub fn contact_point_velocities(&self, v: &Velocities) -> [[f64; 2]; 2] {
        let [d1, d2, d3, d4] = self.d;
        let a = &v.vehicle1;
        let b = &v.vehicle2;
        [
            [a.vx + d3 * a.omega, a.vy - d4 * a.omega],
            [b.vx - d1 * b.omega, b.vy + d2 * b.omega],
        ]
    }

    /// Relative velocity at C (vehicle 1 minus vehicle 2) along n and t: `(vn, vt)`, m/s.
    pub fn relative_velocity(&self, v: &Velocities) -> (f64, f64) {
        self.relative_of(self.contact_point_velocities(v))
    }

    /// `(vn, vt)` of the material-point velocities at C of both vehicles.
    fn relative_of(&self, [p1, p2]: [[f64; 2]; 2]) -> (f64, f64) {
        let rx = p1[0] - p2[0];
        let ry = p1[1] - p2[1];
        (
            rx * self.n[0] + ry * self.n[1],
            rx * self.t[0] + ry * self.t[1],
        )
    }

    /// Checks that the vehicles approach each other at C in the state `v` (contact velocities),
    /// and that a barrier is at rest in it.
    pub fn check_approach(&self, v: &Velocities) -> Result<()> {
        self.check_barrier_state(v)?;
        let (vn, _) = self.relative_velocity(v);
        let speed = v.max_speed().max(1e-9);
        let closing = if self.side != 0.0 {
            -vn * self.side
        } else {
            vn.abs()
        };
        if closing > 1e-12 * speed {
            Ok(())
        } else {
            Err(PimError::NotApproaching {
                normal_velocity: vn,
                direction: if closing.abs() <= 1e-12 * speed {
                    "they move parallel to the crush surface"
                } else {
                    "they move apart"
                },
            })
        }
    }

    /// The sliding direction `sgn(vn) sgn(vt)` of the contact state `v`, or `None` when the
    /// contact point does not slide at contact: `|vt|` is round-off of the contact-point speeds
    /// (at most [`NO_SLIDING_TOL`] of their largest component). The sign factor of equation 5
    /// is this where it is defined and the direction of the no-slip impulse where it is not
    /// ([`crate::friction_direction`], [`crate::contact_friction`]).
    pub fn sliding_sign(&self, v: &Velocities) -> Option<FrictionSign> {
        let points = self.contact_point_velocities(v);
        let (vn, vt) = self.relative_of(points);
        let [p1, p2] = points;
        let scale = p1[0]
            .abs()
            .max(p1[1].abs())
            .max(p2[0].abs())
            .max(p2[1].abs());
        if vt.abs() <= NO_SLIDING_TOL * scale {
            None
        } else {
            FrictionSign::of(vn, vt)
        }
    }
}

/// Velocity of one vehicle: CG velocity components and yaw rate.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
pub struct VehicleVelocity {
    /// CG velocity along the fixed x axis, m/s.
    pub vx: f64,
    /// CG velocity along the fixed y axis, m/s.
    pub vy: f64,
    /// Yaw rate (angular velocity, counter-clockwise positive), rad/s.
    pub omega: f64,
}

impl VehicleVelocity {
    /// Speed of the CG, m/s.
    pub fn speed(&self) -> f64 {
        (self.vx * self.vx + self.vy * self.vy).sqrt()
    }
}

/// The velocities of both vehicles at one instant (contact or separation).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, JsonSchema)]
pub struct Velocities {
    /// Vehicle 1.
    pub vehicle1: VehicleVelocity,
    /// Vehicle 2.
    pub vehicle2: VehicleVelocity,
}

impl Velocities {
    /// The state as `(v1x, v1y, w1, v2x, v2y, w2)`.
    pub fn to_vector(&self) -> Vector6<f64> {
        Vector6::new(
            self.vehicle1.vx,
            self.vehicle1.vy,
            self.vehicle1.omega,
            self.vehicle2.vx,
            self.vehicle2.vy,
            self.vehicle2.omega,
        )
    }

    /// The state from `(v1x, v1y, w1, v2x, v2y, w2)`.
    pub fn from_vector(x: &Vector6<f64>) -> Self {
        Velocities {
            vehicle1: VehicleVelocity {
                vx: x[0],
                vy: x[1],
                omega: x[2],
            },
            vehicle2: VehicleVelocity {
                vx: x[3],
                vy: x[4],
                omega: x[5],
            },
        }
    }

    /// The vehicle's velocity by id.
    pub fn vehicle(&self, id: VehicleId) -> &VehicleVelocity {
        match id {
            VehicleId::One => &self.vehicle1,
            VehicleId::Two => &self.vehicle2,
        }
    }

    /// Largest CG speed of the two vehicles, m/s (a scale for tolerances).
    pub fn max_speed(&self) -> f64 {
        self.vehicle1.speed().max(self.vehicle2.speed())
    }

    /// Checks that every component is finite and of plausible size.
    pub fn validate(&self) -> Result<()> {
        for (id, v) in [
            (VehicleId::One, &self.vehicle1),
            (VehicleId::Two, &self.vehicle2),
        ] {
            for (field, value) in [("vx", v.vx), ("vy", v.vy), ("omega", v.omega)] {
                if !value.is_finite() {
                    return Err(PimError::NonFinite {
                        vehicle: id,
                        field,
                        value,
                    });
                }
                let (limit, unit) = if field == "omega" {
                    (MAX_YAW_RATE, "rad/s")
                } else {
                    (MAX_SPEED, "m/s")
                };
                if value.abs() > limit {
                    return Err(PimError::Implausible {
                        what: format!("{id}.{field}"),
                        value,
                        limit,
                        unit,
                    });
                }
            }
        }
        Ok(())
    }

    /// Total kinetic energy of both vehicles in this state, J (of vehicle 1 alone against a
    /// barrier, which does not move).
    pub fn kinetic_energy(&self, impact: &Impact) -> f64 {
        let [m1, m2] = impact.masses();
        let [i1, i2] = impact.inertias();
        let a = &self.vehicle1;
        let b = &self.vehicle2;
        let first = m1 * (a.vx * a.vx + a.vy * a.vy) + i1 * a.omega * a.omega;
        if impact.is_barrier() {
            return 0.5 * first;
        }
        0.5 * (first + m2 * (b.vx * b.vx + b.vy * b.vy) + i2 * b.omega * b.omega)
    }
}
