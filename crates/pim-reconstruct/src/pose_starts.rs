//! Starting poses drawn from the priors, for a pose fit that ended far above its expectation.
//!
//! See [`screened_poses`].

use crate::outcome::Found;
use crate::pose::{At, PoseUnknown};
use crate::problem::{Reconstruction, Settings};
use rayon::prelude::*;
use statrs::distribution::{ContinuousCDF, Normal};

/// The most poses [`screened_poses`] draws ([`screened_count`]): in six unknowns, every orthant
/// of the priors (which of each unknown's two sides of the stated value) holds one point in two
/// on average, and the refits take about as long as one pose fit.
pub const SCREENED_POSES: usize = 32;

/// How many poses to draw for `n` unknowns: four per orthant of the priors (`4 2^n`), at most
/// [`SCREENED_POSES`]. One unknown gets 8, two 16, three or more 32.
pub fn screened_count(n: usize) -> usize {
    SCREENED_POSES.min(4 << n.min(3))
}

/// A pose of the screen: its offsets (m and rad), the answer refitted there and the whole
/// cost `chi2 + sum (p_j / s_j)^2`.
#[derive(Debug, Clone)]
pub struct Screened {
    /// The offsets from the stated pose, one per unknown.
    pub offsets: Vec<f64>,
    /// The reconstruction refitted at the offsets.
    pub found: Found,
    /// Its chi-square with the priors' share.
    pub cost: f64,
}

/// The pose fit's cost landscape screened for other basins: `count` poses drawn from the
/// priors, each the reconstruction `build` gives refitted there ([`crate::refit`]) from each of
/// `answers` (answers at the stated pose, one per combination of counts of turns worth a
/// start), the lower kept; returned lowest whole cost first.
///
/// The reduced cost `F(p)` that [`crate::fit_pose`] descends has more than one basin where
/// the scene's evidence can be met by moving the contact in more than one way: on a simulated
/// crash (vehicle 1 steered, vehicle 2 with a jammed wheel, the pose stated 1 ft and 3 degrees
/// off on every axis) the descent from the stated pose ends at `F = 17.7` with vehicle 2's CG
/// moved 2.6 prior deviations, behind a ridge of `F = 100` from the basin of the truth
/// (`F = 10.0` at its floor, 14.2 at the truth). The priors say where the pose may be, so the
/// starts are drawn from them: the points `p_j = s_j Phi^-1(u_j)` of an Owen-scrambled Sobol
/// sequence `u` (Burley 2020, seed 0: the same poses on every machine), which fill the
/// priors' bulk more evenly than random draws of the same number.
///
/// A drawn pose where `build` or every refit fails is no start.
pub fn screened_poses<F>(
    build: F,
    unknowns: &[PoseUnknown],
    settings: &Settings,
    answers: &[&Found],
    count: usize,
) -> Vec<Screened>
where
    F: Fn(&[f64]) -> crate::Result<Reconstruction> + Sync,
{
    let mut screened: Vec<Screened> = drawn(unknowns, count)
        .into_par_iter()
        .filter_map(|p| {
            let r = build(&p).ok()?;
            answers
                .iter()
                .filter_map(|from| At::refitted((&r, settings), unknowns, &p, from).ok())
                .filter(|at| at.cost.is_finite())
                .min_by(|a, b| a.cost.total_cmp(&b.cost))
                .map(|at| Screened {
                    offsets: at.p,
                    found: at.found,
                    cost: at.cost,
                })
        })
        .collect();
    screened.sort_by(|a, b| a.cost.total_cmp(&b.cost));
    screened
}

/// `count` poses drawn from the priors: `p_j = s_j Phi^-1(u_j)`, `u` the Owen-scrambled Sobol
/// sequence (seed 0).
fn drawn(unknowns: &[PoseUnknown], count: usize) -> Vec<Vec<f64>> {
    let normal = Normal::standard();
    (0..count)
        .map(|i| {
            unknowns
                .iter()
                .enumerate()
                .map(|(j, u)| {
                    let q = sobol_burley::sample(i as u32, j as u32, 0);
                    u.sigma * normal.inverse_cdf(f64::from(q).clamp(1e-6, 1.0 - 1e-6))
                })
                .collect()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn unknowns(sigmas: &[f64]) -> Vec<PoseUnknown> {
        sigmas
            .iter()
            .enumerate()
            .map(|(j, s)| PoseUnknown {
                name: format!("u{j}"),
                sigma: *s,
                prior: true,
            })
            .collect()
    }

    /// The drawn poses follow the priors: per unknown, the 32 points' mean within 0.05 and
    /// their standard deviation within 6 % of the prior's (random draws would give about 0.18
    /// and 13 %), both sides of every unknown drawn 16 times, the same poses every call.
    #[test]
    fn the_drawn_poses_follow_the_priors() {
        let sigmas = [0.05, 0.3, 0.3, 0.05, 0.3, 0.3, 0.2];
        let u = unknowns(&sigmas);
        assert_eq!(screened_count(7), SCREENED_POSES);
        assert_eq!(screened_count(1), 8);
        assert_eq!(screened_count(2), 16);
        assert_eq!(screened_count(3), SCREENED_POSES);
        let p = drawn(&u, SCREENED_POSES);
        assert_eq!(p, drawn(&u, SCREENED_POSES));
        assert_eq!(p.len(), SCREENED_POSES);
        let n = SCREENED_POSES as f64;
        for (j, s) in sigmas.iter().enumerate() {
            let z: Vec<f64> = p.iter().map(|x| x[j] / s).collect();
            let mean = z.iter().sum::<f64>() / n;
            let sd = (z.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
            assert!(mean.abs() < 0.05, "unknown {j}: mean {mean}");
            assert!((sd - 1.0).abs() < 0.06, "unknown {j}: sd {sd}");
            assert_eq!(z.iter().filter(|x| **x > 0.0).count(), 16, "unknown {j}");
        }
    }
}
