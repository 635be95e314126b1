//! A case file with scene evidence in a batch of case files: answered with its whole
//! reconstruction, as `pim fit` answers it, never with the fit of its contact estimates alone.
//!
//! The file gives one record (its best, and only, branch): the impact at the reconstruction's
//! answer as a fitted branch (so the CSV columns of speeds at contact, delta-V and
//! coefficients read the same as for an impact case) and a `reconstruction` summary: the
//! status, the chi-square and each vehicle's speeds of every phase and its count of turns.

use crate::batch::{BatchPlan, CaseRecord, Outcome};
use crate::case::Case;
use crate::records::BranchRecord;
use crate::reconstruct::ReconstructionOut;
use serde::Serialize;

/// A vehicle through the phases of a batch's reconstruction (SI, natural frame).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneVehicleRecord {
    /// 1 or 2.
    pub vehicle: u8,
    /// Where its braking began, m/s (with a skid).
    pub speed_before_braking: Option<f64>,
    /// At contact, m/s.
    pub speed_at_contact: f64,
    /// At separation, m/s.
    pub speed_at_separation: f64,
    /// Full turns to rest beyond the shortest rotation to the rest heading (counter-clockwise
    /// positive), with a rest heading.
    pub turns: Option<i64>,
}

/// The reconstruction of a batch record.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SceneRecord {
    /// `found`, `inconsistent` or `no_solution`.
    pub status: pim_reconstruct::Status,
    /// Why there is no answer, or what contradicts it.
    pub reason: Option<String>,
    /// The whole chi-square.
    pub chi_square: Option<f64>,
    /// Its degrees of freedom.
    pub degrees_of_freedom: Option<i64>,
    /// Its probability ([`pim_fit::judged_dof`]).
    pub p_value: Option<f64>,
    /// Per vehicle, every phase.
    pub vehicles: Vec<SceneVehicleRecord>,
}

impl SceneRecord {
    fn of(d: &ReconstructionOut) -> Self {
        let b = d.best.as_ref();
        SceneRecord {
            status: d.status,
            reason: d.reason.clone(),
            chi_square: b.map(|b| b.chi_square),
            degrees_of_freedom: b.map(|b| b.degrees_of_freedom),
            p_value: b.and_then(|b| b.p_value),
            vehicles: b
                .map(|b| {
                    b.vehicles
                        .iter()
                        .map(|v| SceneVehicleRecord {
                            vehicle: v.vehicle,
                            speed_before_braking: v.speed_before_braking,
                            speed_at_contact: v.speed_at_contact,
                            speed_at_separation: v.speed_at_separation,
                            turns: v.turns,
                        })
                        .collect()
                })
                .unwrap_or_default(),
        }
    }
}

/// The record of a case with scene evidence: its reconstruction with the plan's settings.
pub fn record(file: &str, case: &Case, plan: &BatchPlan) -> Vec<CaseRecord> {
    let settings = plan.case_settings();
    let done = crate::reconstruct::reconstruct(
        case,
        settings.model,
        settings.moment_form,
        plan.branches.clone(),
    );
    let done = match done {
        Ok(d) => d,
        Err(e) => {
            return vec![CaseRecord {
                error: Some(e.to_string()),
                ..empty(file, plan)
            }]
        }
    };
    let found = done.document.status == pim_reconstruct::Status::Found;
    let branch = done.outcome.best.as_ref().filter(|_| found).map(|b| {
        BranchRecord::new(&pim_fit::BranchReport {
            moment: b.branch,
            status: pim_fit::Status::Optimal,
            reason: None,
            solution: Some(b.solution.clone()),
            identifiability: Vec::new(),
            certificate: b.certificate.clone(),
            geometry: None,
        })
    });
    let moment = done
        .outcome
        .best
        .as_ref()
        .map_or(empty(file, plan).moment_branch, |b| b.branch);
    vec![CaseRecord {
        outcome: if found {
            Outcome::Optimal
        } else {
            Outcome::Infeasible
        },
        moment_branch: moment,
        best: found,
        branch,
        reconstruction: Some(SceneRecord::of(&done.document)),
        ..empty(file, plan)
    }]
}

fn empty(file: &str, plan: &BatchPlan) -> CaseRecord {
    CaseRecord {
        file: file.to_string(),
        cost_function: crate::fitcase::CostChoice::Custom,
        outcome: Outcome::Failed,
        moment_branch: plan
            .branches
            .first()
            .copied()
            .unwrap_or(pim_fit::MomentBranch::Free),
        best: false,
        error: None,
        branch: None,
        intervals: None,
        intervals_error: None,
        notes: Vec::new(),
        damage: None,
        reconstruction: None,
    }
}

/// The intervals of a scene case's record (`pim batch --draws`): the reconstruction's study,
/// its speeds at contact under the names of an impact record's (`speed1`, `speed2`) and every
/// other quantity under its own name.
pub fn intervals(
    case: &Case,
    plan: &BatchPlan,
    draws: usize,
    seed: u64,
) -> Result<std::collections::BTreeMap<String, crate::intervals::Summary>, String> {
    let settings = plan.case_settings();
    let (study, _) = crate::reconstruct_study::run(
        case,
        settings.model,
        settings.moment_form,
        plan.branches.clone(),
        draws,
        seed,
        &|| {},
    )
    .map_err(|e| e.to_string())?;
    Ok(study
        .quantities
        .into_iter()
        .map(|(n, s)| {
            let n = match n.as_str() {
                "vehicle1.speed_at_contact" => "speed1".to_string(),
                "vehicle2.speed_at_contact" => "speed2".to_string(),
                _ => n,
            };
            (n, s)
        })
        .collect())
}
