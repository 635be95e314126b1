//! # pim-case: the case of the PIM toolkit
//!
//! The bottom layer every face and every study stands on: input text to a typed, checked case,
//! with no file or terminal I/O of its own (callers read the text and pass it in).
//!
//! - [`case`]: the TOML case file of a solve, a fit, a run-out or a whole reconstruction
//!   ([`case::Case`]), its [`sections`], its `[uncertainty]` section ([`spread`]), its
//!   `[runout]`/`[scene]`/`[pre_impact]` sections ([`scene_sections`], read into pim-runout's
//!   inputs by [`scene`]) and its `[damage]` ([`damage`]);
//! - the careless-input checks: [`plausibility`] and [`ranges`] (values outside what road
//!   vehicles have), the forms a crash may be written in ([`mod@input`]);
//! - [`motion`]: a motion case, the vehicles from a stated state without an impact;
//! - [`units`]: the `[units]` of a case file and the unit systems of printed tables;
//! - [`edit`]: a case file edited in place, its comments and formatting kept;
//! - [`templates`]: a case started from nothing and its sections added with starting values;
//! - [`survey`]: the scene's surveyed points (`[survey]`, read from a survey's CSV) and the
//!   evidence placed on them;
//! - [`ricsac`]: the RICSAC data file (`data/ricsac.csv`), one [`ricsac::RicsacTest`] per staged
//!   collision, in the papers' geometry;
//! - [`reference`](mod@reference): the paper tables shipped under `data/reference/`.
//!
//! Bad input is an [`InputError`] whose message names the file, line and field.

mod about;
mod asks;
pub mod case;
mod checks;
pub mod contact_pose;
mod contact_sigma;
pub mod damage;
pub mod drawn;
pub mod edit;
pub mod edr;
mod error;
mod estimated;
pub mod fit_sections;
mod forms;
pub mod frictions;
pub mod inertia;
pub mod input;
pub mod motion;
pub mod parse;
pub mod pieces;
pub mod plausibility;
pub mod pre_impact;
pub mod ranges;
pub mod reference;
pub mod ricsac;
pub mod scene;
mod scene_inputs;
pub mod scene_sections;
mod scene_zones;
pub mod sections;
pub mod spread;
pub mod survey;
pub mod templates;
pub mod tolerances;
pub mod tyres;
pub mod units;

pub use error::{InputError, Result};
