//! The document types of `reconstruct_study` (what the study of the same name in pim-studies writes).

use crate::intervals::Summary;
use crate::uncertainty::Sensitivity;
use serde::Serialize;
use std::collections::BTreeMap;

/// The study of a reconstruction.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ReconstructionStudy {
    /// SI, natural frame.
    pub units: crate::records::SiUnits,
    /// `reconstruction`.
    pub kind: &'static str,
    /// Draws made (those asked for, unless the study was cancelled).
    pub draws: usize,
    /// Seed of the random streams.
    pub seed: u64,
    /// Draws with an admissible reconstruction.
    pub feasible_draws: usize,
    /// The nominal reconstruction, by quantity.
    pub nominal: BTreeMap<String, f64>,
    /// Summaries by quantity (speeds m/s, coefficients, energy loss percent).
    pub quantities: BTreeMap<String, Summary>,
    /// Which inputs dominate each quantity (first-order index from the same draws, ten bins).
    pub sensitivity: Vec<Sensitivity>,
    /// The inputs drawn, by name.
    pub inputs: Vec<String>,
    /// Each vehicle's 90 % profile interval of its speed at contact, by quantity
    /// (`vehicle1.speed_at_contact`): the speeds whose best reconstruction lies within 2.71 of
    /// the answer's chi-square (`pim_reconstruct::profile_end`). None where the pose at
    /// contact is fitted or the study was cancelled.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub profiles: BTreeMap<String, pim_reconstruct::ProfileInterval>,
    /// The 90 % interval reported for each speed at contact (m/s), by quantity: on each side
    /// the wider of the draws' (`p05`, `p95`) and the profile's (`profiles`), since each
    /// misses what the other holds (the profile, the inputs drawn that are not evidence; the
    /// draws, how far the evidence's chi-square lets the speed go where it bends). The draws'
    /// alone where there is no profile.
    pub intervals: BTreeMap<String, [f64; 2]>,
    /// Quantities whose nominal value lies outside their own 90 % interval (the draws'
    /// answers are skewed away from the nominal one: a nonlinear or bounded answer, said
    /// beside the interval).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub nominal_outside: Vec<String>,
    /// Present when the study was cancelled: the draws asked for and finished.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cancelled: Option<crate::watch::Cancelled>,
    /// Every feasible draw's value, by quantity (for the histograms; not in the JSON).
    #[serde(skip)]
    pub samples: BTreeMap<String, Vec<f64>>,
    /// Every feasible draw's velocities at separation (SI, natural frame), in the order of
    /// `samples` (for the run-outs' bands on a plan; not in the JSON).
    #[serde(skip)]
    pub separations: Vec<pim_core::Velocities>,
}
