//! The sections only a fit has: the answer's ranges, the branches, each value given against
//! the fit with the fit statistics, and what the data do not determine.

use super::doc::{Block, Section, Table};
use crate::tables::{branch_short, num};
use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_documents::records::{BoundSource, BranchRecord};
use pim_studies::residuals::Residual;
use pim_studies::uncertainty::Study;

/// The answer's 90 % ranges from the uncertainty study.
pub(super) fn ranges(s: &mut Section, study: &Study, u: UnitSystem) {
    let st = study.in_speed_unit(u.speed(1.0));
    s.text(format!(
        "Ranges: {} refits of the crash with its inputs drawn from their stated uncertainties \
         (seed {}), {} with an admissible answer. 5 % of the refits fall below the low end and \
         5 % above the high end.",
        st.draws, st.seed, st.feasible_draws
    ));
    let sp = u.speed_label();
    let mut t = Table::new(&["quantity", "fitted", "5 %", "median", "95 %", "note"]);
    t.numeric[5] = false;
    for &name in st.names() {
        let q = &st.quantities[name];
        let label = match name {
            "e" => "restitution e".to_string(),
            "mu" => "impulse ratio mu".to_string(),
            "em" => "moment restitution em".to_string(),
            "et" => "tangential restitution et".to_string(),
            "friction" => "friction limit".to_string(),
            "speed1" => format!("vehicle 1 speed at contact [{sp}]"),
            "speed2" => format!("vehicle 2 speed at contact [{sp}]"),
            "delta_v1" => format!("vehicle 1 delta-V [{sp}]"),
            "delta_v2" => format!("vehicle 2 delta-V [{sp}]"),
            _ => "kinetic energy lost [%]".to_string(),
        };
        let note = if q.not_determined {
            "not determined by the data: not a confidence interval".to_string()
        } else if let Some(h) = q.reaches_bound {
            format!(
                "ended by the {} bound ({}; {} % of the refits rest on it)",
                h.bound,
                match h.source {
                    BoundSource::Case => "set in the case",
                    BoundSource::Default => "a default, not chosen for this crash",
                },
                num(100.0 * h.share, 0)
            )
        } else if name == "em" && st.branch_share.len() > 1 {
            "spans both moment branches (see below)".to_string()
        } else {
            String::new()
        };
        let prec = if name.starts_with('e') || name == "mu" {
            3
        } else {
            2
        };
        t.row(vec![
            label,
            st.nominal
                .get(name)
                .map_or_else(|| "-".into(), |v| num(*v, prec)),
            num(q.p05, prec),
            num(q.p50, prec),
            num(q.p95, prec),
            note,
        ]);
    }
    s.blocks.push(Block::Table(t));
    if !st.has_branches() {
        return;
    }
    let shares: Vec<String> = st
        .branch_share
        .iter()
        .map(|(b, v)| {
            let words = match b.as_str() {
                "free" => branch_short(pim_fit::MomentBranch::Free),
                "zero" => branch_short(pim_fit::MomentBranch::Zero),
                other => other,
            };
            format!("{words} in {} % of the refits", num(100.0 * v, 1))
        })
        .collect();
    s.text(format!("The best answer is: {}.", shares.join("; ")));
}

/// One row per moment branch (or the tangential model): its coefficients and fit.
pub(super) fn branches_table(r: &pim_fit::FitReport, records: &[BranchRecord]) -> Table {
    if r.model == pim_fit::FitModel::Tangential {
        return tangential_table(r);
    }
    let mut t = Table::new(&[
        "answer",
        "status",
        "e",
        "mu",
        "em",
        "cost",
        "chi-square (dof, p)",
        "energy lost [%]",
    ]);
    t.numeric[1] = false;
    for (b, rec) in r.branches.iter().zip(records) {
        let name = if r.model == pim_fit::FitModel::Tangential {
            "tangential model".to_string()
        } else {
            let best = if Some(b.moment) == r.best {
                " (best)"
            } else {
                ""
            };
            format!("{}{best}", branch_short(b.moment))
        };
        let chi = rec.chi_square.as_ref().map_or_else(
            || "-".to_string(),
            |c| {
                format!(
                    "{} ({}, {})",
                    num(c.value, 3),
                    c.degrees_of_freedom,
                    c.p_value
                        .map_or_else(|| "-".into(), crate::statistics::format_p)
                )
            },
        );
        match &b.solution {
            Some(s) => t.row(vec![
                name,
                format!("{:?}", b.status).to_lowercase(),
                num(s.e, 4),
                num(s.mu, 4),
                num(s.em, 4),
                num(s.cost, 5),
                chi,
                num(s.energy_loss_percent, 2),
            ]),
            None => t.row(without_answer(vec![
                name,
                format!("{:?}", b.status).to_lowercase(),
            ])),
        }
    }
    t
}

