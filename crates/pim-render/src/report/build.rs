//! The content of a crash's report, from a solve or a fit (and its uncertainty study).
//!
//! Numbers are shown in the unit system the caller asks for and in the case's own frame (an
//! SAE case reads SAE's signs); every number printed is one of the JSON document's, converted
//! and rounded, nothing recomputed.

use super::doc::{Block, Document, Section, Table};
use super::fit_sections::{branches_table, ranges, residual_section, undetermined};
use crate::tables::{branch_short, branch_words, how_found, in_frame, num, vehicle_rows};
use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_core::{Convention, VehicleResult};
use pim_studies::documents::{Fitted, Solved};
use pim_studies::uncertainty::Study;

/// The references the method cites.
const REFERENCES: [&str; 4] = [
    "R. M. Brach, Analysis of planar vehicle collisions using equations of impulse and \
     momentum, Accident Analysis & Prevention (1983): the six equations.",
    "R. M. Brach, Momentum and energy analysis of automobile collisions, Structural Impact and \
     Crashworthiness (1984): the corrected moment equation, mu_max.",
    "C. G. Vossou, D. V. Koulocheris, A computational model for the reconstruction of vehicle \
     collisions (2018): the cost functions Q1, Q2, Q3.",
    "J. Kisilowski, J. Zalewski, Analysis of the selected aspects of a crash between two \
     vehicles: normal and tangential restitution with a friction limit (the second model).",
];

/// How to read the report, the same for every crash.
const HOW_TO_READ: [&str; 5] = [
    "Velocities are those of each vehicle's centre of gravity at contact (the moment the \
     crush begins) and at separation; delta-V is the change between them, PDOF the direction \
     of the impulse on the vehicle.",
    "A fit's answer satisfies the six impulse-momentum equations exactly; what it cannot match \
     of the values given shows as residuals. A residual of more than 2 standard deviations, or \
     a p value below 0.05, says the data and the model disagree more than the stated \
     uncertainties allow.",
    "A coefficient that the data do not pin down is listed under 'What the data do not \
     determine': its value is one of many that fit equally well, not a measurement.",
    "An answer that rests on a search bound is ended by that bound, not by the data; a bound \
     marked 'default' was not chosen for this crash.",
    "Every number here is in result.json (SI units, natural frame) with more digits.",
];

/// Which side of the crush surface vehicle 1 lies on, and what that rests on, in a sentence.
fn side_sentence(side: &pim_documents::records::SideOut, u: UnitSystem) -> String {
    let [h1, h2] = side.cg_heights.map(|h| u.length(h));
    let len = u.length_label();
    let basis = match side.basis {
        pim_core::SideBasis::Geometry => {
            "the two centres of gravity lie on opposite sides of the crush plane".to_string()
        }
        pim_core::SideBasis::Mobility => format!(
            "read from the heights of the centres of gravity above the crush plane ({h1:.3} {len} \
             and {h2:.3} {len}: both on one side) weighted by mobility; a choice, which the case \
             can state with [impact] vehicle1_side"
        ),
        pim_core::SideBasis::Case => "as the case states ([impact] vehicle1_side)".to_string(),
        pim_core::SideBasis::Velocities => format!(
            "both centres of gravity lie on one side of the crush plane ({h1:.3} {len} and \
             {h2:.3} {len} above it), and the side is the one under which the case's estimated \
             contact velocities approach; the case can state it with [impact] vehicle1_side"
        ),
    };
    format!(
        "Vehicle 1 lies on the {} side of the crush surface (n at the crush angle): {basis}.",
        side.vehicle1
    )
}

