//! # pim-studies: the questions the PIM toolkit answers
//!
//! One entry per question, each a case (pim-case) and options in and a document
//! (pim-documents) out, with no file or terminal I/O of its own: the faces (the `pim` command,
//! the Python package, the scene editor) read the files, call a study, and write or show its
//! document.
//!
//! - [`check`]: what `pim fit` refuses before it computes, the one check of every write of a
//!   case file;
//! - [`question`]: which question a case asks (the fit of its impact, or its whole
//!   reconstruction), decided once for every face;
//! - [`documents`]: the solve ([`documents::solve`]) and the fit ([`documents::fit`]) of a case;
//! - [`reconstruct`]: the whole reconstruction of a case with scene evidence, and
//!   [`consistency`], its evidence consistency table ([`consistency::answer`]: the
//!   reconstruction as every face answers it);
//! - [`runout`]: each vehicle from separation to rest, or the separation from the scene;
//!   [`playback`]: the answer's motion in time, from the braking before the impact to rest;
//! - [`uncertainty`] and [`reconstruct_study`]: the seeded parametric bootstraps of `pim
//!   uncertainty` (of an impact fit, of a whole reconstruction);
//! - [`batch`]: the refit of a data file; [`case_batch`]: a batch of case files;
//! - [`predict`]: Brach 1984's delta-V prediction for every test of a data file;
//! - [`damage_fit`], [`damage_assess`], [`ricsac_damage`]: the crush as evidence;
//! - [`watch`]: the one observer every long study reports its progress to and can be
//!   cancelled from.
//!
//! Every stop of a study is a count, never a time: the same case gives the same document on
//! every machine. Bad input is an [`InputError`] whose message names the file, line and field.

pub mod batch;
pub mod batch_scene;
pub mod case_batch;
pub mod case_records;
pub mod check;
pub mod consistency;
pub mod damage_assess;
pub mod damage_fit;
pub mod documents;
pub mod earlier;
pub mod fitcase;
pub mod intervals;
mod pieces;
pub mod playback;
pub mod predict;
pub mod question;
pub mod reconstruct;
mod reconstruct_friction;
mod reconstruct_input;
mod reconstruct_open;
mod reconstruct_pose;
pub mod reconstruct_study;
pub mod residuals;
pub mod ricsac_damage;
pub mod runout;
pub use pim_case::tolerances;
pub mod uncertainty;
pub mod watch;

pub use pim_case::{InputError, Result};
