//! A solution seen in the mirrored frame (y and every angle and rotation change sign): how a
//! case written in SAE J670's frame (x forward, y right, angles and yaw clockwise) is answered
//! in its own frame, after it was solved in the natural one; and every conversion between the
//! natural frame, the frame a case is written in and the page of a figure, written once as
//! methods of [`Convention`] ([`Convention::sign`], [`Convention::shown`],
//! [`Convention::to_page`], [`Convention::from_page`], [`Convention::angle_from_page`]).
//!
//! Reflection is a symmetry of the six equations: the mirrored collision with the same
//! coefficients has the mirrored solution. Under it `y`, headings, directions, yaw rates and
//! moments change sign; so do the tangent of the crush surface (`t` is `n` turned by +90 deg
//! in each frame), hence `vt`, `Pt` and the sign factor of equation 5. Magnitudes, normal
//! quantities, energies, coefficients, mu_max (the coefficient at which `Vt = 0`) and the PDOF
//! (already stated clockwise from the nose, the SAE sense) keep.

use crate::model::{wrap_degrees, Convention, VehicleVelocity, Velocities};
use crate::report::{ImpactReport, VehicleResult};

impl VehicleVelocity {
    /// In the mirrored frame: `vy` and `omega` change sign.
    pub fn mirrored(&self) -> Self {
        VehicleVelocity {
            vx: self.vx,
            vy: -self.vy,
            omega: -self.omega,
        }
    }
}

impl Velocities {
    /// Both vehicles in the mirrored frame.
    pub fn mirrored(&self) -> Self {
        Velocities {
            vehicle1: self.vehicle1.mirrored(),
            vehicle2: self.vehicle2.mirrored(),
        }
    }
}

impl VehicleResult {
    /// In the mirrored frame: the heading, the lateral delta-V and the yaw-rate change change
    /// sign; speeds, delta-V magnitudes and the PDOF (clockwise from the nose) keep.
    pub fn mirrored(&self) -> Self {
        VehicleResult {
            heading: wrap_degrees(-self.heading),
            delta_v_lateral: -self.delta_v_lateral,
            yaw_rate_change: -self.yaw_rate_change,
            ..*self
        }
    }
}

impl ImpactReport {
    /// The same solution in the mirrored frame (see the module docs for what changes sign).
    pub fn mirrored(&self) -> Self {
        let mut r = self.clone();
        r.initial = self.initial.mirrored();
        r.separation = self.separation.mirrored();
        let cp = &mut r.contact_points;
        for p in [
            &mut cp.vehicle1_initial,
            &mut cp.vehicle2_initial,
            &mut cp.vehicle1_final,
            &mut cp.vehicle2_final,
        ] {
            p[1] = -p[1];
        }
        r.relative.tangential_initial = -r.relative.tangential_initial;
        r.relative.tangential_final = -r.relative.tangential_final;
        r.impulse.py = -r.impulse.py;
        r.impulse.tangential = -r.impulse.tangential;
        r.impulse.moment = -r.impulse.moment;
        for d in &mut r.delta_v {
            d.dvy = -d.dvy;
            d.domega = -d.domega;
            d.direction = wrap_degrees(-d.direction);
        }
        for v in &mut r.vehicles {
            *v = v.mirrored();
        }
        r.friction_sign = r.friction_sign.flipped();
        r
    }
}

/// A value with a mirror image: how it reads in the mirrored frame.
pub trait Mirror: Clone {
    /// The value in the mirrored frame.
    fn mirrored(&self) -> Self;
}

impl Mirror for VehicleVelocity {
    fn mirrored(&self) -> Self {
        VehicleVelocity::mirrored(self)
    }
}

impl Mirror for Velocities {
    fn mirrored(&self) -> Self {
        Velocities::mirrored(self)
    }
}

impl Mirror for VehicleResult {
    fn mirrored(&self) -> Self {
        VehicleResult::mirrored(self)
    }
}

impl Mirror for ImpactReport {
    fn mirrored(&self) -> Self {
        ImpactReport::mirrored(self)
    }
}

impl<T: Mirror, const N: usize> Mirror for [T; N] {
    fn mirrored(&self) -> Self {
        self.clone().map(|x| x.mirrored())
    }
}

