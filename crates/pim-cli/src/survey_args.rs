//! The arguments of `pim survey` and its help.

use std::path::PathBuf;

/// Examples of `pim survey`.
pub const SURVEY_HELP: &str = "EXAMPLES:
  pim survey case.toml scene_survey.csv --unit ft --origin POI
  pim survey case.toml scene_survey.csv --unit m --origin 1 --rotation 12.5 --dry-run

THE CSV: a line per point, `id, x, y` and optionally `code, description`; a header line naming
those columns (`point`, `pt`, `name` or `number` for the id, `desc` for the description), or
none and that order. Lines starting with # are skipped. A point with no id, coordinates that
are not numbers or an id given twice is refused, naming the CSV's line and column.

THE PLACING: the survey's x and y are the case's written x and y (an SAE case: x north, y
east). --origin makes a survey point the case's origin (the impact area, say; default the
survey's own origin), --rotation turns the survey counter-clockwise as seen on the plan, --unit
converts its length unit into the case's. The points are written into the case's [survey] to a
thousandth (an earlier [survey] is replaced), one to a line, every other byte of the file kept.

EVIDENCE ON A POINT: a rest, a mark, a tyre point at rest or the impact centre may name the
survey point it lies on (`point = \"R1\"`); the case is refused when it no longer lies there, so
a survey imported again that moves or drops a point in use is refused, naming the evidence.
The file is written as `pim set` writes (checked, atomic, never lost).

EXIT STATUS:
  0  written   2  bad input (the file is left as it was)
  4  the file cannot be written";

/// `pim survey`.
#[derive(clap::Args, Debug)]
pub struct SurveyArgs {
    /// The case file (TOML).
    pub case: PathBuf,
    /// The survey's CSV.
    pub csv: PathBuf,
    /// The survey's length unit (default: the case's).
    #[arg(long, value_parser = ["m", "ft"])]
    pub unit: Option<String>,
    /// The survey point made the case's origin (default: the survey's own origin).
    #[arg(long, value_name = "ID")]
    pub origin: Option<String>,
    /// Degrees the survey is turned, counter-clockwise as seen on the plan.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub rotation: f64,
    /// Print the edited file to standard output instead of writing it.
    #[arg(long)]
    pub dry_run: bool,
}