/// The report of a solve of `case`, in the units `u`.
pub fn solve(case: &Case, s: &Solved, u: UnitSystem) -> Result<Document, crate::RenderError> {
    let frame = case.written;
    let r = frame.shown(&s.report);
    let c = &r.coefficients;
    let mut answer = Section::new("Answer");
    answer.text(format!(
        "Solved {} with restitution e = {}, impulse ratio mu = {}, moment restitution em = {}.",
        if s.forward {
            "forwards from the velocities at contact"
        } else {
            "backwards from the velocities at separation"
        },
        c.e,
        c.mu,
        c.em
    ));
    answer
        .blocks
        .push(Block::Table(vehicle_table(&r.vehicles, u, frame)));
    let e = &r.energy;
    answer.text(format!(
        "Kinetic energy {} {lab} at contact, {} {lab} at separation: {} {lab} lost ({} %).",
        num(u.energy(e.initial), 0),
        num(u.energy(e.final_), 0),
        num(u.energy(e.loss), 0),
        num(e.loss_percent, 2),
        lab = u.energy_label()
    ));
    answer.text(format!(
        "Along the crush surface: {}.",
        crate::tables::tangential_words(&r, s.document.model.as_ref())
    ));
    answer.text(side_sentence(&s.document.side, u));
    let mut warnings = case.warnings();
    if !r.admissibility.admissible {
        for reason in r.inadmissibility_reasons() {
            warnings.push(format!("not physically admissible: {reason}"));
        }
    }
    let diagram = crate::diagram::of_solve(case, s);
    let momentum = crate::momentum::figure(
        case,
        &s.report.initial,
        &s.report.separation,
        "momentum.svg",
    )?;
    let mut doc = header(case, "Solve", u);
    doc.sections.push(answer);
    if let Some(d) = super::damage_section::section(case, s.document.damage.as_ref(), None, u)? {
        doc.sections.push(d);
    }
    doc.sections.push(warnings_section(warnings));
    doc.sections
        .push(figures(diagram.svg()?, Some(momentum), Vec::new()));
    doc.sections.push(method(None));
    doc.sections.push(inputs(case, u));
    Ok(doc)
}

/// The report of a fit of `case` under the cost function `cost` (its name), with the
/// uncertainty study when one was run, in the units `u`.
pub fn fit(
    case: &Case,
    f: &Fitted,
    cost: &str,
    study: Option<&Study>,
    u: UnitSystem,
) -> Result<Document, crate::RenderError> {
    let frame = case.written;
    let report = &f.report;
    let best = report.best_branch();
    let record = f
        .document
        .branches
        .iter()
        .find(|r| Some(r.moment) == report.best);
    let mut doc = header(case, &format!("Fit, cost function {cost}"), u);
    let mut answer = Section::new("Answer");
    answer.text(side_sentence(&f.document.side, u));
    let mut warnings = case.warnings();
    warnings.extend(report.notes.iter().cloned());
    match (best, best.and_then(|b| b.solution.as_ref())) {
        (Some(b), Some(sol)) => {
            answer.text(format!(
                "Best fit: {} with restitution e = {}, impulse ratio mu = {} ({} of the \
                 largest that the contact allows, mu_max; {}), moment restitution em = {}; \
                 cost {}.",
                if report.model == pim_fit::FitModel::Tangential {
                    "the tangential-restitution model".to_string()
                } else {
                    branch_words(b.moment)
                },
                num(sol.e, 4),
                num(sol.mu, 4),
                sol.mu_ratio.map_or_else(
                    || "undefined".into(),
                    |r| format!("{} %", num(100.0 * r, 1))
                ),
                if sol.sticking {
                    "the contact point stops sliding"
                } else {
                    "the contact point slides throughout"
                },
                num(sol.em, 4),
                num(sol.cost, 5)
            ));
            let (_, _, shown) = in_frame(sol, frame);
            answer
                .blocks
                .push(Block::Table(vehicle_table(&shown, u, frame)));
            answer.text(format!(
                "Kinetic energy lost: {} {} ({} % of that at contact).",
                num(u.energy(sol.energy_loss), 0),
                u.energy_label(),
                num(sol.energy_loss_percent, 2)
            ));
            if let Some(g) = &b.geometry {
                geometry(&mut answer, g, u, Some(sol.cost));
                if !g.search.proof.is_proven() {
                    warnings.push(format!(
                        "The impact geometry was estimated within the case's bounds: the \
                         coefficients are proven optimal at the reported geometry, but {} (see \
                         Answer).",
                        g.search.proof.statement(Some(sol.cost))
                    ));
                }
            }
            if let Some(study) = study {
                ranges(&mut answer, study, u);
            }
        }
        _ => {
            answer.text("No answer: no moment branch has a physically admissible solution.");
            for b in &report.branches {
                if let Some(reason) = &b.reason {
                    warnings.push(format!("{}: {reason}", branch_short(b.moment)));
                }
            }
        }
    }
    answer
        .blocks
        .push(Block::Table(branches_table(report, &f.document.branches)));
    doc.sections.push(answer);
    if let Some(r) = record {
        doc.sections.push(residual_section(r, u, frame));
    }
    doc.sections
        .push(undetermined(report, record, study, u, &mut warnings));
    if let Some(d) = super::damage_section::section(case, None, f.document.damage.as_ref(), u)? {
        doc.sections.push(d);
    }
    doc.sections.push(warnings_section(warnings));
    let diagram = crate::diagram::of_fit(case, f, cost)?;
    let momentum = match best.and_then(|b| b.solution.as_ref()) {
        Some(sol) => Some(crate::momentum::figure(
            case,
            &sol.initial,
            &sol.separation,
            "momentum.svg",
        )?),
        None => None,
    };
    let extra = match study {
        Some(s) => crate::uncertainty_figures::figures(s, u)?,
        None => Vec::new(),
    };
    doc.sections.push(figures(diagram.svg()?, momentum, extra));
    doc.sections.push(method(Some((cost, f))));
    doc.sections.push(inputs(case, u));
    Ok(doc)
}

