//! `pim report`: the one document a reconstructionist hands over for a crash.

use super::{json, print_out, write_file};
use crate::args::ReportArgs;
use crate::error::{Failure, EXIT_NO_ANSWER};
use crate::inputs::{checked_impact, load_case};
use anyhow::Result;
use pim_render::report::make::Basis;
use std::process::ExitCode;

/// `pim report`.
pub fn run(a: &ReportArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let (_, warnings) = checked_impact(&case)?;
    let options = pim_render::report::make::Options {
        cost: a.cost,
        model: a.model,
        solve: a.solve,
        draws: a.draws,
        seed: a.seed,
        units: a.units.map(Into::into),
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| Failure::Input(format!("--threads: {e}")))?;
    let made = pool
        .install(|| pim_render::report::make::make(&case, &options))
        .map_err(Failure::from)?;
    let doc = &made.document;
    let answered = made.answered();
    let record = match &made.basis {
        Basis::Fit(f) => json(&f.document)?,
        Basis::Solve(s) => json(&s.document)?,
        Basis::Reconstruction(r) => json(&r.document)?,
    };
    let extra = match (&made.study, &made.scene_study) {
        (Some(s), _) => vec![("uncertainty.json".to_string(), json(s)?)],
        (None, Some(s)) => vec![("uncertainty.json".to_string(), json(s)?)],
        (None, None) => Vec::new(),
    };
    match (&a.out, &a.output) {
        (Some(dir), _) => {
            let extra: Vec<(&str, &str)> = extra
                .iter()
                .map(|(n, t)| (n.as_str(), t.as_str()))
                .collect();
            super::write_result_dir(dir, &record, doc, &extra)?;
        }
        (None, Some(file)) => {
            write_file(file, &doc.html())?;
            eprintln!("pim: wrote {}", file.display());
        }
        (None, None) => print_out(&doc.html())?,
    }
    if let Basis::Reconstruction(r) = &made.basis {
        return super::verdict::reconstruction_status(&case, &r.document, a.strict, warnings);
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
