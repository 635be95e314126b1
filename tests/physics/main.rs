//! The physics against the papers and against itself: the published tables, the fits (exact
//! global least squares) against a reference search and the truth, and property tests of the
//! impact mechanics. One test binary; `fit_stress` and `uncertainty_coverage` are their own.
#[path = "../common/mod.rs"]
mod common;

mod barrier;
mod brach1983_tables;
mod brach1984_prediction;
mod brach1984_table2;
mod fit_chi_square;
mod fit_convex;
mod fit_convex_tangential;
mod fit_edr;
mod fit_geometry_proof;
mod fit_identifiability;
mod fit_recovery;
mod fit_reference_search;
mod fit_ricsac;
mod fit_tangential;
mod friction_rule;
mod properties;
mod ricsac_data;
mod vossou2018_rebuild;
