//! Tables, CSV files and the Brach 1984 comparison of a batch run.

use pim_case::reference::BrachRow;
use pim_case::units::UnitSystem;
use pim_documents::records::BranchRecord;
use pim_fit::{CostPreset, MomentBranch, COMPONENT_NAMES};
use pim_studies::batch::{BatchRecord, Outcome};
use pim_studies::uncertainty::Summary;
use serde::Serialize;
use std::fmt::Write as _;

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
    // No "-0.000" for a value that rounds to zero.
    x.map_or_else(
        || "-".into(),
        |v| format!("{:.3}", if v.abs() < 5e-4 { 0.0 } else { v }),
    )
}

/// The summary table: one block per cost function (like Brach 1984 Table 1 and Vossou Table 3).
pub fn summary_table(records: &[BatchRecord], costs: &[CostPreset], u: UnitSystem) -> String {
    let mut s = String::new();
    for &c in costs {
        let _ = writeln!(s, "{}", cost_title(c));
        let _ = writeln!(
            s,
            "test branch status           e      em      mu  mu/mu_max     cost  loss %   |dV1| fit / meas   |dV2| fit / meas  active"
        );
        for r in records.iter().filter(|r| r.cost_function == c) {
            let best = if r.best { "*" } else { " " };
            match (&r.branch, r.solved()) {
                (Some(b), true) => {
                    let dv = b.delta_v.as_ref();
                    let _ = writeln!(
                        s,
                        "{:>4} {:<5}{best} {:<13} {:.3}  {:+.3}  {:+.3}  {:>9}  {:>7.3}  {:>6.1}   {:>6.2} / {:>5.2}    {:>6.2} / {:>5.2}  {}",
                        r.test,
                        r.moment_branch.name(),
                        r.outcome,
                        b.e.unwrap_or(f64::NAN),
                        b.em.unwrap_or(f64::NAN),
                        b.mu.unwrap_or(f64::NAN),
                        f3(b.mu_ratio),
                        b.cost.unwrap_or(f64::NAN),
                        b.energy_loss_percent.unwrap_or(f64::NAN),
                        u.speed(dv.map_or(f64::NAN, |d| d.vehicle1)),
                        u.speed(r.delta_v_measured[0]),
                        u.speed(dv.map_or(f64::NAN, |d| d.vehicle2)),
                        u.speed(r.delta_v_measured[1]),
                        b.active_constraints
                            .iter()
                            .map(|a| a.short())
                            .collect::<Vec<_>>()
                            .join(" "),
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
        let _ = writeln!(
            s,
            "(* = the branch with the lower cost; active: constraints and coefficient bounds that \
             hold with equality at the optimum{})\n",
            if u == UnitSystem::Si {
                String::new()
            } else {
                format!("; delta-V in {}, the cost in (m/s)^2", u.speed_label())
            }
        );
    }
    s
}

/// The models side by side (`pim batch --model pim,tangential`): per cost function and test,
/// the best fit of each model with its coefficients, cost, energy loss and delta-V errors, and
/// per model the mean |delta-V error| over the tests both solved.
pub fn models_table(records: &[BatchRecord], costs: &[CostPreset]) -> String {
    use pim_fit::FitModel;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "The two models side by side: PIM (e, mu, em; best branch) and the tangential model \
         (e, et, friction limit; no moment impulse). dV err = (fitted - measured) / measured \
         |delta-V|, percent.\n"
    );
    let mut tests: Vec<u32> = records.iter().map(|r| r.test).collect();
    tests.dedup();
    let best = |t: u32, c: CostPreset, m: FitModel| {
        records
            .iter()
            .find(|r| r.test == t && r.cost_function == c && r.model == m && r.best && r.solved())
    };
    let pct = |r: &BatchRecord, k: usize| r.delta_v_relative_error.map(|e| 100.0 * e[k]);
    let num = |x: Option<f64>, w: usize, p: usize| {
        x.map_or_else(|| format!("{:>w$}", "-"), |v| format!("{v:>w$.p$}"))
    };
    for &c in costs {
        let _ = writeln!(s, "{}", cost_title(c));
        let _ = writeln!(
            s,
            "test | PIM   branch  e      mu      em       cost  loss %  dV1 err  dV2 err | tangential  e      et     friction        cost  loss %  dV1 err  dV2 err"
        );
        let mut sums = [[0.0_f64; 2]; 2];
        let mut both = 0usize;
        let mut not_worse = 0usize;
        for &t in &tests {
            let (p, q) = (best(t, c, FitModel::Pim), best(t, c, FitModel::Tangential));
            let pim_text = p
                .and_then(|r| r.branch.as_ref().map(|b| (r, b)))
                .map_or_else(
                    || format!("{:<52}", "  no solution"),
                    |(r, b)| {
                        format!(
                            "{:<5} {:.3}  {:+.3}  {:+.3} {} {} {} {}",
                            r.moment_branch.name(),
                            b.e.unwrap_or(f64::NAN),
                            b.mu.unwrap_or(f64::NAN),
                            b.em.unwrap_or(f64::NAN),
                            num(b.cost, 9, 4),
                            num(b.energy_loss_percent, 6, 1),
                            num(pct(r, 0), 7, 1),
                            num(pct(r, 1), 7, 1),
                        )
                    },
                );
            let tan_text = q
                .and_then(|r| r.branch.as_ref().map(|b| (r, b)))
                .map_or_else(
                    || "no solution".to_string(),
                    |(r, b)| {
                        let t = b.tangential.as_ref();
                        let friction = t.map_or_else(
                            || "-".to_string(),
                            |t| match t.mode {
                                pim_core::ContactMode::Slide => format!("{:.3} slide", t.friction),
                                pim_core::ContactMode::Stick => {
                                    format!(">={:.3} stick", t.friction)
                                }
                            },
                        );
                        format!(
                            "{:.3}  {}  {:<14} {} {} {} {}",
                            b.e.unwrap_or(f64::NAN),
                            t.map_or_else(|| "  -   ".to_string(), |t| format!("{:+.3}", t.et)),
                            friction,
                            num(b.cost, 9, 4),
                            num(b.energy_loss_percent, 6, 1),
                            num(pct(r, 0), 7, 1),
                            num(pct(r, 1), 7, 1),
                        )
                    },
                );
            let _ = writeln!(s, "{t:>4} | {pim_text} | {tan_text}");
            if let (Some(p), Some(q)) = (p, q) {
                if let (Some(a), Some(b)) = (p.delta_v_relative_error, q.delta_v_relative_error) {
                    both += 1;
                    for k in 0..2 {
                        sums[0][k] += a[k].abs();
                        sums[1][k] += b[k].abs();
                    }
                }
                let cost = |r: &BatchRecord| r.branch.as_ref().and_then(|b| b.cost);
                if let (Some(a), Some(b)) = (cost(p), cost(q)) {
                    if b <= a * (1.0 + 1e-6) + 1e-9 {
                        not_worse += 1;
                    }
                }
            }
        }
        if both > 0 {
            let n = both as f64;
            let _ = writeln!(
                s,
                "mean |dV err| over the {both} tests both models solve: PIM {:.1} % / {:.1} %, \
                 tangential {:.1} % / {:.1} % (vehicle 1 / 2); the tangential model's cost is \
                 at most PIM's in {not_worse} of them",
                100.0 * sums[0][0] / n,
                100.0 * sums[0][1] / n,
                100.0 * sums[1][0] / n,
                100.0 * sums[1][1] / n,
            );
        }
        let _ = writeln!(s);
    }
    s
}

const SHORT: [&str; 12] = [
    "vi1x", "vi1y", "wi1", "vi2x", "vi2y", "wi2", "vf1x", "vf1y", "wf1", "vf2x", "vf2y", "wf2",
];

/// Per test, the cost functions side by side (best branch of each) and the error of every
/// velocity component against the measurement, the largest flagged (Vossou Tables 4-6).
pub fn compare_costs_table(records: &[BatchRecord], costs: &[CostPreset], u: UnitSystem) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Fitted minus measured velocity per component ({}, {}), best branch of each cost \
         function; * marks the largest |error| of a fit; '=' a component held fixed by that cost \
         function.\n",
        u.speed_label(),
        u.yaw_rate_label()
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
                let fixed = c.holds_fixed(k);
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
                            let x = if k % 3 == 2 {
                                u.yaw_rate(e[k])
                            } else {
                                u.speed(e[k])
                            };
                            format!("{x:+.2}{star}")
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

/// Our free-branch fits under Vossou & Koulocheris (2018)'s conditions beside the costs they
/// print (`printed`: per cost function, per test, the sum of their squared errors).
pub fn v18_table(records: &[BatchRecord], printed: &[(CostPreset, Vec<(u32, f64)>)]) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Against Vossou & Koulocheris 2018 Tables 4-6, under their conditions (Brach's 1983 moment\n\
         equation, mu in [0, 1.2] without mu <= mu_max, e in [0, 0.2], em in [-1, 0]). Their cost is\n\
         the sum of the squares they print (where a fitted component changes sign, those squares\n\
         understate it; see data/README.md).\n\
         test cost | V18 printed | ours    ours - V18 |      e      mu      em  mu_max | admissible"
    );
    for (cost, rows) in printed {
        for &(test, theirs) in rows {
            let Some(r) = records.iter().find(|r| {
                r.test == test
                    && r.cost_function == *cost
                    && r.model == pim_fit::FitModel::Pim
                    && r.moment_branch == MomentBranch::Free
            }) else {
                continue;
            };
            let ours = r.branch.as_ref().filter(|_| r.solved());
            let num = |v: Option<f64>, w: usize| {
                v.map_or(format!("{:>w$}", "-"), |v| format!("{v:>w$.3}"))
            };
            let cost_ours = ours.and_then(|o| o.cost);
            let _ = writeln!(
                s,
                "{test:>4} {:<4} | {theirs:>11.2} | {} {} | {} {} {} {} | {}",
                cost.name(),
                cost_ours.map_or(format!("{:>7}", r.outcome.to_string()), |c| format!(
                    "{c:>7.2}"
                )),
                cost_ours.map_or(format!("{:>12}", "-"), |c| format!("{:>+12.2}", c - theirs)),
                num(ours.and_then(|o| o.e), 6),
                num(ours.and_then(|o| o.mu), 7),
                num(ours.and_then(|o| o.em), 7),
                num(ours.and_then(|o| o.mu_max), 7),
                match ours.and_then(|o| o.admissible) {
                    Some(true) => "yes",
                    Some(false) => "no",
                    None => "-",
                },
            );
        }
    }
    s
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
    model: &'static str,
    branch: &'static str,
    best: bool,
    outcome: Outcome,
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
    speed1_p05: Option<f64>,
    speed1_p95: Option<f64>,
    speed2_p05: Option<f64>,
    speed2_p95: Option<f64>,
    delta_v1_p05: Option<f64>,
    delta_v1_p95: Option<f64>,
    delta_v2_p05: Option<f64>,
    delta_v2_p95: Option<f64>,
    /// Tangential model: stick or slide, et, and the friction limits that give the answer.
    contact_mode: Option<&'static str>,
    et: Option<f64>,
    friction: Option<f64>,
    friction_max: Option<f64>,
}

/// One end of a record's bootstrap interval, when it has one.
fn band(r: &BatchRecord, q: &str, end: fn(&Summary) -> f64) -> Option<f64> {
    r.intervals.as_ref().and_then(|i| i.get(q)).map(end)
}

/// The 90 % intervals of a data-file batch with `--draws`: per test and cost function (best
/// branch), the fitted value and the 5th-95th percentile range of the impact speeds, delta-V,
/// e and the energy loss. `?` marks a quantity the data do not determine (the range is not a
/// confidence statement), `|` a range that a bound of the search ends.
pub fn intervals_table(records: &[BatchRecord], draws: usize, seed: u64, u: UnitSystem) -> String {
    let sp = u.speed_label();
    let mut s = format!(
        "\n90 % intervals from {draws} draws (seed {seed}) of the stated tolerances, best branch of \
         each test and cost function: p05 - p95\n\
         ? = not determined by the data, | = ended by a search bound\n\
         test cost  branch   {:<16}{:<16}{:<16}{:<16}e               loss %\n",
        format!("speed1 {sp}"),
        format!("speed2 {sp}"),
        format!("|dV1| {sp}"),
        format!("|dV2| {sp}"),
    );
    for r in records.iter().filter(|r| r.best) {
        let _ = write!(
            s,
            "{:>4} {:<4}  {:<6}",
            r.test,
            r.cost_function.name(),
            r.moment_branch.name()
        );
        match (&r.intervals, &r.intervals_error) {
            (Some(i), _) => {
                for q in [
                    "speed1",
                    "speed2",
                    "delta_v1",
                    "delta_v2",
                    "e",
                    "energy_loss_percent",
                ] {
                    let cell = i.get(q).map_or_else(
                        || "-".to_string(),
                        |x| {
                            let flag = if x.not_determined {
                                "?"
                            } else if x.reaches_bound.is_some() {
                                "|"
                            } else {
                                ""
                            };
                            let d = if q == "e" { 3 } else { 2 };
                            let k = if q.starts_with("speed") || q.starts_with("delta_v") {
                                u.speed(1.0)
                            } else {
                                1.0
                            };
                            format!("{:.d$} - {:.d$}{flag}", k * x.p05, k * x.p95)
                        },
                    );
                    let _ = write!(s, "  {cell:<14}");
                }
                s.push('\n');
            }
            (None, Some(e)) => {
                let _ = writeln!(s, "  no intervals: {e}");
            }
            (None, None) => s.push('\n'),
        }
    }
    s.push('\n');
    s
}

/// The records as CSV (one row per record; velocity errors in [`errors_csv`]).
pub fn records_csv(records: &[BatchRecord]) -> Result<String, crate::RenderError> {
    let tan = |r: &BatchRecord| r.branch.as_ref().and_then(|b| b.tangential.clone());
    let mut w = csv::Writer::from_writer(Vec::new());
    for r in records {
        let b = r.branch.as_ref();
        w.serialize(CsvRow {
            test: r.test,
            cost_function: r.cost_function.name(),
            model: r.model.name(),
            branch: r.moment_branch.name(),
            best: r.best,
            outcome: r.outcome,
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
            speed1_p05: band(r, "speed1", |s| s.p05),
            speed1_p95: band(r, "speed1", |s| s.p95),
            speed2_p05: band(r, "speed2", |s| s.p05),
            speed2_p95: band(r, "speed2", |s| s.p95),
            delta_v1_p05: band(r, "delta_v1", |s| s.p05),
            delta_v1_p95: band(r, "delta_v1", |s| s.p95),
            delta_v2_p05: band(r, "delta_v2", |s| s.p05),
            delta_v2_p95: band(r, "delta_v2", |s| s.p95),
            contact_mode: tan(r).map(|t| match t.mode {
                pim_core::ContactMode::Stick => "stick",
                pim_core::ContactMode::Slide => "slide",
            }),
            et: tan(r).map(|t| t.et),
            friction: tan(r).map(|t| t.friction),
            friction_max: tan(r).map(|t| t.friction_max),
        })
        .map_err(crate::csv_error)?;
    }
    let bytes = w.into_inner().map_err(crate::csv_error)?;
    String::from_utf8(bytes).map_err(crate::csv_error)
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
