//! `pim draw`, and the result directory of `pim solve --out` / `pim fit --out`: JSON, a short
//! Markdown report and the scale diagram.

use super::write_file;
use crate::args::DrawArgs;
use crate::error::{Failure, EXIT_OK};
use crate::inputs::load_case;
use crate::render::diagram::{Diagram, Solved};
use anyhow::Result;
use pim_core::{Impact, Velocities};
use pim_data::case::Case;
use std::path::Path;
use std::process::ExitCode;

/// `pim draw`: the case at contact; solved when it has `[coefficients]` and a state, with the
/// estimated contact velocities when it is a fit case.
pub fn run(a: &DrawArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let impact = crate::inputs::checked_impact(&case)?;
    let c = &case.content;
    let report = if c.coefficients.is_some() && (c.initial.is_some() || c.final_.is_some()) {
        let coefficients = case.coefficients()?;
        let (state, forward) = case.known_state()?;
        let opts = super::solve::options_of(a.moment_form, a.no_slip);
        Some(
            if forward {
                pim_core::solve_forward(&impact, &coefficients, &state, &opts)
            } else {
                pim_core::solve_backward(&impact, &coefficients, &state, &opts)
            }
            .map_err(|e| Failure::from_core(&case.file, e))?,
        )
    } else {
        None
    };
    let contact = estimated_contact(&case);
    let diagram = diagram(
        &case,
        &impact,
        contact.as_ref(),
        report.as_ref().map(Solved::of_report),
    );
    write_diagram(&diagram, &a.output)?;
    eprintln!("pim: wrote {}", a.output.display());
    Ok(ExitCode::from(EXIT_OK))
}

/// The estimated contact velocities of a fit case, when all six are given.
pub fn estimated_contact(case: &Case) -> Option<Velocities> {
    let est = case.content.estimates?.initial?.components();
    let v: Option<Vec<f64>> = est.iter().copied().collect();
    v.map(|v| Velocities::from_vector(&nalgebra::Vector6::new(v[0], v[1], v[2], v[3], v[4], v[5])))
}

/// The diagram of a case, solved or not.
pub fn diagram(
    case: &Case,
    impact: &Impact,
    contact: Option<&Velocities>,
    solved: Option<Solved>,
) -> Diagram {
    let title = match &case.content.title {
        Some(t) => t.clone(),
        None => case.file.clone(),
    };
    Diagram::new(
        &title,
        impact,
        [&case.content.vehicle1, &case.content.vehicle2],
        contact,
        solved,
    )
}

/// Writes a diagram, creating the parent directory.
pub fn write_diagram(d: &Diagram, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        super::create_dir(dir)?;
    }
    d.write_svg(path)
        .map_err(|e| Failure::Output(format!("{}: cannot write: {e}", path.display())).into())
}

/// Writes `result.json`, `report.md` and `diagram.svg` into `dir`.
pub fn write_result_dir(dir: &Path, json: &str, markdown: &str, d: &Diagram) -> Result<()> {
    super::create_dir(dir)?;
    write_file(&dir.join("result.json"), json)?;
    write_file(&dir.join("report.md"), markdown)?;
    write_diagram(d, &dir.join("diagram.svg"))?;
    eprintln!(
        "pim: wrote result.json, report.md and diagram.svg to {}",
        dir.display()
    );
    Ok(())
}
