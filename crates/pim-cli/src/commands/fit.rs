//! `pim fit`: one case file, both moment branches.

use super::{json, print_out, title_of};
use crate::args::{unique, FitArgs, Format};
use crate::error::{Failure, EXIT_NO_ANSWER};
use crate::inputs::load_case;
use anyhow::Result;
use pim_render::tables;
use pim_studies::documents;
use pim_studies::question::Question;
use std::process::ExitCode;

/// `pim fit`.
pub fn run(a: &FitArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let cost = a.cost;
    let name = cost.map_or("custom", |p| p.name());
    let (_, warnings) = crate::inputs::checked_impact(&case)?;
    let asked = Question::of(&case, cost);
    super::notes(&asked);
    if asked.question == Question::Reconstruction {
        return reconstruction(a, &case, warnings);
    }
    if let Some(from) = &a.from {
        return Err(Failure::Input(format!(
            "--from {}: {} has no scene evidence (no [scene] rest or mark): its fit is a global \
             optimum with nothing to start from",
            from.display(),
            case.file
        ))
        .into());
    }
    if let Some(why) =
        pim_render::diagram::estimated_contact(&case).and_then(|v| case.explain_not_approaching(&v))
    {
        eprintln!(
            "pim: warning: {}: the estimated contact velocities do not approach at the impact \
             centre; {why}",
            case.file
        );
    }
    let fitted = documents::fit(&case, cost, a.model, a.moment_form, unique(&a.branch))
        .map_err(Failure::from)?;
    let (report, document) = (&fitted.report, &fitted.document);
    let record = json(document)?;
    let branch_records = &document.branches;
    let best_record = branch_records
        .iter()
        .find(|r| Some(r.moment) == report.best);
    let units = a.units.map_or_else(
        || pim_case::units::UnitSystem::of(&case.written_units),
        Into::into,
    );
    // Shown in the case's own frame and units (an SAE case is fitted mirrored into the natural
    // form; the JSON stays SI and natural).
    let mut table = tables::fit_table(&title_of(&case), name, report, units, case.written);
    let bounds = tables::bounds_lines(branch_records, report.best, units);
    table.push_str(&bounds);
    for r in branch_records {
        if let Some(c) = &r.chi_square {
            table.push_str(&format!(
                "{}: {}\n",
                tables::branch_short(r.moment),
                pim_render::statistics::chi_square_words(c.value, c.degrees_of_freedom, c.p_value)
            ));
        }
    }
    if let Some(d) = &document.damage {
        table.push_str(&pim_render::damage::fit_damage_lines(d, units));
    }
    if let Some(dir) = &a.out {
        let doc = pim_render::report::build::fit(&case, &fitted, name, None, units)
            .map_err(|e| Failure::Output(format!("{}: cannot draw: {e}", dir.display())))?;
        super::write_result_dir(dir, &record, &doc, &[])?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &table,
    })?;
    if let Some(b) = report.best_branch() {
        let which = match report.model {
            pim_fit::FitModel::Tangential => "the tangential model's fit".to_string(),
            pim_fit::FitModel::Pim => format!("the best branch ({})", b.moment.name()),
        };
        let active = b.solution.as_ref().map(|s| &s.active_constraints[..]);
        super::verdict::bound_warnings(&case.file, &which, active.unwrap_or_default());
    }
    if let Some(g) = report.best_branch().and_then(|b| b.geometry.as_ref()) {
        for r in g.ranges.iter().filter(|r| r.at_bound) {
            eprintln!(
                "pim: warning: {}: the best branch's {} ends on its bound ({:.3}, bounds {:.3} .. \
                 {:.3}): the bound, not the data, ends it; widen [bounds] if the crash allows",
                case.file, r.input, r.value, r.bounds[0], r.bounds[1]
            );
        }
    }
    if report.best.is_none() {
        eprintln!(
            "pim: {}: no branch has an admissible solution (the reasons are in the output)",
            case.file
        );
        return Ok(ExitCode::from(EXIT_NO_ANSWER));
    }
    let mut why = Vec::new();
    if best_record.is_some_and(|r| r.rests_on_default_bound()) {
        why.push(
            "the best branch rests on a default bound (set it in [bounds] to choose it)".into(),
        );
    }
    Ok(crate::inputs::strict_status(a.strict, warnings, why))
}

/// `pim fit` of a case with scene evidence: the three phases in one fit.
fn reconstruction(a: &FitArgs, case: &pim_case::case::Case, warnings: usize) -> Result<ExitCode> {
    // The search of a realistic scene takes seconds: a spinner while it runs; the consistency
    // table of a conflicting scene too: its rows on a bar.
    let bar = super::study::Bar::on_terminal(a.format == crate::args::Format::Table);
    bar.searching("reconstructing: each scene's run-outs searched, then the impact refined");
    let earlier = match &a.from {
        Some(path) => {
            let text = std::fs::read_to_string(path)
                .map_err(|e| Failure::Input(format!("{}: cannot read: {e}", path.display())))?;
            pim_studies::earlier::earlier_states(&path.display().to_string(), &text)
                .map_err(Failure::from)?
        }
        None => Default::default(),
    };
    let how = (a.model, a.moment_form, unique(&a.branch));
    let done =
        pim_studies::consistency::answer_from(case, how, &earlier, &bar).map_err(Failure::from)?;
    bar.0.finish_and_clear();
    let d = &done.document;
    let units = a.units.map_or_else(
        || pim_case::units::UnitSystem::of(&case.written_units),
        Into::into,
    );
    let record = json(d)?;
    let table =
        pim_render::reconstruct::reconstruction_table(&title_of(case), d, units, case.written);
    if let Some(dir) = &a.out {
        super::scene_uncertainty::write_reconstruction(
            dir, case, &done, units, &record, &table, None,
        )?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &table,
    })?;
    super::verdict::reconstruction_status(case, d, a.strict, warnings)
}
