//! A drawn input and how it is written into a copy of the case.

use crate::case::Case;
use crate::spread::Spread;

/// Writes a drawn value into a copy of the case.
pub type Apply = Box<dyn Fn(&mut Case, f64) + Sync + Send>;

/// A drawn input: its name (for the tables), its spread, its nominal value and how a drawn
/// value is written into a copy of the case.
pub struct Input {
    /// The input's name in the study's tables (`vehicle1.mass`, `vehicle2 rest.x`, ...).
    pub name: String,
    /// How it is drawn.
    pub spread: Spread,
    /// Writes a drawn value into a copy of the case.
    pub apply: Apply,
    /// The value the case states.
    pub nominal: f64,
}
