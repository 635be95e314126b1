//! The document types of `intervals` (what the study of the same name in pim-studies writes).

use crate::records::BoundSource;
use pim_fit::SearchBound;
use serde::Serialize;

/// Summary of one quantity over the feasible draws.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Summary {
    /// 5th percentile.
    pub p05: f64,
    /// Median.
    pub p50: f64,
    /// 95th percentile.
    pub p95: f64,
    /// Mean.
    pub mean: f64,
    /// Standard deviation.
    pub sd: f64,
    /// The nominal fit does not determine this quantity (its range within the identifiability
    /// tolerance is open or wide): the interval is not a confidence statement.
    pub not_determined: bool,
    /// The 90 % interval reaches a bound of the search: the bound, not the data, ends it
    /// (which bound, on what share of the draws, and who set it); `None` when no bound does.
    pub reaches_bound: Option<BoundHit>,
}

impl Summary {
    /// The summary of a quantity's values over the feasible draws (percentiles by
    /// [`percentile`], the sample standard deviation); `not_determined` and `reaches_bound` as
    /// the study found them.
    pub fn of(y: &[f64], not_determined: bool, reaches_bound: Option<BoundHit>) -> Summary {
        let mut sorted = y.to_vec();
        sorted.sort_by(f64::total_cmp);
        let n = y.len().max(1) as f64;
        let mean = y.iter().sum::<f64>() / n;
        let sd = (y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0)).sqrt();
        Summary {
            p05: percentile(&sorted, 0.05),
            p50: percentile(&sorted, 0.5),
            p95: percentile(&sorted, 0.95),
            mean,
            sd,
            not_determined,
            reaches_bound,
        }
    }
}

/// A search bound that ends a quantity's interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BoundHit {
    /// The bound (its `[bounds]` key).
    pub bound: SearchBound,
    /// Share of the feasible draws whose fit rests on it.
    pub share: f64,
    /// Who set it: the case, or the default.
    pub source: BoundSource,
}

/// The `p`-quantile (0 to 1) of sorted values, linearly interpolated; NaN when empty.
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = p * (sorted.len() - 1) as f64;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}
