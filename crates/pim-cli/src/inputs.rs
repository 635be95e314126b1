//! Reading input files (the only file reads of the toolkit) and handing their text to pim-studies.

use crate::error::Failure;
use pim_case::case::{Case, MAX_CASE_BYTES};
use pim_case::ricsac::{RicsacTest, MAX_DATA_BYTES};
use std::path::Path;

/// Reads a file that must be a small regular text file, with messages naming it: refused
/// unless it is a regular file, and read with a cap (pim-studies's [`pim_case::input`]), so that
/// no input can make the command wait or read without end.
pub fn read_text_file(path: &Path, max_bytes: u64) -> Result<String, Failure> {
    let name = path.display().to_string();
    let meta = std::fs::metadata(path)
        .map_err(|e| Failure::Input(format!("{name}: cannot read: {}", io_reason(&e))))?;
    pim_case::input::check_file(&name, &meta, max_bytes)?;
    let file = std::fs::File::open(path)
        .map_err(|e| Failure::Input(format!("{name}: cannot read: {}", io_reason(&e))))?;
    Ok(pim_case::input::read_text(&name, file, max_bytes)?)
}

/// A short reason for an I/O error.
pub fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        _ => e.to_string(),
    }
}

/// Reads and parses a case file.
pub fn load_case(path: &Path) -> Result<Case, Failure> {
    let text = read_text_file(path, MAX_CASE_BYTES)?;
    let case = Case::from_text(&path.display().to_string(), &text)?;
    // The damage is read where it is used; checked here so that every command refuses a case
    // whose crush cannot be.
    pim_case::damage::Damage::of(&case)?;
    Ok(case)
}

/// A case for `pim runout`: a case with an impact, or a motion case (`[start]`: the vehicles
/// from a stated state, see `pim_case::motion`).
pub fn load_runout_case(path: &Path) -> Result<Case, Failure> {
    let text = read_text_file(path, MAX_CASE_BYTES)?;
    if pim_case::motion::is_motion(&text) {
        return Ok(Case::motion_from_text(&path.display().to_string(), &text)?);
    }
    load_case(path)
}

/// The collision of a case, checked; then the values it estimated (notes) and its plausibility
/// warnings go to stderr (only for a valid collision, so that an error is never preceded by
/// noise). Also returns how many warnings there were (for `--strict`).
pub fn checked_impact(case: &Case) -> Result<(pim_core::Impact, usize), Failure> {
    let impact = case.impact()?;
    for e in case.estimated() {
        eprintln!("pim: note: {e}");
    }
    let warnings = case.warnings();
    for w in &warnings {
        eprintln!("pim: warning: {w}");
    }
    Ok((impact, warnings.len()))
}

/// The exit status of a command that produced its answer: 0, or under `--strict` 1 when
/// the case drew plausibility warnings (`warnings`) or for any other reason in `why` (an
/// answer on a bound no one set); the reasons are printed.
pub fn strict_status(
    strict: bool,
    warnings: usize,
    mut why: Vec<String>,
) -> std::process::ExitCode {
    use crate::error::{EXIT_OK, EXIT_STRICT};
    if warnings > 0 {
        why.insert(0, format!("{warnings} plausibility warning(s)"));
    }
    if strict && !why.is_empty() {
        eprintln!("pim: --strict: {}", why.join("; "));
        return std::process::ExitCode::from(EXIT_STRICT);
    }
    std::process::ExitCode::from(EXIT_OK)
}

/// Reads and parses a RICSAC data file.
pub fn load_ricsac(path: &Path) -> Result<Vec<RicsacTest>, Failure> {
    let text = read_text_file(path, MAX_DATA_BYTES)?;
    Ok(pim_case::ricsac::parse(&path.display().to_string(), &text)?)
}
