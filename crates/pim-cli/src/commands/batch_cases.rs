//! `pim batch` over case files: each file fitted under each cost function, the records streamed
//! to stdout and to `--out` as they finish (memory does not grow with the number of files).

use crate::args::{BatchArgs, BatchFormat};
use crate::error::{Failure, EXIT_OK, EXIT_SOME_FAILED};
use crate::inputs::{io_reason, read_text_file};
use anyhow::Result;
use pim_case::case::MAX_CASE_BYTES;
use pim_studies::batch::Outcome;
use pim_studies::batch_scene::{add_intervals, case_records};
use pim_studies::case_records::CaseRecord;
use pim_studies::fitcase::CostChoice;
use rayon::prelude::*;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Files fitted in parallel at a time: enough to keep every core busy, small enough that the
/// records in flight stay a few hundred kilobytes.
const CHUNK: usize = 256;

/// A case file's name: `.toml`, in any case (`.TOML` from a tool that writes capitals).
pub fn is_case_file(path: &Path) -> bool {
    path.extension()
        .is_some_and(|x| x.eq_ignore_ascii_case("toml"))
}

/// One entry of the batch: a case file, or the reason it cannot be read (a failed record, like
/// a file that does not parse; the batch goes on).
type Entry = (PathBuf, Option<String>);

/// The case files named on the command line: files as given, directories as their `*.toml`
/// files in name order (the extension in any case). A `*.toml` entry of a directory that is not
/// a readable regular file (a link that leads nowhere or in a loop, a folder, a FIFO, a device)
/// is an entry with its reason, not skipped in silence and not the end of the batch. A data file
/// (`.csv`) among case files is refused by name: it is run on its own.
fn case_files(inputs: &[PathBuf]) -> Result<Vec<Entry>, Failure> {
    let mut out = Vec::new();
    for p in inputs {
        if p.is_dir() {
            let mut found: Vec<Entry> = Vec::new();
            let entries = std::fs::read_dir(p).map_err(|e| {
                Failure::Input(format!("{}: cannot read: {}", p.display(), io_reason(&e)))
            })?;
            for entry in entries {
                let f = entry
                    .map_err(|e| {
                        Failure::Input(format!("{}: cannot read: {}", p.display(), io_reason(&e)))
                    })?
                    .path();
                if !is_case_file(&f) {
                    continue;
                }
                let name = f.display().to_string();
                let why = match std::fs::metadata(&f) {
                    Ok(m) => pim_case::input::check_regular(&name, &m)
                        .err()
                        .map(|e| e.to_string()),
                    Err(e) => Some(format!(
                        "{name}: cannot be read ({}): a link that leads nowhere or in a loop? fix \
                         or remove it",
                        io_reason(&e)
                    )),
                };
                found.push((f, why));
            }
            found.sort();
            if found.is_empty() {
                return Err(Failure::Input(format!(
                    "{}: no .toml case files in this directory",
                    p.display()
                )));
            }
            out.extend(found);
        } else if p.extension().is_some_and(|x| x.eq_ignore_ascii_case("csv")) {
            return Err(Failure::Input(format!(
                "{}: a data file (CSV) among case files: a data file is refitted on its own, \
                 `pim batch {}`",
                p.display(),
                p.display()
            )));
        } else {
            out.push((p.clone(), None));
        }
    }
    Ok(out)
}

/// Counts for the summary.
#[derive(Default)]
struct Tally {
    by_cost: BTreeMap<String, BTreeMap<String, usize>>,
    records: usize,
    unsolved: usize,
    files_failed: usize,
    /// Each file that could not be read or fitted, with its reason.
    failed: Vec<String>,
    /// Records without the intervals `--draws` asked for, with the reason (e.g. nothing in
    /// the case is uncertain).
    no_intervals: Vec<String>,
    /// What in the files had no effect (each once).
    notes: Vec<String>,
}

impl Tally {
    fn add(&mut self, r: &CaseRecord) {
        *self
            .by_cost
            .entry(r.cost_function.name().to_string())
            .or_default()
            .entry(r.outcome.to_string())
            .or_default() += 1;
        self.records += 1;
        if !r.outcome.solved() {
            self.unsolved += 1;
        }
        if let Some(why) = &r.intervals_error {
            self.no_intervals.push(why.clone());
        }
        for n in &r.notes {
            if !self.notes.contains(n) {
                self.notes.push(n.clone());
            }
        }
    }

