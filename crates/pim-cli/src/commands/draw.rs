//! `pim draw`: the scale plan view of a case.

use super::write_diagram;
use crate::args::DrawArgs;
use crate::error::{Failure, EXIT_OK};
use crate::inputs::load_case;
use anyhow::Result;
use std::process::ExitCode;

/// `pim draw`: the case at contact; solved when it has `[coefficients]` and a state, with the
/// estimated contact velocities when it is a fit case.
pub fn run(a: &DrawArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let _ = crate::inputs::checked_impact(&case)?;
    let opts = super::options_of(a.moment_form, a.no_slip);
    let mut diagram = pim_render::diagram::case_diagram(&case, &opts).map_err(Failure::from)?;
    if let Some(u) = a.units {
        diagram.units = u.into();
    }
    write_diagram(&diagram, &a.output)?;
    eprintln!("pim: wrote {}", a.output.display());
    Ok(ExitCode::from(EXIT_OK))
}
