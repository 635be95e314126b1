//! The document types of `case_records` (what the study of the same name in pim-studies writes).

use crate::batch::Outcome;
use crate::fitcase::CostChoice;
use crate::intervals::Summary;
use crate::records::BranchRecord;
use pim_fit::MomentBranch;
use serde::Serialize;
use std::collections::BTreeMap;

/// One record of a batch over case files: one per (file, cost function, moment branch).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct CaseRecord {
    /// The case file.
    pub file: String,
    /// Cost function: a preset of `--cost`, or `custom` (the file's own `[known]`,
    /// estimates, observations, weights or sigmas).
    pub cost_function: CostChoice,
    /// `optimal`, `infeasible`, `limit_reached`, `check_failed` or `failed`.
    pub outcome: Outcome,
    /// The branch of this record.
    pub moment_branch: MomentBranch,
    /// True for the best branch of this (file, cost).
    pub best: bool,
    /// Why the file could not be fitted (it names the file and the field).
    pub error: Option<String>,
    /// The fitted branch (absent when the file failed).
    #[serde(flatten)]
    pub branch: Option<BranchRecord>,
    /// With `pim batch --draws N`, on the best record of each (file, cost): the bootstrap
    /// summaries of `pim uncertainty` (p05, p50, p95, mean, sd) by quantity.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intervals: Option<BTreeMap<String, Summary>>,
    /// Why the intervals could not be computed (e.g. the case gives no sigmas).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub intervals_error: Option<String>,
    /// What in the case had no effect on this fit (e.g. weights or sigmas of components the
    /// cost function holds fixed), said rather than dropped.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
    /// On the best record of a case with `[damage]`: the crush at the answer and the fit with
    /// the crush energy as evidence (as `pim fit` gives them).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damage: Option<crate::damage_fit::FitDamage>,
    /// A case with scene evidence: its whole reconstruction (status, chi-square, the speeds of
    /// every phase, the counts of turns); `branch` is then the impact at its answer.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reconstruction: Option<crate::reconstruct_doc::SceneRecord>,
}

/// The quantities whose 90 % intervals are CSV columns.
pub const INTERVAL_COLUMNS: [&str; 4] = ["speed1", "speed2", "delta_v1", "delta_v2"];

impl CaseRecord {
    /// A record of `file` without an answer (`failed`, with the error when there is one), to
    /// be filled in.
    pub fn failed(
        file: &str,
        cost: CostChoice,
        moment_branch: MomentBranch,
        error: Option<String>,
    ) -> Self {
        CaseRecord {
            file: file.to_string(),
            cost_function: cost,
            outcome: Outcome::Failed,
            moment_branch,
            best: false,
            error,
            branch: None,
            intervals: None,
            intervals_error: None,
            notes: Vec::new(),
            damage: None,
            reconstruction: None,
        }
    }

    /// The column names of [`CaseRecord::csv_row`].
    pub const CSV_HEADER: [&'static str; 31] = [
        "file",
        "cost_function",
        "branch",
        "best",
        "outcome",
        "reason",
        "e",
        "mu",
        "em",
        "mu_max",
        "cost",
        "energy_loss_j",
        "energy_loss_percent",
        "speed1_mps",
        "speed2_mps",
        "delta_v1_mps",
        "delta_v2_mps",
        "pdof1_deg",
        "pdof2_deg",
        "yaw_rate_change1_radps",
        "yaw_rate_change2_radps",
        "admissible",
        "speed1_p05",
        "speed1_p95",
        "speed2_p05",
        "speed2_p95",
        "delta_v1_p05",
        "delta_v1_p95",
        "delta_v2_p05",
        "delta_v2_p95",
        "intervals_note",
    ];

    /// One flat CSV row (SI), in the order of [`CaseRecord::CSV_HEADER`].
    pub fn csv_row(&self) -> Vec<String> {
        let f = |x: Option<f64>| x.map_or_else(String::new, |v| format!("{v}"));
        let b = self.branch.as_ref();
        let v = b.and_then(|b| b.vehicles);
        let per = |k: usize, g: fn(&pim_core::VehicleResult) -> f64| f(v.map(|v| g(&v[k])));
        let scene = self.reconstruction.as_ref().and_then(|r| r.reason.clone());
        let reason = match (&self.error, b.and_then(|b| b.reason.as_ref()), scene) {
            (Some(e), _, _) => e.clone(),
            (None, Some(r), _) => r.to_string(),
            (None, None, Some(r)) => r,
            (None, None, None) => String::new(),
        };
        let mut row = vec![
            self.file.clone(),
            self.cost_function.name().to_string(),
            self.moment_branch.name().to_string(),
            self.best.to_string(),
            self.outcome.to_string(),
            reason,
            f(b.and_then(|b| b.e)),
            f(b.and_then(|b| b.mu)),
            f(b.and_then(|b| b.em)),
            f(b.and_then(|b| b.mu_max)),
            f(b.and_then(|b| b.cost)),
            f(b.and_then(|b| b.energy_loss)),
            f(b.and_then(|b| b.energy_loss_percent)),
            per(0, |r| r.speed_initial),
            per(1, |r| r.speed_initial),
            per(0, |r| r.delta_v),
            per(1, |r| r.delta_v),
            per(0, |r| r.pdof),
            per(1, |r| r.pdof),
            per(0, |r| r.yaw_rate_change),
            per(1, |r| r.yaw_rate_change),
            b.and_then(|b| b.admissible)
                .map_or_else(String::new, |a| a.to_string()),
        ];
        for q in INTERVAL_COLUMNS {
            let s = self.intervals.as_ref().and_then(|i| i.get(q));
            row.push(f(s.map(|s| s.p05)));
            row.push(f(s.map(|s| s.p95)));
        }
        // Why the interval columns are empty, when they were asked for and are.
        row.push(self.intervals_error.clone().unwrap_or_default());
        row
    }
}
