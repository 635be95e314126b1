//! The document types of `predict` (what the study of the same name in pim-studies writes).

use serde::Serialize;

/// Delta-V of one vehicle: measured and the three predictions, m/s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct DeltaVPrediction {
    /// Measured (data file).
    pub measured: f64,
    /// Eq. 14 with L from eq. 16 and the measured energy-loss fraction.
    pub eq14: f64,
    /// Eq. 14 with L = 2/3 (Brach's regression) and the measured energy-loss fraction.
    pub eq14_two_thirds: f64,
    /// Eq. 17: the point-mass delta-V at the critical friction.
    pub eq17: f64,
}

/// One test's prediction.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TestPrediction {
    /// Test number.
    pub test: u32,
    /// L of eq. 16 (alpha = m1 / m2, R = v2 / v1 impact speeds).
    #[serde(rename = "L")]
    pub l: f64,
    /// alpha = m1 / m2.
    pub mass_ratio: f64,
    /// R = v2 / v1 (impact speeds).
    pub speed_ratio: f64,
    /// Fraction of the kinetic energy (rotation included) lost between the measured contact and
    /// separation velocities.
    pub energy_loss_fraction: f64,
    /// mu_m = r / (1 + e) of the point-mass solution.
    pub mu_m_point_mass: f64,
    /// Vehicle 1.
    pub delta_v1: DeltaVPrediction,
    /// Vehicle 2.
    pub delta_v2: DeltaVPrediction,
}
