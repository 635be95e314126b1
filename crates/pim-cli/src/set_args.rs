//! The arguments of `pim set` and its help.

use std::path::PathBuf;

/// Examples of `pim set`.
pub const SET_HELP: &str = "EXAMPLES:
  pim set case.toml scene.vehicle1.rest.x=12.0 scene.vehicle1.rest.heading=150
  pim set case.toml runout.vehicle1.wheels.front_right=locked runout.friction_sigma=0.08
  pim set case.toml observations.0.sigma=2.5 --dry-run     (print the edited file instead)
  v=$(pim set case.toml --print-version)                   (the file's version, nothing changed)
  pim set case.toml runout.friction=0.70 --if-version \"$v\"  (only if nobody changed it since)

A key the file does not write is added to its table. A number is written in the file's units
([units]). The edited case is checked with every check `pim fit` makes: a value it refuses is
refused here with the same message, and nothing is written.

THE FILE IS NEVER LOST: the edited text is written to a temporary file beside the case, synced
and renamed over it (a reader, or a crash at any moment, sees the old file or the new one); its
mode is kept; a link is followed to its real file, which is edited; a read-only file, a FIFO or
a device is refused. Two `pim set` (or `pim serve`'s Save) on one file wait for each other, so
no change is lost. The version printed is the SHA-256 of the file's text; --if-version takes it
(or its first 8 or more characters) and refuses to write, with exit status 4, when the file has
changed since.

EXIT STATUS:
  0  written   2  bad input (the file is left as it was)
  4  the file cannot be written, or (--if-version) it changed since that version";

/// `pim set`.
#[derive(clap::Args, Debug)]
pub struct SetArgs {
    /// The case file (TOML).
    pub case: PathBuf,
    /// The values to set, each KEY=VALUE (a number, true/false, or text).
    #[arg(required_unless_present = "print_version", value_name = "KEY=VALUE")]
    pub values: Vec<String>,
    /// Print the edited file to standard output instead of writing it.
    #[arg(long)]
    pub dry_run: bool,
    /// Write only if the file is still this version (as --print-version or an earlier `pim
    /// set` printed it); otherwise change nothing and exit with status 4.
    #[arg(long, value_name = "VERSION")]
    pub if_version: Option<String>,
    /// Print the file's version (the SHA-256 of its text) and change nothing.
    #[arg(long, conflicts_with_all = ["values", "dry_run"])]
    pub print_version: bool,
}
