//! The subcommands, one module each, and what they share: writing to stdout and files.

pub mod batch;
pub mod batch_cases;
pub mod batch_plan;
pub mod draw;
pub mod fit;
pub mod predict;
pub mod solve;
pub mod uncertainty;

use crate::error::Failure;
use crate::inputs::io_reason;
use anyhow::Result;
use pim_core::{SolveOptions, TangentialCondition};
use pim_data::case::Case;
use pim_render::diagram::Diagram;
use std::io::Write;
use std::path::Path;

/// Writes the command's output to stdout (a closed pipe is not an error).
pub fn print_out(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        Ok(()) => Ok(()),
        // A closed pipe (`pim ... | head`) is not an error of ours.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Failure::Output(format!("cannot write to stdout: {e}")).into()),
    }
}

/// Pretty JSON with a final newline.
pub fn json<T: serde::Serialize>(value: &T) -> Result<String> {
    let mut s = serde_json::to_string_pretty(value)?;
    s.push('\n');
    Ok(s)
}

/// The title of a case: its file, its title and the vehicles' descriptions.
pub fn title_of(case: &Case) -> String {
    let mut t = match &case.content.title {
        Some(t) => format!("{} ({})", case.file, t),
        None => case.file.clone(),
    };
    let c = &case.content;
    if let (Some(a), Some(b)) = (&c.vehicle1.description, &c.vehicle2.description) {
        t.push_str(&format!("\nvehicle1: {a}; vehicle2: {b}"));
    }
    t
}

/// Creates an output directory (and its parents); failures are exit status 4.
pub fn create_dir(dir: &std::path::Path) -> Result<()> {
    std::fs::create_dir_all(dir).map_err(|e| {
        Failure::Output(format!(
            "{}: cannot create the directory: {}",
            dir.display(),
            io_reason(&e)
        ))
        .into()
    })
}

/// Writes an output file; failures are exit status 4.
pub fn write_file(path: &std::path::Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| {
        Failure::Output(format!(
            "{}: cannot write: {}",
            path.display(),
            io_reason(&e)
        ))
        .into()
    })
}

/// The solve options of the command line.
pub fn options_of(moment_form: pim_core::MomentForm, no_slip: bool) -> SolveOptions {
    SolveOptions {
        moment_form,
        tangential: if no_slip {
            TangentialCondition::NoSlip
        } else {
            TangentialCondition::Sliding
        },
    }
}

/// Writes a diagram, creating the parent directory.
pub fn write_diagram(d: &Diagram, path: &Path) -> Result<()> {
    if let Some(dir) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        create_dir(dir)?;
    }
    let svg = d
        .svg()
        .map_err(|e| Failure::Output(format!("{}: cannot draw: {e}", path.display())))?;
    write_file(path, &svg)
}

/// Writes `result.json`, `report.md` and `diagram.svg` into `dir`.
pub fn write_result_dir(dir: &Path, json: &str, markdown: &str, d: &Diagram) -> Result<()> {
    create_dir(dir)?;
    write_file(&dir.join("result.json"), json)?;
    write_file(&dir.join("report.md"), markdown)?;
    write_diagram(d, &dir.join("diagram.svg"))?;
    eprintln!(
        "pim: wrote result.json, report.md and diagram.svg to {}",
        dir.display()
    );
    Ok(())
}

/// Writes figures into `dir`; returns how many.
pub fn write_figures(dir: &Path, figures: &[pim_render::Figure]) -> Result<usize> {
    for f in figures {
        write_file(&dir.join(&f.name), &f.svg)?;
    }
    Ok(figures.len())
}
