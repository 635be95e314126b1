//! `pim solve` and `pim sensitivity`: one case file, forwards or backwards.

use super::{json, print_out, title_of};
use crate::args::{Format, MomentArg, SolveArgs};
use crate::error::{Failure, EXIT_OK};
use crate::inputs::load_case;
use crate::render::{markdown, tables};
use anyhow::Result;
use pim_core::{SolveOptions, TangentialCondition};
use pim_data::records;
use std::process::ExitCode;

/// The solve options of the command line.
pub fn options_of(moment_form: MomentArg, no_slip: bool) -> SolveOptions {
    SolveOptions {
        moment_form: moment_form.into(),
        tangential: if no_slip {
            TangentialCondition::NoSlip
        } else {
            TangentialCondition::Sliding
        },
    }
}

fn options(a: &SolveArgs) -> SolveOptions {
    options_of(a.moment_form, a.no_slip)
}

/// `pim solve`.
pub fn run(a: &SolveArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let impact = crate::inputs::checked_impact(&case)?;
    let coefficients = case.coefficients()?;
    let (state, forward) = case.known_state()?;
    let opts = options(a);
    let report = if forward {
        pim_core::solve_forward(&impact, &coefficients, &state, &opts)
    } else {
        pim_core::solve_backward(&impact, &coefficients, &state, &opts)
    }
    .map_err(|e| match (&e, forward) {
        (pim_core::PimError::NotApproaching { .. }, true) => {
            match case.explain_not_approaching(&state) {
                Some(why) => Failure::Input(format!("{}: {e}; {why}", case.file)),
                None => Failure::from_core(&case.file, e),
            }
        }
        _ => Failure::from_core(&case.file, e),
    })?;
    let record = json(&records::SolveOut::new(&impact, &report, forward))?;
    let table = tables::solve_table(&title_of(&case), &impact, &report, forward, a.units.into());
    if let Some(dir) = &a.out {
        let contact = super::draw::estimated_contact(&case);
        let d = super::draw::diagram(
            &case,
            &impact,
            contact.as_ref(),
            Some(crate::render::diagram::Solved::of_report(&report)),
        );
        let md = markdown::solve(&title_of(&case), &report, forward, a.units.into());
        super::draw::write_result_dir(dir, &record, &md, &d)?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &table,
    })?;
    Ok(ExitCode::from(EXIT_OK))
}

/// `pim sensitivity`.
pub fn sensitivity(a: &SolveArgs, percent: f64) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let impact = crate::inputs::checked_impact(&case)?;
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
    let text = match a.format {
        Format::Json => json(&records::SensitivityOut::new(&impact, &study))?,
        Format::Table => tables::sensitivity_table(&title_of(&case), &study),
    };
    print_out(&text)?;
    Ok(ExitCode::from(EXIT_OK))
}
