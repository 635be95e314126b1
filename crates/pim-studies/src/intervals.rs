//! Summaries of a quantity over the draws of an uncertainty study: percentiles, the share of
//! an input in the spread, and whether a search bound ends the interval.

pub use pim_documents::intervals::{percentile, BoundHit, Summary};
use pim_documents::records::BoundSource;
use pim_fit::SearchBound;

/// The inputs' first-order indices of a quantity (`y`, one value per feasible draw), largest
/// first, those above 0.02: input `j`'s values are `xs[d][j]` of draw `d`.
pub fn dominant_inputs<'a>(
    names: impl Iterator<Item = &'a str>,
    xs: &[&Vec<f64>],
    y: &[f64],
) -> Vec<(String, f64)> {
    let mut shares: Vec<(String, f64)> = names
        .enumerate()
        .map(|(j, name)| {
            let x: Vec<f64> = xs.iter().map(|d| d[j]).collect();
            (name.to_string(), correlation_ratio(&x, y))
        })
        .filter(|(_, s)| *s > 0.02)
        .collect();
    shares.sort_by(|a, b| b.1.total_cmp(&a.1));
    shares
}

/// Share of the draws at or beyond which a bound ends a 90 % interval: when at least 5 % of the
/// draws rest on a bound, the 5th or the 95th percentile is one of them.
pub const BOUND_SHARE: f64 = 0.05;

/// The search bounds a quantity's value depends on directly: e and mu on their ranges, the
/// speeds, delta-V and energy loss on the velocity and yaw-rate bounds; em's range [-1, 0] is
/// physics.
pub fn bounds_of(quantity: &str) -> &'static [SearchBound] {
    match quantity {
        "e" => &[SearchBound::E],
        "mu" => &[SearchBound::Mu],
        "et" => &[SearchBound::Et],
        "friction" => &[SearchBound::Friction],
        "em" => &[],
        _ => &[SearchBound::Velocity, SearchBound::YawRate],
    }
}

/// The bound that ends the interval of `quantity`, if any: the relevant bound with the largest
/// share of draws resting on it, when that share reaches [`BOUND_SHARE`]. `shares` gives, per
/// bound, the share of draws resting on it; `source` who set each bound.
pub fn bound_hit(
    quantity: &str,
    shares: &[(SearchBound, f64)],
    source: &dyn Fn(SearchBound) -> BoundSource,
) -> Option<BoundHit> {
    shares
        .iter()
        .filter(|(b, share)| bounds_of(quantity).contains(b) && *share >= BOUND_SHARE)
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|&(bound, share)| BoundHit {
            bound,
            share,
            source: source(bound),
        })
}

/// The correlation ratio of `y` on `x` with ten quantile bins of `x`: `Var(E[y | bin]) / Var(y)`.
pub fn correlation_ratio(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len();
    if n < 20 {
        return 0.0;
    }
    let mut idx: Vec<usize> = (0..n).collect();
    idx.sort_by(|&a, &b| x[a].total_cmp(&x[b]));
    let mean = y.iter().sum::<f64>() / n as f64;
    let total: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    // A quantity the draws do not move (a known speed, to round-off) has no share to give.
    if (total / n as f64).sqrt() <= 1e-9 * mean.abs() || total <= 0.0 {
        return 0.0;
    }
    let bins = 10;
    let mut between = 0.0;
    for b in 0..bins {
        let part = &idx[b * n / bins..(b + 1) * n / bins];
        if part.is_empty() {
            continue;
        }
        let m = part.iter().map(|&i| y[i]).sum::<f64>() / part.len() as f64;
        between += part.len() as f64 * (m - mean).powi(2);
    }
    // Bias correction: with a constant y given x the binned ratio still picks up noise of
    // about (bins - 1) / n.
    ((between / total) - (bins as f64 - 1.0) / n as f64).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use pim_case::spread::standard_normal;
    use rand::SeedableRng;

    #[test]
    fn correlation_ratio_of_a_function_and_of_noise() {
        let x: Vec<f64> = (0..1000).map(|i| i as f64 / 1000.0).collect();
        let y: Vec<f64> = x.iter().map(|v| v * v).collect();
        assert!(correlation_ratio(&x, &y) > 0.95);
        let mut rng = rand::rngs::StdRng::seed_from_u64(1);
        let noise: Vec<f64> = (0..1000).map(|_| standard_normal(&mut rng)).collect();
        assert!(correlation_ratio(&x, &noise) < 0.02);
        // A quantity the draws leave unchanged but for round-off (a known speed) is driven by
        // no input, not by every one.
        let known: Vec<f64> = x.iter().map(|v| 13.01 + 1e-15 * v).collect();
        assert!(correlation_ratio(&x, &known) < 1e-12);
    }

    #[test]
    fn a_bound_ends_an_interval_from_five_percent_of_the_draws() {
        let shares = [(SearchBound::Velocity, 0.06), (SearchBound::E, 0.5)];
        let default = |_| BoundSource::Default;
        let hit = bound_hit("speed1", &shares, &default).unwrap();
        assert_eq!((hit.bound, hit.share), (SearchBound::Velocity, 0.06));
        assert_eq!(
            bound_hit("e", &shares, &default).unwrap().bound,
            SearchBound::E
        );
        assert_eq!(bound_hit("em", &shares, &default), None);
        let few = [(SearchBound::Velocity, 0.049)];
        assert_eq!(bound_hit("speed1", &few, &default), None);
    }
}
