//! The command line: subcommands, their arguments and the help texts that teach the file formats.

use crate::error::EXIT_CODES_HELP;
use clap::{Parser, Subcommand, ValueEnum};
use pim_core::MomentForm;
use pim_fit::{CostPreset, FitModel, MomentBranch};
use std::path::PathBuf;

const ABOUT: &str = "Planar Impact Mechanics (Brach) for two-vehicle collisions: solve the six \
impulse-momentum equations, study coefficient sensitivity, and fit coefficients to crash data.";

const CASE_HELP: &str = "\
CASE FILE (TOML; SI units unless [units] says otherwise; angles in degrees, counter-clockwise):
  title = \"side impact\"             # optional; top-level keys go before the first [section]
  # convention = \"brach\"           # only for the papers' form: vehicle 1's heading is its tail
  # convention = \"sae\"             # SAE J670: y to the right, headings, angles, yaw clockwise
  [vehicle1]                       # vehicle2 likewise
  mass = 1500.0                    # kg
  yaw_inertia = 2500.0             # kg m^2, about the vertical axis through the CG
  heading = 0.0                    # deg: direction the nose points, from the +x axis
  impact_point = { x = 2.0, y = 0.0 }  # m from the CG, x forward, y to the left: impact centre C
  # or: d = 2.0 and phi = 0.0      # polar form: distance CG to C, angle from the nose
  length = 4.5                     # optional, for `pim draw` (also width, cg_to_front)
  [vehicle2]
  mass = 1500.0
  yaw_inertia = 2500.0
  heading = 90.0
  impact_point = { x = 0.0, y = 0.9 }  # the middle of its left side
  # (or only: barrier = true       # a fixed rigid barrier: no mass or velocities; its face is
  #                                # the crush surface; examples/cases/barrier_small_overlap.toml)
  [impact]
  crush_angle = 0.0                # deg: direction of the crush-surface normal (either sense)
  # vehicle1_side = \"+n\"           # when both CGs lie on one side of the crush plane: where
  #                                # vehicle 1 is (otherwise read from the heights by mobility)
  [coefficients]
  e = 0.1                          # restitution, 0..1
  mu = 0.0                         # impulse ratio Pt/Pn, between 0 and mu_max (0 here: nothing
                                   # slides at C and the impulse passes through both CGs)
  em = 1.0                         # moment restitution, -1..0 or exactly 1 (no moment impulse)
                                   # (or e, et = -1..1, friction >= 0: the second model, normal
                                   # and tangential restitution with a friction limit, forwards;
                                   # or model = \"impc\", e, friction: Carpenter-Welcher, et = -e)
  [initial]                        # velocities at contact; or [final] to solve backwards
  vehicle1 = { vx = 15.0, vy = 0.0, omega = 0.0 }      # m/s, m/s, rad/s (fixed frame)
  vehicle2 = { vx = 0.0, vy = 0.0, omega = 0.0 }
  # or { speed = 15.0, direction = 0.0, omega = 0.0 }  # direction: deg in the case's frame
  # or { forward = 15.0, lateral = 0.0, omega = 0.0 }  # along / across the vehicle (lateral +90
  #                                # deg from the nose: left, or right under \"sae\")
  # Impact centre once in the scene instead of impact_point: [impact] centre = { x, y } and
  # [vehicleN] position = { x, y } (each CG); crush_angle_from_vehicle1 = deg from vehicle 1's nose
  # [units]                        # optional, each defaults to SI:
  # speed = \"mph\"                # m/s, km/h, mph
  # length = \"ft\"                # m, ft
  # mass = \"lb\"                  # kg, lb
  # yaw_inertia = \"slug ft^2\"    # kg m^2, slug ft^2
  # yaw_rate = \"deg/s\"           # rad/s, deg/s
  # stiffness = \"N/cm\"           # crush stiffness A, B: N/m (N/m^2), N/cm (N/cm^2), lbf/in (lbf/in^2)
  # crush = \"cm\"                 # crush depths, damage width, offset: m, cm, mm, in, ft
