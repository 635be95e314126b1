//! A batch over case files: one record per (file, cost function, moment branch), fitted like
//! `pim fit --cost` with the case's own `[bounds]` on top of the plan's settings (a case with
//! scene evidence is answered by [`crate::batch_scene`] with its reconstruction).

use crate::batch::{intervals, BatchPlan};
use crate::fitcase::CostChoice;
pub use pim_documents::case_records::{CaseRecord, INTERVAL_COLUMNS};
use pim_documents::records::BranchRecord;

/// Adds the bootstrap intervals of `pim uncertainty` (`draws` draws, `seed`) to `record`.
pub fn add_intervals(
    record: &mut CaseRecord,
    text: &str,
    plan: &BatchPlan,
    draws: usize,
    seed: u64,
) {
    let study = pim_case::case::Case::from_text(&record.file, text).and_then(|mut case| {
        plan.apply_to_case_file(&mut case);
        intervals(&case, record.cost_function, plan, draws, seed)
    });
    match study {
        Ok(s) => record.intervals = Some(s),
        Err(e) => record.intervals_error = Some(e.message),
    }
}

/// Fits one case file (already read; `text` is its content) under one cost function, like
/// `pim fit --cost`, with the case's own `[bounds]` on top of the plan's settings. A file that
/// cannot be parsed or fitted gives failed records whose `error` names the file and field.
pub fn fit_case_text(
    file: &str,
    text: &str,
    cost: CostChoice,
    plan: &BatchPlan,
) -> Vec<CaseRecord> {
    let failed = |msg: String| -> Vec<CaseRecord> {
        plan.branches
            .iter()
            .map(|&m| CaseRecord::failed(file, cost, m, Some(msg.clone())))
            .collect()
    };
    let case = match pim_case::case::Case::from_text(file, text) {
        Ok(mut c) => {
            plan.apply_to_case_file(&mut c);
            c
        }
        Err(e) => return failed(e.message),
    };
    if let Err(e) = crate::fitcase::check_fit_sections(&case) {
        return failed(e.message);
    }
    let problem = match crate::fitcase::problem(&case, cost) {
        Ok(p) => p,
        Err(e) => return failed(e.message),
    };
    let settings = match crate::fitcase::settings_from(&case, plan.case_settings()) {
        Ok(s) => s,
        Err(e) => return failed(e.message),
    };
    let report = match crate::fitcase::fit(&case, &problem, &settings) {
        Ok(r) => r,
        Err(e) => return failed(e.message),
    };
    let notes = match cost {
        CostChoice::Preset(p) => crate::fitcase::ignored_weights(&case, p),
        CostChoice::Custom => Vec::new(),
    };
    let unit = match crate::fitcase::sigma_unit(&case) {
        Ok(u) => u,
        Err(e) => return failed(e.message),
    };
    let damage = match crate::damage_fit::fit_damage(&case, &problem, &report, &settings, unit) {
        Ok(d) => d,
        Err(e) => return failed(e.message),
    };
    report
        .branches
        .iter()
        .map(|b| CaseRecord {
            file: file.to_string(),
            cost_function: cost,
            outcome: b.status.into(),
            moment_branch: b.moment,
            best: report.best == Some(b.moment),
            error: None,
            branch: Some(
                BranchRecord::new(b).with_bounds(b, settings.get(), &|bound| {
                    crate::fitcase::sets_bound(&case, bound)
                }),
            ),
            intervals: None,
            intervals_error: None,
            notes: notes.clone(),
            damage: damage.clone().filter(|_| report.best == Some(b.moment)),
            reconstruction: None,
        })
        .collect()
}