/// A residual's value in the display units and frame.
fn shown(r: &Residual, x: f64, u: UnitSystem, frame: Convention) -> f64 {
    let x = if r.lateral { frame.sign() * x } else { x };
    if r.unit == "rad/s" {
        u.yaw_rate(x)
    } else {
        u.speed(x)
    }
}

/// A component's name in words (`final.vehicle1.omega` -> `vehicle 1 yaw rate at
/// separation`); an observation's label as it is.
fn given_words(name: &str) -> String {
    let parts: Vec<&str> = name.split('.').collect();
    match parts.as_slice() {
        [state, vehicle, comp] if vehicle.starts_with("vehicle") => {
            let when = if *state == "initial" {
                "contact"
            } else {
                "separation"
            };
            let what = match *comp {
                "omega" => "yaw rate",
                other => other,
            };
            format!("vehicle {} {what} at {when}", &vehicle[7..])
        }
        _ => name.to_string(),
    }
}

/// The residual of every estimate and observation, and the fit statistics.
pub(super) fn residual_section(r: &BranchRecord, u: UnitSystem, frame: Convention) -> Section {
    let mut s = Section::new("Each value given against the fit");
    if r.residuals.is_empty() {
        s.text("No value was estimated: every component was known exactly.");
        return s;
    }
    s.text(
        "Residual = fitted - given, in the unit of its row. With standard deviations (sigma), \
         residual / sigma counts standard deviations; 'share' is the part of the cost the row \
         contributes.",
    );
    let mut t = Table::new(&[
        "value given",
        "unit",
        "given",
        "fitted",
        "residual",
        "sigma",
        "residual / sigma",
        "share of cost [%]",
    ]);
    t.numeric[1] = false;
    for x in &r.residuals {
        let unit = if x.unit == "rad/s" {
            u.yaw_rate_label()
        } else {
            u.speed_label()
        };
        t.row(vec![
            given_words(&x.name),
            unit.to_string(),
            num(shown(x, x.given, u, frame), 3),
            num(shown(x, x.fitted, u, frame), 3),
            num(shown(x, x.residual, u, frame), 3),
            x.sigma.map_or_else(
                || "-".into(),
                |sg| {
                    let sg = if x.unit == "rad/s" {
                        u.yaw_rate(sg)
                    } else {
                        u.speed(sg)
                    };
                    num(sg, 3)
                },
            ),
            x.normalised.map_or_else(
                || "-".into(),
                |n| num(if x.lateral { frame.sign() * n } else { n }, 2),
            ),
            x.share.map_or_else(|| "-".into(), |v| num(100.0 * v, 1)),
        ]);
    }
    s.blocks.push(Block::Table(t));
    match &r.chi_square {
        Some(c) => {
            let verdict = match c.p_value {
                Some(p) if p < 0.05 => {
                    "below 0.05: the misfit is larger than the stated standard deviations \
                     explain; check them and the values given"
                }
                Some(p) if p > 0.99 => {
                    "above 0.99: the fit is closer than the stated standard deviations \
                     suggest; they may be generous"
                }
                Some(_) => "the misfit is what the stated standard deviations lead one to expect",
                None => "not a number",
            };
            s.text(format!(
                "Fit statistics (degrees of freedom: values given minus parameters fitted): \
                 {}: {verdict}.",
                crate::statistics::chi_square_words(c.value, c.degrees_of_freedom, c.p_value)
            ));
        }
        None => {
            s.text(
                "The case gives weights, not standard deviations ([sigma]), so the cost has no \
                 chi-square reading.",
            );
        }
    }
    s
}

