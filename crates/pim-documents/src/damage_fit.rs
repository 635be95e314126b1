//! The document types of `damage_fit` (what the study of the same name in pim-studies writes).

use crate::damage_assess::Assessment;
use pim_fit::MomentBranch;
use serde::Serialize;

/// The damage of a fit, in the document of `pim fit`.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct FitDamage {
    /// The crush at the best answer of the fit without the crush energy.
    pub at_fit: Option<Assessment>,
    /// Whether the crush energy entered a fit as evidence.
    pub evidence: bool,
    /// Why it did not, when it did not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub not_evidence: Option<String>,
    /// The fit with the crush energy as evidence.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub with_energy: Option<EnergyFit>,
}

/// The fit with the crush energy as evidence.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct EnergyFit {
    /// The moment branch of the answer.
    pub moment: MomentBranch,
    /// Restitution.
    pub e: f64,
    /// Equivalent friction.
    pub mu: f64,
    /// Moment restitution.
    pub em: f64,
    /// Velocities at contact.
    pub initial: pim_core::Velocities,
    /// Velocities at separation.
    #[serde(rename = "final")]
    pub final_: pim_core::Velocities,
    /// The whole cost (the case's evidence and the energy's).
    pub cost: f64,
    /// The case's evidence alone at this answer.
    pub cost_without_energy: f64,
    /// The energy's residual, standard deviations: (PIM's loss - the expected loss) / sigma.
    pub energy_z: f64,
    /// The cost's chi-square reading with one more datum (with standard deviations only).
    pub chi_square: Option<pim_fit::ChiSquare>,
    /// True when the case gives no standard deviations: the velocity residuals then count as if
    /// their standard deviation were 1 m/s (1 rad/s) beside the energy's.
    pub velocity_sigma_assumed: bool,
    /// The certified optimum without the energy: no answer can cost less.
    pub lower_bound: f64,
    /// True when the answer meets the lower bound: it is then the global optimum. Otherwise it
    /// is the best found from the starts (each branch's optimum without the energy, then the
    /// optimum within each slice of the e range).
    pub proven: bool,
    /// Exact fits solved.
    pub fits: usize,
    /// The crush at this answer.
    pub damage: Option<Assessment>,
    /// Delta-V of both vehicles at this answer, m/s.
    pub delta_v: [f64; 2],
    /// Kinetic energy loss at this answer, J.
    pub energy_loss: f64,
    /// The whole answer (for the uncertainty study's quantities).
    #[serde(skip)]
    pub solution: pim_fit::Solution,
}
