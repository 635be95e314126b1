//! The report of a case with scene evidence: its whole reconstruction (pre-impact, impact,
//! run-out) as a reconstructionist signs it. The speeds of every phase with their intervals,
//! every piece of evidence against the answer as a table in the case's units, the evidence
//! consistency table when the evidence conflicts, the counts of turns compared, what is
//! proven and what is not, the scene to scale and the plan view at contact in the case's
//! frame, the histograms of the study, and the inputs as given.
//!
//! Every number is one of the JSON documents' (`result.json`, `uncertainty.json`), converted to
//! the report's units and the case's frame, nothing recomputed.

use super::build::{header, inputs, warnings_section};
use super::doc::{Block, Document, Section, Table};
use crate::statistics::{chi_square_words, format_p};
use crate::tables::num;
use crate::Figure;
use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_studies::reconstruct::{Reconstructed, ReconstructionOut};
use pim_studies::reconstruct_study::ReconstructionStudy;

/// How to read the report of a reconstruction, the same for every crash.
const HOW_TO_READ: [&str; 6] = [
    "The speeds are those of each vehicle's centre of gravity: where its braking began (from \
     the pre-impact skid), at contact (the moment the crush begins), at separation, and at \
     rest. They come from one fit of all the evidence at once: the impact's six \
     impulse-momentum equations hold exactly, and each run-out is simulated from separation \
     to rest on four tyres.",
    "Each piece of evidence is listed with its residual (the answer minus the value given), \
     its standard deviation and z (the residual in standard deviations). A z beyond 2, or a \
     chi-square probability p below 0.05, says the evidence disagrees with the answer more \
     than its stated standard deviations allow.",
    "When the evidence conflicts, the consistency table shows the answer with each piece left \
     out in turn: a piece without which the rest fits is the one to check.",
    "The 90 % intervals come from refitting the whole reconstruction with every measured \
     input drawn from its standard deviation (a parametric bootstrap); at contact each is \
     widened to the speeds at which the best reconstruction's chi-square has risen 2.71 above \
     the answer's (the profile interval) where those lie further out. They cover what those \
     standard deviations cover, not errors of the model or of inputs given without one.",
    "What is proven and what is only found is said in its own section: the impact at the \
     answer is a certified optimum; the separation state is the best one the search found.",
    "Every number here is in result.json and uncertainty.json (SI units, natural frame) with \
     more digits.",
];

/// The report of a reconstructed case, with its study when one ran, in the units `u`.
pub fn reconstruction(
    case: &Case,
    done: &Reconstructed,
    study: Option<&ReconstructionStudy>,
    u: UnitSystem,
) -> Result<Document, crate::RenderError> {
    let d = &done.document;
    let frame = case.written;
    let mut doc = header(case, "Reconstruction (pre-impact, impact, run-out)", u);
    doc.sections[0].blocks = vec![Block::List(
        HOW_TO_READ.iter().map(|s| s.to_string()).collect(),
    )];
    let mut warnings = case.warnings();
    doc.sections.push(answer(d, study, u, frame, &mut warnings));
    if let Some(b) = &d.best {
        let mut s = Section::new("Evidence and residuals");
        s.text(format!(
            "Every piece of evidence against the answer, in the case's units ({}).",
            chi_square_words(b.chi_square, b.degrees_of_freedom, b.p_value)
        ));
        s.blocks.push(Block::Table(evidence_table(d, u)));
        doc.sections.push(s);
    }
    if let Some(c) = &d.consistency {
        doc.sections.push(consistency(c, u));
    }
    doc.sections.push(proven(d, frame));
    doc.sections.push(warnings_section(warnings));
    doc.sections.push(figures(case, done, study, u)?);
    doc.sections.push(inputs(case, u));
    Ok(doc)
}

