//! # pim-documents: the answers of the PIM toolkit
//!
//! The typed JSON documents every study writes and every face reads: the command's
//! `--format json`, the Python package's results, the scene editor's messages. Each is a Rust
//! type with `Serialize` and a JSON Schema ([`schema`], committed under `docs/schema/`). The
//! numbers are SI, angles in degrees, in the natural frame ([`records::SiUnits`]), whatever the
//! case's units and convention.
//!
//! Below the studies (which make the documents) and above the case (whose units and sides they
//! name); no computation of its own beyond reading library reports into documents.

pub mod batch;
pub mod case_records;
pub mod damage_assess;
pub mod damage_fit;
pub mod fitcase;
pub mod intervals;
pub mod predict;
pub mod reconstruct_doc;
pub mod reconstruct_study;
pub mod records;
pub mod residuals;
pub mod ricsac_damage;
pub mod runout;
pub mod schema;
pub mod uncertainty;
pub mod watch;