/// The estimated impact geometry: each input with the values whose cost stays within the
/// tolerance, and how the geometry was searched.
fn geometry(s: &mut Section, g: &pim_fit::GeometryEstimate, u: UnitSystem, cost: Option<f64>) {
    let tolerance = g.ranges.first().map_or(0.01, |r| r.tolerance);
    s.text(format!(
        "Estimated impact geometry (searched within the case's bounds; the range holds the \
         values whose cost stays within {} % of the optimum, on scans through it; \
         \"on a bound\": the bound, not the data, ends the estimate; \"not determined\": the \
         range covers half of the bounds or more):",
        num(100.0 * tolerance, 0)
    ));
    let mut t = Table::new(&["input", "estimate", "range", "bounds", "note"]);
    for r in &g.ranges {
        let (f, unit): (&dyn Fn(f64) -> String, &str) =
            if pim_fit::GeometryInput::name_is_length(&r.input) {
                (&|x| num(u.length(x), 3), u.length_label())
            } else {
                (&|x| num(x, 2), "deg")
            };
        let mut note = Vec::new();
        if r.at_bound {
            note.push("on a bound");
        }
        if !r.identifiable {
            note.push("not determined");
        }
        t.row(vec![
            r.input.clone(),
            format!("{} {unit}", f(r.value)),
            format!("{} .. {}", f(r.low), f(r.high)),
            format!("{} .. {}", f(r.bounds[0]), f(r.bounds[1])),
            note.join(", "),
        ]);
    }
    s.blocks.push(Block::Table(t));
    s.text(format!(
        "How the geometry was searched: {} ({} complete fits of the coefficients).",
        g.search
            .method
            .strip_prefix("geometry: ")
            .unwrap_or(&g.search.method),
        g.search.fits
    ));
    s.text(format!(
        "What is proven: the coefficients are optimal at the reported geometry; {}.",
        g.search.proof.statement(cost)
    ));
}

/// Title, what was done, and how to read the report.
pub(super) fn header(case: &Case, what: &str, u: UnitSystem) -> Document {
    let title = case.heading();
    let mut subtitle = vec![format!("{what} of {}.", case.file)];
    if let Some((a, b)) = case.descriptions() {
        subtitle.push(format!("Vehicle 1: {a}; vehicle 2: {b}."));
    }
    subtitle.push(format!(
        "Shown in {} units; {}. Computed by pim {}.",
        match u {
            UnitSystem::Si => "SI",
            UnitSystem::Us => "US",
            UnitSystem::Kmh => "km/h and metric",
        },
        crate::tables::frame_line(case.written),
        env!("CARGO_PKG_VERSION")
    ));
    let mut read = Section::new("How to read this");
    read.blocks.push(Block::List(
        HOW_TO_READ.iter().map(|s| s.to_string()).collect(),
    ));
    Document {
        title,
        subtitle,
        sections: vec![read],
    }
}

/// The per-vehicle table (speeds, delta-V, PDOF, yaw-rate change).
fn vehicle_table(v: &[VehicleResult; 2], u: UnitSystem, frame: Convention) -> Table {
    let mut t = Table::new(&["", "vehicle 1", "vehicle 2"]);
    for (label, [a, b]) in vehicle_rows(v, u, frame) {
        let label = match label.strip_prefix("  ") {
            Some(part) => format!("delta-V {part}"),
            None => label,
        };
        t.row(vec![label, a, b]);
    }
    t
}

pub(super) fn warnings_section(w: Vec<String>) -> Section {
    let mut s = Section::new("Warnings");
    if w.is_empty() {
        s.text("None.");
    } else {
        s.blocks.push(Block::Warnings(w));
    }
    s
}

