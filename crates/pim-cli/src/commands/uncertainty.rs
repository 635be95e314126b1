//! `pim uncertainty`: the seeded parametric bootstrap of a fit case.

use super::{json, print_out, title_of};
use crate::args::{Format, UncertaintyArgs};
use crate::error::Failure;
use crate::inputs::{checked_impact, load_case};
use anyhow::Result;
use pim_case::units::UnitSystem;
use pim_documents::records::BoundSource;
use pim_studies::fitcase::CostChoice;
use pim_studies::uncertainty::{self, Study};
use std::fmt::Write as _;
use std::process::ExitCode;

/// The table of a study, its speeds in the unit system `u`.
fn table(title: &str, s: &Study, u: UnitSystem) -> String {
    let s = &s.in_speed_unit(u.speed(1.0));
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{title}\nparametric bootstrap: {} draws (seed {}), {} with an admissible fit\n",
        s.draws, s.seed, s.feasible_draws
    );
    let _ = writeln!(
        t,
        "{:<22} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "quantity", "nominal", "p05", "p50", "p95", "mean", "sd", "sd (lin.)"
    );
    for &name in s.names() {
        let q = &s.quantities[name];
        let nominal = s
            .nominal
            .get(name)
            .map_or_else(|| "-".to_string(), |v| format!("{v:.4}"));
        let lin = s
            .linearised_sd
            .get(name)
            .map_or_else(|| "-".to_string(), |v| format!("{v:.4}"));
        let _ = writeln!(
            t,
            "{name:<22} {nominal:>10} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {lin:>10}{}",
            q.p05,
            q.p50,
            q.p95,
            q.mean,
            q.sd,
            if q.not_determined {
                "  NOT DETERMINED by the data: not a confidence interval".to_string()
            } else if s.nominal.get(name).is_some_and(|v| {
                let tol = 1e-9 * (1.0 + v.abs());
                *v < q.p05 - tol || *v > q.p95 + tol
            }) {
                "  the nominal value lies OUTSIDE its 90 % interval: the draws' answers are \
                 skewed away from it"
                    .to_string()
            } else if let Some(h) = q.reaches_bound {
                format!(
                    "  ENDED BY the {} bound ({}; {:.0} % of the draws rest on it), not by the data",
                    h.bound,
                    match h.source {
                        BoundSource::Case => "set in [bounds]",
                        BoundSource::Default => "a default: set [bounds] to choose it",
                    },
                    100.0 * h.share
                )
            } else {
                String::new()
            }
        );
    }
    let _ = writeln!(
        t,
        "(speeds at contact and delta-V in {}, energy loss in %; sd (lin.): delta method)\n",
        u.speed_label()
    );
    if !s.nominal_bounds.is_empty() {
        let list: Vec<String> = s
            .nominal_bounds
            .iter()
            .map(|b| format!("{} ({})", b.at, b.bound))
            .collect();
        let _ = writeln!(t, "the nominal fit rests on bounds: {}", list.join(", "));
    }
    if s.has_branches() {
        let shares: Vec<String> = s
            .branch_share
            .iter()
            .map(|(b, v)| format!("{b} {:.1} %", 100.0 * v))
            .collect();
        let _ = writeln!(t, "best branch over the draws: {}", shares.join(", "));
    }
    let _ = writeln!(
        t,
        "\ndominant inputs (first-order index, correlation ratio):"
    );
    for sens in &s.sensitivity {
        let _ = writeln!(
            t,
            "  {:<22} {}",
            sens.quantity,
            super::study::dominant(sens)
        );
    }
    t
}

/// `pim uncertainty`.
pub fn run(a: &UncertaintyArgs) -> Result<ExitCode> {
    let case = load_case(&a.case)?;
    let (_, warnings) = checked_impact(&case)?;
    if a.draws == 0 {
        return Err(Failure::Input("--draws must be at least 1".into()).into());
    }
    let asked = pim_studies::question::Question::of(&case, a.cost);
    super::notes(&asked);
    if asked.question == pim_studies::question::Question::Reconstruction {
        return super::scene_uncertainty::run(a, &case, warnings);
    }
    let choice = match a.cost {
        Some(c) => CostChoice::Preset(c),
        None => CostChoice::Custom,
    };
    let unc = case.spreads();
    let (pool, bar) = super::study::pool_and_bar(a)?;
    let observer = super::study::Bar(bar.clone());
    let study = pool.install(|| {
        uncertainty::run(
            &case,
            &unc,
            choice,
            pim_fit::FitSettings {
                model: a.model,
                ..Default::default()
            },
            a.draws,
            a.seed,
            &observer,
        )
    })?;
    bar.finish_and_clear();
    if study.feasible_draws == 0 {
        return Err(Failure::NoAnswer(format!(
            "{}: none of the {} draws has an admissible fit, so there are no intervals (the \
             nominal fit and the spread of the inputs leave nothing feasible: check [bounds], \
             [sigma] and [uncertainty])",
            case.file, study.draws
        ))
        .into());
    }
    let record = json(&study)?;
    let units = a
        .units
        .map_or_else(|| UnitSystem::of(&case.written_units), Into::into);
    let text = table(&title_of(&case), &study, units);
    if let Some(dir) = &a.out {
        // The report of the nominal fit with the study's ranges and figures.
        let fitted = pim_studies::documents::fit(
            &case,
            a.cost,
            pim_fit::FitModel::Pim,
            pim_core::MomentForm::Corrected,
            pim_fit::MomentBranch::ALL.to_vec(),
        )
        .map_err(Failure::from)?;
        let name = a.cost.map_or("custom", |p| p.name());
        let doc = pim_render::report::build::fit(&case, &fitted, name, Some(&study), units)
            .map_err(|e| Failure::Output(format!("{}: figures: {e}", dir.display())))?;
        let out = super::output::OutDir::create(dir)?;
        out.write("uncertainty.json", &record)?;
        out.write("uncertainty.txt", &text)?;
        super::write_report(&out, &doc)?;
        out.commit()?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &text,
    })?;
    let mut why = Vec::new();
    let ended: Vec<&str> = study
        .names()
        .iter()
        .filter(|q| {
            study.quantities[**q]
                .reaches_bound
                .is_some_and(|h| h.source == BoundSource::Default)
        })
        .copied()
        .collect();
    if !ended.is_empty() {
        why.push(format!(
            "the intervals of {} are ended by a default bound (set it in [bounds] to choose it)",
            ended.join(", ")
        ));
    }
    if study
        .nominal_bounds
        .iter()
        .any(|b| b.source == BoundSource::Default)
    {
        why.push("the nominal fit rests on a default bound".into());
    }
    Ok(crate::inputs::strict_status(a.strict, warnings, why))
}
