//! The coefficients of PIM and the options of a solve.

use crate::error::{PimError, Result};
use serde::{Deserialize, Serialize};

/// The three impact coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Coefficients {
    /// Coefficient of restitution e (normal to the crush surface), in [0, 1].
    pub e: f64,
    /// Equivalent friction coefficient mu: tangential over normal impulse, signed (see the crate docs).
    pub mu: f64,
    /// Moment coefficient of restitution e_m, in [-1, 0] or exactly 1.
    #[serde(rename = "em")]
    pub em: f64,
}

/// Tolerance for "e_m is exactly 1".
pub const EM_ONE_TOL: f64 = 1e-12;

impl Coefficients {
    /// Checks the domain: all finite, `0 <= e <= 1`, `-1 <= em <= 0` or `em = 1`.
    pub fn validate(&self) -> Result<()> {
        for (name, value) in [("e", self.e), ("mu", self.mu), ("em", self.em)] {
            if !value.is_finite() {
                return Err(PimError::NonFiniteValue { field: name, value });
            }
        }
        if !(0.0..=1.0).contains(&self.e) {
            return Err(PimError::CoefficientOutOfRange {
                name: "e",
                value: self.e,
                domain: "0 <= e <= 1",
            });
        }
        if !((-1.0..=0.0).contains(&self.em) || (self.em - 1.0).abs() <= EM_ONE_TOL) {
            return Err(PimError::CoefficientOutOfRange {
                name: "em",
                value: self.em,
                domain: "-1 <= em <= 0, or em = 1",
            });
        }
        Ok(())
    }
}

/// Which form of the moment equation (6) to use.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum MomentForm {
    /// The corrected form of the 1984 appendix: `(W2 - W1)(1 - em) = em B`. The default.
    #[default]
    Corrected,
    /// The form of the 1983 BASIC listing, `(W1 - W2)(1 - em) = em B`, which carries a sign
    /// error; only for reproducing the 1983 tables.
    Brach1983,
}

/// Which tangential condition closes the system.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum TangentialCondition {
    /// Equation 5: the tangential impulse is mu' times the normal impulse. The default.
    #[default]
    Sliding,
    /// Equation 5a: no relative tangential velocity at separation (sliding ended before it).
    NoSlip,
}

/// Options of a solve.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub struct SolveOptions {
    /// Form of the moment equation.
    pub moment_form: MomentForm,
    /// Sliding (equation 5) or no slip (equation 5a).
    pub tangential: TangentialCondition,
}

impl MomentForm {
    /// Both forms, the default first.
    pub const ALL: [MomentForm; 2] = [MomentForm::Corrected, MomentForm::Brach1983];

    /// The name used in case files, on the command line and in Python: `corrected`,
    /// `brach1983`.
    pub fn name(self) -> &'static str {
        match self {
            MomentForm::Corrected => "corrected",
            MomentForm::Brach1983 => "brach1983",
        }
    }

    /// What the form is, in a line.
    pub fn description(self) -> &'static str {
        match self {
            MomentForm::Corrected => "The corrected moment equation of Brach 1984 (default)",
            MomentForm::Brach1983 => {
                "The 1983 BASIC listing's form, with its sign error; to reproduce the 1983 tables"
            }
        }
    }
}

impl std::str::FromStr for MomentForm {
    type Err = crate::names::UnknownName;
    /// By [`MomentForm::name`]; the error lists the accepted names.
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        crate::names::parse_name(s, &Self::ALL, Self::name)
    }
}
