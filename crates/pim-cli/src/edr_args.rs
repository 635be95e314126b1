//! The arguments of `pim edr` and its help.

use std::path::PathBuf;

/// Examples of `pim edr`.
pub const EDR_HELP: &str = "EXAMPLES:
  pim edr case.toml suv_precrash.txt --vehicle 2 --unit km/h
  pim edr case.toml sedan_precrash.csv --vehicle 1 --sigma 1.5 --dry-run

THE TABLE: the pre-crash rows as a crash data report prints them, a row to a line: time,
speed, service brake, accelerator pedal (tabs, commas, semicolons or spaces between). A header
naming the columns (any of `time`, `speed`, `brake`, `accelerator`/`throttle` in its fields)
sets their order; without one the order is time, speed, brake, accelerator. Times are seconds
before contact (-2.5 and 2.5 are the same row); the brake is on/off (yes/no, 1/0, applied);
the accelerator a percentage. A row that is not a number, a brake neither on nor off or a time
given twice is refused, naming its line and column.

WHAT IS WRITTEN: the rows as [pre_impact.vehicleN] edr_history (drawn beside the answer's
speeds before contact: speed_history.svg of pim fit --out, and the editor), and, unless
--no-record, the one record of evidence they give as the vehicle's edr (replacing any): the
row nearest contact carried to contact, with the deceleration of the rows that end the table
braking (from the table itself), or none when the brake is off at that row. The rows are one
speed history, not independent measurements, so they give one record, not one each. The file
is written as `pim set` writes (checked, atomic, never lost).

EXIT STATUS:
  0  written   2  bad input (the file is left as it was)
  4  the file cannot be written";

/// `pim edr`.
#[derive(clap::Args, Debug)]
pub struct EdrArgs {
    /// The case file (TOML).
    pub case: PathBuf,
    /// The pre-crash table (text: rows of time, speed, brake, accelerator).
    pub table: PathBuf,
    /// The vehicle whose recorder it is.
    #[arg(long, value_parser = clap::value_parser!(u8).range(1..=2))]
    pub vehicle: u8,
    /// The table's speed unit (default: the case's).
    #[arg(long, value_parser = ["mph", "km/h", "m/s"])]
    pub unit: Option<String>,
    /// The record's standard deviation, in the case's speed unit (default: 0.45 m/s, about
    /// 1 mph).
    #[arg(long)]
    pub sigma: Option<f64>,
    /// Write the rows only, not the record of evidence (the vehicle's edr is kept).
    #[arg(long)]
    pub no_record: bool,
    /// Print the edited file to standard output instead of writing it.
    #[arg(long)]
    pub dry_run: bool,
}
