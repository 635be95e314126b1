//! `pim batch DATA --damage CRUSH`: each test's crush beside its Q2 fit.

use crate::error::Failure;
use pim_case::ricsac::RicsacTest;
use pim_studies::ricsac_damage::{damage_records, parse_crush, parse_measured, DamageRecord};
use std::path::Path;

/// The damage records of `tests` from the crush file `path`, with Neades' Table 5.3 when
/// `data/reference/neades2011_table5_3.csv` is next to the data file.
pub fn records(
    path: &Path,
    data: &Path,
    tests: &[RicsacTest],
    settings: &pim_fit::FitSettings,
) -> Result<Vec<DamageRecord>, Failure> {
    let text = crate::inputs::read_text_file(path, pim_case::ricsac::MAX_DATA_BYTES)?;
    let crush =
        parse_crush(&text).map_err(|e| Failure::Input(format!("{}: {e}", path.display())))?;
    let measured = data
        .parent()
        .map(|d| d.join("reference").join("neades2011_table5_3.csv"))
        .filter(|p| p.is_file())
        .and_then(|p| crate::inputs::read_text_file(&p, pim_case::ricsac::MAX_DATA_BYTES).ok())
        .and_then(|t| parse_measured(&t).ok())
        .unwrap_or_default();
    Ok(damage_records(tests, &crush, &measured, settings))
}
