//! Scans through the optimum along each coefficient, for the identifiability ranges.
//!
//! Profiled problems (one state known): along `(mu, em)` through the optimum, each point at its
//! best e, and on each of those lines the exact ends of the e interval where the cost stays near
//! the optimum. Otherwise along each coefficient of the optimum's space. A sticking optimum is
//! also scanned in the sliding mode through mu = its mu_max, where the data may trade restitution
//! against approach speed just as well while sliding.

use super::outcome::{near_limit, Outcome, Point};
use super::space::{spaces, Dim, Space};
use crate::inner::{Eval, Inner, LineAt};
use crate::problem::MomentBranch;
use crate::settings::FitSettings;
use pim_core::{Coefficients, TangentialCondition};

/// Points along each dimension of `space` through `centre` (and the centre itself).
fn through(space: &Space, centre: &[f64], n: impl Fn(usize) -> usize) -> Vec<Vec<f64>> {
    let mut points = vec![centre.to_vec()];
    for (k, d) in space.dims.iter().enumerate() {
        for v in (Dim { n: n(k), ..*d }).axis() {
            let mut p = centre.to_vec();
            p[k] = v;
            points.push(p);
        }
    }
    points
}

/// The spaces to scan for an optimum: its own, and the sliding one through a sticking optimum.
fn scanned(
    branch: MomentBranch,
    settings: &FitSettings,
    profile: bool,
    best: &Point,
) -> Vec<Space> {
    spaces(branch, settings, profile, Default::default())
        .into_iter()
        .filter(|s| s.mode == best.at.mode || best.at.mode == TangentialCondition::NoSlip)
        .collect()
}

/// The optimum's coefficients in a space (mu = the optimum's mu_eff).
fn centre(space: &Space, best: &Point) -> Vec<f64> {
    // The tangential model's sliding space through a sticking optimum: at the friction limit
    // that its impulse ratio reaches.
    let mu = if space.et_axis && space.mode != best.at.mode {
        best.candidate.mu_eff.abs()
    } else {
        best.candidate.mu_eff
    };
    space.point_of(&Coefficients { mu, ..best.at.c }, best.at.et)
}

/// Runs the scans and records every feasible point.
pub(crate) fn scan(inner: &Inner, settings: &FitSettings, branch: MomentBranch, out: &mut Outcome) {
    let Some(best) = out.best else {
        return;
    };
    let s = &settings.search;
    // Points above the near-optimal limit add nothing to the ranges: they are not solved
    // exactly once their lower bound exceeds it.
    let cutoff = near_limit(
        out.incumbent(),
        settings.identifiability_tolerance,
        out.data_scale,
    );
    if !out.profiled_e {
        for space in scanned(branch, settings, false, &best) {
            // Along mu in the sliding space through a sticking optimum: a finer scan.
            let mu_axis = if space.mode != best.at.mode {
                1
            } else {
                usize::MAX
            };
            let n = |k: usize| {
                if k == mu_axis {
                    s.scan_points_mu
                } else {
                    s.scan_points
                }
            };
            for p in through(&space, &centre(&space, &best), n) {
                out.exact_below(inner, &space, &p, cutoff);
            }
        }
        return;
    }
    let mut lines: Vec<(LineAt, f64)> = Vec::new();
    for space in scanned(branch, settings, true, &best) {
        for p in through(&space, &centre(&space, &best), |_| s.scan_points) {
            for &sign in inner.signs_in(space.mode) {
                out.evaluations += 1;
                out.exact_solves += 1;
                let (at, eval) = space.eval(inner, &p, sign, true, cutoff);
                let Eval::Feasible(candidate) = eval else {
                    continue;
                };
                out.record(Point { at, candidate });
                let line = LineAt {
                    e_range: settings.e,
                    mu: at.c.mu,
                    em: at.c.em,
                    mode: space.mode,
                    sign,
                };
                lines.push((line, candidate.cost));
            }
        }
    }
    // The limit of the final optimum (a scan point may have improved it a little), pulled in by
    // a relative 1e-12 so that the ends stay inside it after round-off.
    let limit = near_limit(
        out.incumbent(),
        settings.identifiability_tolerance,
        out.data_scale,
    ) * (1.0 - 1e-12);
    for (at, line_best) in lines {
        if line_best > limit {
            // Even the best e of this line is not near the optimum.
            continue;
        }
        for (c, candidate) in inner.profile_level_ends(&at, limit) {
            out.record(Point {
                at: crate::inner::At {
                    c,
                    mode: at.mode,
                    sign: at.sign,
                    et: 0.0,
                },
                candidate,
            });
        }
    }
}
