//! Delta-V from the initial conditions and the energy loss (Brach 1984, section 6).
//!
//! Brach found the combination
//!
//! ```text
//! L_i = m_i dV_i dT^beta / P,     P = [(m1 v1)^2 + (m2 v2)^2]^(1/2)        (13)
//! ```
//!
//! (`dV_i` the delta-V magnitude of vehicle i, `dT` the fraction of the kinetic energy lost,
//! `v_i` the impact speeds) nearly constant over the RICSAC tests, with `beta = -1/2` and
//! `L_i` about 2/3, which gives the prediction
//!
//! ```text
//! dV_i = L_i P dT^(1/2) / m_i                                               (14)
//! ```
//!
//! For a point-mass impact at the critical friction (`mu = mu_m`, sliding ends at separation),
//! with `mbar = m1 m2 / (m1 + m2)` and `r = (v2t - v1t) / (v2n - v1n)`, eq. 13 is
//!
//! ```text
//! L_i^2 = [r^2 + (1 + e)^2] mbar (m1 v1^2 + m2 v2^2) / ([r^2 + 1 - e^2] (m1^2 v1^2 + m2^2 v2^2))   (15)
//! ```
//!
//! The paper prints `(1 - e)^2` where this has `1 - e^2`: the energy fraction of the point-mass
//! solution at `mu = mu_m` is its eq. 12, `T_L = mbar (v2n - v1n)^2 (1 - e^2 + r^2) / 2`, over
//! `T = (m1 v1^2 + m2 v2^2) / 2`, and with eq. 17 for `dV_i` the `(1 - e^2 + r^2)` of eq. 12 is
//! what divides. The two agree at `e = 0`, where eq. 15 becomes, with `alpha = m1 / m2` and
//! `R = v2 / v1`,
//!
//! ```text
//! L_i = [alpha (alpha + R^2) / ((1 + alpha)(alpha^2 + R^2))]^(1/2)          (16)
//! ```
//!
//! (0.7071 for equal masses at any speed ratio). The point-mass delta-V at `mu = mu_m` is
//!
//! ```text
//! dV_i = (mbar / m_i) [(1 + e)^2 + r^2]^(1/2) |v2n - v1n|,     mu_m = r / (1 + e)   (17)
//! ```
//!
//! which [`crate::solve_point_mass`] with the no-slip condition computes.

use crate::coefficients::{Coefficients, TangentialCondition};
use crate::error::Result;
use crate::point_mass::{solve_point_mass, PointMassImpact};

/// `L` of eq. 16 for the mass ratio `alpha = m1 / m2` and the speed ratio `R = v2 / v1`.
pub fn l_factor(alpha: f64, speed_ratio: f64) -> f64 {
    let r2 = speed_ratio * speed_ratio;
    (alpha * (alpha + r2) / ((1.0 + alpha) * (alpha * alpha + r2))).sqrt()
}

/// `L^2` of eq. 15 (as corrected: `1 - e^2` in the denominator) for masses, impact speeds,
/// restitution and the tangential-to-normal ratio `r` of the relative approach velocity.
pub fn l_squared_point_mass(masses: [f64; 2], speeds: [f64; 2], e: f64, r: f64) -> f64 {
    let [m1, m2] = masses;
    let [v1, v2] = speeds;
    let mbar = m1 * m2 / (m1 + m2);
    (r * r + (1.0 + e).powi(2)) * mbar * (m1 * v1 * v1 + m2 * v2 * v2)
        / ((r * r + 1.0 - e * e) * (m1 * m1 * v1 * v1 + m2 * m2 * v2 * v2))
}

/// `P` of eq. 13: `[(m1 v1)^2 + (m2 v2)^2]^(1/2)`, kg m/s.
pub fn momentum_scale(masses: [f64; 2], speeds: [f64; 2]) -> f64 {
    (masses[0] * speeds[0]).hypot(masses[1] * speeds[1])
}

/// Delta-V of both vehicles by eq. 14 with the factor `l` and the energy-loss fraction
/// `energy_fraction` (0..1), m/s.
pub fn delta_v_eq14(l: f64, masses: [f64; 2], speeds: [f64; 2], energy_fraction: f64) -> [f64; 2] {
    let p = momentum_scale(masses, speeds) * energy_fraction.max(0.0).sqrt();
    [l * p / masses[0], l * p / masses[1]]
}

