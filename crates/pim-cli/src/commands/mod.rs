//! The subcommands, one module each, and what they share: writing to stdout and files.

pub mod batch;
pub mod batch_cases;
pub mod batch_damage;
pub mod batch_plan;
pub mod draw;
pub mod edr;
pub mod fit;
pub mod output;
pub mod predict;
pub mod rectify;
pub mod report;
pub mod runout;
pub mod scene_uncertainty;
pub mod serve;
pub mod set;
pub mod solve;
pub mod study;
pub mod survey;
pub mod uncertainty;
pub mod verdict;

use crate::error::Failure;
use crate::inputs::io_reason;
use anyhow::Result;
use pim_case::case::Case;
use pim_core::{SolveOptions, TangentialCondition};
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

/// Pretty JSON with a final newline, every object's keys in alphabetical order: the form the
/// data-file batch and `predict-dv` have always been written in.
pub fn json_sorted<T: serde::Serialize>(value: &T) -> Result<String> {
    json(&serde_json::to_value(value)?)
}

/// Pretty JSON with a final newline.
pub fn json<T: serde::Serialize>(value: &T) -> Result<String> {
    let mut s = serde_json::to_string_pretty(value)?;
    s.push('\n');
    Ok(s)
}

/// The title of a case: its file, its title and the vehicles' descriptions (pim-render's, so
/// that every front end titles a case alike).
pub fn title_of(case: &Case) -> String {
    pim_render::text::case_title(case)
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

/// Writes an output file under its final name only when it is complete (written beside it,
/// then renamed; a device or pipe is written directly); failures are exit status 4 and leave an
/// earlier file as it was.
pub fn write_file(path: &std::path::Path, text: &str) -> Result<()> {
    write_file_bytes(path, text.as_bytes())
}

/// [`write_file`] of bytes (an image).
pub fn write_file_bytes(path: &std::path::Path, text: &[u8]) -> Result<()> {
    let fail = |e: std::io::Error| -> anyhow::Error {
        Failure::Output(format!(
            "{}: cannot write: {}",
            path.display(),
            io_reason(&e)
        ))
        .into()
    };
    if path.is_dir() {
        return Err(
            Failure::Output(format!("{}: is a folder; give a file name", path.display())).into(),
        );
    }
    // A device or pipe (`-o /dev/stdout`) is written as it is: it holds no half-written file,
    // and renaming over it would replace the device itself.
    if std::fs::metadata(path).is_ok_and(|m| !m.is_file()) {
        return std::fs::write(path, text).map_err(fail);
    }
    let tmp =
        std::path::PathBuf::from(format!("{}.pim-{}.tmp", path.display(), std::process::id()));
    if let Err(e) = std::fs::write(&tmp, text) {
        let _ = std::fs::remove_file(&tmp);
        return Err(fail(e));
    }
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        fail(e)
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

/// Writes the report into an output folder: `report.html`, `report.md` and the report's
/// figures (`diagram.svg`, `momentum.svg`, ...); returns the names written.
pub fn write_report(
    out: &output::OutDir,
    doc: &pim_render::report::Document,
) -> Result<Vec<String>> {
    out.write("report.html", &doc.html())?;
    out.write("report.md", &doc.markdown())?;
    let mut names = vec!["report.html".to_string(), "report.md".to_string()];
    for f in doc.figures() {
        out.write(&f.name, &f.svg)?;
        names.push(f.name.clone());
    }
    Ok(names)
}

/// Writes `result.json` (and any `extra` files) and the report (see [`write_report`]) into
/// the folder `dir` (as a whole, see [`output::OutDir`]).
pub fn write_result_dir(
    dir: &Path,
    json: &str,
    doc: &pim_render::report::Document,
    extra: &[(&str, &str)],
) -> Result<()> {
    let out = output::OutDir::create(dir)?;
    out.write("result.json", json)?;
    let mut names = vec!["result.json".to_string()];
    for (name, text) in extra {
        out.write(name, text)?;
        names.push(name.to_string());
    }
    names.extend(write_report(&out, doc)?);
    out.commit()?;
    eprintln!("pim: wrote {} to {}", names.join(", "), dir.display());
    Ok(())
}

/// Writes figures into an output folder; returns how many.
pub fn write_figures(out: &output::OutDir, figures: &[pim_render::Figure]) -> Result<usize> {
    for f in figures {
        out.write(&f.name, &f.svg)?;
    }
    Ok(figures.len())
}

/// The notes of the question a case asks, on standard error.
pub fn notes(asked: &pim_studies::question::Asked) {
    for n in &asked.notes {
        eprintln!("pim: note: {n}");
    }
}
