//! A batch of the folder's case files in the background: the records `pim batch DIR --format
//! json` writes (one per file, cost and branch; a scene case's reconstruction in its record),
//! with the command's default plan (each file's own cost, both moment branches, the corrected
//! moment equation, PIM).

use pim_studies::case_batch::{CaseBatch, CaseText};
use pim_studies::fitcase::CostChoice;
use pim_studies::watch::Observer;

/// The records of `files` (name and text, or why it could not be read), in their order,
/// answered in parallel; the observer sees each finished file and can cancel (the files not
/// started then give no records, and the document says how many were asked and done).
///
/// # Errors
/// None of its own: a file that fails gives failed records, as in `pim batch`.
pub fn batch(files: &[CaseText], observer: &dyn Observer) -> serde_json::Value {
    let plan = pim_studies::batch::BatchPlan::new(
        &pim_fit::CostPreset::ALL,
        &pim_fit::MomentBranch::ALL,
        pim_fit::DEFAULT_E_RANGE[1],
        pim_core::MomentForm::Corrected,
    )
    .expect("the default plan is valid");
    let batch = CaseBatch {
        choices: vec![CostChoice::Custom],
        plan,
        draws: 0,
        seed: 1,
    };
    let records = batch.records(files, observer);
    let done = records.iter().filter(|r| !r.is_empty()).count();
    let records: Vec<&pim_studies::case_records::CaseRecord> = records.iter().flatten().collect();
    serde_json::json!({
        "files": files.len(),
        "records": records,
        "cancelled": (done < files.len()).then(|| serde_json::json!({ "asked": files.len(), "done": done })),
    })
}
