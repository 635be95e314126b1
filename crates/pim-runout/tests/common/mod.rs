//! Helpers of the run-out tests: random chassis and starts, and an independent implementation
//! of the model to check it against.
#![allow(dead_code)]

pub mod runout;
