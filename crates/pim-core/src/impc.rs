//! The impulse-momentum model of Carpenter & Welcher (IMPC), as IMPC spreadsheets and
//! pycrash's `impc.py` compute it: restitution `e` on both axes of the crush surface while the
//! impulse ratio `|Pt / Pn|` stays within the friction coefficient (the impulse is `1 + e` times
//! the one that brings the contact point to rest), the ratio capped at the coefficient on that
//! impulse's side otherwise (the friction rule), no moment impulse.
//!
//! It is the tangential-restitution model with `et = -e`; this type is its preset, an
//! [`ImpactModel`] of its own with two coefficients.

use crate::error::Result;
use crate::impact_model::{ImpactModel, ModelSolution};
use crate::model::{Impact, Velocities};
use crate::tangential::TangentialCoefficients;

/// IMPC's coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Impc {
    /// Restitution, on both axes while the cap does not bind, in [0, 1].
    pub e: f64,
    /// Cap of the impulse ratio `|Pt / Pn|`, >= 0.
    pub friction: f64,
}

impl Impc {
    /// The same model as the tangential-restitution model's preset (`et = -e`).
    pub fn as_tangential(&self) -> TangentialCoefficients {
        TangentialCoefficients::impc(self.e, self.friction)
    }
}

impl ImpactModel for Impc {
    fn name(&self) -> &'static str {
        "impc"
    }

    fn description(&self) -> &'static str {
        "Carpenter & Welcher's impulse-momentum model (IMPC): restitution e on both axes, the \
         impulse ratio capped at the friction coefficient"
    }

    fn coefficients(&self) -> Vec<(&'static str, f64)> {
        vec![("e", self.e), ("friction", self.friction)]
    }

    fn validate(&self) -> Result<()> {
        self.as_tangential().validate()
    }

    fn solve(&self, impact: &Impact, initial: &Velocities) -> Result<ModelSolution> {
        self.as_tangential().solve(impact, initial)
    }
}
