//! The arguments of `pim set` and its help.

use std::path::PathBuf;

/// Examples of `pim set`.
pub const SET_HELP: &str = "EXAMPLES:
  pim set case.toml scene.vehicle1.rest.x=12.0 scene.vehicle1.rest.heading=150
  pim set case.toml runout.vehicle1.wheels.front_right=locked runout.friction_sigma=0.08
  pim set case.toml observations.0.sigma=2.5 --dry-run     (print the edited file instead)

A key the file does not write is added to its table. A number is written in the file's units
([units]); the message of a value the case refuses is the one `pim fit` gives.

EXIT STATUS:
  0  written   2  bad input (the file is left as it was)   4  the file cannot be written";

/// `pim set`.
#[derive(clap::Args, Debug)]
pub struct SetArgs {
    /// The case file (TOML).
    pub case: PathBuf,
    /// The values to set, each KEY=VALUE (a number, true/false, or text).
    #[arg(required = true, value_name = "KEY=VALUE")]
    pub values: Vec<String>,
    /// Print the edited file to standard output instead of writing it.
    #[arg(long)]
    pub dry_run: bool,
}
