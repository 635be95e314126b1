//! The closed-form point-mass impact (Brach 1983 Appendix A; Brach 1984 eq. 6-12).
//!
//! Two particles meet at one point; the crush surface has normal n = (cos Gamma, sin Gamma) and
//! tangent t = (-sin Gamma, cos Gamma). With `mbar = m1 m2 / (m1 + m2)` and the normal impulse on
//! vehicle 1 `Pn = mbar (1 + e)(v2n - v1n)`:
//!
//! ```text
//! V1n = v1n + Pn / m1        V2n = v2n - Pn / m2
//! V1t = v1t + mu' Pn / m1    V2t = v2t - mu' Pn / m2
//! ```
//!
//! where `mu' = mu sgn(vn) sgn(vt)` as in equation 5 (`+mu` without sliding at contact, where
//! only mu = 0 is admissible: see the friction rule of the crate docs), or `mu' = r / (1 + e)` with
//! `r = (v2t - v1t)/(v2n - v1n)` under the no-slip condition. This is an independent cross-check of
//! the 6x6 solve with `d1 = d2 = 0` and no rotation.

use crate::coefficients::{Coefficients, TangentialCondition};
use crate::error::{PimError, Result};
use serde::{Deserialize, Serialize};

/// A point-mass impact: masses, crush angle and the two planar velocities at contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PointMassImpact {
    /// Masses `[m1, m2]`, kg (`m2` infinite for a fixed barrier: the reduced mass is then m1).
    pub masses: [f64; 2],
    /// Crush-surface angle Gamma to the y axis, degrees.
    pub crush_angle: f64,
    /// Velocities `[[v1x, v1y], [v2x, v2y]]` at contact, m/s.
    pub initial: [[f64; 2]; 2],
}

/// The closed-form solution.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PointMassSolution {
    /// Velocities `[[V1x, V1y], [V2x, V2y]]` at separation, m/s.
    pub separation: [[f64; 2]; 2],
    /// Normal impulse on vehicle 1, N s.
    pub normal_impulse: f64,
    /// The signed impulse ratio actually used (mu' of equation 5).
    pub mu_effective: f64,
    /// Critical ratio in the sign convention of equation 5: `|r| / (1 + e)` (a point-mass
    /// impact has no coupling, so it is never negative; 0 without sliding at contact).
    pub mu_max: f64,
    /// mu lies between 0 and mu_max (always under the no-slip form): the friction rule of
    /// [`crate::classify_friction`].
    pub friction_ok: bool,
    /// Kinetic energy loss from Brach 1984 eq. 10, J.
    pub energy_loss: f64,
    /// Largest possible energy loss, Brach 1984 eq. 12, J.
    pub max_energy_loss: f64,
}

/// Solves the point-mass impact in closed form.
pub fn solve_point_mass(
    impact: &PointMassImpact,
    coefficients: &Coefficients,
    tangential: TangentialCondition,
) -> Result<PointMassSolution> {
    coefficients.validate()?;
    let [m1, m2] = impact.masses;
    let g = impact.crush_angle.to_radians();
    let (s, c) = g.sin_cos();
    let n = [c, s];
    let t = [-s, c];
    let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
    let [v1, v2] = impact.initial;
    let (v1n, v1t, v2n, v2t) = (dot(v1, n), dot(v1, t), dot(v2, n), dot(v2, t));
    let vn = v1n - v2n;
    let vt = v1t - v2t;
    if vn == 0.0 || !vn.is_finite() {
        return Err(PimError::NotApproaching {
            normal_velocity: vn,
            direction: "they move parallel to the crush surface",
        });
    }
    let e = coefficients.e;
    // Reduced mass; against a barrier (m2 infinite) it is m1.
    let mbar = if m2.is_infinite() {
        m1
    } else {
        m1 * m2 / (m1 + m2)
    };
    let pn = mbar * (1.0 + e) * (v2n - v1n);
    let r = (v2t - v1t) / (v2n - v1n);
    // The one friction rule (`crate::friction_direction`): the sliding direction at contact, or
    // where vt is round-off of the speeds the direction of the no-slip impulse, whose ratio
    // r / (1 + e) has the sign of vt / vn: without sliding it has no tangential part, so the
    // sign is +1 and only mu = 0 is admissible.
    let scale = dot(v1, v1).sqrt().max(dot(v2, v2).sqrt());
    let sliding = if vt.abs() <= crate::model::NO_SLIDING_TOL * scale {
        None
    } else {
        crate::FrictionSign::of(vn, vt)
    };
    let no_slip = crate::CriticalImpulse {
        normal: pn,
        tangential: pn * r / (1.0 + e),
    };
    let (sign, _) = crate::friction_direction(sliding, || Some(no_slip));
    let mu_max = no_slip.mu_max(sign).unwrap_or(0.0);
    let mu_eff = match tangential {
        TangentialCondition::Sliding => coefficients.mu * sign.value(),
        TangentialCondition::NoSlip => r / (1.0 + e),
    };
    let big_v1n = v1n + pn / m1;
    let big_v2n = v2n - pn / m2;
    let big_v1t = v1t + mu_eff * pn / m1;
    let big_v2t = v2t - mu_eff * pn / m2;
    let back = |vn: f64, vt: f64| [vn * n[0] + vt * t[0], vn * n[1] + vt * t[1]];
    let dv2 = (v2n - v1n).powi(2);
    Ok(PointMassSolution {
        separation: [back(big_v1n, big_v1t), back(big_v2n, big_v2t)],
        normal_impulse: pn,
        mu_effective: mu_eff,
        mu_max,
        friction_ok: match tangential {
            TangentialCondition::Sliding => {
                crate::classify_friction(coefficients.mu, Some(mu_max)).admissible
            }
            TangentialCondition::NoSlip => true,
        },
        energy_loss: mbar
            * dv2
            * (1.0 + e)
            * ((1.0 - e) + 2.0 * mu_eff * r - (1.0 + e) * mu_eff * mu_eff)
            / 2.0,
        max_energy_loss: 0.5 * mbar * dv2 * (1.0 - e * e + r * r),
    })
}
