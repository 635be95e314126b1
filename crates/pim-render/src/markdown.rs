//! The short Markdown reports of `pim solve --out` and `pim fit --out`.

use crate::tables::{tangential_words, vehicle_rows};
use pim_core::{Convention, ImpactReport, VehicleResult};
use pim_data::units::UnitSystem;
use std::fmt::Write as _;

/// The per-vehicle table (the rows of the text tables).
fn vehicles(s: &mut String, v: &[VehicleResult; 2], u: UnitSystem, frame: Convention) {
    let _ = writeln!(s, "| | vehicle 1 | vehicle 2 |\n|---|---:|---:|");
    for (label, [a, b]) in vehicle_rows(v, u, frame) {
        let label = match label.strip_prefix("  ") {
            Some(part) => format!("delta-V {part}"),
            None => label,
        };
        let _ = writeln!(s, "| {label} | {a} | {b} |");
    }
}

/// The report of a solve, in the unit system `u` and the frame `frame` (`r` already in it).
pub fn solve(
    title: &str,
    r: &ImpactReport,
    forward: bool,
    u: UnitSystem,
    frame: Convention,
) -> String {
    let mut s = String::new();
    let c = &r.coefficients;
    let _ = writeln!(s, "# {}\n", title.lines().next().unwrap_or(title));
    for line in title.lines().skip(1) {
        let _ = writeln!(s, "{line}\n");
    }
    let _ = writeln!(
        s,
        "Solved {} with e = {}, mu = {}, em = {}.\n\n![plan view at contact](diagram.svg)\n",
        if forward { "forwards" } else { "backwards" },
        c.e,
        c.mu,
        c.em
    );
    let _ = writeln!(s, "{}.\n", crate::tables::frame_line(frame));
    vehicles(&mut s, &r.vehicles, u, frame);
    let e = &r.energy;
    let _ = writeln!(
        s,
        "\nKinetic energy: {:.0} J at contact, {:.0} J at separation; loss {:.0} J ({:.2} %).\n",
        e.initial, e.final_, e.loss, e.loss_percent
    );
    let _ = writeln!(s, "Along the crush surface: {}.\n", tangential_words(r));
    if r.admissibility.admissible {
        let _ = writeln!(s, "The solution is physically admissible.");
    } else {
        let _ = writeln!(s, "**The solution is not physically admissible:**\n");
        for reason in r.inadmissibility_reasons() {
            let _ = writeln!(s, "- {reason}");
        }
    }
    let _ = writeln!(s, "\nEvery number, in SI, is in result.json.");
    s
}

/// The report of a fit.
pub fn fit(
    title: &str,
    cost: &str,
    r: &pim_fit::FitReport,
    u: UnitSystem,
    frame: Convention,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "# {}\n", title.lines().next().unwrap_or(title));
    let _ = writeln!(s, "Fit with cost function {cost}.\n");
    if r.model == pim_fit::FitModel::Tangential {
        tangential_fit(&mut s, r);
    } else {
        pim_fit_table(&mut s, r);
    }
    if let Some(sol) = r.best_branch().and_then(|b| b.solution.as_ref()) {
        let _ = writeln!(
            s,
            "\n## Best branch\n\n![plan view at contact, fitted velocities](diagram.svg)\n"
        );
        let (_, _, shown) = crate::tables::in_frame(sol, frame);
        vehicles(&mut s, &shown, u, frame);
        let _ = writeln!(
            s,
            "\nKinetic energy loss {:.0} {} ({:.2} %).",
            u.energy(sol.energy_loss),
            u.energy_label(),
            sol.energy_loss_percent
        );
    } else {
        let _ = writeln!(s, "\nNo branch has an admissible solution.");
    }
    let _ = writeln!(s, "\nEvery number, in SI, is in result.json.");
    s
}

/// The tangential model's line of a fit report: mode, e, et and the friction limits.
fn tangential_fit(s: &mut String, r: &pim_fit::FitReport) {
    let _ = writeln!(
        s,
        "Tangential-restitution model (normal restitution e, tangential restitution et, \
         friction limit; no moment impulse).\n"
    );
    let _ = writeln!(
        s,
        "| status | mode | e | et | friction limit | cost | energy loss [%] |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---|---:|---:|");
    for b in &r.branches {
        match b
            .solution
            .as_ref()
            .and_then(|x| x.tangential.as_ref().map(|t| (x, t)))
        {
            Some((x, t)) => {
                let (mode, et, friction) = match t.mode {
                    pim_core::ContactMode::Stick => (
                        "stick",
                        format!("{:+.4}", t.et),
                        format!("{:.4} to {:.4}", t.friction, t.friction_max),
                    ),
                    pim_core::ContactMode::Slide => (
                        "slide",
                        "any whose sticking would exceed the limit".to_string(),
                        format!("{:.4}", t.friction),
                    ),
                };
                let _ = writeln!(
                    s,
                    "| {} | {mode} | {:.4} | {et} | {friction} | {:.5} | {:.2} |",
                    b.status, x.e, x.cost, x.energy_loss_percent
                );
            }
            None => {
                let _ = writeln!(s, "| {} | | | | | | |", b.status);
            }
        }
        if let Some(reason) = &b.reason {
            let _ = writeln!(s, "\n{reason}");
        }
    }
}

/// PIM's table of a fit report: one row per branch, then the reasons and notes.
fn pim_fit_table(s: &mut String, r: &pim_fit::FitReport) {
    let _ = writeln!(
        s,
        "| branch | status | e | mu | em | cost | energy loss [%] |"
    );
    let _ = writeln!(s, "|---|---|---:|---:|---:|---:|---:|");
    for b in &r.branches {
        let best = if Some(b.moment) == r.best {
            " (best)"
        } else {
            ""
        };
        match &b.solution {
            Some(x) => {
                let _ = writeln!(
                    s,
                    "| {}{best} | {} | {:.4} | {:.4} | {:.4} | {:.5} | {:.2} |",
                    b.moment.name(),
                    b.status,
                    x.e,
                    x.mu,
                    x.em,
                    x.cost,
                    x.energy_loss_percent
                );
            }
            None => {
                let _ = writeln!(s, "| {} | {} | | | | | |", b.moment.name(), b.status);
            }
        }
    }
    for b in &r.branches {
        if let Some(reason) = &b.reason {
            let _ = writeln!(s, "\nBranch {}: {reason}", b.moment.name());
        }
    }
    for n in &r.notes {
        let _ = writeln!(s, "\nNote: {n}");
    }
}
