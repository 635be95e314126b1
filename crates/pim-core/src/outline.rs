//! Impact-centre distance from vehicle dimensions and crush: a documented geometric rule.
//!
//! When no published distance d from the CG to the impact centre C exists, it is derived from
//! the vehicle outline and the residual crush:
//!
//! 1. The outline is the rectangle `-cg_to_rear <= x <= cg_to_front`, `|y| <= width / 2` in the
//!    vehicle's body frame (x forward, y to the left, origin at the CG).
//! 2. The impact centre lies on the ray from the CG at angle phi from the forward axis
//!    (counter-clockwise positive). This is the papers' convention: C sits at
//!    `d (cos phi, sin phi)` in the body frame of either vehicle, the forward direction of
//!    vehicle 1 being `theta1 + 180 deg` and that of vehicle 2 `theta2` (see the crate docs:
//!    `r1 = -(D4, D3)`, `r2 = (D2, D1)`).
//! 3. The damaged face is the face through which that ray leaves the undeformed outline; it is
//!    moved inwards by the mean of the crush depths C1..C6 measured on it.
//! 4. d is the distance from the CG to where the ray leaves the deformed outline.
//!
//! Checked against Brach 1984 Table 2 (RICSAC 6, d = 2.56 / 0.61 m): the rule gives 2.60 / 0.53 m.

use serde::{Deserialize, Serialize};

/// The plan-view outline of a vehicle about its CG, m.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Outline {
    /// Distance from the CG to the front face, m.
    pub cg_to_front: f64,
    /// Distance from the CG to the rear face, m.
    pub cg_to_rear: f64,
    /// Overall width, m.
    pub width: f64,
}

/// A face of the outline.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Face {
    /// The front.
    Front,
    /// The rear.
    Rear,
    /// The left side.
    Left,
    /// The right side.
    Right,
}

/// Typical length and width of a passenger vehicle of this mass, m (small car, compact,
/// mid-size, full-size / light truck): for a drawing or a plausibility check when the case gives
/// no dimensions.
pub fn typical_dimensions(mass: f64) -> (f64, f64) {
    match mass {
        m if m < 1100.0 => (3.9, 1.65),
        m if m < 1500.0 => (4.4, 1.75),
        m if m < 2000.0 => (4.85, 1.85),
        _ => (5.3, 2.0),
    }
}

impl Outline {
    /// Overall length, m.
    pub fn length(&self) -> f64 {
        self.cg_to_front + self.cg_to_rear
    }

    /// Corners in the body frame (x forward, y to the left, m), counter-clockwise from the
    /// front left.
    pub fn corners(&self) -> [[f64; 2]; 4] {
        let h = self.width / 2.0;
        [
            [self.cg_to_front, h],
            [-self.cg_to_rear, h],
            [-self.cg_to_rear, -h],
            [self.cg_to_front, -h],
        ]
    }

    /// Distance from the CG to where the ray along the body-frame unit direction `w` leaves
    /// the outline, m.
    pub fn exit_along(&self, w: [f64; 2]) -> f64 {
        exit_dir(w[0], w[1], self.faces()).0
    }

    /// Distances from the CG to the front, rear, left and right faces.
    fn faces(&self) -> [f64; 4] {
        let half = self.width / 2.0;
        [self.cg_to_front, self.cg_to_rear, half, half]
    }
}

/// Where the ray at angle `phi_deg` leaves a rectangle whose faces are at the given distances
/// (front, rear, left, right; all > 0): (distance, face).
fn exit(phi_deg: f64, faces: [f64; 4]) -> (f64, Face) {
    let (s, c) = phi_deg.to_radians().sin_cos();
    exit_dir(c, s, faces)
}

/// Where the ray along the unit direction `(c, s)` leaves the rectangle: (distance, face).
fn exit_dir(c: f64, s: f64, faces: [f64; 4]) -> (f64, Face) {
    let mut best = (f64::INFINITY, Face::Front);
    for (dist, comp, face) in [
        (faces[0], c, Face::Front),
        (faces[1], -c, Face::Rear),
        (faces[2], s, Face::Left),
        (faces[3], -s, Face::Right),
    ] {
        if comp > 1e-12 {
            let t = dist / comp;
            if t < best.0 {
                best = (t, face);
            }
        }
    }
    best
}

/// The damaged face hit by the ray at `phi_deg` (degrees, from the forward axis, to the left
/// positive) on the undeformed outline.
pub fn damaged_face(outline: &Outline, phi_deg: f64) -> Face {
    exit(phi_deg, outline.faces()).1
}

/// Distance d from the CG to the impact centre, m, by the rule of this module: the ray at
/// `phi_deg` meets the outline whose damaged face is moved in by `mean_crush` (m).
pub fn impact_centre_distance(outline: &Outline, phi_deg: f64, mean_crush: f64) -> (f64, Face) {
    let mut faces = outline.faces();
    let face = damaged_face(outline, phi_deg);
    let k = match face {
        Face::Front => 0,
        Face::Rear => 1,
        Face::Left => 2,
        Face::Right => 3,
    };
    faces[k] = (faces[k] - mean_crush).max(0.0);
    (exit(phi_deg, faces).0, face)
}
