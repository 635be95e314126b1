//! `pim batch` and `pim compare-costs`: the refit of a data file.

use super::batch_plan::plan;
use super::print_out;
use crate::args::{BatchArgs, BatchFormat};
use crate::error::{Failure, EXIT_OK, EXIT_SOME_FAILED};
use crate::inputs::load_ricsac;
use anyhow::Result;
use pim_case::reference::parse_brach;
use pim_render::{batch_tables, figures};
use pim_studies::batch;
use std::process::ExitCode;

/// Reads a tolerances file (`--tolerances`).
fn load_tolerances(
    path: &std::path::Path,
) -> Result<pim_studies::uncertainty::Tolerances, Failure> {
    let text = crate::inputs::read_text_file(path, pim_case::case::MAX_CASE_BYTES)?;
    Ok(pim_studies::uncertainty::Tolerances::from_text(
        &path.display().to_string(),
        &text,
    )?)
}

/// `pim batch` and (`compare`) `pim compare-costs`: a data file, or case files.
pub fn run(a: &BatchArgs, compare: bool) -> Result<ExitCode> {
    refuse_unused(a, compare)?;
    let data = match a.inputs.as_slice() {
        [one] if !one.is_dir() && !super::batch_cases::is_case_file(one) => one.clone(),
        _ if compare => {
            return Err(Failure::Input(
                "compare-costs takes a data file (CSV), not case files".into(),
            )
            .into())
        }
        _ if a.damage.is_some() => {
            return Err(Failure::Input(
                "--damage goes with a data file (CSV): case files give their crush in [damage]"
                    .into(),
            )
            .into())
        }
        _ => return super::batch_cases::run(a),
    };
    let tolerances = tolerances_of(a)?;
    let file = data.display().to_string();
    let mut tests = load_ricsac(&data)?;
    if !a.tests.is_empty() {
        for t in &a.tests {
            if !tests.iter().any(|r| r.test == *t) {
                let have: Vec<String> = tests.iter().map(|r| r.test.to_string()).collect();
                return Err(Failure::Input(format!(
                    "--tests: test {t} is not in {file} (it has {})",
                    have.join(", ")
                ))
                .into());
            }
        }
        tests.retain(|r| a.tests.contains(&r.test));
    }
    let plan = plan(a)?;
    // A data file has no [units]: its tables are SI unless --units says otherwise.
    let units: pim_case::units::UnitSystem =
        a.units.map_or(pim_case::units::UnitSystem::Si, Into::into);
    let (records, damage) = fitted(a, (&tests, &plan), (&file, &data), tolerances.as_ref())?;
    let damage_text = damage
        .as_ref()
        .map(|d| pim_render::damage_batch::damage_table(d, units));
    let (brach, v18) = references(a, &data, &plan);
    // The PIM tables and figures read PIM's records; the models side by side read all.
    let pim_records: Vec<batch::BatchRecord> = records
        .iter()
        .filter(|r| r.model == pim_fit::FitModel::Pim)
        .cloned()
        .collect();
    let several = plan.models != [pim_fit::FitModel::Pim];
    let models_text = several.then(|| batch_tables::models_table(&records, &plan.costs));
    let mut summary = batch_tables::summary_table(&pim_records, &plan.costs, units);
    if a.conditions == crate::args::Conditions::V18 {
        summary.insert_str(
            0,
            "Conditions: Vossou & Koulocheris 2018 (--conditions v18): Brach's 1983 moment \
             equation (with its sign error), mu in [0, 1.2] without mu <= mu_max, em in [-1, 0]; \
             answers with mu above mu_max reverse the sliding (mu/mu_max > 1).\n\n",
        );
    }
    if tolerances.is_some() {
        summary.push_str(&batch_tables::intervals_table(
            &records, a.draws, a.seed, units,
        ));
    }
    let compare_text = batch_tables::compare_costs_table(&pim_records, &plan.costs, units);
    let brach_text = brach
        .as_ref()
        .filter(|_| plan.costs.contains(&pim_fit::CostPreset::Q2) && !pim_records.is_empty())
        .map(|b| batch_tables::brach_table(&pim_records, b));
    let records_json = super::json_sorted(&pim_documents::schema::DataBatchOut {
        data: file.clone(),
        records: records.clone(),
    })?;
    let v18_text = v18.map(|p| batch_tables::v18_table(&pim_records, &p));
    let records_csv =
        batch_tables::records_csv(&records).map_err(|e| Failure::Output(e.to_string()))?;
    let text = match a.format {
        BatchFormat::Json => records_json.clone(),
        BatchFormat::Csv => records_csv.clone(),
        BatchFormat::Table if compare => compare_text.clone(),
        BatchFormat::Table => table_text(
            (&file, tests.len()),
            &pim_records,
            &summary,
            [&models_text, &brach_text, &v18_text, &damage_text],
        ),
    };
    print_out(&text)?;
    if let Some(dir) = &a.out {
        let written = Written {
            records: (&records, &pim_records),
            csv: (&records_csv, &records_json),
            texts: (&summary, &compare_text),
            optional: [&brach_text, &v18_text, &damage_text, &models_text],
            damage: damage.as_ref(),
        };
        write_out(a, dir, (&file, &plan), written)?;
    }
    let unsolved = records.iter().filter(|r| !r.solved()).count();
    if unsolved > 0 && a.format != BatchFormat::Json {
        eprintln!(
            "pim: {} of {} records solved; {unsolved} have no solution (infeasible data or a \
             failed row), their rows say why",
            records.len() - unsolved,
            records.len()
        );
    }
    Ok(ExitCode::from(if unsolved > 0 && a.strict {
        EXIT_SOME_FAILED
    } else {
        EXIT_OK
    }))
}

