//! From the crush energies to the collision: the other vehicle's crush by the force balance,
//! the energies' standard deviations, what the energy is compared with, CRASH3's delta-V.

use crate::energy::{crush_energy, input, CrushError, Profile, Stiffness};
use serde::{Deserialize, Serialize};

/// The crush depths of a vehicle whose damage was not measured, from the force balance at the
/// interface: at every point of the common damage width the force per unit width is the same
/// on both faces, `A1 + B1 C1 = A2 + B2 C2`, so `C2 = (A1 + B1 C1 - A2) / B2`, held at 0 where
/// the measured vehicle's force stays below the other's onset of residual crush (CRASH3's
/// rule). The profile has the measured one's width and points.
///
/// # Errors
/// [`CrushError::Input`] for a profile or stiffness outside its ranges.
pub fn balanced_profile(
    measured: &Profile,
    measured_stiffness: &Stiffness,
    other_stiffness: &Stiffness,
) -> Result<Profile, CrushError> {
    measured.check()?;
    measured_stiffness.check()?;
    other_stiffness.check()?;
    let (a1, b1) = (measured_stiffness.a, measured_stiffness.b);
    let (a2, b2) = (other_stiffness.a, other_stiffness.b);
    Ok(Profile {
        width: measured.width,
        depths: measured
            .depths
            .iter()
            .map(|c| ((a1 + b1 * c - a2) / b2).max(0.0))
            .collect(),
    })
}

/// Standard deviations of a damage profile's inputs (each 0 when exact).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ProfileSigmas {
    /// Of A, N/m.
    pub a: f64,
    /// Of B, N/m^2.
    pub b: f64,
    /// Of each crush depth, m (independent from point to point).
    pub depth: f64,
    /// Of the damage width, m.
    pub width: f64,
}

impl ProfileSigmas {
    /// Checks that each is a number of at least 0.
    ///
    /// # Errors
    /// [`CrushError::Input`] naming the sigma.
    pub fn check(&self) -> Result<(), CrushError> {
        for (field, x) in [
            ("a_sigma", self.a),
            ("b_sigma", self.b),
            ("depth_sigma", self.depth),
            ("width_sigma", self.width),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(input(field, format!("{x}: must be a number of at least 0")));
            }
        }
        Ok(())
    }
}

/// The standard deviation of [`crush_energy`], J, to first order in independent errors of A,
/// B, the width and each depth:
///
/// ```text
/// dE/dA  = integral (C + A/B) dw          dE/dB = integral (C^2/2 - A^2/(2 B^2)) dw
/// dE/dL  = E / L                           dE/dCi = (A + B C) weighted by the hat function of point i
/// ```
///
/// (the last integrated exactly over the two intervals beside point i).
///
/// # Errors
/// [`CrushError::Input`] for a profile, stiffness or sigma outside its ranges.
pub fn crush_energy_sigma(
    profile: &Profile,
    stiffness: &Stiffness,
    sigmas: &ProfileSigmas,
) -> Result<f64, CrushError> {
    let e = crush_energy(profile, stiffness)?;
    sigmas.check()?;
    let (a, b) = (stiffness.a, stiffness.b);
    let n = profile.depths.len();
    let h = profile.width / (n - 1) as f64;
    let c = &profile.depths;
    let (mut d_a, mut d_b) = (
        a / b * profile.width,
        -a * a / (2.0 * b * b) * profile.width,
    );
    let mut d_c = vec![0.0; n];
    for i in 0..n - 1 {
        let (c0, c1) = (c[i], c[i + 1]);
        d_a += h * 0.5 * (c0 + c1);
        d_b += h * 0.5 * (c0 * c0 + c0 * c1 + c1 * c1) / 3.0;
        // d/dc0 of h (A (c0 + c1)/2 + B (c0^2 + c0 c1 + c1^2)/6), and the same for c1.
        d_c[i] += h * (0.5 * a + b * (2.0 * c0 + c1) / 6.0);
        d_c[i + 1] += h * (0.5 * a + b * (c0 + 2.0 * c1) / 6.0);
    }
    let d_l = e / profile.width;
    let var = (d_a * sigmas.a).powi(2)
        + (d_b * sigmas.b).powi(2)
        + (d_l * sigmas.width).powi(2)
        + d_c.iter().map(|d| (d * sigmas.depth).powi(2)).sum::<f64>();
    Ok(var.sqrt())
}

