//! The vehicles as drawn: outlines about the CG, and a barrier as a wall.

use pim_case::case::VehicleSection;
use pim_core::Impact;

/// A vehicle's plan-view outline as drawn: pim-core's outline about the CG, and whether its
/// dimensions are the case's or defaults for the mass class.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outline {
    /// The outline, m.
    pub body: pim_core::outline::Outline,
    /// True when the dimensions are defaults for the mass class, not the case's.
    pub defaulted: bool,
}

impl Outline {
    /// The case's outline, or the default of its mass class enlarged (if needed) to reach the
    /// impact centre at `point` (body frame, m).
    pub fn of(v: &VehicleSection, point: [f64; 2]) -> Self {
        let (body, defaulted) = v.outline();
        if !defaulted {
            return Outline { body, defaulted };
        }
        Outline {
            body: pim_core::outline::Outline {
                cg_to_front: body.cg_to_front.max(point[0]),
                cg_to_rear: body.cg_to_rear.max(-point[0]),
                width: body.width.max(2.0 * point[1].abs()),
            },
            defaulted,
        }
    }

    /// Corners in the body frame, counter-clockwise from front left.
    pub(super) fn corners(&self) -> [[f64; 2]; 4] {
        self.body.corners()
    }

    /// Distance from the CG to the outline along the body-frame unit direction `w`.
    pub(super) fn exit(&self, w: [f64; 2]) -> f64 {
        self.body.exit_along(w)
    }

    /// Length, m.
    pub fn length(&self) -> f64 {
        self.body.length()
    }

    /// Overall width, m.
    pub fn width(&self) -> f64 {
        self.body.width
    }
}

/// What is drawn for one vehicle.
#[derive(Debug, Clone)]
pub struct DrawnVehicle {
    /// Label, e.g. `vehicle 1 (striking car)`.
    pub label: String,
    /// Its outline.
    pub outline: Outline,
    /// Nose direction, degrees counter-clockwise from +x.
    pub heading: f64,
    /// CG position (C at the origin), m.
    pub cg: [f64; 2],
    /// CG velocity at contact, m/s.
    pub contact: Option<[f64; 2]>,
    /// CG velocity at separation, m/s.
    pub separation: Option<[f64; 2]>,
    /// Yaw rate at separation, rad/s (counter-clockwise positive), when solved.
    pub yaw_separation: Option<f64>,
    /// Impulse on this vehicle, N s.
    pub impulse: Option<[f64; 2]>,
    /// Delta-V direction (fixed frame, unit) with PDOF and clock, when solved.
    pub pdof: Option<([f64; 2], f64, u8)>,
    /// A fixed barrier: drawn as a wall along the crush surface, its face through C.
    pub barrier: bool,
}

/// A barrier as a wall: its face on the crush surface through C, 0.3 m thick on the side away
/// from vehicle 1's CG, as long as 1.2 times vehicle 1.
pub(super) fn barrier_wall(impact: &Impact, vehicle1: &DrawnVehicle) -> DrawnVehicle {
    let n = impact.normal();
    let cg1 = vehicle1.cg;
    // Unit normal towards vehicle 1's side.
    let towards = if cg1[0] * n[0] + cg1[1] * n[1] >= 0.0 {
        n
    } else {
        [-n[0], -n[1]]
    };
    let thick = 0.3;
    let length = 1.2 * vehicle1.outline.length();
    DrawnVehicle {
        label: "barrier (fixed, rigid)".to_string(),
        outline: Outline {
            body: pim_core::outline::Outline {
                cg_to_front: thick / 2.0,
                cg_to_rear: thick / 2.0,
                width: length,
            },
            defaulted: false,
        },
        heading: towards[1].atan2(towards[0]).to_degrees(),
        cg: [-towards[0] * thick / 2.0, -towards[1] * thick / 2.0],
        contact: None,
        separation: None,
        yaw_separation: None,
        impulse: None,
        pdof: None,
        barrier: true,
    }
}

pub(super) fn rotate(p: [f64; 2], deg: f64) -> [f64; 2] {
    let (s, c) = deg.to_radians().sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}
