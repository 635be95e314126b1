//! `pim solve` and `pim sensitivity`: one case file, forwards or backwards.

use super::{json, print_out, title_of};
use crate::args::{Format, SolveArgs};
use crate::error::{Failure, EXIT_OK};
use crate::inputs::load_case;
use anyhow::Result;
use pim_core::SolveOptions;
use pim_data::{documents, records};
use pim_render::{markdown, tables};
use std::process::ExitCode;

fn options(a: &SolveArgs) -> SolveOptions {
    super::options_of(a.moment_form, a.no_slip)
}

/// `pim solve`.
pub fn run(a: &SolveArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    crate::inputs::checked_impact(&case)?;
    let documents::Solved {
        impact,
        report,
        forward,
        document,
    } = documents::solve(&case, &options(a)).map_err(Failure::from)?;
    let record = json(&document)?;
    let mut table =
        tables::solve_table(&title_of(&case), &impact, &report, forward, a.units.into());
    if let Some(m) = &document.model {
        let c = m.coefficients;
        let how = match m.mode {
            pim_core::ContactMode::Stick => format!(
                "sticks: vt' = et vt within the friction limit (|Pt/Pn| = {:.3} <= {})",
                m.stick_ratio.abs(),
                c.friction
            ),
            pim_core::ContactMode::Slide => format!(
                "slides: sticking would need Pt/Pn = {:+.3}, beyond the friction limit {}, so \
                 Pt/Pn = {:+} (the limit on the sticking impulse's side)",
                m.stick_ratio, c.friction, m.impulse_ratio
            ),
        };
        let line = format!(
            "model: normal and tangential restitution with a friction limit (e = {}, et = {}, \
             friction = {}); it {how}; as PIM with the equivalent coefficients:\n",
            c.e, c.et, c.friction
        );
        if let Some(at) = table.find("solved forwards") {
            table.insert_str(at, &line);
        }
    }
    if let Some(dir) = &a.out {
        let contact = pim_render::diagram::estimated_contact(&case);
        let d = pim_render::diagram::diagram(
            &case,
            &impact,
            contact.as_ref(),
            Some(pim_render::diagram::Solved::of_report(&report)),
        );
        let md = markdown::solve(&title_of(&case), &report, forward, a.units.into());
        super::write_result_dir(dir, &record, &md, &d)?;
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
