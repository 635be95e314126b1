//! `pim solve` and `pim sensitivity`: one case file, forwards or backwards.

use super::{json, print_out, title_of};
use crate::args::{Format, SolveArgs};
use crate::error::Failure;
use crate::inputs::load_case;
use anyhow::Result;
use pim_case::units::UnitSystem;
use pim_core::SolveOptions;
use pim_documents::records;
use pim_render::tables;
use pim_studies::documents;
use std::process::ExitCode;

fn options(a: &SolveArgs) -> SolveOptions {
    super::options_of(a.moment_form, a.no_slip)
}

/// `pim solve`.
pub fn run(a: &SolveArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let (_, warnings) = crate::inputs::checked_impact(&case)?;
    let solved = documents::solve(&case, &options(a)).map_err(Failure::from)?;
    let document = &solved.document;
    let record = json(&document)?;
    // Shown in the case's own units and frame (the JSON stays SI and natural, and says so).
    let units = a
        .units
        .map_or_else(|| UnitSystem::of(&case.written_units), Into::into);
    let table = pim_render::solved::solved_table(&title_of(&case), &solved, units, case.written);
    if let Some(dir) = &a.out {
        let doc = pim_render::report::build::solve(&case, &solved, units)
            .map_err(|e| Failure::Output(format!("{}: cannot draw: {e}", dir.display())))?;
        super::write_result_dir(dir, &record, &doc, &[])?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &table,
    })?;
    Ok(crate::inputs::strict_status(a.strict, warnings, Vec::new()))
}

/// `pim sensitivity`.
pub fn sensitivity(a: &SolveArgs, percent: f64) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let (impact, warnings) = crate::inputs::checked_impact(&case)?;
    let coefficients = case.coefficients()?;
    let (state, forward) = case.known_state()?;
    if !forward {
        return Err(Failure::Input(format!(
            "{}: the sensitivity study solves forwards and needs [initial], not [final]",
            case.file
        ))
        .into());
    }
    let study = pim_core::sensitivity(&impact, &coefficients, &state, &options(a), percent)
        .map_err(|e| Failure::from_core(&case.file, e))?;
    let record = json(&records::SensitivityOut::new(&impact, &study))?;
    let units = a
        .units
        .map_or_else(|| UnitSystem::of(&case.written_units), Into::into);
    let table = tables::sensitivity_table(&title_of(&case), &study, units, case.written);
    if let Some(dir) = &a.out {
        let out = super::output::OutDir::create(dir)?;
        out.write("sensitivity.json", &record)?;
        out.write("sensitivity.txt", &table)?;
        out.commit()?;
        eprintln!(
            "pim: wrote sensitivity.json and sensitivity.txt to {}",
            dir.display()
        );
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &table,
    })?;
    Ok(crate::inputs::strict_status(a.strict, warnings, Vec::new()))
}