/// The arguments `pim compare-costs` accepts but does not use: refused, not ignored.
fn refuse_unused(a: &BatchArgs, compare: bool) -> Result<()> {
    if compare && a.damage.is_some() {
        return Err(Failure::Input(
            "compare-costs compares the cost functions' fits: --damage is for `pim batch \
             DATA.csv --damage CRUSH.csv`"
                .into(),
        )
        .into());
    }
    if compare && (a.draws > 0 || a.tolerances.is_some()) {
        // Accepted by the shared arguments, used by nothing here: refused, not ignored.
        return Err(Failure::Input(
            "compare-costs compares the cost functions' fits and draws no intervals: \
             --draws and --tolerances are for `pim batch DATA.csv --draws N --tolerances FILE`"
                .into(),
        )
        .into());
    }
    Ok(())
}

/// `--tolerances` with `--draws`: the data file's standard deviations, or `None` without
/// draws.
fn tolerances_of(a: &BatchArgs) -> Result<Option<pim_studies::uncertainty::Tolerances>> {
    Ok(match (&a.tolerances, a.draws) {
        (None, 0) => None,
        (Some(_), 0) => {
            return Err(
                Failure::Input("--tolerances is used with --draws N (N >= 1)".into()).into(),
            )
        }
        (None, _) => {
            return Err(Failure::Input(
                "--draws with a data file needs --tolerances FILE: the data file gives no \
                 standard deviations (see `pim batch --help`, INTERVALS FOR A DATA FILE)"
                    .into(),
            )
            .into())
        }
        (Some(path), _) => Some(load_tolerances(path)?),
    })
}

/// The records of every test under the plan (with their intervals where `tolerances` are
/// given), and the crush energies of `--damage`; on `--threads` threads where given, a
/// progress bar on a terminal.
fn fitted(
    a: &BatchArgs,
    (tests, plan): (&[pim_case::ricsac::RicsacTest], &batch::BatchPlan),
    (file, data): (&str, &std::path::Path),
    tolerances: Option<&pim_studies::uncertainty::Tolerances>,
) -> Result<(
    Vec<batch::BatchRecord>,
    Option<Vec<pim_studies::ricsac_damage::DamageRecord>>,
)> {
    let n_jobs = (tests.len() * plan.costs.len()) as u64;
    let show =
        a.format != BatchFormat::Json && std::io::IsTerminal::is_terminal(&std::io::stderr());
    let bar = if show {
        let b = indicatif::ProgressBar::new(n_jobs);
        b.set_message("fitting");
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let observer = super::study::Bar(bar.clone());
    let work = || {
        let mut records = batch::run(tests, plan, &observer);
        if let Some(t) = tolerances {
            bar.set_message("intervals");
            batch::add_data_intervals(&mut records, tests, file, t, plan, a.draws, a.seed);
        }
        records
    };
    let records = match a.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| Failure::Input(format!("--threads {n}: {e}")))?
            .install(work),
        None => work(),
    };
    bar.finish_and_clear();
    let damage = match &a.damage {
        Some(path) => {
            let work = || super::batch_damage::records(path, data, tests, &plan.settings);
            Some(match a.threads {
                Some(n) => rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .map_err(|e| Failure::Input(format!("--threads {n}: {e}")))?
                    .install(work)?,
                None => work()?,
            })
        }
        None => None,
    };
    Ok((records, damage))
}

/// V18's printed costs, per cost function.
type Printed = Vec<(pim_fit::CostPreset, Vec<(u32, f64)>)>;

