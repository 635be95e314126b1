//! The document types of `residuals` (what the study of the same name in pim-studies writes).

use serde::Serialize;

/// One term of the cost: an estimated component or an observation, against the fit.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Residual {
    /// What was given: a velocity component (`final.vehicle1.vx`) or an observation by its
    /// label (`observation "EDR"`, `observation 2`).
    pub name: String,
    /// `estimate`, or the observation's kind (`delta_v_longitudinal`, `speed_along_heading`,
    /// ...).
    pub kind: String,
    /// `m/s`, or `rad/s` for a yaw rate.
    pub unit: &'static str,
    /// The given value.
    pub given: f64,
    /// The fitted value.
    pub fitted: f64,
    /// `fitted - given`.
    pub residual: f64,
    /// The term's weight in the cost.
    pub weight: f64,
    /// The standard deviation the case gives (none when it gives weights).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// `residual / sigma`: how many standard deviations the fit is from the value given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normalised: Option<f64>,
    /// The term's part of the cost, `weight residual^2 / cost` (none when the cost is 0).
    pub share: Option<f64>,
    /// True when the value is across the x axis or a yaw rate: its sign changes in SAE's
    /// mirrored frame.
    pub lateral: bool,
}
