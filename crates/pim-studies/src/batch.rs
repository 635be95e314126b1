//! The RICSAC batch refit: every (test, cost function, moment branch) fitted, as flat, typed
//! records.

use crate::fitcase::CostChoice;
use crate::uncertainty::{Summary, Tolerances};
use pim_case::ricsac::RicsacTest;
pub use pim_documents::batch::{BatchRecord, Outcome};
use pim_documents::records::BranchRecord;
use pim_fit::{CostPreset, FitModel, FitProblem, FitSettings, MomentBranch, COMPONENT_NAMES};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// What to run.
#[derive(Debug, Clone)]
pub struct BatchPlan {
    /// Cost functions, in order.
    pub costs: Vec<CostPreset>,
    /// Moment branches, in order (of PIM; the tangential model has one).
    pub branches: Vec<MomentBranch>,
    /// Models fitted, in order (default PIM only).
    pub models: Vec<FitModel>,
    /// Fit settings (bounds, moment form) shared by every fit.
    pub settings: FitSettings,
    /// Record the wall time of each fit (makes the output differ from run to run).
    pub timing: bool,
    /// The upper bound of e given for the batch (`--e-max`), which case files without
    /// `[bounds] e` take instead of e's physical range; `None` when not given.
    pub case_e_max: Option<f64>,
}

/// A batch plan that cannot be made.
#[derive(Debug, thiserror::Error)]
pub enum PlanError {
    /// e's upper bound gives no range of e the fit accepts.
    #[error("e_max {e_max}: {source}")]
    EMax {
        /// The upper bound asked for.
        e_max: f64,
        /// Why the fit refuses it.
        #[source]
        source: pim_fit::FitError,
    },
}

impl BatchPlan {
    /// The settings a case of the batch starts from (its `[bounds]` then apply, see
    /// [`crate::fitcase::settings_from`]): the plan's branches and moment form.
    pub fn case_settings(&self) -> FitSettings {
        FitSettings {
            branches: self.branches.clone(),
            ..self.settings.clone()
        }
    }

    /// A case file of the batch with what the batch states for every case: e's upper bound
    /// `--e-max`, when given, where the file's `[bounds]` does not set e.
    pub fn apply_to_case_file(&self, case: &mut pim_case::case::Case) {
        if let Some(hi) = self.case_e_max {
            case.bound_e_unless_set(hi);
        }
    }

    /// A data-file test as a case with the batch's bounds stated (V18's velocity and yaw-rate
    /// bounds, e and mu of the plan), so that its draws search what its fit searched.
    pub fn apply_to_data_case(&self, case: &mut pim_case::case::Case) {
        let s = &self.settings;
        case.state_bounds(s.e, s.mu, s.velocity_bound, s.yaw_rate_bound);
    }

    /// Vossou & Koulocheris (2018)'s conditions: Brach's 1983 moment equation, mu in
    /// [0, 1.2] bounded by that box alone (no mu <= mu_max), e_m in [-1, 0] (the free branch
    /// only); e, the velocity and yaw-rate bounds as the plan has them (V18's are the defaults:
    /// e in [0, 0.2], 20 m/s, 5 rad/s).
    pub fn with_v18_conditions(mut self) -> Self {
        self.settings.moment_form = pim_core::MomentForm::Brach1983;
        self.settings.mu = [0.0, 1.2];
        self.settings.mu_max_condition = false;
        self.branches = vec![MomentBranch::Free];
        self
    }

    /// A plan with the default fit settings except the upper bound of e and the moment form,
    /// checked once (a bad value is an error, not a failed record per fit). Repeated costs and
    /// branches are kept once, in their first order.
    pub fn new(
        costs: &[CostPreset],
        branches: &[MomentBranch],
        e_max: f64,
        moment_form: pim_core::MomentForm,
    ) -> std::result::Result<Self, PlanError> {
        let settings = FitSettings {
            e: [0.0, e_max],
            moment_form,
            ..Default::default()
        };
        settings
            .clone()
            .check()
            .map_err(|source| PlanError::EMax { e_max, source })?;
        fn unique<T: Copy + PartialEq>(v: &[T]) -> Vec<T> {
            let mut out: Vec<T> = Vec::new();
            for x in v {
                if !out.contains(x) {
                    out.push(*x);
                }
            }
            out
        }
        Ok(BatchPlan {
            costs: unique(costs),
            branches: unique(branches),
            models: vec![FitModel::Pim],
            settings,
            timing: false,
            case_e_max: None,
        })
    }

    /// The same plan fitting these models (repeats kept once, in their first order).
    pub fn with_models(mut self, models: &[FitModel]) -> Self {
        self.models = Vec::new();
        for m in models {
            if !self.models.contains(m) {
                self.models.push(*m);
            }
        }
        self
    }
}

/// Runs the plan over the tests, in parallel; the records come out in (test, cost, model,
/// branch) order whatever the thread count. The observer sees each finished job (phase
/// `fits`: all the models of a test and cost); once it cancels, no new job starts and the
/// records of the jobs finished are returned.
pub fn run(
    tests: &[RicsacTest],
    plan: &BatchPlan,
    observer: &dyn crate::watch::Observer,
) -> Vec<BatchRecord> {
    let jobs: Vec<(&RicsacTest, CostPreset)> = tests
        .iter()
        .flat_map(|t| plan.costs.iter().map(move |&c| (t, c)))
        .collect();
    let phase = crate::watch::Phase::start(observer, "fits", jobs.len());
    let results: Vec<Vec<BatchRecord>> = jobs
        .par_iter()
        .map(|&(t, cost)| {
            if phase.stopped() {
                return Vec::new();
            }
            let start = std::time::Instant::now();
            let mut out: Vec<BatchRecord> = plan
                .models
                .iter()
                .flat_map(|&m| fit_one(t, cost, m, plan))
                .collect();
            if plan.timing {
                let secs = start.elapsed().as_secs_f64();
                out.iter_mut().for_each(|r| r.fit_seconds = Some(secs));
            }
            phase.step();
            out
        })
        .collect();
    results.into_iter().flatten().collect()
}