/// The reference tables beside the data file (`reference/`): Brach's 1984 Table 1, or, under
/// V18's conditions, V18's printed costs (then not Brach's).
fn references(
    a: &BatchArgs,
    data: &std::path::Path,
    plan: &batch::BatchPlan,
) -> (Option<Vec<pim_case::reference::BrachRow>>, Option<Printed>) {
    let brach = data
        .parent()
        .map(|d| d.join("reference").join("brach1984_table1.csv"))
        .filter(|p| p.is_file())
        .and_then(|p| crate::inputs::read_text_file(&p, pim_case::ricsac::MAX_DATA_BYTES).ok())
        .and_then(|t| parse_brach(&t).ok());
    // V18's printed costs, per cost function, when the batch runs under their conditions.
    let v18 = (a.conditions == crate::args::Conditions::V18)
        .then(|| {
            let mut printed = Vec::new();
            for cost in pim_fit::CostPreset::ALL
                .into_iter()
                .filter(|c| plan.costs.contains(c))
            {
                let path = data
                    .parent()?
                    .join("reference")
                    .join(pim_case::reference::vossou_table(cost));
                let text =
                    crate::inputs::read_text_file(&path, pim_case::ricsac::MAX_DATA_BYTES).ok()?;
                let rows = pim_case::reference::parse_vossou(&text).ok()?;
                printed.push((cost, rows));
            }
            Some(printed)
        })
        .flatten();
    let brach = brach.filter(|_| v18.is_none());
    (brach, v18)
}

/// The batch's table: the summary of PIM's records, then the models side by side, Brach's
/// table, V18's and the crush energies (`optional`, in that order), each where there is one.
fn table_text(
    (file, tests): (&str, usize),
    pim_records: &[batch::BatchRecord],
    summary: &str,
    optional: [&Option<String>; 4],
) -> String {
    let mut t = format!("{file}: {tests} tests\n\n");
    if !pim_records.is_empty() {
        t.push_str(summary);
    }
    let [models, brach, v18, damage] = optional;
    for text in [models, brach, v18].into_iter().flatten() {
        t.push_str(text);
    }
    if let Some(d) = damage {
        t.push('\n');
        t.push_str(d);
    }
    t
}

/// What `--out` writes besides the figures: the records (all, PIM's), their CSV and JSON, the
/// summary and the costs compared, then Brach's table, V18's, the crush energies and the models
/// side by side where there are.
struct Written<'a> {
    records: (&'a [batch::BatchRecord], &'a [batch::BatchRecord]),
    csv: (&'a str, &'a str),
    texts: (&'a str, &'a str),
    optional: [&'a Option<String>; 4],
    damage: Option<&'a Vec<pim_studies::ricsac_damage::DamageRecord>>,
}

/// Writes the batch's tables and figures into `dir` (`--out`), all or nothing.
fn write_out(
    a: &BatchArgs,
    dir: &std::path::Path,
    (file, plan): (&str, &batch::BatchPlan),
    written: Written,
) -> Result<()> {
    let Written {
        records: (records, pim_records),
        csv: (records_csv, records_json),
        texts: (summary, compare_text),
        optional: [brach_text, v18_text, damage_text, models_text],
        damage,
    } = written;
    let out = super::output::OutDir::create(dir)?;
    out.write("records.csv", records_csv)?;
    out.write("records.json", records_json)?;
    let mut tables = 2;
    let mut figs = Vec::new();
    if !pim_records.is_empty() {
        out.write(
            "velocity_errors.csv",
            &batch_tables::errors_csv(pim_records),
        )?;
        out.write("summary.txt", summary)?;
        out.write("compare_costs.txt", compare_text)?;
        tables += 3;
        figs = figures::all(pim_records, &plan.costs, &plan.settings)
            .map_err(|e| Failure::Output(format!("{}: figures: {e}", dir.display())))?;
    }
    if let Some(b) = brach_text {
        out.write("brach1984.txt", b)?;
        tables += 1;
    }
    if let Some(v) = v18_text {
        out.write("v18.txt", v)?;
        tables += 1;
    }
    if let (Some(d), Some(text)) = (damage, damage_text) {
        out.write("damage.txt", text)?;
        out.write(
            "damage.csv",
            &pim_render::damage_batch::damage_csv(d).map_err(|e| Failure::render(dir, e))?,
        )?;
        out.write(
            "damage.json",
            &super::json_sorted(&pim_documents::schema::DamageBatchOut {
                data: file.to_string(),
                records: d.to_vec(),
            })?,
        )?;
        tables += 1;
        figs.push(
            pim_render::damage_batch::crush_energy_figure(d)
                .map_err(|e| Failure::Output(format!("{}: figures: {e}", dir.display())))?,
        );
    }
    if let Some(m) = models_text {
        out.write("models.txt", m)?;
        tables += 1;
        figs.push(
            figures::models(records, &plan.costs, &plan.models)
                .map_err(|e| Failure::Output(format!("{}: figures: {e}", dir.display())))?,
        );
    }
    super::write_figures(&out, &figs)?;
    out.commit()?;
    if a.format != BatchFormat::Json {
        eprintln!(
            "pim: wrote {tables} tables and {} figures to {}",
            figs.len(),
            dir.display()
        );
    }
    Ok(())
}
