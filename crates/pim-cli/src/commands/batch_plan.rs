//! The plan of a batch (a data file or case files) from its flags.

use crate::args::{unique, BatchArgs};
use crate::error::Failure;
use pim_studies::batch;

/// The plan of a batch from its flags, checked once (a bad flag is an input error, not a failed
/// record per fit): `--threads`, `--e-max`, `--moment-form`, `--cost`, `--branch`, `--timing`.
/// Without `--cost`, a data file is refitted under Q1, Q2 and Q3 (`costs`; case files then fit
/// their own cost instead).
pub fn plan(a: &BatchArgs) -> Result<batch::BatchPlan, Failure> {
    if a.threads == Some(0) {
        return Err(Failure::Input("--threads must be at least 1".into()));
    }
    let costs: Vec<pim_fit::CostPreset> = if a.cost.is_empty() {
        pim_fit::CostPreset::ALL.to_vec()
    } else {
        unique(&a.cost)
    };
    let branches: Vec<pim_fit::MomentBranch> = unique(&a.branch);
    let e_max = a.e_max.unwrap_or(pim_fit::DEFAULT_E_RANGE[1]);
    let mut plan =
        batch::BatchPlan::new(&costs, &branches, e_max, a.moment_form).map_err(|e| match e {
            batch::PlanError::EMax { e_max, source } => {
                Failure::Input(format!("--e-max {e_max}: {source}"))
            }
        })?;
    if a.conditions == crate::args::Conditions::V18 {
        plan = plan.with_v18_conditions();
    }
    plan.timing = a.timing;
    plan.case_e_max = a.e_max;
    let models: Vec<pim_fit::FitModel> = a.model.to_vec();
    Ok(plan.with_models(&models))
}
