//! Library part of the `pim` command: case files, the RICSAC data file, output records.
//!
//! The binary (`src/main.rs`) owns argument parsing, printing and exit codes; this library reads
//! and checks input files and shapes results, and is what the reference tests load data through.

pub mod batch;
pub mod case;
pub mod error;
pub mod figures;
pub mod fitcase;
pub mod output;
pub mod ricsac;
