//! `pim`: Planar Impact Mechanics for two-vehicle collision reconstruction.
//!
//! `main` only maps the outcome of [`run`] to an exit status; every message is printed once.

use anyhow::Result;
use clap::{Parser, Subcommand, ValueEnum};
use pim_cli::error::{self, Failure, EXIT_CODES_HELP, EXIT_OK};
use pim_cli::{case, output};
use pim_core::{MomentForm, SolveOptions, TangentialCondition};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

const ABOUT: &str = "Planar Impact Mechanics (Brach) for two-vehicle collisions: solve the six \
impulse-momentum equations, study coefficient sensitivity, and fit coefficients to crash data.";

const CASE_HELP: &str = "\
CASE FILE (TOML, SI units, angles in degrees):
  [vehicle1]                       # vehicle2 likewise
  mass = 1955.0                    # kg
  yaw_inertia = 4723.0             # kg m^2
  heading = 0.0                    # deg, theta: length axis to the x axis
  d = 1.8                          # m, CG to impact centre C
  phi = 0.0                        # deg, CG-to-C line to the length axis
  [impact]
  crush_angle = -30.0              # deg, Gamma: crush surface to the y axis
  [coefficients]
  e = 0.015                        # restitution, 0..1
  mu = 0.968                       # equivalent friction (signed impulse ratio)
  em = -0.774                      # moment restitution, -1..0 or exactly 1
  [initial]                        # velocities at contact; or [final] to solve backwards
  vehicle1 = { vx = -13.01, vy = 0.0, omega = 0.0 }      # m/s, m/s, rad/s
  vehicle2 = { vx = 6.505, vy = 11.267, omega = 0.0 }";

#[derive(Parser, Debug)]
#[command(name = "pim", version, about = ABOUT, after_help = EXIT_CODES_HELP)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum Format {
    /// Human-readable table.
    Table,
    /// One JSON document on stdout.
    Json,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum MomentArg {
    /// The corrected moment equation of Brach 1984 (default).
    Corrected,
    /// The 1983 BASIC listing's form, with its sign error; to reproduce the 1983 tables.
    Brach1983,
}

#[derive(clap::Args, Debug)]
struct SolveArgs {
    /// The case file (TOML); see CASE FILE below.
    case: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// Form of the moment equation (6).
    #[arg(long, value_enum, default_value_t = MomentArg::Corrected)]
    moment_form: MomentArg,
    /// Use the no-slip condition (5a, Vt = 0 at separation) instead of friction (5); mu is then
    /// ignored and the friction it implies is reported as mu_max.
    #[arg(long)]
    no_slip: bool,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Solve the impact equations: separation velocities from [initial], or contact velocities
    /// from [final] (backwards), with delta-V, impulses, energy loss, mu_max and admissibility.
    #[command(after_help = format!("{CASE_HELP}\n\n{EXIT_CODES_HELP}"))]
    Solve(SolveArgs),
    /// Vary each coefficient by -/+ P percent, solve every combination and average the effect of
    /// each level (Brach 1983 Tables 4-6). Needs [initial].
    #[command(after_help = format!("{CASE_HELP}\n\n{EXIT_CODES_HELP}"))]
    Sensitivity {
        #[command(flatten)]
        solve: SolveArgs,
        /// The variation P in percent (0 <= P < 100).
        #[arg(long, default_value_t = 10.0)]
        percent: f64,
    },
}

fn options(a: &SolveArgs) -> SolveOptions {
    SolveOptions {
        moment_form: match a.moment_form {
            MomentArg::Corrected => MomentForm::Corrected,
            MomentArg::Brach1983 => MomentForm::Brach1983,
        },
        tangential: if a.no_slip {
            TangentialCondition::NoSlip
        } else {
            TangentialCondition::Sliding
        },
    }
}

fn print_out(text: &str) -> Result<()> {
    let mut out = std::io::stdout().lock();
    match out.write_all(text.as_bytes()).and_then(|_| out.flush()) {
        Ok(()) => Ok(()),
        // A closed pipe (`pim ... | head`) is not an error of ours.
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        Err(e) => Err(Failure::Output(format!("cannot write to stdout: {e}")).into()),
    }
}

fn json<T: serde::Serialize>(value: &T) -> Result<String> {
    let mut s = serde_json::to_string_pretty(value)?;
    s.push('\n');
    Ok(s)
}

fn title_of(case: &case::Case) -> String {
    let mut t = match &case.content.title {
        Some(t) => format!("{} ({})", case.file, t),
        None => case.file.clone(),
    };
    let c = &case.content;
    if let (Some(a), Some(b)) = (&c.vehicle1.description, &c.vehicle2.description) {
        t.push_str(&format!("\nvehicle1: {a}; vehicle2: {b}"));
    }
    t
}

fn cmd_solve(a: &SolveArgs) -> Result<ExitCode> {
    let case = case::Case::load(&a.case)?;
    let impact = case.impact()?;
    let coefficients = case.coefficients()?;
    let (state, forward) = case.known_state()?;
    let opts = options(a);
    let report = if forward {
        pim_core::solve_forward(&impact, &coefficients, &state, &opts)
    } else {
        pim_core::solve_backward(&impact, &coefficients, &state, &opts)
    }
    .map_err(|e| Failure::from_core(&case.file, e))?;
    let text = match a.format {
        Format::Json => json(&output::SolveOut::new(&impact, &report, forward))?,
        Format::Table => output::solve_table(&title_of(&case), &impact, &report, forward),
    };
    print_out(&text)?;
    Ok(ExitCode::from(EXIT_OK))
}

fn cmd_sensitivity(a: &SolveArgs, percent: f64) -> Result<ExitCode> {
    let case = case::Case::load(&a.case)?;
    let impact = case.impact()?;
    let coefficients = case.coefficients()?;
    let (state, forward) = case.known_state()?;
    if !forward {
        return Err(Failure::Input(format!(
            "{}: the sensitivity study solves forwards and needs [initial], not [final]",
            case.file
        ))
        .into());
    }
    let study = pim_core::sensitivity(&impact, &coefficients, &state, &options(a), percent)
        .map_err(|e| Failure::from_core(&case.file, e))?;
    let text = match a.format {
        Format::Json => json(&output::SensitivityOut::new(&impact, &study))?,
        Format::Table => output::sensitivity_table(&title_of(&case), &study),
    };
    print_out(&text)?;
    Ok(ExitCode::from(EXIT_OK))
}

fn run(cli: Cli) -> Result<ExitCode> {
    match &cli.command {
        Command::Solve(a) => cmd_solve(a),
        Command::Sensitivity { solve, percent } => cmd_sensitivity(solve, *percent),
    }
}

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let code = if e.use_stderr() {
                error::EXIT_BAD_INPUT
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
                .map_or(error::EXIT_BAD_INPUT, Failure::code);
            eprintln!("pim: {err:#}");
            ExitCode::from(code)
        }
    }
}