fn answer(
    d: &ReconstructionOut,
    study: Option<&ReconstructionStudy>,
    u: UnitSystem,
    frame: Convention,
    warnings: &mut Vec<String>,
) -> Section {
    let mut s = Section::new("Answer");
    let Some(b) = &d.best else {
        s.text(format!(
            "No reconstruction: {}.",
            d.reason.as_deref().unwrap_or("none found")
        ));
        warnings.push("There is no answer to sign: see the consistency table.".into());
        return s;
    };
    if let Some(why) = &d.reason {
        s.blocks.push(Block::Warnings(vec![format!(
            "Contradicted by the evidence: {why}. The best reconstruction found is shown for \
             inspection, not as an answer; the consistency table shows which pieces disagree."
        )]));
    }
    let spd = u.speed_label();
    // A speed at contact's reported interval (the draws' widened to the profile's); the other
    // phases' the draws'.
    let interval = |name: &str| {
        study
            .and_then(|st| {
                st.intervals
                    .get(name)
                    .map(|[lo, hi]| (*lo, *hi))
                    .or_else(|| st.quantities.get(name).map(|q| (q.p05, q.p95)))
            })
            .map_or_else(String::new, |(lo, hi)| {
                format!(" ({} .. {})", num(u.speed(lo), 1), num(u.speed(hi), 1))
            })
    };
    let sgn = frame.sign();
    let mut t = Table::new(&[
        "vehicle",
        &format!("before braking [{spd}]"),
        &format!("at contact [{spd}]"),
        &format!("at separation [{spd}]"),
        "full turns to rest",
        &format!("rest x, y [{}], heading [deg]", u.length_label()),
    ]);
    for p in &b.vehicles {
        let v = p.vehicle;
        t.row(vec![
            format!("{v}"),
            p.speed_before_braking.map_or_else(
                || "-".into(),
                |x| {
                    format!(
                        "{}{}",
                        num(u.speed(x), 2),
                        interval(&format!("vehicle{v}.speed_before_braking"))
                    )
                },
            ),
            format!(
                "{}{}",
                num(u.speed(p.speed_at_contact), 2),
                interval(&format!("vehicle{v}.speed_at_contact"))
            ),
            format!(
                "{}{}",
                num(u.speed(p.speed_at_separation), 2),
                interval(&format!("vehicle{v}.speed_at_separation"))
            ),
            p.turns
                .map_or_else(|| "-".into(), |k| (sgn as i64 * k).to_string()),
            p.rest.map_or_else(
                || "-".into(),
                |r| {
                    format!(
                        "{}, {}, {}",
                        num(u.length(r.x), 2),
                        num(u.length(sgn * r.y), 2),
                        num(sgn * r.heading, 1)
                    )
                },
            ),
        ]);
    }
    s.blocks.push(Block::Table(t));
    s.text(match study {
        Some(st) => format!(
            "In brackets: the 90 % interval of {} refits with every measured input drawn ({} with \
             an answer; seed {}), at contact widened on each side to the profile's end (the speed \
             at which the best reconstruction's chi-square has risen 2.71 above the answer's) \
             where that is wider. Turns: full turns beyond the shortest rotation to the rest \
             heading, {} positive.",
            st.draws,
            st.feasible_draws,
            st.seed,
            frame.positive_sense()
        ),
        None => {
            "No uncertainty study was run (`--draws 0`): the speeds have no intervals here.".into()
        }
    });
    s.text(format!(
        "The impact: restitution e = {}, impulse ratio mu = {}, moment restitution em = {} ({} \
         branch); {} % of the kinetic energy at contact lost.",
        num(b.e, 4),
        num(b.mu, 4),
        num(b.em, 4),
        b.branch.name(),
        num(b.energy_loss_percent, 1)
    ));
    s.text(format!(
        "Fit: {}.",
        chi_square_words(b.chi_square, b.degrees_of_freedom, b.p_value)
    ));
    warnings.extend(answer_warnings(b, study));
    s
}

/// What the signer of an answer `b` is warned of: a poor fit, an impact ended on a bound, a
/// nominal value outside its own interval.
fn answer_warnings(
    b: &pim_studies::reconstruct::BestOut,
    study: Option<&ReconstructionStudy>,
) -> Vec<String> {
    let mut warnings = Vec::new();
    if let Some(p) = b.p_value.filter(|p| *p < pim_reconstruct::POOR_FIT_P) {
        warnings.push(format!(
            "The reconstruction fits poorly (p = {}): the evidence disagrees more than its \
             standard deviations allow; see the consistency table.",
            format_p(p)
        ));
    }
    for r in &b.bounds_reached {
        warnings.push(format!(
            "The impact ends on a bound ({} at [bounds] {}, {}): the bound, not the evidence, \
             ends it there.",
            r.at,
            r.bound,
            match r.source {
                pim_documents::records::BoundSource::Case => "set for this crash",
                pim_documents::records::BoundSource::Default => "a default, not set for this crash",
            }
        ));
    }
    if let Some(st) = study {
        for q in &st.nominal_outside {
            warnings.push(format!(
                "The nominal {q} lies outside its own 90 % interval: the refits' answers are \
                 skewed away from it (a nonlinear or bounded answer); read the interval, not \
                 the nominal value alone."
            ));
        }
    }
    warnings
}

fn evidence_table(d: &ReconstructionOut, u: UnitSystem) -> Table {
    let mut t = Table::new(&[
        "evidence", "phase", "unit", "residual", "sigma", "z", "share %",
    ]);
    t.numeric[1] = false;
    t.numeric[2] = false;
    for e in d.best.iter().flat_map(|b| &b.evidence) {
        let (k, unit) = crate::reconstruct::evidence_unit(e, u);
        t.row(vec![
            e.name.clone(),
            e.phase.replace('_', "-"),
            unit.to_string(),
            num(e.residual * k, 3),
            num(e.sigma * k, 3),
            num(e.z, 2),
            num(e.share_percent, 1),
        ]);
    }
    t
}

