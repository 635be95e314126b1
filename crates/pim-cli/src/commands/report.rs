//! `pim report`: the one document a reconstructionist hands over for a crash.

use super::{json, print_out, write_file};
use crate::args::ReportArgs;
use crate::error::{Failure, EXIT_NO_ANSWER};
use crate::inputs::{checked_impact, load_case};
use anyhow::Result;
use pim_data::documents;
use pim_data::fitcase::CostChoice;
use pim_data::units::UnitSystem;
use std::process::ExitCode;

/// The draws of a report's uncertainty study when `--draws` is not given.
pub const DEFAULT_REPORT_DRAWS: usize = 200;

/// `pim report`.
pub fn run(a: &ReportArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let (_, warnings) = checked_impact(&case)?;
    let units = a
        .units
        .map_or_else(|| UnitSystem::of(&case.written_units), Into::into);
    let c = &case.content;
    let is_fit =
        !a.solve && (c.estimates.is_some() || c.known.is_some() || !c.observations.is_empty());
    let cannot = |e: String| Failure::Output(format!("{}: cannot draw: {e}", case.file));
    let (doc, record, extra, answered) = if is_fit {
        let cost = a.cost;
        let name = cost.map_or("custom", |p| p.name());
        let fitted = documents::fit(
            &case,
            cost,
            a.model,
            pim_core::MomentForm::Corrected,
            a.model.branches(&pim_fit::MomentBranch::ALL),
        )
        .map_err(Failure::from)?;
        let answered = fitted.report.best.is_some();
        // The uncertainty study, when the case says what is uncertain.
        let uncertain = c.sigma.is_some() || c.uncertainty.is_some();
        let draws = a
            .draws
            .unwrap_or(if uncertain { DEFAULT_REPORT_DRAWS } else { 0 });
        let study = if draws > 0 && answered && a.model == pim_fit::FitModel::Pim {
            let choice = cost.map_or(CostChoice::Custom, CostChoice::Preset);
            let unc = c.uncertainty.unwrap_or_default();
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(a.threads.unwrap_or(0))
                .build()
                .map_err(|e| Failure::Input(format!("--threads: {e}")))?;
            let s = pool.install(|| {
                pim_data::uncertainty::run(
                    &case,
                    &unc,
                    choice,
                    pim_fit::FitSettings::default(),
                    draws,
                    a.seed,
                    &|| {},
                )
            })?;
            (s.feasible_draws > 0).then_some(s)
        } else {
            None
        };
        let doc = pim_render::report::build::fit(&case, &fitted, name, study.as_ref(), units)
            .map_err(cannot)?;
        let extra = match &study {
            Some(s) => vec![("uncertainty.json".to_string(), json(s)?)],
            None => Vec::new(),
        };
        (doc, json(&fitted.document)?, extra, answered)
    } else {
        let solved = documents::solve(&case, &super::options_of(Default::default(), false))
            .map_err(Failure::from)?;
        let doc = pim_render::report::build::solve(&case, &solved, units).map_err(cannot)?;
        (doc, json(&solved.document)?, Vec::new(), true)
    };
    match (&a.out, &a.output) {
        (Some(dir), _) => {
            let extra: Vec<(&str, &str)> = extra
                .iter()
                .map(|(n, t)| (n.as_str(), t.as_str()))
                .collect();
            super::write_result_dir(dir, &record, &doc, &extra)?;
        }
        (None, Some(file)) => {
            write_file(file, &doc.html())?;
            eprintln!("pim: wrote {}", file.display());
        }
        (None, None) => print_out(&doc.html())?,
    }
    if !answered {
        eprintln!(
            "pim: {}: no branch has an admissible solution (the report says why)",
            case.file
        );
        return Ok(ExitCode::from(EXIT_NO_ANSWER));
    }
    Ok(crate::inputs::strict_status(a.strict, warnings, Vec::new()))
}
