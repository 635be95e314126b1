//! Helpers of the reconstruction tests: the run-out's random chassis and starts, and random
//! collisions with a known truth.
#![allow(dead_code)]

pub mod crash;
mod impact;
#[path = "../../../pim-runout/tests/common/runout.rs"]
pub mod runout;
#[allow(unused_imports)]
pub use impact::*;
