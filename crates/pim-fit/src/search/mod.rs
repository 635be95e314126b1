//! The outer search over the coefficient box of one moment branch, and its record.
//!
//! 1. Grid ([`space`]): every grid point is evaluated for each friction sign at its
//!    equality-only optimum, a lower bound of the exact inner value. Points whose bound could
//!    still beat the best feasible value are then solved exactly, in order of their bounds, so
//!    the grid minimum is exact.
//! 2. Refinement ([`refine`]): Nelder-Mead from the best grid points of distinct cells, from the
//!    other local minima of the grid and from the samples of narrow friction bands (up to
//!    `max_refinement_starts`), then a compass search with Hooke-Jeeves pattern moves from
//!    every result near the best; grids are refined before an infeasible verdict.
//! 3. Scans ([`scan`]) through the optimum for the identifiability ranges.
//! 4. The [`Outcome`] counts what was done, for the certificate, and whether the refinements
//!    from different starts agree.

mod outcome;
mod refine;
mod scan;
mod space;

pub(crate) use outcome::{near_limit, Outcome, Point, Sample};
pub(crate) use space::product;

use crate::certificate::Fallback;
use crate::convex::Verdict;
use crate::inner::{Eval, Inner};
use crate::problem::MomentBranch;
use crate::report::Violation;
use crate::settings::FitSettings;
use space::{spaces, Space};

/// Searches one branch: the one place that decides its route. The convex decomposition first
/// (exact, for PIM with every component estimated); where it does not apply or cannot certify
/// its answer, the typed reason is kept for the certificate and the grid search decides.
pub(crate) fn search_branch(
    inner: &Inner,
    settings: &FitSettings,
    branch: MomentBranch,
) -> Outcome {
    let fresh = || Outcome {
        data_scale: inner.data_scale(),
        profiled_e: inner.profiles(),
        friction_max: (inner.family.friction() == crate::family::Friction::Limit)
            .then_some(settings.friction[1]),
        ..Outcome::default()
    };
    let mut out = fresh();
    match crate::convex::bnb::solve(inner, settings, branch) {
        Verdict::Optimal {
            at,
            candidate,
            counts,
        } => {
            out.convex = Some(counts);
            out.evaluations = counts.patterns;
            out.exact_solves = counts.solved;
            out.record(Point { at, candidate });
            if settings.ranges {
                scan::scan(inner, settings, branch, &mut out);
            }
            return out;
        }
        Verdict::Infeasible { counts } => {
            // Proven infeasible. Where the data alone say why, that is the answer.
            if crate::inner::direct_reason(inner, crate::report::Limits::of(settings)).is_some() {
                out.convex = Some(counts);
                out.evaluations = counts.patterns;
                return out;
            }
            // Otherwise the grid's points count which conditions fail, for the reason; no
            // refinement is needed for a verdict already proven. Should a grid point be
            // feasible after all (the routes disagree), the whole grid search decides.
            let faces = inner.singular_faces();
            for space in spaces(branch, settings, out.profiled_e, faces) {
                grid(inner, &space, &mut out);
            }
            if out.best.is_none() {
                out.convex = Some(counts);
                return out;
            }
            out = fresh();
            out.fallback = Some(Fallback::NoPatternFeasible);
        }
        Verdict::Search(why) => out.fallback = Some(why),
    }
    let faces = inner.singular_faces();
    for space in spaces(branch, settings, out.profiled_e, faces) {
        let g = grid(inner, &space, &mut out);
        refine_from_grid(inner, settings, &space, &g, &mut out);
    }
    // An infeasible verdict is a strong statement: a feasible set thinner than the grid spacing
    // is looked for on finer grids first.
    let mut finer = settings.clone();
    for _ in 0..settings.search.infeasible_refinements {
        if out.best.is_some() {
            break;
        }
        finer.grid = finer.grid.map(|n| 2 * n - 1);
        for space in spaces(branch, &finer, out.profiled_e, faces) {
            let g = grid(inner, &space, &mut out);
            refine_from_grid(inner, &finer, &space, &g, &mut out);
        }
    }
    // Agreement of the refinements with the optimum.
    if let Some(best) = out.best {
        let m = best.candidate.cost;
        let close = |f: f64| f <= m + settings.search.agreement_tolerance * (1.0 + m);
        out.refinements_agreeing = out.finals.iter().filter(|(f, _)| close(*f)).count();
        out.limit_reached =
            out.refinements_agreeing == 1 && out.finals.iter().any(|(f, hit)| close(*f) && *hit);
    }
    if settings.ranges {
        scan::scan(inner, settings, branch, &mut out);
    }
    out
}