    fn text(&self, files: usize) -> String {
        let mut s = format!(
            "{files} case files, {} records ({} solved, {} without a solution); {} files could not be read or fitted\n\n",
            self.records,
            self.records - self.unsolved,
            self.unsolved,
            self.files_failed
        );
        s.push_str("cost    outcome          records\n");
        for (cost, outcomes) in &self.by_cost {
            for (o, n) in outcomes {
                s.push_str(&format!("{cost:<7} {o:<16} {n:>7}\n"));
            }
        }
        if !self.notes.is_empty() {
            s.push_str("\nnotes:\n");
            for n in &self.notes {
                s.push_str(&format!("  {n}\n"));
            }
        }
        if !self.no_intervals.is_empty() {
            s.push_str(&format!(
                "\nno intervals for {} records (--draws):\n",
                self.no_intervals.len()
            ));
            for why in &self.no_intervals {
                s.push_str(&format!("  {why}\n"));
            }
        }
        if !self.failed.is_empty() {
            s.push_str("\nfiles that could not be read or fitted:\n");
            for f in &self.failed {
                s.push_str(&format!("  {f}\n"));
            }
        }
        s
    }
}

/// `Ok` when `e` is stdout's reader having gone away (a closed pipe, `pim batch ... | head`),
/// which is not an error of ours; the error otherwise.
fn closed_or(e: csv::Error) -> Result<()> {
    match e.kind() {
        csv::ErrorKind::Io(io) if io.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        _ => Err(Failure::Output(format!("cannot write to stdout: {e}")).into()),
    }
}

fn out_err(path: &Path, e: std::io::Error) -> Failure {
    Failure::Output(format!(
        "{}: cannot write: {}",
        path.display(),
        io_reason(&e)
    ))
}

