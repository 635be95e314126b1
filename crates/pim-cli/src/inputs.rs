//! Reading input files (the only file reads of the toolkit) and handing their text to pim-data.

use crate::error::Failure;
use pim_data::case::{Case, MAX_CASE_BYTES};
use pim_data::ricsac::{RicsacTest, MAX_DATA_BYTES};
use std::path::Path;

/// Reads a file that must be a small regular text file, with messages naming it.
pub fn read_text_file(path: &Path, max_bytes: u64) -> Result<String, Failure> {
    let name = path.display();
    let meta = std::fs::metadata(path)
        .map_err(|e| Failure::Input(format!("{name}: cannot read: {}", io_reason(&e))))?;
    if meta.is_dir() {
        return Err(Failure::Input(format!(
            "{name}: is a directory, expected a file"
        )));
    }
    if meta.len() > max_bytes {
        return Err(Failure::Input(format!(
            "{name}: is {} bytes, larger than the {} bytes accepted for this kind of file",
            meta.len(),
            max_bytes
        )));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| Failure::Input(format!("{name}: cannot read: {}", io_reason(&e))))?;
    String::from_utf8(bytes).map_err(|e| {
        Failure::Input(format!(
            "{name}: is not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
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
    Ok(Case::from_text(&path.display().to_string(), &text)?)
}

/// The collision of a case, checked; then its plausibility warnings go to stderr (only for a
/// valid collision, so that an error is never preceded by noise).
pub fn checked_impact(case: &Case) -> Result<pim_core::Impact, Failure> {
    let impact = case.impact()?;
    for w in case.warnings() {
        eprintln!("pim: warning: {w}");
    }
    Ok(impact)
}

/// Reads and parses a RICSAC data file.
pub fn load_ricsac(path: &Path) -> Result<Vec<RicsacTest>, Failure> {
    let text = read_text_file(path, MAX_DATA_BYTES)?;
    Ok(pim_data::ricsac::parse(&path.display().to_string(), &text)?)
}