fn fit_one(
    t: &RicsacTest,
    cost: CostPreset,
    model: FitModel,
    plan: &BatchPlan,
) -> Vec<BatchRecord> {
    let measured = [t.dv1_measured_mps, t.dv2_measured_mps];
    let branches = model.branches(&plan.branches);
    let failed = |msg: String| -> Vec<BatchRecord> {
        branches
            .iter()
            .map(|&m| BatchRecord {
                test: t.test,
                cost_function: cost,
                model,
                outcome: Outcome::Failed,
                line: t.line,
                branch: None,
                error: Some(msg.clone()),
                moment_branch: m,
                best: false,
                delta_v_measured: measured,
                delta_v_relative_error: None,
                velocity_error: None,
                max_error_component: None,
                max_error: None,
                fit_seconds: None,
                intervals: None,
                intervals_error: None,
            })
            .collect()
    };
    let impact = match t.impact() {
        Ok(i) => i,
        Err(e) => return failed(e.to_string()),
    };
    let settings = FitSettings {
        model,
        branches: branches.clone(),
        ..plan.settings.clone()
    };
    let settings = match settings.check() {
        Ok(s) => s,
        Err(e) => return failed(e.to_string()),
    };
    let problem = FitProblem::from_preset(impact, cost, &t.initial(), &t.separation(), None);
    let report = match pim_fit::fit(&problem, &settings) {
        Ok(r) => r,
        Err(e) => return failed(e.to_string()),
    };
    let mut meas = [0.0; 12];
    meas[..6].copy_from_slice(t.initial().to_vector().as_slice());
    meas[6..].copy_from_slice(t.separation().to_vector().as_slice());
    report
        .branches
        .iter()
        .map(|b| {
            let rec = BranchRecord::new(b);
            let fitted = match (&rec.initial, &rec.final_) {
                (Some(i), Some(f)) => {
                    let mut u = [0.0; 12];
                    u[..6].copy_from_slice(&i.to_array());
                    u[6..].copy_from_slice(&f.to_array());
                    Some(u)
                }
                _ => None,
            };
            let err = fitted.map(|u| {
                let mut e = [0.0; 12];
                for k in 0..12 {
                    e[k] = u[k] - meas[k];
                }
                e
            });
            let (max_c, max_e) = match err {
                Some(e) => {
                    let k = (0..12)
                        .max_by(|&a, &b| e[a].abs().total_cmp(&e[b].abs()))
                        .unwrap_or(0);
                    (Some(COMPONENT_NAMES[k].to_string()), Some(e[k]))
                }
                None => (None, None),
            };
            let rel = rec.delta_v.as_ref().map(|dv| {
                [
                    (dv.vehicle1 - measured[0]) / measured[0],
                    (dv.vehicle2 - measured[1]) / measured[1],
                ]
            });
            BatchRecord {
                test: t.test,
                cost_function: cost,
                model,
                outcome: b.status.into(),
                line: t.line,
                best: report.best == Some(b.moment),
                moment_branch: b.moment,
                branch: Some(rec),
                error: None,
                delta_v_measured: measured,
                delta_v_relative_error: rel,
                velocity_error: err,
                max_error_component: max_c,
                max_error: max_e,
                fit_seconds: None,
                intervals: None,
                intervals_error: None,
            }
        })
        .collect()
}

/// The summaries of `pim uncertainty` for one case under one cost function and the plan's
/// branches and settings.
pub(crate) fn intervals(
    case: &pim_case::case::Case,
    cost: CostChoice,
    plan: &BatchPlan,
    draws: usize,
    seed: u64,
) -> pim_case::Result<BTreeMap<String, Summary>> {
    let unc = case.spreads();
    crate::uncertainty::run(
        case,
        &unc,
        cost,
        plan.case_settings(),
        draws,
        seed,
        &crate::watch::Unwatched,
    )
    .map(|s| s.quantities)
}

/// Adds the bootstrap intervals of `pim uncertainty` to the best record of each (test, cost) of
/// a data-file batch: each test's measured velocities are the estimates, `tolerances` gives
/// every test the same standard deviations, and the draws are those of `pim uncertainty` with
/// `draws` and `seed` (the same for every test). `file` names the data file in messages.
pub fn add_data_intervals(
    records: &mut [BatchRecord],
    tests: &[RicsacTest],
    file: &str,
    tolerances: &Tolerances,
    plan: &BatchPlan,
    draws: usize,
    seed: u64,
) {
    // The draws fit PIM (the plan's settings): its best records get them.
    for r in records
        .iter_mut()
        .filter(|r| r.best && r.model == FitModel::Pim)
    {
        let Some(t) = tests.iter().find(|t| t.test == r.test) else {
            continue;
        };
        let study = t
            .case(&format!("{file} test {}", t.test))
            .and_then(|mut case| {
                plan.apply_to_data_case(&mut case);
                tolerances.apply(&mut case);
                intervals(
                    &case,
                    CostChoice::Preset(r.cost_function),
                    plan,
                    draws,
                    seed,
                )
            });
        match study {
            Ok(s) => r.intervals = Some(s),
            Err(e) => r.intervals_error = Some(e.message),
        }
    }
}