/// What the data do not pin down: loose coefficients, free velocity components, bounds, the
/// other branch; also the active limits, as warnings.
pub(super) fn undetermined(
    report: &pim_fit::FitReport,
    record: Option<&BranchRecord>,
    study: Option<&Study>,
    u: UnitSystem,
    warnings: &mut Vec<String>,
) -> Section {
    let mut s = Section::new("What the data do not determine");
    let mut items = Vec::new();
    if let Some(b) = report.best_branch() {
        for i in b.identifiability.iter().filter(|i| !i.identifiable) {
            items.push(format!(
                "{}: any value from {} to {}{} fits within {} % of the best cost.",
                i.coefficient,
                num(i.low, 3),
                num(i.high, 3),
                if i.open_ended { " and beyond" } else { "" },
                num(100.0 * i.tolerance, 0)
            ));
        }
        if let Some(sol) = &b.solution {
            if !sol.undetermined.is_empty() {
                let names: Vec<&str> = sol.undetermined.iter().map(|c| c.name()).collect();
                items.push(format!(
                    "the velocity components {} are neither given nor fixed by the equations: \
                     their fitted values are one choice of many.",
                    names.join(", ")
                ));
            }
        }
    }
    if let Some(r) = record {
        let bounds = crate::tables::bounds_lines(std::slice::from_ref(r), report.best, u);
        for line in bounds.lines() {
            items.push(line.to_string());
        }
    }
    if let Some(st) = study {
        for name in st
            .names()
            .iter()
            .filter(|q| st.quantities[**q].not_determined)
        {
            items.push(format!(
                "{name}: its spread over the refits is not a confidence interval (the data do \
                 not determine it)."
            ));
        }
    }
    if report.branches.len() == 2 {
        let costs: Vec<Option<f64>> = report
            .branches
            .iter()
            .map(|b| b.solution.as_ref().map(|s| s.cost))
            .collect();
        if let (Some(a), Some(b)) = (costs[0], costs[1]) {
            let (lo, hi) = (a.min(b), a.max(b));
            if hi <= lo * 1.1 + 1e-12 {
                items.push(format!(
                    "which moment branch: both fit about equally well (costs {} and {}).",
                    num(a, 5),
                    num(b, 5)
                ));
            }
        }
    }
    if let Some(sol) = report.best_branch().and_then(|b| b.solution.as_ref()) {
        for a in &sol.active_constraints {
            warnings.push(format!("the best answer is at the end of a range: {a}"));
        }
    }
    if items.is_empty() {
        s.text("Nothing found: every coefficient is pinned down within 1 % of the best cost and no bound is reached.");
    } else {
        s.blocks.push(Block::List(items));
    }
    s
}

/// The tangential model's row: contact mode, e, et and the friction limits that give the
/// answer.
fn tangential_table(r: &pim_fit::FitReport) -> Table {
    let mut t = Table::new(&[
        "status",
        "mode",
        "e",
        "et",
        "friction limit",
        "cost",
        "energy lost [%]",
    ]);
    t.numeric[1] = false;
    t.numeric[3] = false;
    t.numeric[4] = false;
    for b in &r.branches {
        let status = format!("{:?}", b.status).to_lowercase();
        match b
            .solution
            .as_ref()
            .and_then(|x| x.tangential.as_ref().map(|t| (x, t)))
        {
            Some((x, tf)) => {
                let (mode, et, friction) = match tf.mode {
                    pim_core::ContactMode::Stick => (
                        "stick",
                        num(tf.et, 4),
                        format!("{} to {}", num(tf.friction, 4), num(tf.friction_max, 4)),
                    ),
                    pim_core::ContactMode::Slide => (
                        "slide",
                        "any whose sticking would exceed the limit".to_string(),
                        num(tf.friction, 4),
                    ),
                };
                t.row(vec![
                    status,
                    mode.into(),
                    num(x.e, 4),
                    et,
                    friction,
                    num(x.cost, 5),
                    num(x.energy_loss_percent, 2),
                ]);
            }
            None => t.row(without_answer(vec![status])),
        }
    }
    t
}

/// A table row of a branch without an answer: its first cells, then a dash in each of the
/// six value columns.
fn without_answer(mut first: Vec<String>) -> Vec<String> {
    first.extend(std::iter::repeat_n("-".to_string(), 6));
    first
}
