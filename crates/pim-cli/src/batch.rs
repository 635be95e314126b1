//! The RICSAC batch refit: every (test, cost function, moment branch) fitted, as flat records,
//! tables and CSV.

use crate::output::BranchRecord;
use crate::ricsac::RicsacTest;
use pim_fit::{CostPreset, FitProblem, FitSettings, MomentBranch, COMPONENT_NAMES};
use rayon::prelude::*;
use serde::Serialize;
use std::fmt::Write as _;

/// What to run.
#[derive(Debug, Clone)]
pub struct BatchPlan {
    /// Cost functions, in order.
    pub costs: Vec<CostPreset>,
    /// Moment branches, in order.
    pub branches: Vec<MomentBranch>,
    /// Fit settings (bounds, moment form) shared by every fit.
    pub settings: FitSettings,
    /// Record the wall time of each fit (makes the output differ from run to run).
    pub timing: bool,
}

/// One record per (test, cost, branch).
#[derive(Debug, Clone, Serialize)]
pub struct BatchRecord {
    /// RICSAC test number.
    pub test: u32,
    /// Cost function.
    pub cost_function: CostPreset,
    /// `optimal`, `infeasible`, `limit_reached` or `failed` (the row could not be fitted).
    pub outcome: String,
    /// Line of the data file.
    pub line: u64,
    /// The fitted branch (absent when the row failed).
    #[serde(flatten)]
    pub branch: Option<BranchRecord>,
    /// Why the row failed.
    pub error: Option<String>,
    /// The branch of this record (also when failed).
    pub moment_branch: MomentBranch,
    /// True for the best branch of this (test, cost).
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
}

impl BatchRecord {
    /// True when the record has an answer (optimal or limit reached).
    pub fn solved(&self) -> bool {
        self.outcome == "optimal" || self.outcome == "limit_reached"
    }
}

fn status_name(s: pim_fit::Status) -> String {
    s.to_string()
}

/// Runs the plan over the tests, in parallel; the records come out in (test, cost, branch)
/// order whatever the thread count. `tick` is called once per finished fit.
pub fn run(tests: &[RicsacTest], plan: &BatchPlan, tick: &(dyn Fn() + Sync)) -> Vec<BatchRecord> {
    let jobs: Vec<(&RicsacTest, CostPreset)> = tests
        .iter()
        .flat_map(|t| plan.costs.iter().map(move |&c| (t, c)))
        .collect();
    let results: Vec<Vec<BatchRecord>> = jobs
        .par_iter()
        .map(|&(t, cost)| {
            let start = std::time::Instant::now();
            let mut out = fit_one(t, cost, plan);
            if plan.timing {
                let secs = start.elapsed().as_secs_f64();
                out.iter_mut().for_each(|r| r.fit_seconds = Some(secs));
            }
            tick();
            out
        })
        .collect();
    results.into_iter().flatten().collect()
}

fn fit_one(t: &RicsacTest, cost: CostPreset, plan: &BatchPlan) -> Vec<BatchRecord> {
    let measured = [t.dv1_measured_mps, t.dv2_measured_mps];
    let failed = |msg: String| -> Vec<BatchRecord> {
        plan.branches
            .iter()
            .map(|&m| BatchRecord {
                test: t.test,
                cost_function: cost,
                outcome: "failed".to_string(),
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
            })
            .collect()
    };
    let impact = match t.impact() {
        Ok(i) => i,
        Err(e) => return failed(e.to_string()),
    };
    let settings = FitSettings {
        branches: plan.branches.clone(),
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
                outcome: status_name(b.status),
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
            }
        })
        .collect()
}

fn cost_title(c: CostPreset) -> &'static str {
    match c {
        CostPreset::Q1 => "Q1: separation velocities known exactly, contact velocities estimated",
        CostPreset::Q2 => {
            "Q2: contact velocities known exactly, separation velocities estimated (Brach's fits)"
        }
        CostPreset::Q3 => "Q3: all twelve velocity components estimated",
    }
}

fn f3(x: Option<f64>) -> String {
    x.map_or_else(|| "-".into(), |v| format!("{v:.3}"))
}