/// What the crush energy is compared with.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum EnergyRelation {
    /// CRASH3's convention: the crush energy is the kinetic energy the collision loses.
    #[default]
    EnergyLoss,
    /// The crush energy is the energy absorbed up to maximum crush (what a barrier test
    /// calibrated on `m V^2 / 2` measures): in a central impact with restitution e the
    /// collision loses `(1 - e^2)` of it.
    Compression,
}

impl EnergyRelation {
    /// The name used in case files and outputs.
    pub fn name(self) -> &'static str {
        match self {
            EnergyRelation::EnergyLoss => "energy_loss",
            EnergyRelation::Compression => "compression",
        }
    }

    /// The kinetic energy loss this relation expects from a crush energy `crush` (J) at
    /// restitution `e`: `crush` itself, or `(1 - e^2) crush`.
    pub fn expected_loss(self, crush: f64, e: f64) -> f64 {
        match self {
            EnergyRelation::EnergyLoss => crush,
            EnergyRelation::Compression => (1.0 - e * e) * crush,
        }
    }
}

/// CRASH3's effective-mass factor of a vehicle for an impulse whose line of action passes
/// `moment_arm` (m) from its CG: `gamma = k^2 / (k^2 + h^2)` with `k^2 = I / m`. An impulse
/// `P` at that arm changes the velocity of the point it acts on, along its line, by
/// `P / (gamma m)`: the vehicle's effective mass there is `gamma m`.
pub fn effective_mass_factor(mass: f64, yaw_inertia: f64, moment_arm: f64) -> f64 {
    if !mass.is_finite() {
        return 1.0;
    }
    let k2 = yaw_inertia / mass;
    k2 / (k2 + moment_arm * moment_arm)
}

/// CRASH3's delta-V of both vehicles' centres of mass from the total crush energy `energy`
/// (J), m/s. With no restitution and a common velocity of the contact points along the
/// impulse at its end, the energy lost is `E = P^2 / 2 (1/(g1 m1) + 1/(g2 m2))`, so
///
/// ```text
/// P = sqrt(2 E (g1 m1)(g2 m2) / (g1 m1 + g2 m2)),   dV_i = P / m_i
/// ```
///
/// (`g_i` from [`effective_mass_factor`]). With both factors 1 this is the point-mass delta-V
/// of a central collinear collision with e = 0, `dV1 = sqrt(2 E m2 / (m1 (m1 + m2)))`. An
/// infinite `masses[1]` is a rigid barrier: `P = sqrt(2 E g1 m1)` and `dV2 = 0`.
///
/// # Errors
/// [`CrushError::Input`] for an energy below 0 or a mass or factor out of range.
pub fn crash3_delta_v(
    energy: f64,
    masses: [f64; 2],
    factors: [f64; 2],
) -> Result<[f64; 2], CrushError> {
    if !(energy.is_finite() && energy >= 0.0) {
        return Err(input(
            "energy",
            format!("{energy}: must be a number of at least 0 J"),
        ));
    }
    if !(masses[0].is_finite() && masses[0] > 0.0 && masses[1] > 0.0) {
        return Err(input(
            "mass",
            format!("{:?}: masses must be above 0 kg", masses),
        ));
    }
    if factors
        .iter()
        .any(|g| !(g.is_finite() && *g > 0.0 && *g <= 1.0))
    {
        return Err(input(
            "effective_mass_factor",
            format!("{:?}: each must lie in (0, 1]", factors),
        ));
    }
    let m1 = factors[0] * masses[0];
    let p = if masses[1].is_finite() {
        let m2 = factors[1] * masses[1];
        (2.0 * energy * m1 * m2 / (m1 + m2)).sqrt()
    } else {
        (2.0 * energy * m1).sqrt()
    };
    Ok([p / masses[0], p / masses[1]])
}
