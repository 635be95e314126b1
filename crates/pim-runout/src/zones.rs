//! Friction zones: areas of the ground with a friction of their own (a parking lot, a verge,
//! gravel, a wet patch), each wheel running on the friction under its contact patch.
//!
//! A zone is a polygon in the fixed frame. The friction at a point is the road's (the chassis's
//! [`friction`](crate::Chassis::friction)) changed by each zone in the order given, a later zone
//! over an earlier one where they overlap:
//! ```text
//! mu(p) = mu_road;   for each zone z:  mu(p) += w_z(p) (mu_z - mu(p))
//! w_z(p) = clamp(1/2 + d_z(p) / EDGE, 0, 1)
//! ```
//! with `d_z(p)` the signed distance of `p` from the zone's boundary (positive inside). A
//! contact patch straddling an edge grips with each surface in proportion to its length on
//! it: `w_z` is exactly that share for a patch [`EDGE`] long crossing the edge square on, so
//! the friction of a wheel changes linearly over the patch's length as it crosses, and the
//! forces stay continuous in the state (the integrator follows a wheel across an edge without
//! a jump to locate). The work a sliding wheel does across an edge is the same as with a
//! sharp edge: the change is symmetric about it.

use serde::{Deserialize, Serialize};

/// Highest friction accepted, of the road or a zone (a coefficient beyond it is a typing error,
/// not a road).
pub const MAX_FRICTION: f64 = 1.5;

/// The length of a tyre's contact patch over which its friction changes from one surface to
/// the next, m: 0.2 m (a passenger car tyre's patch is 0.12 to 0.2 m long).
pub const EDGE: f64 = 0.2;

/// An area of the ground with a friction of its own.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Zone {
    /// The polygon's corners in order (either sense), m, in the fixed frame: at least three,
    /// the last joined to the first.
    pub corners: Vec<[f64; 2]>,
    /// Its friction coefficient.
    pub friction: f64,
}

impl Zone {
    /// The signed distance of `p` from the boundary, m: positive inside, negative outside
    /// (inside by the even-odd rule, so a polygon that crosses itself has holes).
    pub fn signed_distance(&self, p: [f64; 2]) -> f64 {
        let n = self.corners.len();
        let mut nearest = f64::INFINITY;
        let mut inside = false;
        for i in 0..n {
            let a = self.corners[i];
            let b = self.corners[(i + 1) % n];
            nearest = nearest.min(segment_distance(p, a, b));
            if (a[1] > p[1]) != (b[1] > p[1]) {
                let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
                if p[0] < x {
                    inside = !inside;
                }
            }
        }
        if inside {
            nearest
        } else {
            -nearest
        }
    }

    /// The share of a contact patch at `p` that lies on the zone (0 to 1, see the module docs).
    pub fn share(&self, p: [f64; 2]) -> f64 {
        (0.5 + self.signed_distance(p) / EDGE).clamp(0.0, 1.0)
    }

    /// Checks the corners (at least three, finite, an area) and the friction (above 0, at most
    /// [`MAX_FRICTION`]): the field at fault (`corners` or `friction`) and
    /// why.
    pub fn check(&self) -> std::result::Result<(), (&'static str, String)> {
        if self.corners.len() < 3 {
            return Err((
                "corners",
                format!(
                    "a zone needs at least three corners, not {}",
                    self.corners.len()
                ),
            ));
        }
        if let Some(c) = self
            .corners
            .iter()
            .find(|c| !c.iter().all(|x| x.is_finite()))
        {
            return Err(("corners", format!("corner {c:?}: must be finite numbers")));
        }
        if self.area() <= 1e-6 {
            return Err((
                "corners",
                "the corners enclose no area (they lie on one line)".into(),
            ));
        }
        let f = self.friction;
        if !(f.is_finite() && f > 0.0 && f <= MAX_FRICTION) {
            return Err((
                "friction",
                format!("{f}: must be above 0 and at most {}", MAX_FRICTION),
            ));
        }
        Ok(())
    }

    /// The enclosed area, m^2 (the shoelace formula, either sense).
    pub fn area(&self) -> f64 {
        let n = self.corners.len();
        (0..n)
            .map(|i| {
                let (a, b) = (self.corners[i], self.corners[(i + 1) % n]);
                a[0] * b[1] - b[0] * a[1]
            })
            .sum::<f64>()
            .abs()
            / 2.0
    }
}

/// The friction at `p` on a road of friction `road` with `zones` (see the module docs).
pub fn friction_at(road: f64, zones: &[Zone], p: [f64; 2]) -> f64 {
    zones.iter().fold(road, |mu, z| match z.share(p) {
        w if w >= 1.0 => z.friction,
        w if w > 0.0 => mu + w * (z.friction - mu),
        _ => mu,
    })
}

/// The distance from `p` to the segment `a`-`b`, m.
fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (ex, ey) = (a[0] + t * dx - p[0], a[1] + t * dy - p[1]);
    (ex * ex + ey * ey).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> Zone {
        Zone {
            corners: vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]],
            friction: 0.3,
        }
    }

    #[test]
    fn the_friction_changes_over_a_patch_length_about_the_edge() {
        let z = [square()];
        assert!((friction_at(0.8, &z, [5.0, 5.0]) - 0.3).abs() < 1e-15);
        assert!((friction_at(0.8, &z, [-1.0, 5.0]) - 0.8).abs() < 1e-15);
        assert!((friction_at(0.8, &z, [0.0, 5.0]) - 0.55).abs() < 1e-12);
        // A quarter of the patch inside: a quarter of the way to the zone's friction.
        assert!((friction_at(0.8, &z, [-0.05, 5.0]) - (0.8 - 0.25 * 0.5)).abs() < 1e-12);
        assert!((square().signed_distance([2.0, 5.0]) - 2.0).abs() < 1e-12);
        assert!((square().signed_distance([13.0, 14.0]) + 5.0).abs() < 1e-12);
    }

    #[test]
    fn a_later_zone_lies_over_an_earlier_one() {
        let inner = Zone {
            corners: vec![[4.0, 4.0], [6.0, 4.0], [6.0, 6.0], [4.0, 6.0]],
            friction: 0.1,
        };
        let z = [square(), inner];
        assert!((friction_at(0.8, &z, [5.0, 5.0]) - 0.1).abs() < 1e-15);
        assert!((friction_at(0.8, &z, [2.0, 2.0]) - 0.3).abs() < 1e-15);
    }

    #[test]
    fn a_zone_without_an_area_or_with_a_bad_friction_is_refused() {
        let line = Zone {
            corners: vec![[0.0, 0.0], [1.0, 1.0], [2.0, 2.0]],
            friction: 0.5,
        };
        assert!(line.check().unwrap_err().1.contains("no area"));
        let mut z = square();
        z.friction = 2.0;
        assert_eq!(z.check().unwrap_err().0, "friction");
        z.corners.truncate(2);
        assert!(z.check().unwrap_err().1.contains("at least three"));
        assert!(square().check().is_ok());
    }
}