/// The summary table: one block per cost function (like Brach 1984 Table 1 and Vossou Table 3).
pub fn summary_table(records: &[BatchRecord], costs: &[CostPreset]) -> String {
    let mut s = String::new();
    for &c in costs {
        let _ = writeln!(s, "{}", cost_title(c));
        let _ = writeln!(
            s,
            "test branch status           e      em      mu  mu/mu_max     cost  loss %   |dV1| fit / meas   |dV2| fit / meas"
        );
        for r in records.iter().filter(|r| r.cost_function == c) {
            let best = if r.best { "*" } else { " " };
            match (&r.branch, r.solved()) {
                (Some(b), true) => {
                    let dv = b.delta_v.as_ref();
                    let _ = writeln!(
                        s,
                        "{:>4} {:<5}{best} {:<13} {:.3}  {:+.3}  {:+.3}  {:>9}  {:>7.3}  {:>6.1}   {:>6.2} / {:>5.2}    {:>6.2} / {:>5.2}",
                        r.test,
                        r.moment_branch.name(),
                        r.outcome,
                        b.e.unwrap_or(f64::NAN),
                        b.em.unwrap_or(f64::NAN),
                        b.mu.unwrap_or(f64::NAN),
                        f3(b.mu_ratio),
                        b.cost.unwrap_or(f64::NAN),
                        b.energy_loss_percent.unwrap_or(f64::NAN),
                        dv.map_or(f64::NAN, |d| d.vehicle1),
                        r.delta_v_measured[0],
                        dv.map_or(f64::NAN, |d| d.vehicle2),
                        r.delta_v_measured[1],
                    );
                }
                _ => {
                    let why = r
                        .error
                        .clone()
                        .or_else(|| {
                            r.branch
                                .as_ref()
                                .and_then(|b| b.reason.as_ref().map(|x| x.to_string()))
                        })
                        .unwrap_or_default();
                    let _ = writeln!(
                        s,
                        "{:>4} {:<5}  {:<13} {why}",
                        r.test,
                        r.moment_branch.name(),
                        r.outcome
                    );
                }
            }
        }
        let _ = writeln!(s, "(* = the branch with the lower cost)\n");
    }
    s
}

const SHORT: [&str; 12] = [
    "vi1x", "vi1y", "wi1", "vi2x", "vi2y", "wi2", "vf1x", "vf1y", "wf1", "vf2x", "vf2y", "wf2",
];

/// Per test, the cost functions side by side (best branch of each) and the error of every
/// velocity component against the measurement, the largest flagged (Vossou Tables 4-6).
pub fn compare_costs_table(records: &[BatchRecord], costs: &[CostPreset]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Fitted minus measured velocity per component (m/s, rad/s), best branch of each cost \
         function; * marks the largest |error| of a fit; '=' a component held fixed by that cost \
         function.\n"
    );
    let mut tests: Vec<u32> = records.iter().map(|r| r.test).collect();
    tests.dedup();
    for t in tests {
        let _ = write!(s, "test {t:>2}  ");
        let cols: Vec<Option<&BatchRecord>> = costs
            .iter()
            .map(|&c| {
                records
                    .iter()
                    .find(|r| r.test == t && r.cost_function == c && r.best)
            })
            .collect();
        for (c, r) in costs.iter().zip(&cols) {
            let label = match r {
                Some(r) => format!("{} ({})", c.name(), r.moment_branch.name()),
                None => format!("{} (none)", c.name()),
            };
            let _ = write!(s, "{label:>13}");
        }
        let _ = writeln!(s);
        for k in 0..12 {
            let _ = write!(s, "  {:<8}", SHORT[k]);
            for (c, r) in costs.iter().zip(&cols) {
                let fixed = matches!((c, k < 6), (CostPreset::Q1, false) | (CostPreset::Q2, true));
                let cell = match r.and_then(|r| r.velocity_error.map(|e| (e, r))) {
                    Some((e, r)) => {
                        let star = if r.max_error_component.as_deref() == Some(COMPONENT_NAMES[k]) {
                            "*"
                        } else {
                            " "
                        };
                        if fixed {
                            "=".to_string()
                        } else {
                            format!("{:+.2}{star}", e[k])
                        }
                    }
                    None => "-".to_string(),
                };
                let _ = write!(s, "{cell:>13}");
            }
            let _ = writeln!(s);
        }
        let _ = write!(s, "  {:<8}", "cost");
        for r in &cols {
            let _ = write!(
                s,
                "{:>13}",
                r.and_then(|r| r.branch.as_ref())
                    .map_or("infeasible".to_string(), |b| f3(b.cost))
            );
        }
        let _ = writeln!(s, "\n");
    }
    s
}

/// One row of Brach 1984 Table 1 (`data/reference/brach1984_table1.csv`).
#[derive(Debug, Clone, serde::Deserialize)]
pub struct BrachRow {
    /// A (em free) or B (em = 1).
    pub branch: String,
    /// Test number.
    pub test: u32,
    /// Brach's sum of squares (his units and weights).
    pub sum_of_squares: f64,
    /// Energy loss, percent.
    pub energy_loss_percent: f64,
    /// Restitution.
    pub e: f64,
    /// Moment restitution.
    pub em: f64,
    /// Friction.
    pub mu: f64,
}

/// Parses the Brach 1984 Table 1 reference file.
pub fn parse_brach(text: &str) -> Result<Vec<BrachRow>, String> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    rdr.deserialize()
        .collect::<Result<Vec<BrachRow>, _>>()
        .map_err(|e| e.to_string())
}

