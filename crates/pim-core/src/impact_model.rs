//! Impact models as types: what a front end asks of a model, whichever it is.
//!
//! A model is its coefficients (with their domains) and the transfer of a contact state to
//! separation under the friction rule ([`crate::friction`]), reported as PIM's
//! [`ImpactReport`] with equivalent coefficients and the model's own admissibility. PIM
//! ([`PimModel`]), the tangential-restitution model ([`TangentialCoefficients`]) and the
//! Carpenter-Welcher IMPC ([`crate::Impc`]) implement it; a further model is one type that
//! implements [`ImpactModel`] and one line where a case file names it.

use crate::coefficients::{Coefficients, SolveOptions};
use crate::error::{PimError, Result};
use crate::model::{Impact, Velocities};
use crate::report::ImpactReport;
use crate::tangential::{solve_tangential, ContactMode, TangentialCoefficients};
use serde::Serialize;

/// For a model that decides between sticking and sliding: which acted, and the impulse ratios.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ContactOutcome {
    /// Stick or slide.
    pub mode: ContactMode,
    /// The impulse ratio `Pt / Pn` that acted.
    pub impulse_ratio: f64,
    /// The impulse ratio that sticking would need.
    pub stick_ratio: f64,
}

/// A model's solution.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelSolution {
    /// The solution as PIM's report (PIM's equivalent coefficients), with the model's own
    /// admissibility.
    pub report: ImpactReport,
    /// The stick/slide decision, for the models that make one.
    pub contact: Option<ContactOutcome>,
}

/// An impact model: its name, its coefficients and their domains, and its solve.
pub trait ImpactModel: std::fmt::Debug + Send + Sync {
    /// The name used in case files and documents (`pim`, `tangential`, `impc`).
    fn name(&self) -> &'static str;

    /// What the model is, in a line.
    fn description(&self) -> &'static str;

    /// Its coefficients by name, in the order a case file gives them.
    fn coefficients(&self) -> Vec<(&'static str, f64)>;

    /// Checks the coefficients against their domains.
    fn validate(&self) -> Result<()>;

    /// The separation state from the contact state, with every derived result.
    fn solve(&self, impact: &Impact, initial: &Velocities) -> Result<ModelSolution>;

    /// The contact state from the separation state, where the model can be inverted; by
    /// default it cannot (an input error that says so).
    fn solve_backward(&self, _impact: &Impact, _separation: &Velocities) -> Result<ModelSolution> {
        Err(PimError::Unsupported(format!(
            "the {} model solves forwards only: give the velocities at contact",
            self.name()
        )))
    }
}

/// Planar Impact Mechanics with its coefficients and solve options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PimModel {
    /// e, mu, e_m.
    pub coefficients: Coefficients,
    /// Moment form and tangential condition.
    pub options: SolveOptions,
}

impl ImpactModel for PimModel {
    fn name(&self) -> &'static str {
        "pim"
    }

    fn description(&self) -> &'static str {
        "Planar Impact Mechanics: restitution e, equivalent friction mu, moment restitution em"
    }

    fn coefficients(&self) -> Vec<(&'static str, f64)> {
        let c = &self.coefficients;
        vec![("e", c.e), ("mu", c.mu), ("em", c.em)]
    }

    fn validate(&self) -> Result<()> {
        self.coefficients.validate()
    }

    fn solve(&self, impact: &Impact, initial: &Velocities) -> Result<ModelSolution> {
        let report = crate::solve_forward(impact, &self.coefficients, initial, &self.options)?;
        Ok(ModelSolution {
            report,
            contact: None,
        })
    }

    fn solve_backward(&self, impact: &Impact, separation: &Velocities) -> Result<ModelSolution> {
        let report = crate::solve_backward(impact, &self.coefficients, separation, &self.options)?;
        Ok(ModelSolution {
            report,
            contact: None,
        })
    }
}

impl ImpactModel for TangentialCoefficients {
    fn name(&self) -> &'static str {
        "tangential"
    }

    fn description(&self) -> &'static str {
        "normal and tangential restitution with a friction limit"
    }

    fn coefficients(&self) -> Vec<(&'static str, f64)> {
        vec![("e", self.e), ("et", self.et), ("friction", self.friction)]
    }

    fn validate(&self) -> Result<()> {
        TangentialCoefficients::validate(self)
    }

    fn solve(&self, impact: &Impact, initial: &Velocities) -> Result<ModelSolution> {
        let t = solve_tangential(impact, self, initial)?;
        Ok(ModelSolution {
            report: t.report,
            contact: Some(ContactOutcome {
                mode: t.mode,
                impulse_ratio: t.impulse_ratio,
                stick_ratio: t.stick_ratio,
            }),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Impc;

    #[test]
    fn every_model_answers_through_the_trait() {
        // RICSAC 7 (Brach 1983 Table 1), as the tangential model's tests build it.
        let (impact, x) = (
            crate::tangential::tests::impact(),
            crate::tangential::tests::initial(),
        );
        let pim = PimModel {
            coefficients: Coefficients {
                e: 0.1,
                mu: 0.3,
                em: 1.0,
            },
            options: SolveOptions::default(),
        };
        let impc = Impc {
            e: 0.1,
            friction: 0.3,
        };
        let models: [&dyn ImpactModel; 3] = [&pim, &impc.as_tangential(), &impc];
        let names: Vec<&str> = models.iter().map(|m| m.name()).collect();
        assert_eq!(names, ["pim", "tangential", "impc"]);
        let direct = crate::solve_forward(&impact, &pim.coefficients, &x, &pim.options).unwrap();
        let a = models[0].solve(&impact, &x).unwrap();
        assert_eq!(a.report, direct);
        // IMPC is the tangential model with et = -e, and it does not solve backwards.
        let (b, c) = (
            models[1].solve(&impact, &x).unwrap(),
            models[2].solve(&impact, &x).unwrap(),
        );
        assert_eq!(b, c);
        assert_eq!(impc.coefficients(), [("e", 0.1), ("friction", 0.3)]);
        let back = models[2].solve_backward(&impact, &a.report.separation);
        assert!(matches!(back, Err(PimError::Unsupported(_))));
        assert!(models[0]
            .solve_backward(&impact, &a.report.separation)
            .is_ok());
    }
}