/// The evaluated grid of a space.
struct Grid {
    /// The regular grid points, then the samples of narrow friction bands.
    pts: Vec<Vec<f64>>,
    /// The best exact value of each point (`None`: no feasible sign).
    values: Vec<Option<f64>>,
    /// Number of regular grid points (the first of `pts`).
    n_grid: usize,
    /// Width of the friction band of each band sample (0 for a regular grid point).
    bands: Vec<f64>,
}

/// The grid of a space: relaxed evaluations, then exact solves where the lower bound could still
/// win, then samples of the friction bands narrower than the grid.
fn grid(inner: &Inner, space: &Space, out: &mut Outcome) -> Grid {
    let mut pts = space.grid();
    let n_grid = pts.len();
    let mut bands = vec![0.0; n_grid];
    out.grid_points += pts.len();
    let mut values: Vec<Option<f64>> = vec![None; pts.len()];
    let mut found: Vec<(usize, Point)> = Vec::new();
    let mut pending: Vec<(f64, usize, pim_core::FrictionSign)> = Vec::new();
    for (i, p) in pts.iter().enumerate() {
        for &sign in inner.signs_in(space.mode) {
            out.evaluations += 1;
            let (at, eval) = space.eval(inner, p, sign, false, f64::INFINITY);
            match eval {
                Eval::Feasible(candidate) => found.push((i, Point { at, candidate })),
                Eval::Pending {
                    lower_bound,
                    violation,
                } => {
                    pending.push((lower_bound, i, sign));
                    *out.violations.entry(violation).or_default() += 1;
                }
                Eval::Infeasible(v) => *out.violations.entry(v).or_default() += 1,
            }
        }
    }
    for &(i, p) in &found {
        keep(out, &mut values, i, p);
    }
    pending.sort_by(|a, b| a.0.total_cmp(&b.0));
    for (lb, i, sign) in pending {
        let best = out.incumbent();
        if lb >= best {
            continue;
        }
        out.evaluations += 1;
        out.exact_solves += 1;
        let (at, eval) = space.eval(inner, &pts[i], sign, true, best);
        match eval {
            Eval::Feasible(candidate) => {
                let p = Point { at, candidate };
                found.push((i, p));
                keep(out, &mut values, i, p);
            }
            Eval::Infeasible(Violation::EnergyUncertified) => out.uncertified += 1,
            Eval::Infeasible(_) | Eval::Pending { .. } => {}
        }
    }
    // Friction bands: mu is admissible between 0 and mu_max, which depends on the point. A band
    // that holds fewer than two grid values of mu is sampled at its middle as well, so that a
    // narrow admissible band (a small or negative mu_max) is not stepped over.
    if let Some(k) = space.mu_axis() {
        let spacing = space.dims[k].spacing();
        let mut extra: Vec<(Vec<f64>, f64)> = Vec::new();
        for (i, p) in &found {
            let Some(m) = inner.mu_max(&p.at, &p.candidate) else {
                continue;
            };
            // The band of this point's friction sign, [0, m], and that of the other sign,
            // [0, -m] (mu_max changes sign with it, and near mu = 0 the contact state, and so
            // the consistent sign, can change).
            for band in [m, -m] {
                let (lo, hi) = (band.min(0.0), band.max(0.0));
                let inside = space.dims[k]
                    .axis()
                    .iter()
                    .filter(|&&v| v > lo && v < hi)
                    .count();
                let mid = (0.5 * band).clamp(space.dims[k].lo, space.dims[k].hi);
                if inside >= 2 || (hi - lo) >= 2.0 * spacing || mid == 0.0 {
                    continue;
                }
                let mut q = pts[*i].clone();
                q[k] = mid;
                if !extra
                    .iter()
                    .map(|e| &e.0)
                    .chain(pts.iter())
                    .any(|e| e == &q)
                {
                    extra.push((q, hi - lo));
                }
            }
        }
        for (q, width) in extra {
            let i = pts.len();
            pts.push(q);
            values.push(None);
            bands.push(width);
            out.grid_points += 1;
            if let Some(p) = out.exact(inner, space, &pts[i]) {
                values[i] = Some(p.candidate.cost);
            }
        }
    }
    Grid {
        pts,
        values,
        n_grid,
        bands,
    }
}

/// Records a feasible grid point and keeps the best value of its point.
fn keep(out: &mut Outcome, values: &mut [Option<f64>], i: usize, p: Point) {
    out.record(p);
    if values[i].is_none_or(|v| p.candidate.cost < v) {
        values[i] = Some(p.candidate.cost);
    }
}

