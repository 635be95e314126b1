//! `pim`: Planar Impact Mechanics for two-vehicle collision reconstruction.
//!
//! `main` only maps the outcome of [`run`] to an exit status; every message is printed once.

use anyhow::Result;
use clap::{Parser, Subcommand, ValueEnum};
use pim_cli::error::{self, Failure, EXIT_CODES_HELP, EXIT_OK};
use pim_cli::{batch, case, figures, fitcase, output, ricsac};
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
    /// Refit every RICSAC test of a data file under each cost function and moment branch (the
    /// main job): summary tables, the comparison with Brach 1984 Table 1, JSON or CSV records,
    /// and with --out, CSV files and SVG figures.
    #[command(after_help = format!("{BATCH_HELP}\n\n{EXIT_CODES_HELP}"))]
    Batch(BatchArgs),
    /// Per test, the cost functions side by side and the error of every velocity component
    /// against the measurement, the largest flagged (as Vossou & Koulocheris 2018 Tables 4-6).
    #[command(after_help = format!("{BATCH_HELP}\n\n{EXIT_CODES_HELP}"))]
    CompareCosts(BatchArgs),
}

const BATCH_HELP: &str = "\
DATA FILE: a CSV with one row per test, columns as in data/ricsac.csv (see data/README.md);
the file's header must match exactly. A row whose physics fails (the vehicles do not approach,
a singular system) is reported in its records as `failed`; the other rows are still fitted.

OUTPUT (--out DIR): records.csv (one row per test, cost function and branch), records.json,
velocity_errors.csv (fitted minus measured per component), summary.txt, compare_costs.txt,
brach1984.txt (when data/reference/brach1984_table1.csv is next to the data file), and the
figures cost.svg, coefficients.svg, delta_v.svg, separation.svg.

The records are identical for any --threads. Exit status 1 means some records are infeasible
(an answer: the data admit no solution, the reason is in the record) or failed; for the RICSAC
data, Q1 is infeasible for tests 1, 6, 7, 10 and 11.";

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
enum BatchFormat {
    /// Human-readable tables.
    Table,
    /// One JSON document with every record.
    Json,
    /// One CSV row per record.
    Csv,
}

#[derive(clap::Args, Debug)]
struct BatchArgs {
    /// The data file.
    #[arg(default_value = "data/ricsac.csv")]
    data: PathBuf,
    /// Cost functions.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [CostArg::Q1, CostArg::Q2, CostArg::Q3])]
    cost: Vec<CostArg>,
    /// Moment branches.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [BranchArg::Free, BranchArg::Zero])]
    branch: Vec<BranchArg>,
    /// Only these tests (numbers as in the data file), e.g. --tests 1,6,7.
    #[arg(long, value_delimiter = ',')]
    tests: Vec<u32>,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = BatchFormat::Table)]
    format: BatchFormat,
    /// Also write CSV tables and SVG figures into this directory (created if needed).
    #[arg(long)]
    out: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Upper bound of e (default 0.2; Brach 1984 needed up to 0.42).
    #[arg(long, default_value_t = 0.2)]
    e_max: f64,
    /// Form of the moment equation (6).
    #[arg(long, value_enum, default_value_t = MomentArg::Corrected)]
    moment_form: MomentArg,
    /// Add each fit's wall time (`fit_seconds`) to the records (output then varies run to run).
    #[arg(long)]
    timing: bool,
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

fn presets(c: &[CostArg]) -> Vec<pim_fit::CostPreset> {
    let mut out = Vec::new();
    for x in c {
        let p = match x {
            CostArg::Q1 => pim_fit::CostPreset::Q1,
            CostArg::Q2 => pim_fit::CostPreset::Q2,
            CostArg::Q3 => pim_fit::CostPreset::Q3,
        };
        if !out.contains(&p) {
            out.push(p);
        }
    }
    out
}

fn write_file(path: &std::path::Path, text: &str) -> Result<()> {
    std::fs::write(path, text).map_err(|e| {
        Failure::Output(format!(
            "{}: cannot write: {}",
            path.display(),
            case::io_reason(&e)
        ))
        .into()
    })
}

