//! `pim`: Planar Impact Mechanics for two-vehicle collision reconstruction.
//!
//! `main` only maps the outcome of [`run`] to an exit status; every message is printed once.
//! Modules: [`args`] (the command line and its help), [`commands`] (one per subcommand),
//! [`inputs`] (reading files into pim-studies's parsers), [`runout_help`] (the help of `pim
//! runout`), [`error`] (failure categories and exit codes); tables, CSV and figures come from
//! pim-render.

mod args;
mod commands;
mod edr_args;
mod error;
mod fit_help;
mod inputs;
mod rectify_args;
mod runout_help;
mod serve_args;
mod set_args;
mod survey_args;

use anyhow::Result;
use args::{Cli, Command};
use clap::Parser;
use error::{Failure, EXIT_BAD_INPUT, EXIT_OK};
use std::process::ExitCode;

fn run(cli: Cli) -> Result<ExitCode> {
    match &cli.command {
        Command::Solve(a) => commands::solve::run(a),
        Command::Sensitivity { solve, percent } => commands::solve::sensitivity(solve, *percent),
        Command::Fit(a) => commands::fit::run(a),
        Command::Draw(a) => commands::draw::run(a),
        Command::Uncertainty(a) => commands::uncertainty::run(a),
        Command::Report(a) => commands::report::run(a),
        Command::Runout(a) => commands::runout::run(a),
        Command::PredictDv(a) => commands::predict::run(a),
        Command::Batch(a) => commands::batch::run(a, false),
        Command::CompareCosts(a) => commands::batch::run(a, true),
        Command::Set(a) => commands::set::run(a),
        Command::Survey(a) => commands::survey::run(a),
        Command::Edr(a) => commands::edr::run(a),
        Command::Serve(a) => commands::serve::run(a),
        Command::Rectify(a) => commands::rectify::run(a),
    }
}

/// A bad value of a flag in the one form of every message, `pim: FLAG: what is wrong; what
/// is accepted` (clap's own rendering, with its usage, for everything else).
fn flag_message(e: &clap::Error) -> Option<String> {
    use clap::error::{ContextKind, ContextValue, ErrorKind};
    let text = |k: ContextKind| match e.get(k) {
        Some(ContextValue::String(s)) => Some(s.clone()),
        Some(ContextValue::Strings(v)) => Some(v.join(", ")),
        _ => None,
    };
    let flag = text(ContextKind::InvalidArg)?;
    let flag = flag.split_whitespace().next().unwrap_or(&flag).to_string();
    let value = text(ContextKind::InvalidValue).unwrap_or_default();
    match e.kind() {
        ErrorKind::ValueValidation => {
            let why = std::error::Error::source(e).map(|s| s.to_string())?;
            if why.contains(&value) {
                Some(format!("pim: {flag}: {why}"))
            } else {
                Some(format!("pim: {flag}: {value:?}: {why}; expected a number"))
            }
        }
        ErrorKind::InvalidValue => {
            let accepted = text(ContextKind::ValidValue).unwrap_or_default();
            Some(format!(
                "pim: {flag}: {value:?} is not an accepted value; accepted: {accepted}"
            ))
        }
        _ => None,
    }
}

/// Whether standard output was closed when the program started. The Rust runtime opens a
/// closed standard descriptor on `/dev/null` for reading and writing before `main`, which a
/// shell's redirection to `/dev/null` never does (it opens it for writing only): that is how a
/// closed descriptor is told from an output thrown away on purpose.
fn stdout_closed() -> bool {
    use rustix::fs::{FileType, OFlags};
    let out = std::io::stdout();
    let (Ok(flags), Ok(stat)) = (rustix::fs::fcntl_getfl(&out), rustix::fs::fstat(&out)) else {
        return true;
    };
    let null = FileType::from_raw_mode(stat.st_mode) == FileType::CharacterDevice
        && rustix::fs::major(stat.st_rdev) == 1
        && rustix::fs::minor(stat.st_rdev) == 3;
    null && (flags & OFlags::RWMODE) == OFlags::RDWR
}

/// Exit status of a command stopped by Ctrl-C (128 + SIGINT, as a shell reports it).
const EXIT_INTERRUPTED: i32 = 130;

fn main() -> ExitCode {
    // Ctrl-C: said, and the shell's status for it. Every file is written whole or not at all
    // (beside its target, then renamed), so stopping here leaves no half-written file.
    let _ = ctrlc::set_handler(|| {
        eprintln!("pim: interrupted");
        std::process::exit(EXIT_INTERRUPTED);
    });
    // A closed standard output (`pim ... >&-`) would swallow every answer in silence: refused
    // before anything is computed.
    if stdout_closed() {
        eprintln!("pim: standard output is closed: nothing could be written (give it a file)");
        return ExitCode::from(error::EXIT_IO);
    }
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() {
                EXIT_BAD_INPUT
            } else {
                EXIT_OK
            };
            match flag_message(&e) {
                Some(m) => eprintln!("{m}"),
                None => {
                    let _ = e.print();
                }
            }
            return ExitCode::from(code);
        }
    };
    match run(cli) {
        Ok(code) => code,
        Err(err) => {
            let code = err
                .downcast_ref::<Failure>()
                .map_or(EXIT_BAD_INPUT, Failure::code);
            eprintln!("pim: {err:#}");
            ExitCode::from(code)
        }
    }
}