DAMAGE (optional; `pim solve` and `pim fit` then set the crush beside PIM's energy loss):
  # [damage]
  # relation = \"energy_loss\"     # CRASH3's convention; or \"compression\": loss = (1 - e^2) crush
  # [damage.vehicle1]              # vehicle2 likewise
  # side = \"front\"               # the damaged face: front, rear, left, right
  # width = 168.0                  # damage width, [units] crush
  # depths = [0, 3, 5, 10, 13, 16] # crush depths equally spaced across it (2, 4, 6 or any n >= 2)
  # offset = 10.0                  # centre of damage: front/rear from the centreline, + left
  #                                # (SAE: + right); left/right from the CG along the length, + forward
  # a = 624.0                      # stiffness A and B ([units] stiffness)
  # b = 23.0
  # pdof = 10.0                    # optional: deg clockwise from the nose; default the impulse's
  # a_sigma = 62.0                 # optional standard deviations: a_sigma, b_sigma, depth_sigma,
  #                                # width_sigma (the crush energy's sigma follows)
  # A vehicle given side, a and b but no depths takes its crush from the other's by the force
  # balance A1 + B1 C1 = A2 + B2 C2. Out: per vehicle the crush energy (exact integral of the
  # linear stiffness over the profile) times the direction-of-force factor 1 + tan^2 (held at
  # 2 beyond 45 deg), the barrier-equivalent speed, CRASH3's delta-V with the effective-mass
  # factors k^2/(k^2+h^2) against PIM's, and the total against PIM's energy loss.
  # Example: examples/cases/ricsac7_damage.toml
This example is examples/cases/side_impact.toml (and side_impact_us.toml in US units;
tbone_sae_us.toml in SAE's frame with speeds and directions).";

#[derive(Parser, Debug)]
#[command(name = "pim", version, about = ABOUT, after_help = EXIT_CODES_HELP)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Human-readable table.
    Table,
    /// One JSON document on stdout.
    Json,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum UnitsArg {
    /// m/s, m, kg, rad/s.
    Si,
    /// mph, ft, lb, deg/s.
    Us,
    /// km/h, m, kg, deg/s.
    Kmh,
}

impl From<UnitsArg> for pim_case::units::UnitSystem {
    fn from(u: UnitsArg) -> Self {
        match u {
            UnitsArg::Si => Self::Si,
            UnitsArg::Us => Self::Us,
            UnitsArg::Kmh => Self::Kmh,
        }
    }
}

/// A value of a named choice of the library (moment form, cost function, branch, model): its
/// names and their help come from the library, so the command accepts what the library calls
/// them.
fn choice<T: Copy + Send + Sync + 'static>(
    all: &'static [T],
    name: fn(T) -> &'static str,
    help: fn(T) -> &'static str,
) -> impl clap::builder::TypedValueParser<Value = T> {
    use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
    PossibleValuesParser::new(
        all.iter()
            .map(move |&v| PossibleValue::new(name(v)).help(help(v))),
    )
    .map(move |s: String| {
        all.iter()
            .copied()
            .find(|&v| name(v) == s)
            .expect("clap passes only possible values")
    })
}

pub use pim_case::ranges::{MAX_DRAWS, MAX_THREADS};

/// A count between `lo` and `hi`.
fn count(s: &str, lo: usize, hi: usize, what: &str) -> Result<usize, String> {
    let n: usize = s
        .trim()
        .parse()
        .map_err(|_| format!("{s:?} is not a whole number; {what} takes {lo} to {hi}"))?;
    if n < lo || n > hi {
        return Err(format!("{n} is out of range; {what} takes {lo} to {hi}"));
    }
    Ok(n)
}

fn draws(s: &str) -> Result<usize, String> {
    count(s, 1, MAX_DRAWS, "--draws")
}

fn batch_draws(s: &str) -> Result<usize, String> {
    count(s, 0, MAX_DRAWS, "--draws (0: no intervals)")
}

fn threads(s: &str) -> Result<usize, String> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    count(
        s,
        1,
        MAX_THREADS,
        &format!("--threads (this machine has {cores} cores)"),
    )
}

fn moment_form() -> impl clap::builder::TypedValueParser<Value = MomentForm> {
    choice(&MomentForm::ALL, MomentForm::name, MomentForm::description)
}

fn cost() -> impl clap::builder::TypedValueParser<Value = CostPreset> {
    choice(&CostPreset::ALL, CostPreset::name, CostPreset::description)
}

fn branch() -> impl clap::builder::TypedValueParser<Value = MomentBranch> {
    choice(
        &MomentBranch::ALL,
        MomentBranch::name,
        MomentBranch::description,
    )
}

fn model() -> impl clap::builder::TypedValueParser<Value = FitModel> {
    choice(&FitModel::ALL, FitModel::name, FitModel::description)
}

