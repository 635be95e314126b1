//! `pim edr`: an EDR's pre-crash table imported into a case file's `[pre_impact.vehicleN]`.

use crate::edr_args::EdrArgs;
use crate::error::{Failure, EXIT_OK};
use anyhow::Result;
use pim_case::edr::Import;
use pim_case::units::SpeedUnit;
use pim_store::WriteOptions;
use std::process::ExitCode;

/// `pim edr CASE TABLE`.
pub fn run(a: &EdrArgs) -> Result<ExitCode> {
    let name = a.case.display().to_string();
    let source = a.table.display().to_string();
    let table = std::fs::read_to_string(&a.table)
        .map_err(|e| Failure::Input(format!("{source}: cannot read: {e}")))?;
    let import = Import {
        vehicle: a.vehicle,
        unit: a.unit.as_deref().map(|u| match u {
            "mph" => SpeedUnit::MilesPerHour,
            "km/h" => SpeedUnit::KilometresPerHour,
            _ => SpeedUnit::MetresPerSecond,
        }),
        sigma: a.sigma,
        record: !a.no_record,
    };
    let edit = |current: &pim_store::Stored| {
        pim_case::edr::import(&name, &current.text, (&source, &table), &import)
    };
    let done = super::set::write_or_print(&a.case, &WriteOptions::default(), a.dry_run, edit)?;
    if !a.dry_run {
        eprintln!(
            "pim: {name}: [pre_impact.vehicle{}] edr_history from {source}{} (version {})",
            a.vehicle,
            if a.no_record { "" } else { " and its record" },
            done.version.short()
        );
    }
    Ok(ExitCode::from(EXIT_OK))
}