/// Nelder-Mead from the best grid points of distinct cells (more than one cell apart), then the
/// compass search from every result within `polish_within` of the best (the others are distinct
/// local minima). A friction-band sample is refined twice, from the grid's simplex and from one
/// of its band's width along mu (a refinement that stays in the band instead of stepping over
/// it); the latter is always polished (its band is a local minimum of its own that the grid's
/// values do not rank).
fn refine_from_grid(
    inner: &Inner,
    settings: &FitSettings,
    space: &Space,
    grid: &Grid,
    out: &mut Outcome,
) {
    let (pts, values, n_grid) = (&grid.pts, &grid.values, grid.n_grid);
    if space.dims.is_empty() {
        // A single point, solved exactly: nothing to refine.
        return;
    }
    let s = &settings.search;
    let mut order: Vec<usize> = (0..pts.len()).filter(|&i| values[i].is_some()).collect();
    order.sort_by(|&a, &b| {
        values[a]
            .unwrap_or(f64::INFINITY)
            .total_cmp(&values[b].unwrap_or(f64::INFINITY))
    });
    let spacing: Vec<f64> = space.dims.iter().map(|d| d.spacing()).collect();
    let mut starts: Vec<usize> = Vec::new();
    for &i in &order {
        if starts.len() >= s.refinement_starts {
            break;
        }
        let far = starts.iter().all(|&j| {
            pts[i]
                .iter()
                .zip(&pts[j])
                .zip(&spacing)
                .any(|((a, b), sp)| (a - b).abs() > 1.5 * sp)
        });
        if far {
            starts.push(i);
        }
    }
    // The other local minima of the grid: no grid neighbour (one step along any set of axes)
    // is better.
    let value = |i: usize| values[i].unwrap_or(f64::INFINITY);
    let neighbours = |i: usize, j: usize| {
        i != j
            && pts[i]
                .iter()
                .zip(&pts[j])
                .zip(&spacing)
                .all(|((a, b), sp)| (a - b).abs() <= 1.01 * sp)
    };
    for &i in &order {
        if starts.len() >= s.max_refinement_starts.max(s.refinement_starts) {
            break;
        }
        if starts.contains(&i) {
            continue;
        }
        // Band samples (after the regular grid) are starts of their own: their band is
        // narrower than the grid, so its neighbours say little about it.
        let band_sample = i >= n_grid;
        if band_sample || (0..n_grid).all(|j| !neighbours(i, j) || value(j) >= value(i)) {
            starts.push(i);
        }
    }
    // The first simplex of a start: the grid's; a band sample is refined from that and again
    // from one of its band's width along mu (a simplex inside the band), marked narrow.
    let first_steps = |i: usize| -> Vec<(Vec<f64>, bool)> {
        let mut all = vec![(spacing.clone(), false)];
        if let Some(k) = space.mu_axis() {
            if grid.bands[i] > 0.0 && grid.bands[i] < spacing[k] {
                let mut narrow = spacing.clone();
                narrow[k] = grid.bands[i];
                all.push((narrow, true));
            }
        }
        all
    };
    // (point, cost, iteration limit hit, started inside a narrow band)
    let mut refined: Vec<(Vec<f64>, f64, bool, bool)> = Vec::new();
    for &i in &starts {
        let tol = s.nelder_mead_tolerance * (1.0 + values[i].unwrap_or(0.0));
        for (steps, narrow) in first_steps(i) {
            out.refinements += 1;
            let (best, hit) = refine::nelder_mead(inner, space, &pts[i], &steps, tol, s, out);
            if let Some(b) = best {
                if let Some(p) = out.exact(inner, space, &b) {
                    refined.push((b, p.candidate.cost, hit, narrow));
                }
            }
        }
    }
    refined.sort_by(|a, b| a.1.total_cmp(&b.1));
    let lead = refined.first().map_or(f64::INFINITY, |r| r.1);
    // A refinement that ended where one already polished started (within a thousandth of the
    // grid spacing) shares its polish: the compass would retrace it.
    let twin = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .zip(&spacing)
            .all(|((x, y), sp)| (x - y).abs() <= 1e-3 * sp)
    };
    let mut polished: Vec<(Vec<f64>, f64)> = Vec::new();
    for (p, cost, hit, narrow) in refined {
        if narrow || cost <= lead + s.polish_within * (1.0 + lead.abs()) {
            if let Some((_, value)) = polished.iter().find(|(q, _)| twin(&p, q)) {
                let value = value.min(cost);
                out.finals.push((value, hit && value >= cost));
                continue;
            }
            let (_, value) = refine::compass(inner, space, p.clone(), cost, s, out);
            out.finals.push((value, hit && value >= cost));
            polished.push((p, value));
        } else {
            out.finals.push((cost, hit));
        }
    }
}
