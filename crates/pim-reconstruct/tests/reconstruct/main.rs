//! The reconstruction against simulated crashes: frictions, long spins, the nonlinear impact and the whole fit. One test binary.
#[path = "../common/mod.rs"]
mod common;

mod friction;
mod long_spins;
mod nonlinear;
mod reconstruct;
