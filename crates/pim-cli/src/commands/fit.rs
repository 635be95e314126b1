//! `pim fit`: one case file, both moment branches.

use super::{json, print_out, title_of};
use crate::args::{unique, FitArgs, Format};
use crate::error::{Failure, EXIT_NO_ANSWER, EXIT_OK};
use crate::inputs::load_case;
use crate::render::{markdown, tables};
use anyhow::Result;
use pim_data::{fitcase, records};
use std::process::ExitCode;

/// `pim fit`.
pub fn run(a: &FitArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    for (name, present) in [
        ("[coefficients]", case.content.coefficients.is_some()),
        ("[initial]", case.content.initial.is_some()),
        ("[final]", case.content.final_.is_some()),
    ] {
        if present {
            return Err(Failure::Input(format!(
                "{}: {name} is for `pim solve`; a fit takes [estimates.initial] / [estimates.final]",
                case.file
            ))
            .into());
        }
    }
    let (choice, name) = match a.cost {
        Some(c) => {
            let p = pim_fit::CostPreset::from(c);
            (fitcase::CostChoice::Preset(p), p.name())
        }
        None => (fitcase::CostChoice::Custom, "custom"),
    };
    crate::inputs::checked_impact(&case)?;
    if let Some(why) =
        super::draw::estimated_contact(&case).and_then(|v| case.explain_not_approaching(&v))
    {
        eprintln!(
            "pim: warning: {}: the estimated contact velocities do not approach at the impact \
             centre; {why}",
            case.file
        );
    }
    let problem = fitcase::problem(&case, choice)?;
    let settings = fitcase::settings(&case, a.moment_form.into(), unique(&a.branch))?;
    let report = pim_fit::fit(&problem, &settings)
        .map_err(|e| Failure::Input(format!("{}: {e}", case.file)))?;
    let unit = fitcase::sigma_unit(&case)?;
    let branch_records: Vec<records::BranchRecord> = report
        .branches
        .iter()
        .map(|b| records::BranchRecord::new(b).with_chi_square(&problem, unit))
        .collect();
    let record = json(&records::FitOut {
        cost_function: name.to_string(),
        branches: branch_records.clone(),
        best: report.best,
        notes: report.notes.clone(),
    })?;
    let mut table = tables::fit_table(&title_of(&case), name, &report, a.units.into());
    for r in &branch_records {
        if let Some(c) = &r.chi_square {
            table.push_str(&format!(
                "branch {}: chi-square {:.3} with {} degrees of freedom, p = {}\n",
                r.moment.name(),
                c.value,
                c.degrees_of_freedom,
                c.p_value
                    .map_or_else(|| "undefined".to_string(), |p| format!("{p:.4}"))
            ));
        }
    }
    if let Some(dir) = &a.out {
        let contact = super::draw::estimated_contact(&case);
        let best = report.best_branch().and_then(|b| b.solution.as_ref());
        let d = super::draw::diagram(
            &case,
            &problem.impact,
            contact.as_ref(),
            best.map(crate::render::diagram::Solved::of_fit),
        );
        let md = markdown::fit(&title_of(&case), name, &report, a.units.into());
        super::draw::write_result_dir(dir, &record, &md, &d)?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &table,
    })?;
    if let Some(b) = report.best_branch() {
        use pim_fit::ActiveConstraint as A;
        for a in b.solution.iter().flat_map(|s| &s.active_constraints) {
            let hint = match a {
                A::EHigh => "the data want more restitution: widen [bounds] e",
                A::MuLow | A::MuHigh => "widen [bounds] mu",
                A::VelocityBound(_) => "widen [bounds] velocity / yaw_rate, or check the estimates",
                A::EmLow => "em = -1 is the end of its physical range",
                _ => continue,
            };
            eprintln!(
                "pim: warning: {}: the best branch ({}) ends on a bound: {a}; {hint}",
                case.file,
                b.moment.name()
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
    Ok(ExitCode::from(EXIT_OK))
}