#[derive(clap::Args, Debug)]
pub struct SolveArgs {
    /// The case file (TOML); see CASE FILE below.
    pub case: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Form of the moment equation (6).
    #[arg(long, value_parser = moment_form(), default_value = "corrected")]
    pub moment_form: MomentForm,
    /// Use the no-slip condition (5a, Vt = 0 at separation) instead of friction (5); mu is then
    /// ignored and the friction it implies is reported as mu_max.
    #[arg(long)]
    pub no_slip: bool,
    /// Units of the table and report.md (default: the case's [units], by its speed unit; JSON
    /// is always SI).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Also write into this directory (created if needed): result.json, the report
    /// (report.html, report.md) and its figures diagram.svg and momentum.svg (`pim
    /// sensitivity`: sensitivity.json and sensitivity.txt).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Exit with status 1 (after the output) when the case draws a plausibility warning
    /// (for scripts and signed reports).
    #[arg(long)]
    pub strict: bool,
}

#[derive(clap::Args, Debug)]
pub struct DrawArgs {
    /// The case file (TOML); see CASE FILE below.
    pub case: PathBuf,
    /// The SVG file to write.
    #[arg(long, short = 'o')]
    pub output: PathBuf,
    /// Form of the moment equation (6), when the case is solved.
    #[arg(long, value_parser = moment_form(), default_value = "corrected")]
    pub moment_form: MomentForm,
    /// Solve with the no-slip condition (5a) instead of friction (5).
    #[arg(long)]
    pub no_slip: bool,
    /// Units of the axes and labels (default: the case's [units], by its speed unit).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
}

