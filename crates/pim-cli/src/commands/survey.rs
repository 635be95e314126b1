//! `pim survey`: a survey's CSV imported into a case file's `[survey]`.

use crate::error::{Failure, EXIT_OK};
use crate::survey_args::SurveyArgs;
use anyhow::Result;
use pim_case::survey::Import;
use pim_case::units::LengthUnit;
use pim_store::WriteOptions;
use std::process::ExitCode;

/// `pim survey CASE CSV`.
pub fn run(a: &SurveyArgs) -> Result<ExitCode> {
    let name = a.case.display().to_string();
    let source = a.csv.display().to_string();
    let csv = std::fs::read_to_string(&a.csv)
        .map_err(|e| Failure::Input(format!("{source}: cannot read: {e}")))?;
    let import = Import {
        unit: a.unit.as_deref().map(|u| match u {
            "ft" => LengthUnit::Foot,
            _ => LengthUnit::Metre,
        }),
        origin: a.origin.clone(),
        rotation: a.rotation,
    };
    // The file's name only: the survey is kept beside the case.
    let kept = a
        .csv
        .file_name()
        .map_or(source.clone(), |n| n.to_string_lossy().into_owned());
    let edit = |current: &pim_store::Stored| {
        let text = pim_case::survey::import(&name, &current.text, (&kept, &csv), &import).map_err(
            |e| {
                e.message
                    .replacen(&format!("{kept}:"), &format!("{source}:"), 1)
            },
        )?;
        Ok::<_, String>(text)
    };
    let done = super::set::write_or_print(&a.case, &WriteOptions::default(), a.dry_run, edit)?;
    if !a.dry_run {
        let points = pim_case::case::Case::from_text(&name, &done.text)
            .ok()
            .and_then(|c| c.survey().cloned())
            .map_or(0, |s| s.points.len());
        eprintln!(
            "pim: {name}: [survey] of {points} points from {source} (version {})",
            done.version.short()
        );
    }
    Ok(ExitCode::from(EXIT_OK))
}
