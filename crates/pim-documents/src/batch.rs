//! The document types of `batch` (what the study of the same name in pim-studies writes).

use crate::intervals::Summary;
use crate::records::BranchRecord;
use pim_fit::{CostPreset, FitModel, MomentBranch, Status};
use serde::Serialize;
use std::collections::BTreeMap;
use std::fmt;

/// The outcome of one record: the fit's status, or `failed` when the row could not be fitted.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Outcome {
    /// The global optimum was found.
    Optimal,
    /// The data admit no solution (the reason is in the record).
    Infeasible,
    /// A solution was found but a refinement hit its iteration limit.
    LimitReached,
    /// The best point failed pim-core's check (a defect, reported).
    CheckFailed,
    /// The row could not be fitted (its physics or settings are invalid).
    Failed,
}

impl From<Status> for Outcome {
    fn from(s: Status) -> Self {
        match s {
            Status::Optimal => Outcome::Optimal,
            Status::Infeasible => Outcome::Infeasible,
            Status::LimitReached => Outcome::LimitReached,
            Status::CheckFailed => Outcome::CheckFailed,
        }
    }
}

impl Outcome {
    /// True when the record has an answer (optimal or limit reached).
    pub fn solved(self) -> bool {
        matches!(self, Outcome::Optimal | Outcome::LimitReached)
    }
}

impl fmt::Display for Outcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(match self {
            Outcome::Optimal => "optimal",
            Outcome::Infeasible => "infeasible",
            Outcome::LimitReached => "limit_reached",
            Outcome::CheckFailed => "check_failed",
            Outcome::Failed => "failed",
        })
    }
}

/// One record per (test, cost, branch).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct BatchRecord {
    /// RICSAC test number.
    pub test: u32,
    /// Cost function.
    pub cost_function: CostPreset,
    /// The model fitted: `pim` or `tangential`.
    pub model: FitModel,
    /// `optimal`, `infeasible`, `limit_reached`, `check_failed` or `failed`.
    pub outcome: Outcome,
    /// Line of the data file.
    pub line: u64,
    /// The fitted branch (absent when the row failed).
    #[serde(flatten)]
    pub branch: Option<BranchRecord>,
    /// Why the row failed.
    pub error: Option<String>,
    /// The branch of this record (also when failed).
    pub moment_branch: MomentBranch,
    /// True for the best branch of this (test, cost, model).
    pub best: bool,
    /// Measured |delta-V| of vehicle 1 and 2 (data file), m/s.
    pub delta_v_measured: [f64; 2],
    /// (fitted - measured) / measured |delta-V| per vehicle.
    pub delta_v_relative_error: Option<[f64; 2]>,
    /// Fitted minus measured, per component of U (m/s, rad/s), in the order of `components`.
    pub velocity_error: Option<[f64; 12]>,
    /// The component with the largest absolute error.
    pub max_error_component: Option<String>,
    /// Its error.
    pub max_error: Option<f64>,
    /// Wall time of the fit of this (test, cost function), all its branches, s (only with timing).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fit_seconds: Option<f64>,
    /// With `pim batch DATA --draws N --tolerances FILE`, on the best record of each (test,
    /// cost): the bootstrap summaries of `pim uncertainty` by quantity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intervals: Option<BTreeMap<String, Summary>>,
    /// Why the intervals could not be computed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intervals_error: Option<String>,
}

impl BatchRecord {
    /// True when the record has an answer (optimal or limit reached).
    pub fn solved(&self) -> bool {
        self.outcome.solved()
    }
}
