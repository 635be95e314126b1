//! `pim runout`: each vehicle from separation to rest, or its separation velocities from the
//! scene.

use super::{json, print_out, write_file};
use crate::args::{Format, RunoutArgs};
use crate::error::{Failure, EXIT_NO_ANSWER, EXIT_OK};
use crate::inputs::load_runout_case;
use crate::runout_help::RunoutSource;
use anyhow::Result;
use pim_case::units::UnitSystem;
use pim_studies::runout::Source;
use std::process::ExitCode;

/// `pim runout`.
pub fn run(a: &RunoutArgs) -> Result<ExitCode> {
    let case = load_runout_case(&a.case)?;
    if !case.is_motion() {
        let _ = crate::inputs::checked_impact(&case)?;
    }
    if !case.has_runout() {
        return Err(Failure::Input(format!(
            "{}: no [runout] section: give the road friction and, per vehicle, [runout.vehicleN] \
             with wheelbase, track and the wheels' states (see `pim runout --help`)",
            case.file
        ))
        .into());
    }
    let source = a.from.map(|s| match s {
        RunoutSource::Final => Source::Final,
        RunoutSource::Solve => Source::Solve,
        RunoutSource::Fit => Source::Fit,
        RunoutSource::Scene => Source::Scene,
    });
    let given = if source == Some(Source::Fit) {
        Some(pim_studies::runout::fitted_separation(&case, a.cost).map_err(Failure::from)?)
    } else {
        None
    };
    let result = pim_studies::runout::runout(&case, source, given, a.sample, a.wheels)
        .map_err(Failure::from)?;
    let units = a
        .units
        .map_or_else(|| UnitSystem::of(&case.written_units), Into::into);
    let title = pim_render::text::case_title(&case);
    if let Some(path) = &a.draw {
        let svg = pim_render::runout::runout_svg(&title, &result, units, case.written, a.every)
            .map_err(|e| Failure::Output(format!("{}: cannot draw: {e}", path.display())))?;
        write_file(path, &svg)?;
        eprintln!("pim: wrote {}", path.display());
    }
    print_out(&match a.format {
        Format::Json => json(&result.document)?,
        Format::Table => pim_render::runout::runout_table(&title, &result, units, case.written),
    })?;
    if let Some(why) = result.no_answer() {
        eprintln!("pim: {}: {why}", case.file);
        return Ok(ExitCode::from(EXIT_NO_ANSWER));
    }
    Ok(ExitCode::from(EXIT_OK))
}
