//! # pim-studies: the PIM toolkit's inputs and records
//!
//! What every front end of the toolkit shares (the `pim` command, the tests, benchmarks and
//! examples, language bindings), with no file or terminal I/O of its own: callers read the text
//! and pass it in.
//!
//! - [`case`]: the TOML case file of a solve, a sensitivity study or a fit ([`case::Case`]),
//!   its [`sections`] and its `[uncertainty]` section ([`spread`]), and [`fitcase`], the fit
//!   problem and settings it describes;
//! - [`ricsac`]: the RICSAC data file (`data/ricsac.csv`), one [`ricsac::RicsacTest`] per staged
//!   collision, in the papers' geometry;
//! - [`reference`](mod@reference): the paper tables shipped under `data/reference/`;
//! - [`batch`]: the batch refit of a data file, as typed [`batch::BatchRecord`]s;
//! - [`predict`]: Brach 1984's delta-V prediction for every test of a data file;
//! - [`records`]: the JSON documents of a solve, a sensitivity study and a fit;
//! - [`scene`]: the `[runout]` and `[scene]` sections, read into pim-runout's inputs;
//! - [`edit`]: a case file edited in place, its comments and formatting kept;
//! - [`units`]: the `[units]` of a case file and the unit systems of printed tables;
//! - [`uncertainty`]: the seeded parametric bootstrap of `pim uncertainty`.
//!
//! Bad input is an [`InputError`] whose message names the file, line and field.

pub mod batch;
pub mod batch_scene;
pub mod case_records;
pub mod consistency;
pub mod damage_assess;
mod damage_draws;
pub mod damage_fit;
pub mod documents;
pub mod fitcase;
pub mod intervals;
mod measured_inputs;
pub mod predict;
pub mod reconstruct;
pub mod reconstruct_study;
pub mod residuals;
pub mod ricsac_damage;
pub mod runout;
pub mod tolerances;
pub mod uncertainty;
pub mod watch;

pub use pim_case::{InputError, Result};
