//! `pim draw`, and the result directory of `pim solve --out` / `pim fit --out`: JSON, a short
//! Markdown report and the scale diagram.

use super::write_file;
use crate::args::DrawArgs;
use crate::error::{Failure, EXIT_OK};
use crate::inputs::load_case;
use crate::render::diagram::Diagram;
use anyhow::Result;
use std::path::Path;
use std::process::ExitCode;

/// `pim draw`: the case at contact; solved when it has `[coefficients]` and a state, with the
/// estimated contact velocities when it is a fit case.
pub fn run(a: &DrawArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    crate::inputs::checked_impact(&case)?;
    let opts = super::solve::options_of(a.moment_form, a.no_slip);
    let diagram = pim_cli::diagram::case_diagram(&case, &opts).map_err(Failure::from)?;
    write_diagram(&diagram, &a.output)?;
    eprintln!("pim: wrote {}", a.output.display());
    Ok(ExitCode::from(EXIT_OK))
}

pub use pim_cli::diagram::{diagram, estimated_contact};

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
