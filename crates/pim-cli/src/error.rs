//! Failure categories of the command and their exit codes.

use std::fmt;

/// Exit status: success.
pub const EXIT_OK: u8 = 0;
/// Exit status with --strict: the answer came with a warning (solve, fit, uncertainty: a
/// plausibility warning, or an answer that rests on a bound no one set for the crash; batch:
/// some records are infeasible or failed). The output was written all the same.
pub const EXIT_STRICT: u8 = 1;
/// Exit status (batch with --strict): some records are infeasible or failed; the others were
/// written.
pub const EXIT_SOME_FAILED: u8 = EXIT_STRICT;
/// Exit status: bad input (command line, file, field, value); nothing was computed.
pub const EXIT_BAD_INPUT: u8 = 2;
/// Exit status: valid input for which the model has no answer (singular or inconsistent system).
pub const EXIT_NO_ANSWER: u8 = 3;
/// Exit status: an output file could not be written.
pub const EXIT_IO: u8 = 4;

/// The exit codes, as printed in `--help`.
pub const EXIT_CODES_HELP: &str = "\
EXIT STATUS:
  0  success (batch: it ran and wrote its results; infeasible records are counted in it)
  1  with --strict, an answer that came with a warning: solve, fit and uncertainty when the
     case drew a plausibility warning or (fit, uncertainty) the answer rests on a bound the
     case does not set (a default); batch and compare-costs when some records are infeasible
     or failed (their rows say why). The output is complete all the same
  2  bad input: a command-line flag, a file that cannot be read, or a field with a bad value;
     the message names the file, line and field
  3  the input is valid but the model has no answer: singular or inconsistent equations, or
     (fit) no moment branch has an admissible solution; the output still says why
  4  an output file or directory could not be written

ERRORS are printed once on stderr as `pim: <file>: <where>: <what>`.";

/// A failure with its category.
#[derive(Debug)]
pub enum Failure {
    /// Bad input: exit status 2.
    Input(String),
    /// The model cannot answer: exit status 3.
    NoAnswer(String),
    /// Writing output failed: exit status 4.
    Output(String),
}

impl Failure {
    /// The exit status of this failure.
    pub fn code(&self) -> u8 {
        match self {
            Failure::Input(_) => EXIT_BAD_INPUT,
            Failure::NoAnswer(_) => EXIT_NO_ANSWER,
            Failure::Output(_) => EXIT_IO,
        }
    }

    /// Classifies a pim-core error raised while solving the case in `file`: singular or
    /// inconsistent equations are "no answer" (3), anything else bad input (2).
    pub fn from_core(file: &str, e: pim_core::PimError) -> Self {
        pim_studies::documents::DocumentError::from_core(file, e).into()
    }

    /// A figure or drawing that could not be made for the output `place` (a folder, a file):
    /// the studies' located errors as they classify themselves, any other an output failure
    /// (exit status 4) naming `place`.
    pub fn render(place: &std::path::Path, e: pim_render::RenderError) -> Self {
        match e {
            pim_render::RenderError::Input(d) => d.into(),
            e => Failure::Output(format!("{}: {e}", place.display())),
        }
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Input(m) | Failure::NoAnswer(m) | Failure::Output(m) => f.write_str(m),
        }
    }
}

impl std::error::Error for Failure {}

impl From<pim_case::InputError> for Failure {
    fn from(e: pim_case::InputError) -> Self {
        Failure::Input(e.message)
    }
}

impl From<pim_studies::documents::DocumentError> for Failure {
    fn from(e: pim_studies::documents::DocumentError) -> Self {
        use pim_studies::documents::DocumentError as D;
        match e {
            D::Input(m) => Failure::Input(m),
            D::NoAnswer(m) => Failure::NoAnswer(m),
        }
    }
}
