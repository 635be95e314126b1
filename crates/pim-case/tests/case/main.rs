//! The case file: edits in place, motion, the RICSAC loader, the tyre and friction zones. One test
//! binary.

mod contact_pose;
mod edit;
mod edr;
mod inertia;
mod motion;
mod ricsac_loader;
mod survey;
mod templates;
mod tyre;
mod zones;
