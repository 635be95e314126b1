//! `pim batch` over case files: each file fitted under each cost function, the records streamed
//! to stdout and to `--out` as they finish (memory does not grow with the number of files).

use crate::args::{BatchArgs, BatchFormat};
use crate::error::{Failure, EXIT_OK, EXIT_SOME_FAILED};
use crate::inputs::{io_reason, read_text_file};
use anyhow::Result;
use pim_case::case::MAX_CASE_BYTES;
use pim_studies::case_batch::{CaseBatch, CaseText, Tally};
use pim_studies::case_records::CaseRecord;
use pim_studies::fitcase::CostChoice;
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

/// The summary of a batch of case files: the counts, the notes, the files without intervals
/// and those that could not be read or fitted.
fn summary_text(tally: &Tally, files: usize) -> String {
    let t = tally;
    let mut s = format!(
        "{files} case files, {} records ({} solved, {} without a solution); {} files could not be read or fitted\n\n",
        t.records,
        t.records - t.unsolved,
        t.unsolved,
        t.files_failed
    );
    s.push_str("cost    outcome          records\n");
    for (cost, outcomes) in &t.by_cost {
        for (o, n) in outcomes {
            s.push_str(&format!("{cost:<7} {o:<16} {n:>7}\n"));
        }
    }
    if !t.notes.is_empty() {
        s.push_str("\nnotes:\n");
        for n in &t.notes {
            s.push_str(&format!("  {n}\n"));
        }
    }
    if !t.no_intervals.is_empty() {
        s.push_str(&format!(
            "\nno intervals for {} records (--draws):\n",
            t.no_intervals.len()
        ));
        for why in &t.no_intervals {
            s.push_str(&format!("  {why}\n"));
        }
    }
    if !t.failed.is_empty() {
        s.push_str("\nfiles that could not be read or fitted:\n");
        for f in &t.failed {
            s.push_str(&format!("  {f}\n"));
        }
    }
    s
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

/// The arguments that select among a data file's rows or models, or give its tolerances:
/// refused with case files, not ignored.
fn refuse_data_only(a: &BatchArgs) -> Result<()> {
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
    Ok(())
}

/// Where the records stream to: `--out`'s records.csv and records.jsonl (named in messages by
/// their final paths), and stdout as CSV or JSON lines (`--format`).
struct Sinks {
    csv_file: Option<(PathBuf, csv::Writer<std::fs::File>)>,
    jsonl_file: Option<(PathBuf, std::io::BufWriter<std::fs::File>)>,
    stdout_csv: Option<csv::Writer<std::io::StdoutLock<'static>>>,
    format: BatchFormat,
}

impl Sinks {
    /// Opened before any work, so that an unwritable directory fails at once; each CSV with
    /// its header.
    fn open(out: Option<&super::output::OutDir>, format: BatchFormat) -> Result<Self> {
        let mut sinks = Sinks {
            csv_file: None,
            jsonl_file: None,
            stdout_csv: None,
            format,
        };
        if let Some(out) = out {
            // Written in the staging folder, named in messages by their final paths.
            let (p, shown) = (out.file("records.csv"), out.shown("records.csv"));
            let mut w = csv::Writer::from_path(&p)
                .map_err(|e| Failure::Output(format!("{}: {e}", shown.display())))?;
            w.write_record(CaseRecord::CSV_HEADER)
                .map_err(|e| Failure::Output(format!("{}: {e}", shown.display())))?;
            sinks.csv_file = Some((shown, w));
            let (p, shown) = (out.file("records.jsonl"), out.shown("records.jsonl"));
            let f = std::fs::File::create(&p).map_err(|e| out_err(&shown, e))?;
            sinks.jsonl_file = Some((shown, std::io::BufWriter::new(f)));
        }
        sinks.stdout_csv = (format == BatchFormat::Csv)
            .then(|| csv::Writer::from_writer(std::io::stdout().lock()));
        if let Some(w) = &mut sinks.stdout_csv {
            if let Err(e) = w.write_record(CaseRecord::CSV_HEADER) {
                closed_or(e)?;
                sinks.stdout_csv = None;
            }
        }
        Ok(sinks)
    }

    /// One record to every sink.
    fn write(&mut self, r: &CaseRecord) -> Result<()> {
        let row = r.csv_row();
        if let Some((p, w)) = &mut self.csv_file {
            w.write_record(&row)
                .map_err(|e| Failure::Output(format!("{}: {e}", p.display())))?;
        }
        if let Some((p, w)) = &mut self.jsonl_file {
            serde_json::to_writer(&mut *w, r)?;
            w.write_all(b"\n").map_err(|e| out_err(p, e))?;
        }
        match self.format {
            BatchFormat::Csv => {
                if let Some(w) = &mut self.stdout_csv {
                    if let Err(e) = w.write_record(&row) {
                        // A reader that stopped (`| head`) ends our stdout quietly.
                        closed_or(e)?;
                        self.stdout_csv = None;
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
        Ok(())
    }

    /// Stdout's CSV flushed after each chunk of files.
    fn flush_stdout(&mut self) -> Result<()> {
        if let Some(w) = &mut self.stdout_csv {
            if let Err(e) = w.flush() {
                closed_or(csv::Error::from(e))?;
                self.stdout_csv = None;
            }
        }
        Ok(())
    }

    /// The files flushed at the end.
    fn finish(self) -> Result<()> {
        if let Some((p, mut w)) = self.csv_file {
            w.flush().map_err(|e| out_err(&p, e))?;
        }
        if let Some((p, mut w)) = self.jsonl_file {
            w.flush().map_err(|e| out_err(&p, e))?;
        }
        Ok(())
    }
}

/// `pim batch CASES...`.
pub fn run(a: &BatchArgs) -> Result<ExitCode> {
    let files = case_files(&a.inputs)?;
    refuse_data_only(a)?;
    let plan = super::batch_plan::plan(a)?;
    // Each file's own cost, unless --cost names presets.
    let choices: Vec<CostChoice> = if a.cost.is_empty() {
        vec![CostChoice::Custom]
    } else {
        plan.costs.iter().map(|&c| CostChoice::Preset(c)).collect()
    };
    let batch = CaseBatch {
        choices,
        plan,
        draws: a.draws,
        seed: a.seed,
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| Failure::Input(format!("--threads: {e}")))?;

    // Outputs, opened before any work so that an unwritable directory fails at once.
    let out = a
        .out
        .as_deref()
        .map(super::output::OutDir::create)
        .transpose()?;
    let mut sinks = Sinks::open(out.as_ref(), a.format)?;
    let bar = super::study::Bar::on_terminal(true);
    bar.0.set_length(files.len() as u64);
    let mut tally = Tally::default();
    for (k, chunk) in files.chunks(CHUNK).enumerate() {
        let texts: Vec<CaseText> = chunk
            .iter()
            .map(|(path, unreadable)| CaseText {
                name: path.display().to_string(),
                text: match unreadable {
                    Some(why) => Err(why.clone()),
                    None => read_text_file(path, MAX_CASE_BYTES).map_err(|e| e.to_string()),
                },
            })
            .collect();
        let progress = super::study::Offset {
            bar: &bar,
            before: (k * CHUNK) as u64,
        };
        let records = pool.install(|| batch.records(&texts, &progress));
        for file_records in records {
            for why in tally.add_file(&file_records) {
                eprintln!("pim: {why}");
            }
            for r in &file_records {
                sinks.write(r)?;
            }
        }
        sinks.flush_stdout()?;
    }
    bar.0.finish_and_clear();
    let summary = summary_text(&tally, files.len());
    sinks.finish()?;
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