/// Our Q2 fits beside Brach 1984 Table 1 (branch free vs A, zero vs B).
pub fn brach_table(records: &[BatchRecord], brach: &[BrachRow]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Q2 against Brach 1984 Table 1 (A: em in [-1, 0], B: em = 1). Brach allowed e up to 0.42;\n\
         differences for tests 7, 10, 12 come from the data (see data/README.md).\n\
         test br |     e  Brach |     em  Brach |     mu  Brach | loss %  Brach |  cost  Brach's SS"
    );
    for r in records.iter().filter(|r| r.cost_function == CostPreset::Q2) {
        let letter = if r.moment_branch == MomentBranch::Free {
            "A"
        } else {
            "B"
        };
        let Some(b) = brach
            .iter()
            .find(|b| b.test == r.test && b.branch == letter)
        else {
            continue;
        };
        let ours = r.branch.as_ref().filter(|_| r.solved());
        let g = |f: fn(&BranchRecord) -> Option<f64>| {
            ours.and_then(f)
                .map_or("     -".into(), |v| format!("{v:+.3}"))
        };
        let _ = writeln!(
            s,
            "{:>4} {}  | {} {:+.3} | {} {:+.3} | {} {:+.3} | {:>6} {:>6.1} | {:>5} {:>6.1}",
            r.test,
            letter,
            g(|b| b.e),
            b.e,
            g(|b| b.em),
            b.em,
            g(|b| b.mu),
            b.mu,
            ours.and_then(|o| o.energy_loss_percent)
                .map_or("-".into(), |v| format!("{v:.1}")),
            b.energy_loss_percent,
            ours.and_then(|o| o.cost)
                .map_or("-".into(), |v| format!("{v:.2}")),
            b.sum_of_squares
        );
    }
    s
}

/// A flat CSV row.
#[derive(Debug, Serialize)]
struct CsvRow {
    test: u32,
    cost_function: &'static str,
    branch: &'static str,
    best: bool,
    outcome: String,
    reason: Option<String>,
    e: Option<f64>,
    mu: Option<f64>,
    em: Option<f64>,
    mu_max: Option<f64>,
    mu_ratio: Option<f64>,
    sticking: Option<bool>,
    cost: Option<f64>,
    energy_loss_percent: Option<f64>,
    dv1_fitted: Option<f64>,
    dv1_measured: f64,
    dv2_fitted: Option<f64>,
    dv2_measured: f64,
    max_residual: Option<f64>,
    admissible: Option<bool>,
    max_error_component: Option<String>,
    max_error: Option<f64>,
}

/// The records as CSV (one row per record; velocity errors in [`errors_csv`]).
pub fn records_csv(records: &[BatchRecord]) -> Result<String, String> {
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in records {
        let b = r.branch.as_ref();
        w.serialize(CsvRow {
            test: r.test,
            cost_function: r.cost_function.name(),
            branch: r.moment_branch.name(),
            best: r.best,
            outcome: r.outcome.clone(),
            reason: r
                .error
                .clone()
                .or_else(|| b.and_then(|b| b.reason.as_ref().map(|x| x.to_string()))),
            e: b.and_then(|b| b.e),
            mu: b.and_then(|b| b.mu),
            em: b.and_then(|b| b.em),
            mu_max: b.and_then(|b| b.mu_max),
            mu_ratio: b.and_then(|b| b.mu_ratio),
            sticking: b.and_then(|b| b.sticking),
            cost: b.and_then(|b| b.cost),
            energy_loss_percent: b.and_then(|b| b.energy_loss_percent),
            dv1_fitted: b.and_then(|b| b.delta_v.as_ref().map(|d| d.vehicle1)),
            dv1_measured: r.delta_v_measured[0],
            dv2_fitted: b.and_then(|b| b.delta_v.as_ref().map(|d| d.vehicle2)),
            dv2_measured: r.delta_v_measured[1],
            max_residual: b.and_then(|b| b.max_residual),
            admissible: b.and_then(|b| b.admissible),
            max_error_component: r.max_error_component.clone(),
            max_error: r.max_error,
        })
        .map_err(|e| e.to_string())?;
    }
    let bytes = w.into_inner().map_err(|e| e.to_string())?;
    String::from_utf8(bytes).map_err(|e| e.to_string())
}

/// Fitted minus measured velocity per component and record, as CSV.
pub fn errors_csv(records: &[BatchRecord]) -> String {
    let mut s = String::from("test,cost_function,branch");
    for n in SHORT {
        s.push(',');
        s.push_str(n);
    }
    s.push('\n');
    for r in records {
        let _ = write!(
            s,
            "{},{},{}",
            r.test,
            r.cost_function.name(),
            r.moment_branch.name()
        );
        for k in 0..12 {
            match r.velocity_error {
                Some(e) => {
                    let _ = write!(s, ",{}", e[k]);
                }
                None => s.push(','),
            }
        }
        s.push('\n');
    }
    s
}
