//! An event data recorder's pre-crash table pasted in the page: its rows written as the
//! vehicle's `[pre_impact.vehicleN] edr_history`, and the one record of evidence they give as
//! its `edr` ([`pim_case::edr`]).

use crate::AnswerError;
use serde::Deserialize;

/// A pasted table and how to import it.
#[derive(Debug, Clone, Deserialize)]
pub struct EdrImport {
    /// The table as pasted (rows of time, speed, brake, accelerator; a header or none).
    pub table: String,
    /// The vehicle, the table's unit, the record's sigma, whether to write the record.
    #[serde(flatten)]
    pub import: pim_case::edr::Import,
}

/// The case text with the pasted table imported (not saved).
///
/// # Errors
/// Text that is not TOML, the table's faults (named at its line), a vehicle other than 1 or
/// 2, a sigma not above 0.
pub fn import_edr(file: &str, text: &str, e: &EdrImport) -> Result<String, AnswerError> {
    pim_case::edr::import(file, text, ("the pasted table", &e.table), &e.import)
        .map_err(|err| AnswerError::Input(err.to_string()))
}