/// The point-mass prediction of eq. 17.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointMassPrediction {
    /// `r = (v2t - v1t) / (v2n - v1n)`.
    pub r: f64,
    /// `mu_m = |r| / (1 + e)`.
    pub mu_m: f64,
    /// Delta-V of both vehicles, m/s.
    pub delta_v: [f64; 2],
    /// Energy-loss fraction of the point-mass solution at `mu = mu_m` (eq. 12 over the initial
    /// kinetic energy).
    pub energy_fraction: f64,
}

/// Eq. 17: the point-mass delta-V at the critical friction, for restitution `e`.
pub fn point_mass_eq17(impact: &PointMassImpact, e: f64) -> Result<PointMassPrediction> {
    let c = Coefficients {
        e,
        mu: 0.0,
        em: 1.0,
    };
    let s = solve_point_mass(impact, &c, TangentialCondition::NoSlip)?;
    let [m1, m2] = impact.masses;
    let dv = |i: usize| {
        let a = impact.initial[i];
        let b = s.separation[i];
        (b[0] - a[0]).hypot(b[1] - a[1])
    };
    let t0 = 0.5
        * (m1 * (impact.initial[0][0].powi(2) + impact.initial[0][1].powi(2))
            + m2 * (impact.initial[1][0].powi(2) + impact.initial[1][1].powi(2)));
    Ok(PointMassPrediction {
        r: s.mu_max * (1.0 + e),
        mu_m: s.mu_max,
        delta_v: [dv(0), dv(1)],
        energy_fraction: if t0 > 0.0 { s.energy_loss / t0 } else { 0.0 },
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equal_masses_give_l_of_one_over_root_two_at_any_speed_ratio() {
        for r in [0.0, 0.3, 1.0, 2.5, 10.0] {
            assert!((l_factor(1.0, r) - std::f64::consts::FRAC_1_SQRT_2).abs() < 1e-15);
        }
        // Eq. 16 is eq. 15 at e = 0, for any r.
        for (alpha, big_r, r) in [(0.5, 0.8, 0.3), (2.0, 1.3, 1.1), (1.6, 0.2, 0.0)] {
            let m = [alpha * 1000.0, 1000.0];
            let v = [10.0, big_r * 10.0];
            let l2 = l_squared_point_mass(m, v, 0.0, r);
            assert!((l2.sqrt() - l_factor(alpha, big_r)).abs() < 1e-12);
        }
    }

    #[test]
    fn corrected_eq15_is_eq13_of_the_point_mass_solution() {
        // Eq. 13 (beta = -1/2) evaluated on the point-mass solution at mu = mu_m equals eq. 15
        // with 1 - e^2; the printed (1 - e)^2 does not.
        let imp = PointMassImpact {
            masses: [1200.0, 1800.0],
            crush_angle: 20.0,
            initial: [[14.0, 0.0], [0.0, 9.0]],
        };
        let e = 0.3;
        let p = point_mass_eq17(&imp, e).unwrap();
        let speeds = [14.0, 9.0];
        let l13 = imp.masses[0] * p.delta_v[0]
            / (momentum_scale(imp.masses, speeds) * p.energy_fraction.sqrt());
        let l15 = l_squared_point_mass(imp.masses, speeds, e, p.r).sqrt();
        assert!((l13 - l15).abs() < 1e-12, "{l13} vs {l15}");
        let [m1, m2] = imp.masses;
        let mbar = m1 * m2 / (m1 + m2);
        let printed = ((p.r * p.r + (1.0 + e).powi(2)) * mbar * (m1 * 196.0 + m2 * 81.0)
            / ((p.r * p.r + (1.0 - e).powi(2)) * (m1 * m1 * 196.0 + m2 * m2 * 81.0)))
            .sqrt();
        assert!((printed - l13).abs() > 0.05);
        // Vehicle 2's L is the same number (equal and opposite impulses).
        let l13_2 = imp.masses[1] * p.delta_v[1]
            / (momentum_scale(imp.masses, speeds) * p.energy_fraction.sqrt());
        assert!((l13_2 - l13).abs() < 1e-12);
    }
}
