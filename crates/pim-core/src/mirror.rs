//! A solution seen in the mirrored frame (y and every angle and rotation change sign): how a
//! case written in SAE J670's frame (x forward, y right, angles and yaw clockwise) is answered
//! in its own frame, after it was solved in the natural one.
//!
//! Reflection is a symmetry of the six equations: the mirrored collision with the same
//! coefficients has the mirrored solution. Under it `y`, headings, directions, yaw rates and
//! moments change sign; so do the tangent of the crush surface (`t` is `n` turned by +90 deg
//! in each frame), hence `vt`, `Pt` and the sign factor of equation 5. Magnitudes, normal
//! quantities, energies, coefficients, mu_max (the coefficient at which `Vt = 0`) and the PDOF
//! (already stated clockwise from the nose, the SAE sense) keep.

use crate::model::{wrap_degrees, VehicleVelocity, Velocities};
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