#[derive(clap::Args, Debug)]
pub struct RunoutArgs {
    /// The case file (TOML); see CASE FILE below.
    pub case: PathBuf,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Where the separation velocities come from (default: [final], else the solve of
    /// [coefficients] and [initial], else the scene).
    #[arg(long, value_enum)]
    pub from: Option<crate::runout_help::RunoutSource>,
    /// Cost function of --from fit.
    #[arg(long, value_parser = cost())]
    pub cost: Option<CostPreset>,
    /// Sample the JSON path every this many seconds (at most 100,000 samples per path).
    #[arg(long, default_value_t = 0.1, value_parser = crate::runout_help::positive_seconds)]
    pub sample: f64,
    /// With each sample of the JSON path, each wheel's normal load, slip angle and tyre force.
    #[arg(long)]
    pub wheels: bool,
    /// Also draw the plan view of the run-out to this SVG file.
    #[arg(long)]
    pub draw: Option<PathBuf>,
    /// Outlines in the drawing every this many seconds.
    #[arg(long, default_value_t = 0.5, value_parser = crate::runout_help::positive_seconds)]
    pub every: f64,
    /// Units of the table and the drawing (default: the case's [units]; JSON is always SI).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
}

#[derive(clap::Args, Debug)]
pub struct UncertaintyArgs {
    /// The case file (TOML).
    pub case: PathBuf,
    /// Cost function; without it the case's [known] and [estimates] define the problem.
    #[arg(long, value_parser = cost())]
    pub cost: Option<CostPreset>,
    /// The model every draw fits: `pim` (e, mu, em) or `tangential` (e, et and the friction
    /// limit in their places).
    #[arg(long, value_parser = model(), default_value = "pim")]
    pub model: FitModel,
    /// Number of draws (1 to 1,000,000).
    #[arg(long, default_value_t = 200, value_parser = draws, allow_negative_numbers = true)]
    pub draws: usize,
    /// Seed of the random streams.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Worker threads (default: all cores; at most 256).
    #[arg(long, value_parser = threads, allow_negative_numbers = true)]
    pub threads: Option<usize>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Units of the table and figures (default: the case's [units], by its speed unit; JSON
    /// is always SI).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Also write uncertainty.json, uncertainty.txt, the figures histograms.svg (speeds and
    /// delta-V with their 90 % bands), speeds.svg (speed 1 against speed 2) and tornado.svg
    /// (dominant inputs), and the crash's report (report.html, report.md, diagram.svg,
    /// momentum.svg) with the ranges into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Exit with status 1 (after the output) when the case draws a plausibility warning, or an
    /// interval reaches a bound the case does not set (a default)
    /// (for scripts and signed reports).
    #[arg(long)]
    pub strict: bool,
}

#[derive(clap::Args, Debug)]
pub struct ReportArgs {
    /// The case file (TOML): a fit case (estimates, known values, observations) is fitted, a
    /// solve case ([coefficients] and [initial] or [final]) is solved.
    pub case: PathBuf,
    /// Cost function of a fit; without it the case's [known] and [estimates] define the
    /// problem.
    #[arg(long, value_parser = cost())]
    pub cost: Option<CostPreset>,
    /// The model fitted (also by every draw of the uncertainty study).
    #[arg(long, value_parser = model(), default_value = "pim")]
    pub model: FitModel,
    /// Refits of the uncertainty study that gives the answer's ranges (0: none; default 200
    /// when the case gives [sigma] or [uncertainty], else 0).
    #[arg(long, value_parser = batch_draws, allow_negative_numbers = true)]
    pub draws: Option<usize>,
    /// Seed of the study's random streams.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Worker threads of the study (default: all cores; at most 256).
    #[arg(long, value_parser = threads, allow_negative_numbers = true)]
    pub threads: Option<usize>,
    /// Units of the report (default: the case's [units], by its speed unit).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Write the HTML report to this file (default: stdout).
    #[arg(long, short = 'o', conflicts_with = "out")]
    pub output: Option<PathBuf>,
    /// Write the whole report into this directory instead: report.html, report.md beside its
    /// figures (diagram.svg, momentum.svg and the study's), result.json and uncertainty.json.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Report the solve ([coefficients] and [initial] or [final]) of a case that also holds a
    /// fit.
    #[arg(long, conflicts_with_all = ["cost", "draws"])]
    pub solve: bool,
    /// Exit with status 1 (after the output) when the case draws a plausibility warning.
    #[arg(long)]
    pub strict: bool,
}

#[derive(clap::Args, Debug)]
pub struct PredictArgs {
    /// The data file.
    #[arg(default_value = "data/ricsac.csv")]
    pub data: PathBuf,
    /// Restitution used in eq. 17 (Brach: 0 unless known).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub e: f64,
    /// Units of the table (default SI; a data file has no [units]). JSON is always SI.
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Also write predict_dv.json, predict_dv.txt and the figure predict_dv.svg (L against the
    /// speed ratio for several mass ratios, as Brach's Fig. 3, and predicted against measured
    /// delta-V) into this directory.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

#[derive(Subcommand, Debug)]
pub enum Command {
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
        #[arg(long, default_value_t = 10.0, allow_negative_numbers = true)]
        percent: f64,
    },
    /// Fit e, mu, em and the twelve velocities to estimates and observations (weighted least
    /// squares, global search), for both moment branches: em in [-1, 0] ("free") and em = 1
    /// ("zero"). Infeasible data are reported with the reason.
    #[command(after_help = format!("{}\n\n{EXIT_CODES_HELP}", crate::fit_help::FIT_HELP))]
    Fit(FitArgs),
    /// Draw a case to scale at contact (plan view, SVG): outlines, CGs, noses, the impact
    /// centre, the crush surface with n and t, the velocities at contact, and when the case has
    /// [coefficients] and a state, the velocities at separation, the impulses and the PDOF.
    #[command(after_help = format!("{CASE_HELP}\n\n{EXIT_CODES_HELP}"))]
    Draw(DrawArgs),
    /// How sure is the answer: a seeded parametric bootstrap. Each draw perturbs the estimates by
    /// their [sigma] and the inputs the fit takes as exact by [uncertainty], refits both
    /// branches and keeps the best; prints 5/50/95 % percentiles, mean and sd of e, mu, em, the
    /// impact speeds, delta-V and the energy loss, the branch shares, and the inputs that
    /// dominate each quantity. Bit-identical for any --threads.
    #[command(after_help = crate::fit_help::UNCERTAINTY_HELP)]
    Uncertainty(UncertaintyArgs),
    /// The run-out of each vehicle from separation to rest (a planar four-wheel model): rest
    /// position and heading, distance, time, turns and the path; or, without separation
    /// velocities, their estimate from the scene's rest positions and marks, per count of turns.
    #[command(after_help = crate::runout_help::RUNOUT_HELP)]
    Runout(RunoutArgs),
    /// One self-contained document for a crash, HTML with its figures inline (prints to PDF),
    /// or with --out Markdown beside the figures: the inputs, the method, the answer and its
    /// ranges, the evidence against it, what the data do not determine, every warning.
    #[command(after_help = format!("{CASE_HELP}\n\n{EXIT_CODES_HELP}"))]
    Report(ReportArgs),
    /// Change values of a case file in place: each KEY=VALUE names a value by its dotted path
    /// as the file writes it (`scene.vehicle1.rest.x`, `observations.0.sigma`), in the file's
    /// own units; comments, key order and number formatting are kept everywhere else, and the
    /// edited case is checked as every command reads a case before it is written.
    #[command(after_help = crate::set_args::SET_HELP)]
    Set(crate::set_args::SetArgs),
    /// A survey's points (CSV: id, x, y, code, description) imported into a case's [survey].
    #[command(after_help = crate::survey_args::SURVEY_HELP)]
    Survey(crate::survey_args::SurveyArgs),
    /// An EDR's pre-crash table (time, speed, brake, accelerator) imported into a case.
    #[command(after_help = crate::edr_args::EDR_HELP)]
    Edr(crate::edr_args::EdrArgs),
    /// The scene editor in the browser: serves a folder of case files (or one case and its
    /// folder) on this machine and prints the address to open. The page draws the scene to
    /// scale (vehicles at contact and at rest, run-out paths, rest positions and marks with
    /// their standard deviations), the speeds and the case's TOML side by side; drag a rest
    /// position, or edit the TOML, and the case is solved again; Save writes the TOML back
    /// (comments and layout kept), where `pim fit FILE` gives what the page showed.
    #[command(after_help = crate::serve_args::SERVE_HELP)]
    Serve(crate::serve_args::ServeArgs),
    /// A photo of the road made into a plan-view image by four or more points of known plan
    /// position (a homography), with each point's residual and the [background] to use it.
    #[command(after_help = crate::rectify_args::RECTIFY_HELP)]
    Rectify(crate::rectify_args::RectifyArgs),
    /// Brach 1984 section 6: predict each test's delta-V from its impact speeds, masses and
    /// energy loss (eq. 14 with L from eq. 16 and with L = 2/3) and from the point-mass
    /// solution at the critical friction (eq. 17), beside the measured delta-V.
    PredictDv(PredictArgs),
    /// Refit every RICSAC test of a data file under each cost function and moment branch (the
    /// main job): summary tables, the comparison with Brach 1984 Table 1, JSON or CSV records,
    /// and with --out, CSV files and SVG figures. Given case files or a directory, fit each of
    /// them instead, streaming the records.
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

CASE FILES: `pim batch cases/*.toml` or `pim batch cases/` fits every case file with its own
cost (as `pim fit` without --cost: its [known], estimates, observations, weights or sigmas, and
its [bounds]), or under each --cost preset when given, for each branch. A file that cannot be
read or fitted is named on stderr and in the summary with its reason. Records stream to the output
as they finish, so memory does not grow with the number of files: --format csv or json (one
JSON record per line) on stdout, and with --out DIR records.csv, records.jsonl and summary.txt.
A file that cannot be read or fitted is a `failed` record naming the file and field; the
others complete. With --draws N the best record of each file and cost function also carries the
intervals of `pim uncertainty` (same draws and --seed; CSV columns speed1_p05 ... delta_v2_p95).

INTERVALS FOR A DATA FILE: a data file holds measurements without their standard deviations, so
`pim batch data/ricsac.csv --draws 200 --tolerances tol.toml` takes them from a file that applies
to every test (each a standard deviation, in the file's [units]):
  [sigma.initial]                  # the measured velocities at contact
  vehicle1 = { vx = 0.5, vy = 0.5, omega = 0.1 }
  vehicle2 = { vx = 0.5, vy = 0.5, omega = 0.1 }
  [sigma.final]                    # and at separation
  vehicle1 = { vx = 0.5, vy = 0.5, omega = 0.2 }
  vehicle2 = { vx = 0.5, vy = 0.5, omega = 0.2 }
  [uncertainty]                    # optional: inputs the fit takes as exact
  vehicle1 = { mass = 20.0, d = 0.1, phi = 3.0 }
  impact = { crush_angle = 3.0 }
The best record of each test and cost function then carries the intervals (JSON `intervals`,
CSV columns speed1_p05 ... delta_v2_p95, and a table). Example: examples/ricsac_tolerances.toml.

CRUSH: `pim batch data/ricsac.csv --damage data/ricsac_vehicles.csv` adds each test's crush (the
EDCRASH RICSAC profiles and stiffness of Neades 2011, Appendix D): the damaged face of each car is
the face its phi points to; the crush energies (exact integral of CRASH3's linear stiffness over
the profile, times the direction-of-force factor of the fitted impulse) are set beside the Q2
fit's energy loss (CRASH3's convention: crush energy = energy loss), CRASH3's delta-V beside
PIM's and the measured ones (Neades 2011 Table 5.3, from data/reference/neades2011_table5_3.csv
when it is next to the data file), and the Q2 fit is repeated with the crush energy as
evidence (A and B with an assumed 10 % standard deviation, each depth 2 cm: none is
published). Table damage.txt, damage.csv, damage.json and the figure crush_energy.svg.

OUTPUT (--out DIR): records.csv (one row per test, cost function and branch), records.json,
velocity_errors.csv (fitted minus measured per component), summary.txt, compare_costs.txt,
brach1984.txt (when data/reference/brach1984_table1.csv is next to the data file), and the
figures cost.svg, coefficients.svg, delta_v.svg, separation.svg.

The records are identical for any --threads. Infeasible records are answers (the data admit
no solution; the reason is in the record) and are counted in the summary; the exit status is 0
when the batch ran and wrote its results, or with --strict 1 when any record is infeasible or
failed. For the RICSAC data, Q1 is infeasible for tests 1, 6, 7, 10 and 11.";

/// The conditions of a batch's fits (`--conditions`).
#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum Conditions {
    /// The corrected moment equation and mu between 0 and mu_max, both branches.
    Corrected,
    /// Vossou & Koulocheris (2018): Brach's 1983 moment equation, mu in [0, 1.2] by its box
    /// alone, e_m in [-1, 0].
    V18,
}

#[derive(Copy, Clone, Debug, PartialEq, Eq, ValueEnum)]
pub enum BatchFormat {
    /// Human-readable tables.
    Table,
    /// One JSON document with every record.
    Json,
    /// One CSV row per record.
    Csv,
}

#[derive(clap::Args, Debug)]
pub struct BatchArgs {
    /// A RICSAC-style data file (CSV), or case files (TOML) and directories of case files.
    #[arg(default_value = "data/ricsac.csv", num_args = 1..)]
    pub inputs: Vec<PathBuf>,
    /// Cost functions (data file: default q1,q2,q3; case files: default each file's own cost,
    /// its [known], estimates, observations, weights or sigmas, as `pim fit` without --cost).
    #[arg(long, value_parser = cost(), value_delimiter = ',')]
    pub cost: Vec<CostPreset>,
    /// Moment branches (of PIM).
    #[arg(long, value_parser = branch(), value_delimiter = ',', default_values = ["free", "zero"])]
    pub branch: Vec<MomentBranch>,
    /// Models fitted, e.g. --model pim,tangential: every test and cost function under each,
    /// side by side in models.txt and models.svg (with --out) and the table (data files only).
    #[arg(long, value_parser = model(), value_delimiter = ',', default_values = ["pim"])]
    pub model: Vec<FitModel>,
    /// Only these tests (numbers as in the data file), e.g. --tests 1,6,7.
    #[arg(long, value_delimiter = ',')]
    pub tests: Vec<u32>,
    /// Output format on stdout.
    #[arg(long, value_enum, default_value_t = BatchFormat::Table)]
    pub format: BatchFormat,
    /// Units of a data file's tables (delta-V, velocity errors, intervals; default SI). Records
    /// (JSON, CSV) are always SI.
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Also write CSV tables and SVG figures into this directory (created if needed).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Worker threads (default: all cores; at most 256).
    #[arg(long, value_parser = threads, allow_negative_numbers = true)]
    pub threads: Option<usize>,
    /// Upper bound of e (data file: default 0.2, Brach's and V18's setting; Brach 1984 needed
    /// up to 0.42. Case files: for those whose [bounds] do not set e, else e's physical range
    /// [0, 1]).
    #[arg(long, allow_negative_numbers = true)]
    pub e_max: Option<f64>,
    /// Form of the moment equation (6).
    #[arg(long, value_parser = moment_form(), default_value = "corrected")]
    pub moment_form: MomentForm,
    /// The conditions of the fit. `corrected` (default): the corrected moment equation, mu
    /// between 0 and mu_max (the tangential impulse may not reverse the sliding), both
    /// branches. `v18`: Vossou & Koulocheris (2018)'s setting made explicit, to compare with
    /// their Tables 4-6: Brach's 1983 moment equation (with its sign error), mu in [0, 1.2]
    /// bounded by that box alone (no mu <= mu_max), e in [0, 0.2] (or --e-max), e_m in [-1, 0]
    /// (the free branch only), |v| <= 20 m/s, |omega| <= 5 rad/s; a data file with
    /// reference/vossou2018_table{4,5,6}.csv next to it gets v18.txt (their printed costs
    /// beside ours) in the table and with --out. Overrides --moment-form and --branch.
    #[arg(long, value_enum, default_value_t = Conditions::Corrected)]
    pub conditions: Conditions,
    /// Add each fit's wall time (`fit_seconds`) to the records (output then varies run to run).
    #[arg(long)]
    pub timing: bool,
    /// Exit with status 1 when any record is infeasible or failed (for scripts).
    #[arg(long)]
    pub strict: bool,
    /// Case files only: add the 90 % intervals of `pim uncertainty` (this many draws) to the
    /// best record of each file and cost function (the case needs [sigma] and/or [uncertainty]).
    #[arg(long, default_value_t = 0, value_parser = batch_draws, allow_negative_numbers = true)]
    pub draws: usize,
    /// Seed of the draws (with --draws).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub seed: u64,
    /// Data file only, with --draws: a TOML file of standard deviations applied to every test
    /// ([units], [sigma.initial], [sigma.final], [uncertainty]; see below).
    #[arg(long, value_name = "FILE")]
    pub tolerances: Option<PathBuf>,
    /// Data file only: the crush of every car (CSV, like data/ricsac_vehicles.csv: damage
    /// length and offset, C1..C6 in cm, A in N/cm, B in N/cm^2, CG to front and rear, width):
    /// each test's crush energies beside its Q2 fit, CRASH3's delta-V beside PIM's, and the Q2
    /// fit with the crush energy as evidence (see CRUSH below).
    #[arg(long, value_name = "FILE")]
    pub damage: Option<PathBuf>,
}

#[derive(clap::Args, Debug)]
pub struct FitArgs {
    /// The case file (TOML); see CASE FILE below.
    pub case: PathBuf,
    /// Cost function; without it the case's [known] and [estimates] define the problem.
    #[arg(long, value_parser = cost())]
    pub cost: Option<CostPreset>,
    /// The model fitted. `tangential` estimates e, et and the friction limit within
    /// [bounds] e, et (default [-1, 1]) and friction (default [0, 1.2]), with the same cost
    /// functions, observations and global search; it has no moment impulse, so --branch does
    /// not apply.
    #[arg(long, value_parser = model(), default_value = "pim")]
    pub model: FitModel,
    /// Moment branches to fit.
    #[arg(long, value_parser = branch(), value_delimiter = ',', default_values = ["free", "zero"])]
    pub branch: Vec<MomentBranch>,
    /// Output format.
    #[arg(long, value_enum, default_value_t = Format::Table)]
    pub format: Format,
    /// Form of the moment equation (6).
    #[arg(long, value_parser = moment_form(), default_value = "corrected")]
    pub moment_form: MomentForm,
    /// Units of the table and report.md (default: the case's [units], by its speed unit; JSON
    /// is always SI).
    #[arg(long, value_enum)]
    pub units: Option<UnitsArg>,
    /// Also write into this directory (created if needed): result.json, the report
    /// (report.html, report.md) and its figures diagram.svg and momentum.svg of the best branch.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Exit with status 1 (after the output) when the case draws a plausibility warning, or the best
    /// branch rests on a bound the case does not set (a default)
    /// (for scripts and signed reports).
    #[arg(long)]
    pub strict: bool,
    /// A case with scene evidence: also refine from the answer (its states, on its fitted
    /// frictions) in this JSON document (`pim fit --format json` or `--out`'s result.json, of
    /// this case before an edit or of a neighbouring one); the search runs as without it and the
    /// lower answer is kept, so a small change of the case changes the answer a little.
    #[arg(long, value_name = "RESULT_JSON")]
    pub from: Option<PathBuf>,
}

/// The distinct values of a list of arguments, in their first order.
pub fn unique<T: Copy + PartialEq>(list: &[T]) -> Vec<T> {
    let mut out: Vec<T> = Vec::new();
    for &t in list {
        if !out.contains(&t) {
            out.push(t);
        }
    }
    out
}
