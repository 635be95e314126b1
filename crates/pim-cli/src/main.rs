//! `pim`: Planar Impact Mechanics for two-vehicle collision reconstruction.
//!
//! `main` only maps the outcome of [`run`] to an exit status; every message is printed once.
//! Modules: [`args`] (the command line and its help), [`commands`] (one per subcommand),
//! [`inputs`] (reading files into pim-data's parsers), [`render`] (tables, CSV, figures),
//! [`error`] (failure categories and exit codes).

mod args;
mod commands;
mod error;
mod inputs;

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
        Command::PredictDv(a) => commands::predict::run(a),
        Command::Batch(a) => commands::batch::run(a, false),
        Command::CompareCosts(a) => commands::batch::run(a, true),
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() {
                EXIT_BAD_INPUT
            } else {
                EXIT_OK
            };
            let _ = e.print();
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