fn consistency(c: &pim_studies::consistency::Consistency, u: UnitSystem) -> Section {
    let mut s = Section::new("Evidence consistency");
    s.text(
        "The whole reconstruction again with each piece of evidence left out in turn (a \
         vehicle's rest position with its heading counts as one piece): its chi-square, its \
         probability and the speeds at contact without it.",
    );
    let spd = u.speed_label();
    let mut t = Table::new(&[
        "left out",
        "chi-square",
        "dof",
        "p",
        "consistent",
        &format!("vehicle 1 [{spd}]"),
        &format!("vehicle 2 [{spd}]"),
        "largest remaining residual (z)",
    ]);
    t.numeric[4] = false;
    t.numeric[7] = false;
    for r in std::iter::once(&c.all).chain(&c.rows) {
        t.row(crate::reconstruct::consistency_cells(r, u).to_vec());
    }
    s.blocks.push(Block::Table(t));
    s.text(c.summary.clone());
    s
}

fn proven(d: &ReconstructionOut, frame: Convention) -> Section {
    let mut s = Section::new("What is proven and what is not");
    s.text(format!("How the answer was found: {}.", d.method));
    s.text(format!("Proven: {}.", d.proven));
    let sgn: i64 = frame.turns(1);
    let mut t = Table::new(&["counts of turns", "chi-square", "state"]);
    t.numeric[2] = false;
    for c in d.counts.iter().filter(|c| c.chi_square.is_some()) {
        t.row(vec![
            c.turns
                .iter()
                .zip(&d.scene_vehicles)
                .map(|(k, v)| {
                    format!(
                        "vehicle {v}: {}",
                        k.map_or_else(|| "-".into(), |k| (sgn * k).to_string())
                    )
                })
                .collect::<Vec<_>>()
                .join(", "),
            c.chi_square.map_or_else(|| "-".into(), |x| num(x, 3)),
            c.state.replace('_', " "),
        ]);
    }
    s.text(
        "The counts of turns refined (the others' bounds exclude them; all are in result.json):",
    );
    s.blocks.push(Block::Table(t));
    if !d.undetermined.is_empty() {
        s.text("Not determined by the evidence, or not proven:");
        s.blocks.push(Block::List(d.undetermined.clone()));
    }
    s
}

fn figures(
    case: &Case,
    done: &Reconstructed,
    study: Option<&ReconstructionStudy>,
    u: UnitSystem,
) -> Result<Section, crate::RenderError> {
    let mut s = Section::new("Figures");
    if let Some(svg) = crate::runout::reconstruction_scene(case, done, u)? {
        s.blocks.push(Block::Figure(
            Figure {
                name: "scene.svg".into(),
                svg,
            },
            "The scene to scale: each vehicle's path from separation to rest (outlines every \
             0.5 s), its rest as reconstructed (filled) and as measured (dashed, with a cross), \
             the marks with their standard deviations, and the braking before the impact."
                .into(),
        ));
    }
    if let Some(b) = &done.outcome.best {
        let impact = &done.input.reconstruction.contact.impact;
        let diagram = crate::diagram::diagram(
            case,
            impact,
            None,
            Some(crate::diagram::Solved::of_fit(&b.solution)),
        )
        .labelled(u, case.written);
        s.blocks.push(Block::Figure(
            Figure {
                name: "diagram.svg".into(),
                svg: diagram.svg()?,
            },
            "The impact at contact, to scale and laid as the scene: outlines, impact centre, \
             crush surface, velocities at contact and separation, the impulse on each vehicle."
                .into(),
        ));
    }
    if let Some(st) = study.filter(|st| st.feasible_draws > 0) {
        s.blocks.push(Block::Figure(
            histograms(st, u)?,
            "The refits' speeds: a histogram of each, its 90 % interval shaded, the nominal \
             answer as a black line."
                .into(),
        ));
    }
    Ok(s)
}

/// Histograms of every speed of a reconstruction study, in `u`.
fn histograms(st: &ReconstructionStudy, u: UnitSystem) -> Result<Figure, crate::RenderError> {
    let names: Vec<&String> = st
        .quantities
        .keys()
        .filter(|n| n.contains("speed"))
        .collect();
    let rows = names.len().div_ceil(2).max(1);
    let k = u.speed(1.0);
    let spd = u.speed_label();
    crate::svg_figure("histograms.svg", (1000, 300 * rows as u32), |root| {
        for (area, name) in root.split_evenly((rows, 2)).iter().zip(&names) {
            let v: Vec<f64> = st
                .samples
                .get(*name)
                .map_or_else(Vec::new, |v| v.iter().map(|x| x * k).collect());
            let q = &st.quantities[*name];
            let label = format!("{} [{spd}]", name.replace(['.', '_'], " "));
            crate::uncertainty_figures::histogram(
                area,
                &v,
                [q.p05 * k, q.p95 * k],
                st.nominal.get(*name).map(|n| n * k),
                &label,
                format!("{label}: 90 % {:.1} .. {:.1}", q.p05 * k, q.p95 * k),
            )?;
        }
        Ok(())
    })
}
