//! A case file with scene evidence in a batch of case files: answered with its whole
//! reconstruction, as `pim fit` answers it, never with the fit of its contact estimates alone.
//!
//! The file gives one record (its best, and only, branch): the impact at the reconstruction's
//! answer as a fitted branch (so the CSV columns of speeds at contact, delta-V and
//! coefficients read the same as for an impact case) and a `reconstruction` summary: the
//! status, the chi-square and each vehicle's speeds of every phase and its count of turns.

use crate::batch::{BatchPlan, Outcome};
use crate::case_records::CaseRecord;
use pim_case::case::Case;
pub use pim_documents::reconstruct_doc::{SceneRecord, SceneVehicleRecord};
use pim_documents::records::BranchRecord;

/// The records of one case file of a batch (already read; `text` is its content) under one
/// cost function: a case with scene evidence under its own cost is answered with its
/// reconstruction ([`record`]), every other case with the fit of [`crate::case_records::fit_case_text`].
pub fn case_records(
    file: &str,
    text: &str,
    cost: crate::fitcase::CostChoice,
    plan: &BatchPlan,
) -> Vec<CaseRecord> {
    if cost == crate::fitcase::CostChoice::Custom {
        if let Ok(mut case) = Case::from_text(file, text) {
            plan.apply_to_case_file(&mut case);
            let asked = crate::question::Question::of(&case, None);
            if asked.question == crate::question::Question::Reconstruction {
                let mut records = record(file, &case, plan);
                for r in &mut records {
                    r.notes.extend(asked.notes.iter().cloned());
                }
                return records;
            }
        }
    }
    crate::case_records::fit_case_text(file, text, cost, plan)
}

/// Adds the bootstrap intervals to a record of [`case_records`]: the reconstruction's study for
/// a scene case ([`intervals`]), `pim uncertainty`'s for the others.
pub fn add_intervals(r: &mut CaseRecord, text: &str, plan: &BatchPlan, draws: usize, seed: u64) {
    if r.reconstruction.is_none() {
        return crate::case_records::add_intervals(r, text, plan, draws, seed);
    }
    // The record says why, in the document's words.
    let study = match Case::from_text(&r.file, text) {
        Err(e) => Err(e.message),
        Ok(mut case) => {
            plan.apply_to_case_file(&mut case);
            intervals(&case, plan, draws, seed).map_err(|e| e.to_string())
        }
    };
    match study {
        Ok(s) => r.intervals = Some(s),
        Err(e) => r.intervals_error = Some(e),
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
    let branch = plan
        .branches
        .first()
        .copied()
        .unwrap_or(pim_fit::MomentBranch::Free);
    CaseRecord::failed(file, crate::fitcase::CostChoice::Custom, branch, None)
}

/// The intervals of a scene case's record (`pim batch --draws`): the reconstruction's study,
/// its speeds at contact under the names of an impact record's (`speed1`, `speed2`) and every
/// other quantity under its own name.
pub fn intervals(
    case: &Case,
    plan: &BatchPlan,
    draws: usize,
    seed: u64,
) -> Result<
    std::collections::BTreeMap<String, crate::intervals::Summary>,
    crate::documents::DocumentError,
> {
    let settings = plan.case_settings();
    let (study, _) = crate::reconstruct_study::run(
        case,
        settings.model,
        settings.moment_form,
        plan.branches.clone(),
        draws,
        seed,
        &crate::watch::Unwatched,
    )?;
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