/// The plan view, the momentum diagram (none without an answer) and the study's figures.
fn figures(diagram: String, momentum: Option<crate::Figure>, extra: Vec<crate::Figure>) -> Section {
    let mut s = Section::new("Figures");
    s.blocks.push(Block::Figure(
        crate::Figure {
            name: "diagram.svg".into(),
            svg: diagram,
        },
        "Plan view at contact, to scale: outlines, impact centre, crush surface, velocities \
         at contact and separation, the impulse on each vehicle and the separation yaw rates."
            .into(),
    ));
    s.blocks.extend(momentum.map(|m| {
        Block::Figure(
            m,
            "Momentum diagram, to scale: each vehicle's momentum at contact and at separation, \
         placed head to tail; both chains end at the same total momentum, which the impact \
         does not change."
                .into(),
        )
    }));
    for f in extra {
        let caption = match f.name.as_str() {
            "histograms.svg" => "The refits' answers: histograms of each quantity.",
            "speeds.svg" => "The refits' speeds at contact, one point per refit.",
            "tornado.svg" => "Which inputs move each answer most (first-order sensitivity).",
            _ => "The uncertainty study.",
        };
        s.blocks.push(Block::Figure(f, caption.into()));
    }
    s
}

fn method(fit: Option<(&str, &Fitted)>) -> Section {
    let mut s = Section::new("Method");
    let tangential = fit.is_some_and(|(_, f)| f.report.model == pim_fit::FitModel::Tangential);
    s.text(if tangential {
        "Normal and tangential restitution with a friction limit (Kisilowski & Zalewski; the \
         family of PC-Crash's and Virtual CRASH's impulse models): one impulse at the impact \
         centre, no moment impulse, gives the relative velocity there the normal restitution e \
         and the tangential restitution et, unless that needs more than the friction limit \
         times the normal impulse, in which case the vehicles slide at the limit."
    } else {
        "Planar impact mechanics (PIM): six impulse-momentum equations relate the velocities of \
         the two vehicles at contact to those at separation through restitution e, the impulse \
         ratio mu and moment restitution em, with the moment equation as corrected by Brach \
         (1984)."
    });
    if let Some((cost, f)) = fit {
        let description = match pim_fit::CostPreset::ALL.iter().find(|p| p.name() == cost) {
            Some(p) => p.description().to_string(),
            None => "the case's own known and estimated values".to_string(),
        };
        let (friction, branches) = if tangential {
            (
                "keep the impulse ratio within the friction limit (sticking) or at it where \
                 sticking would need more (sliding)",
                "the model has one branch, searched for its global optimum".to_string(),
            )
        } else {
            (
                "keep friction within what the contact allows (mu <= mu_max)",
                format!(
                    "each moment branch is searched for its global optimum ({} branch(es))",
                    f.report.branches.len()
                ),
            )
        };
        s.text(format!(
            "The fit finds the coefficients and the twelve velocities that satisfy the \
             equations exactly, {friction} and create no energy, and that are closest, in \
             weighted least squares, to the values given (cost function {cost}: \
             {description}); {branches}."
        ));
        if let Some(b) = f.report.best_branch() {
            s.text(format!("{}.", how_found(&b.certificate)));
        }
    }
    s.blocks.push(Block::List(
        REFERENCES.iter().map(|r| r.to_string()).collect(),
    ));
    s
}

/// The inputs as given: the file, verbatim, and its units and frame.
pub(super) fn inputs(case: &Case, u: UnitSystem) -> Section {
    let mut s = Section::new("Inputs as given");
    let v = case.vehicles();
    let mut t = Table::new(&["", "vehicle 1", "vehicle 2"]);
    t.row(vec![
        "description".into(),
        v[0].description.clone().unwrap_or_default(),
        v[1].description.clone().unwrap_or_default(),
    ]);
    t.row(vec![
        format!("mass [{}]", u.mass_label()),
        num(u.mass(v[0].mass), 1),
        if case.is_barrier() {
            "fixed barrier".into()
        } else {
            num(u.mass(v[1].mass), 1)
        },
    ]);
    let inertia = |k: usize| {
        let x = num(u.yaw_inertia(v[k].yaw_inertia), 0);
        match v[k].yaw_inertia_source {
            pim_case::inertia::InertiaSource::Outline => format!("{x} (estimated)"),
            pim_case::inertia::InertiaSource::Stated => x,
        }
    };
    t.row(vec![
        format!("yaw inertia [{}]", u.yaw_inertia_label()),
        inertia(0),
        if case.is_barrier() {
            "fixed barrier".into()
        } else {
            inertia(1)
        },
    ]);
    s.blocks.push(Block::Table(t));
    for e in case.estimated() {
        s.text(format!("Estimated: {e}."));
    }
    s.text(format!(
        "The case file, exactly as given (its own units: {}):",
        case.written_units.describe()
    ));
    s.blocks
        .push(Block::Source(case.file.clone(), case.source.clone()));
    s
}