fn cmd_batch(a: &BatchArgs, compare: bool) -> Result<ExitCode> {
    let file = a.data.display().to_string();
    let mut tests = ricsac::load(&a.data)?;
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
    if let Some(n) = a.threads {
        if n == 0 {
            return Err(Failure::Input("--threads must be at least 1".into()).into());
        }
    }
    let settings = pim_fit::FitSettings {
        e: [0.0, a.e_max],
        moment_form: moment_form(a.moment_form),
        ..Default::default()
    };
    // Check the shared settings once, so a bad flag is an input error, not 66 failed records.
    settings
        .clone()
        .check()
        .map_err(|e| Failure::Input(format!("--e-max: {e}")))?;
    let plan = batch::BatchPlan {
        costs: presets(&a.cost),
        branches: branches(&a.branch),
        settings,
        timing: a.timing,
    };
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
    let tick = || bar.inc(1);
    let records = match a.threads {
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| Failure::Input(format!("--threads {n}: {e}")))?
            .install(|| batch::run(&tests, &plan, &tick)),
        None => batch::run(&tests, &plan, &tick),
    };
    bar.finish_and_clear();
    let brach = a
        .data
        .parent()
        .map(|d| d.join("reference").join("brach1984_table1.csv"))
        .filter(|p| p.is_file())
        .and_then(|p| std::fs::read_to_string(p).ok())
        .and_then(|t| batch::parse_brach(&t).ok());
    let summary = batch::summary_table(&records, &plan.costs);
    let compare_text = batch::compare_costs_table(&records, &plan.costs);
    let brach_text = brach
        .as_ref()
        .filter(|_| plan.costs.contains(&pim_fit::CostPreset::Q2))
        .map(|b| batch::brach_table(&records, b));
    let records_json = json(&serde_json::json!({ "data": file, "records": records }))?;
    let records_csv = batch::records_csv(&records).map_err(Failure::Output)?;
    let text = match a.format {
        BatchFormat::Json => records_json.clone(),
        BatchFormat::Csv => records_csv.clone(),
        BatchFormat::Table if compare => compare_text.clone(),
        BatchFormat::Table => {
            let mut t = format!("{file}: {} tests\n\n{summary}", tests.len());
            if let Some(b) = &brach_text {
                t.push_str(b);
            }
            t
        }
    };
    print_out(&text)?;
    if let Some(dir) = &a.out {
        std::fs::create_dir_all(dir).map_err(|e| {
            Failure::Output(format!(
                "{}: cannot create the directory: {}",
                dir.display(),
                case::io_reason(&e)
            ))
        })?;
        write_file(&dir.join("records.csv"), &records_csv)?;
        write_file(&dir.join("records.json"), &records_json)?;
        write_file(
            &dir.join("velocity_errors.csv"),
            &batch::errors_csv(&records),
        )?;
        write_file(&dir.join("summary.txt"), &summary)?;
        write_file(&dir.join("compare_costs.txt"), &compare_text)?;
        if let Some(b) = &brach_text {
            write_file(&dir.join("brach1984.txt"), b)?;
        }
        let figs = figures::write_all(&records, &plan.costs, dir)
            .map_err(|e| Failure::Output(format!("{}: figures: {e}", dir.display())))?;
        if a.format != BatchFormat::Json {
            eprintln!(
                "pim: wrote {} tables and {} figures to {}",
                if brach_text.is_some() { 6 } else { 5 },
                figs.len(),
                dir.display()
            );
        }
    }
    let unsolved = records.iter().filter(|r| !r.solved()).count();
    if unsolved > 0 {
        if a.format != BatchFormat::Json {
            eprintln!(
                "pim: {unsolved} of {} records have no solution (infeasible or failed); their rows say why",
                records.len()
            );
        }
        return Ok(ExitCode::from(error::EXIT_SOME_FAILED));
    }
    Ok(ExitCode::from(EXIT_OK))
}

fn run(cli: Cli) -> Result<ExitCode> {
    match &cli.command {
        Command::Solve(a) => cmd_solve(a),
        Command::Sensitivity { solve, percent } => cmd_sensitivity(solve, *percent),
        Command::Fit(a) => cmd_fit(a),
        Command::Batch(a) => cmd_batch(a, false),
        Command::CompareCosts(a) => cmd_batch(a, true),
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