/// `pim batch CASES...`.
pub fn run(a: &BatchArgs) -> Result<ExitCode> {
    let files = case_files(&a.inputs)?;
    if !a.tests.is_empty() {
        return Err(
            Failure::Input("--tests selects rows of a data file, not case files".into()).into(),
        );
    }
    if a.model != [pim_fit::FitModel::Pim] {
        return Err(Failure::Input(
            "--model compares the models over a data file; fit a case file with the tangential \
             model by `pim fit CASE --model tangential`"
                .into(),
        )
        .into());
    }
    if a.tolerances.is_some() {
        return Err(Failure::Input(
            "--tolerances is for a data file; case files carry their own [sigma] and \
             [uncertainty]"
                .into(),
        )
        .into());
    }
    let plan = super::batch_plan::plan(a)?;
    // Each file's own cost, unless --cost names presets.
    let choices: Vec<CostChoice> = if a.cost.is_empty() {
        vec![CostChoice::Custom]
    } else {
        plan.costs.iter().map(|&c| CostChoice::Preset(c)).collect()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| Failure::Input(format!("--threads: {e}")))?;

    // Outputs, opened before any work so that an unwritable directory fails at once.
    let mut csv_file = None;
    let mut jsonl_file = None;
    let out = a
        .out
        .as_deref()
        .map(super::output::OutDir::create)
        .transpose()?;
    if let Some(out) = &out {
        // Written in the staging folder, named in messages by their final paths.
        let (p, shown) = (out.file("records.csv"), out.shown("records.csv"));
        let mut w = csv::Writer::from_path(&p)
            .map_err(|e| Failure::Output(format!("{}: {e}", shown.display())))?;
        w.write_record(CaseRecord::CSV_HEADER)
            .map_err(|e| Failure::Output(format!("{}: {e}", shown.display())))?;
        csv_file = Some((shown, w));
        let (p, shown) = (out.file("records.jsonl"), out.shown("records.jsonl"));
        let f = std::fs::File::create(&p).map_err(|e| out_err(&shown, e))?;
        jsonl_file = Some((shown, std::io::BufWriter::new(f)));
    }
    let stdout = std::io::stdout();
    let mut stdout_csv =
        (a.format == BatchFormat::Csv).then(|| csv::Writer::from_writer(stdout.lock()));
    if let Some(w) = &mut stdout_csv {
        if let Err(e) = w.write_record(CaseRecord::CSV_HEADER) {
            closed_or(e)?;
            stdout_csv = None;
        }
    }
    let show = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let bar = if show {
        let b = indicatif::ProgressBar::new(files.len() as u64);
        b.set_message("fitting case files");
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let mut tally = Tally::default();
    for chunk in files.chunks(CHUNK) {
        let records: Vec<Vec<CaseRecord>> = pool.install(|| {
            chunk
                .par_iter()
                .map(|(path, unreadable)| {
                    let name = path.display().to_string();
                    let text = match unreadable {
                        Some(why) => Err(why.clone()),
                        None => read_text_file(path, MAX_CASE_BYTES).map_err(|e| e.to_string()),
                    };
                    let out = match text {
                        Ok(text) => choices
                            .iter()
                            .flat_map(|&c| {
                                let mut recs = case_records(&name, &text, c, &plan);
                                if a.draws > 0 {
                                    if let Some(best) = recs.iter_mut().find(|r| r.best) {
                                        add_intervals(best, &text, &plan, a.draws, a.seed);
                                    }
                                }
                                recs
                            })
                            .collect(),
                        Err(e) => choices
                            .iter()
                            .flat_map(|&c| plan.branches.iter().map(move |&m| (c, m)))
                            .map(|(c, m)| CaseRecord::failed(&name, c, m, Some(e.clone())))
                            .collect(),
                    };
                    bar.inc(1);
                    out
                })
                .collect()
        });
        for file_records in records {
            if file_records.iter().all(|r| r.outcome == Outcome::Failed) {
                tally.files_failed += 1;
                // The error names the file (and line and field).
                let mut reasons: Vec<&str> = file_records
                    .iter()
                    .filter_map(|r| r.error.as_deref())
                    .collect();
                reasons.dedup();
                for why in reasons {
                    eprintln!("pim: {why}");
                    tally.failed.push(why.to_string());
                }
            }
            for r in &file_records {
                tally.add(r);
                let row = r.csv_row();
                if let Some((p, w)) = &mut csv_file {
                    w.write_record(&row)
                        .map_err(|e| Failure::Output(format!("{}: {e}", p.display())))?;
                }
                if let Some((p, w)) = &mut jsonl_file {
                    serde_json::to_writer(&mut *w, r)?;
                    w.write_all(b"\n").map_err(|e| out_err(p, e))?;
                }
                match a.format {
                    BatchFormat::Csv => {
                        if let Some(w) = &mut stdout_csv {
                            if let Err(e) = w.write_record(&row) {
                                // A reader that stopped (`| head`) ends our stdout quietly.
                                closed_or(e)?;
                                stdout_csv = None;
                            }
                        }
                    }
                    BatchFormat::Json => {
                        let mut line = serde_json::to_string(r)?;
                        line.push('\n');
                        super::print_out(&line)?;
                    }
                    BatchFormat::Table => {}
                }
            }
        }
        if let Some(w) = &mut stdout_csv {
            if let Err(e) = w.flush() {
                closed_or(csv::Error::from(e))?;
                stdout_csv = None;
            }
        }
    }
    bar.finish_and_clear();
    let summary = tally.text(files.len());
    if let Some((p, mut w)) = csv_file {
        w.flush().map_err(|e| out_err(&p, e))?;
    }
    if let Some((p, mut w)) = jsonl_file {
        w.flush().map_err(|e| out_err(&p, e))?;
    }
    if let Some(out) = out {
        out.write("summary.txt", &summary)?;
        let dir = out.target().to_path_buf();
        out.commit()?;
        eprintln!(
            "pim: wrote records.csv, records.jsonl and summary.txt to {}",
            dir.display()
        );
    }
    if a.format == BatchFormat::Table {
        super::print_out(&summary)?;
    } else {
        eprint!("{summary}");
    }
    if tally.files_failed == files.len() {
        // Nothing could be read or fitted: the run answered nothing, whatever it wrote.
        return Err(Failure::Input(format!(
            "none of the {} case files could be read or fitted (each is named above)",
            files.len()
        ))
        .into());
    }
    Ok(ExitCode::from(if tally.unsolved > 0 && a.strict {
        EXIT_SOME_FAILED
    } else {
        EXIT_OK
    }))
}
