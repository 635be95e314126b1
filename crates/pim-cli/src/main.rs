//! `pim`: Planar Impact Mechanics for two-vehicle collision reconstruction.
//!
//! `main` only maps the outcome of [`run`] to an exit status; every message is printed once.

use anyhow::Result;
use clap::{Parser, Subcommand, ValueEnum};
use pim_cli::error::{self, Failure, EXIT_CODES_HELP, EXIT_OK};
use pim_cli::{case, fitcase, output};
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
    /// Fit e, mu, em and the twelve velocities to estimates and observations (weighted least
    /// squares, global search), for both moment branches: em in [-1, 0] ("free") and em = 1
    /// ("zero"). Infeasible data are reported with the reason.
    #[command(after_help = format!("{FIT_HELP}\n\n{EXIT_CODES_HELP}"))]
    Fit(FitArgs),
}

const FIT_HELP: &str = "\
CASE FILE: as for `pim solve` ([vehicle1], [vehicle2], [impact]), without [coefficients],
[initial], [final], plus:
  [estimates.initial]              # estimated velocities at contact (partial allowed)
  vehicle1 = { vx = -13.01, vy = 0.0, omega = 0.0 }
  vehicle2 = { vx = 6.50, vy = 11.27, omega = 0.0 }
  [estimates.final]                # estimated velocities at separation
  vehicle1 = { vx = -7.74, vy = 1.48, omega = -0.52 }
  vehicle2 = { vx = -2.22, vy = 8.64, omega = -3.35 }
  [weights.initial]                # optional, same shape, in (0, 1], default 1
  vehicle1 = { omega = 0.5 }
  [known.initial]                  # without --cost only: components held fixed
  vehicle1 = { omega = 0.0 }
  [bounds]                         # optional; these are the defaults
  e = [0.0, 0.2]
  mu = [-1.2, 1.2]                 # and always between 0 and mu_max
  velocity = 20.0                  # m/s, every linear component
  yaw_rate = 5.0                   # rad/s
  [[observations]]                 # optional, e.g. what an event data recorder gave
  kind = \"delta_v_longitudinal\"   # delta_v_lateral, speed_along_heading, lateral_velocity
  vehicle = 1
  value = -5.1                     # m/s, along the vehicle's own axes
  weight = 1.0

COST FUNCTIONS (--cost):
  q1  separation velocities known exactly, contact velocities estimated
  q2  contact velocities known exactly, separation velocities estimated (Brach's fits)
  q3  all twelve estimated
  (none) [known] held fixed, [estimates] estimated, everything else unknown";

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum CostArg {
    /// Separation velocities known, contact velocities estimated.
    Q1,
    /// Contact velocities known, separation velocities estimated.
    Q2,
    /// All twelve estimated.
    Q3,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum BranchArg {
    /// em in [-1, 0].
    Free,
    /// em = 1 (no moment impulse).
    Zero,
}

#[derive(clap::Args, Debug)]
struct FitArgs {
    /// The case file (TOML); see CASE FILE below.
    case: PathBuf,
    /// Cost function; without it the case's [known] and [estimates] define the problem.
    #[arg(long, value_enum)]
    cost: Option<CostArg>,
    /// Moment branches to fit.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [BranchArg::Free, BranchArg::Zero])]
    branch: Vec<BranchArg>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    format: Format,
    /// Form of the moment equation (6).
    #[arg(long, value_enum, default_value_t = MomentArg::Corrected)]
    moment_form: MomentArg,
}

fn moment_form(m: MomentArg) -> MomentForm {
    match m {
        MomentArg::Corrected => MomentForm::Corrected,
        MomentArg::Brach1983 => MomentForm::Brach1983,
    }
}

fn branches(b: &[BranchArg]) -> Vec<pim_fit::MomentBranch> {
    let mut out = Vec::new();
    for x in b {
        let m = match x {
            BranchArg::Free => pim_fit::MomentBranch::Free,
            BranchArg::Zero => pim_fit::MomentBranch::Zero,
        };
        if !out.contains(&m) {
            out.push(m);
        }
    }
    out
}

fn cmd_fit(a: &FitArgs) -> Result<ExitCode> {
    let case = case::Case::load(&a.case)?;
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
        Some(CostArg::Q1) => (fitcase::CostChoice::Preset(pim_fit::CostPreset::Q1), "q1"),
        Some(CostArg::Q2) => (fitcase::CostChoice::Preset(pim_fit::CostPreset::Q2), "q2"),
        Some(CostArg::Q3) => (fitcase::CostChoice::Preset(pim_fit::CostPreset::Q3), "q3"),
        None => (fitcase::CostChoice::Custom, "custom"),
    };
    let problem = fitcase::problem(&case, choice)?;
    let settings = fitcase::settings(&case, moment_form(a.moment_form), branches(&a.branch))?;
    let report = pim_fit::fit(&problem, &settings)
        .map_err(|e| Failure::Input(format!("{}: {e}", case.file)))?;
    let text = match a.format {
        Format::Json => json(&output::FitOut {
            cost_function: name.to_string(),
            branches: report
                .branches
                .iter()
                .map(output::BranchRecord::new)
                .collect(),
            best: report.best,
            notes: report.notes.clone(),
        })?,
        Format::Table => output::fit_table(&title_of(&case), name, &report),
    };
    print_out(&text)?;
    if report.best.is_none() {
        eprintln!(
            "pim: {}: no branch has an admissible solution (the reasons are in the output)",
            case.file
        );
        return Ok(ExitCode::from(error::EXIT_NO_ANSWER));
    }
    Ok(ExitCode::from(EXIT_OK))
}

fn options(a: &SolveArgs) -> SolveOptions {
    SolveOptions {
        moment_form: moment_form(a.moment_form),
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
        Command::Fit(a) => cmd_fit(a),
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
