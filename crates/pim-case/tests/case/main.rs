//! The case file: edits in place, motion, the RICSAC loader and the tyre. One test binary.

mod edit;
mod motion;
mod ricsac_loader;
mod tyre;