/// The frame a case is written in, as every face shows it and reads it back: the toolkit
/// computes in the natural frame (y to the left of x, angles counter-clockwise); a case written
/// in SAE J670's frame (y to the right, angles clockwise) is shown mirrored, and every figure
/// lies its plan on the page the same way (an SAE plan as a map: x up, y to the right; a
/// rotation of the natural plan, never a reflection). Each conversion is written here once.
impl Convention {
    /// The convention of a case file's name (`natural`, `brach` or `sae`; [`Convention::name`]).
    pub fn named(name: &str) -> Option<Self> {
        [Convention::Natural, Convention::Brach, Convention::Sae]
            .into_iter()
            .find(|c| c.name() == name)
    }

    /// Whether both vehicles' headings are written as where their noses point (natural and
    /// SAE); the papers' form writes vehicle 1's tail.
    pub fn heads_by_nose(self) -> bool {
        self != Convention::Brach
    }

    /// Whether this frame is the natural one mirrored (SAE J670).
    pub fn mirrors(self) -> bool {
        self == Convention::Sae
    }

    /// The factor from the natural frame to this one (and back) of a y coordinate, an angle, a
    /// heading or a yaw rate: -1 in SAE's frame, 1 otherwise.
    pub fn sign(self) -> f64 {
        if self.mirrors() {
            -1.0
        } else {
            1.0
        }
    }

    /// A count of turns of the natural frame in this one.
    pub fn turns(self, k: i64) -> i64 {
        if self.mirrors() {
            -k
        } else {
            k
        }
    }

    /// `x` (of the natural frame) as this frame shows it.
    pub fn shown<T: Mirror>(self, x: &T) -> T {
        if self.mirrors() {
            x.mirrored()
        } else {
            x.clone()
        }
    }

    /// The sense of positive angles, headings and yaw rates in this frame.
    pub fn positive_sense(self) -> &'static str {
        if self.mirrors() {
            "clockwise"
        } else {
            "counter-clockwise"
        }
    }

    /// A point (or vector) of the natural frame, in any length unit, on the page of a figure:
    /// to the right, up.
    pub fn to_page(self, p: [f64; 2]) -> [f64; 2] {
        if self.mirrors() {
            [-p[1], p[0]]
        } else {
            p
        }
    }

    /// A point of the page (to the right, up) in this frame's coordinates `[x, y]` (SAE: x up,
    /// y to the right).
    pub fn from_page(self, p: [f64; 2]) -> [f64; 2] {
        if self.mirrors() {
            [p[1], p[0]]
        } else {
            p
        }
    }

    /// A point (or the deviations along the axes) written in this frame, on the page: SAE's y
    /// to the right, x up ([`Convention::from_page`]'s inverse).
    pub fn page_of_written(self, p: [f64; 2]) -> [f64; 2] {
        self.to_page([p[0], self.sign() * p[1]])
    }

    /// A direction on the page (degrees counter-clockwise from the page's right) as a heading of
    /// this frame (SAE: clockwise from x, which points up).
    pub fn angle_from_page(self, degrees: f64) -> f64 {
        if self.mirrors() {
            90.0 - degrees
        } else {
            degrees
        }
    }
}

#[cfg(test)]
mod frame_tests {
    use super::*;

    /// An SAE point 30 east (y = 30) and 10 north (x = 10) is (10, -30) in the natural frame,
    /// lies 30 to the right and 10 up on the page, and reads back as (10, 30); a heading due
    /// east on the page (0 deg) is SAE's 90 deg. The natural frame is the page's.
    #[test]
    fn the_frame_goes_to_the_page_and_back() {
        let close = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-12;
        let sae = Convention::Sae;
        let natural = [10.0, sae.sign() * 30.0];
        assert!(close(natural, [10.0, -30.0]));
        assert!(close(sae.to_page(natural), [30.0, 10.0]));
        assert!(close(sae.from_page(sae.to_page(natural)), [10.0, 30.0]));
        assert!(close(sae.page_of_written([10.0, 30.0]), [30.0, 10.0]));
        assert!((sae.angle_from_page(0.0) - 90.0).abs() < 1e-12);
        let n = Convention::Natural;
        assert!(close(n.from_page(n.to_page([1.0, 2.0])), [1.0, 2.0]));
        assert!((n.sign() - 1.0).abs() < 1e-12);
        assert_eq!((n.turns(2), sae.turns(2)), (2, -2));
        let v = VehicleVelocity {
            vx: 1.0,
            vy: 2.0,
            omega: 3.0,
        };
        assert!((sae.shown(&v).vy + 2.0).abs() < 1e-12);
        assert_eq!(n.shown(&v), v);
        assert_eq!(Convention::named("sae"), Some(sae));
        assert!(!Convention::Brach.heads_by_nose());
    }
}
