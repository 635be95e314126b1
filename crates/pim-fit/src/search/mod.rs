//! The outer search over the coefficient box of one moment branch, and its record.
//!
//! 1. Grid ([`space`]): every grid point is evaluated for each friction sign at its
//!    equality-only optimum, a lower bound of the exact inner value. Points whose bound could
//!    still beat the best feasible value are then solved exactly, in order of their bounds, so
//!    the grid minimum is exact.
//! 2. Refinement ([`refine`]): Nelder-Mead from the best grid points of distinct cells, then a
//!    compass search from every result near the best.
//! 3. Scans ([`scan`]) through the optimum for the identifiability ranges.
//! 4. The [`Outcome`] counts what was done, for the certificate, and whether the refinements
//!    from different starts agree.

mod outcome;
mod refine;
mod scan;
mod space;

pub(crate) use outcome::{near_limit, Outcome, Point, Sample};

use crate::inner::{Eval, Inner};
use crate::problem::MomentBranch;
use crate::report::Violation;
use crate::settings::FitSettings;
use space::{spaces, Space};

/// Searches one branch.
pub(crate) fn search_branch(
    inner: &Inner,
    settings: &FitSettings,
    branch: MomentBranch,
) -> Outcome {
    let mut out = Outcome {
        data_scale: inner.data_scale(),
        profiled_e: inner.profiles(),
        ..Outcome::default()
    };
    for space in spaces(branch, settings, out.profiled_e, inner.singular_faces()) {
        let (pts, values) = grid(inner, &space, &mut out);
        refine_from_grid(inner, settings, &space, &pts, &values, &mut out);
    }
    // Agreement of the refinements with the optimum.
    if let Some(best) = out.best {
        let m = best.candidate.cost;
        let close = |f: f64| f <= m + settings.search.agreement_tolerance * (1.0 + m);
        out.refinements_agreeing = out.finals.iter().filter(|(f, _)| close(*f)).count();
        out.limit_reached =
            out.refinements_agreeing == 1 && out.finals.iter().any(|(f, hit)| close(*f) && *hit);
    }
    scan::scan(inner, settings, branch, &mut out);
    out
}

/// The grid of a space: relaxed evaluations, then exact solves where the lower bound could still
/// win. Returns the points and the best exact value of each (`None`: no feasible sign).
fn grid(inner: &Inner, space: &Space, out: &mut Outcome) -> (Vec<Vec<f64>>, Vec<Option<f64>>) {
    let pts = space.grid();
    out.grid_points += pts.len();
    let mut values: Vec<Option<f64>> = vec![None; pts.len()];
    let mut keep = |out: &mut Outcome, i: usize, p: Point| {
        out.record(p);
        if values[i].is_none_or(|v| p.candidate.cost < v) {
            values[i] = Some(p.candidate.cost);
        }
    };
    let mut pending: Vec<(f64, usize, pim_core::FrictionSign)> = Vec::new();
    for (i, p) in pts.iter().enumerate() {
        for &sign in inner.signs() {
            out.evaluations += 1;
            let (at, eval) = space.eval(inner, p, sign, false, f64::INFINITY);
            match eval {
                Eval::Feasible(candidate) => keep(out, i, Point { at, candidate }),
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
            Eval::Feasible(candidate) => keep(out, i, Point { at, candidate }),
            Eval::Infeasible(Violation::EnergyUncertified) => out.uncertified += 1,
            Eval::Infeasible(_) | Eval::Pending { .. } => {}
        }
    }
    (pts, values)
}

/// Nelder-Mead from the best grid points of distinct cells (more than one cell apart), then the
/// compass search from every result within `polish_within` of the best (the others are distinct
/// local minima).
fn refine_from_grid(
    inner: &Inner,
    settings: &FitSettings,
    space: &Space,
    pts: &[Vec<f64>],
    values: &[Option<f64>],
    out: &mut Outcome,
) {
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
    let mut refined: Vec<(Vec<f64>, f64, bool)> = Vec::new();
    for &i in &starts {
        out.refinements += 1;
        let tol = s.nelder_mead_tolerance * (1.0 + values[i].unwrap_or(0.0));
        let (best, hit) = refine::nelder_mead(inner, space, &pts[i], tol, s, out);
        if let Some(b) = best {
            if let Some(p) = out.exact(inner, space, &b) {
                refined.push((b, p.candidate.cost, hit));
            }
        }
    }
    refined.sort_by(|a, b| a.1.total_cmp(&b.1));
    let lead = refined.first().map_or(f64::INFINITY, |r| r.1);
    for (p, cost, hit) in refined {
        if cost <= lead + s.polish_within * (1.0 + lead.abs()) {
            let (_, polished) = refine::compass(inner, space, p, cost, s, out);
            out.finals.push((polished, hit && polished >= cost));
        } else {
            out.finals.push((cost, hit));
        }
    }
}
