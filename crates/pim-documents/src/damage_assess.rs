//! The document types of `damage_assess` (what the study of the same name in pim-studies writes).

use pim_crush::EnergyRelation;
use serde::Serialize;

/// One vehicle's crush at a pair of states.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct VehicleAssessment {
    /// The damaged face.
    pub side: pim_case::damage::Side,
    /// False when the profile follows from the other vehicle's by the force balance.
    pub measured: bool,
    /// The crush depths used, m.
    pub depths: Vec<f64>,
    /// The damage width, m.
    pub width: f64,
    /// Energy of the profile before the direction-of-force factor, J.
    pub crush_energy: f64,
    /// The PDOF used, degrees clockwise from the nose (where the force comes from).
    pub pdof: f64,
    /// `impulse` (from the states) or `case`.
    pub pdof_from: &'static str,
    /// The force's angle from the face's normal, degrees.
    pub alpha: f64,
    /// `1 + tan^2(alpha)`, alpha held at 45 deg.
    pub pdof_factor: f64,
    /// The energy with the factor, J.
    pub energy: f64,
    /// Its standard deviation, J.
    pub energy_sigma: f64,
    /// Barrier-equivalent speed, m/s: `sqrt(2 E / m)`.
    pub barrier_equivalent_speed: f64,
    /// Moment arm of the impulse's line about the CG, m.
    pub moment_arm: f64,
    /// `k^2 / (k^2 + h^2)`.
    pub effective_mass_factor: f64,
    /// CRASH3's delta-V from the total energy, m/s.
    pub crash3_delta_v: f64,
    /// PIM's delta-V at the states, m/s.
    pub pim_delta_v: f64,
}

/// Both vehicles' crush against PIM's energy loss at a pair of states.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Assessment {
    /// What the crush energy is compared with.
    pub relation: EnergyRelation,
    /// Per vehicle (`None` without damage).
    pub vehicles: [Option<VehicleAssessment>; 2],
    /// The sum of the vehicles' energies, J.
    pub crush_energy: f64,
    /// Its standard deviation, J.
    pub crush_energy_sigma: f64,
    /// The restitution at the states, `-Vn / vn` at the impact centre.
    pub e: f64,
    /// The kinetic energy loss the relation expects from the crush, J.
    pub expected_loss: f64,
    /// Its standard deviation, J.
    pub expected_loss_sigma: f64,
    /// PIM's kinetic energy loss at the states, J.
    pub energy_loss: f64,
    /// `energy_loss - expected_loss`, J.
    pub difference: f64,
    /// The difference in standard deviations (`None` when the sigma is 0).
    pub z: Option<f64>,
    /// What the relation means at this e, in words.
    pub relation_note: String,
    /// What to look at (held factors, a force out of a face, a vehicle without damage).
    pub warnings: Vec<String>,
}
