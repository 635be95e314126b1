//! The branch-and-bound over e_m intervals that solves a branch as the union of its sign
//! patterns' QPs, and the checks of its answer.

use super::dual::{self, Row};
use super::Counts;
use super::{Formulation, Pattern, Verdict};
use crate::certificate::Fallback;
use crate::inner::{At, Candidate, Inner};
use crate::problem::MomentBranch;
use crate::settings::FitSettings;

impl Formulation {
    /// Solves the patterns of one e_m interval with the incumbent as cutoff, updating it with
    /// every optimum that passes the exact check. Returns the lowest values among the optima
    /// that fail it, or why the general search must decide.
    #[allow(clippy::type_complexity)]
    fn interval(
        &self,
        inner: &Inner,
        branch: MomentBranch,
        em: [f64; 2],
        best: &mut Option<(f64, At, Candidate)>,
        counts: &mut Counts,
    ) -> Result<Failed, Fallback> {
        let mut work: Vec<(f64, Pattern, Vec<Row>)> = Vec::new();
        for p in self.patterns(inner, branch, em) {
            let rows = self
                .pattern_rows(inner, &p, branch)
                .ok_or(Fallback::DegenerateGeometry)?;
            let bound = rows
                .iter()
                .map(|r| self.objective.bound(r))
                .fold(self.common_bound, f64::max);
            work.push((bound, p, rows));
        }
        work.sort_by(|a, b| a.0.total_cmp(&b.0));
        counts.patterns += work.len();
        let mut failed = Failed::default();
        let mut all_rows: Vec<Row> = Vec::with_capacity(self.common.len() + 12);
        for (bound, p, rows) in &work {
            let incumbent = value(best);
            if *bound >= incumbent {
                counts.pruned += 1;
                continue;
            }
            all_rows.clear();
            all_rows.extend_from_slice(&self.common);
            all_rows.extend_from_slice(rows);
            match self.objective.solve(&all_rows, incumbent) {
                dual::Outcome::Solved { z, f, .. } => {
                    counts.solved += 1;
                    let (at, candidate) = self.candidate(inner, p, &z);
                    // A point where the six equations are singular is no answer of PIM's
                    // forward solve; the general search, which works through the transfer
                    // matrix, stays off it.
                    if inner.transfer(&at).is_none() {
                        return Err(Fallback::Singular);
                    }
                    let check = inner
                        .constraints(&at)
                        .check(at.c.e, &candidate.x, &candidate.xf);
                    if check.ok() {
                        if f < incumbent {
                            *best = Some((f, at, candidate));
                        }
                    } else if !check.ratio_ok || check.linear.is_some() {
                        if failed.relaxed.is_none_or(|(g, _)| f < g) {
                            failed.relaxed = Some((f, at.c.em));
                        }
                    } else {
                        failed.energy = failed.energy.min(f);
                    }
                }
                dual::Outcome::Cutoff(_) | dual::Outcome::Infeasible => counts.pruned += 1,
                dual::Outcome::Failed => return Err(Fallback::QpFailed),
            }
        }
        Ok(failed)
    }
}

/// The best cost found so far (in the QP's value), infinite before the first.
fn value(best: &Option<(f64, At, Candidate)>) -> f64 {
    best.as_ref().map_or(f64::INFINITY, |b| b.0)
}

/// The pattern optima of an interval that fail the exact check.
#[derive(Debug, Clone, Copy)]
pub(super) struct Failed {
    /// The lowest one that fails the friction ratio (or, to round-off, a linear row), with its
    /// e_m: the relaxation of the ratios over the interval is not exact there, and a smaller
    /// interval may be.
    pub relaxed: Option<(f64, f64)>,
    /// The lowest one that fails the energy condition alone, which no interval makes convex.
    pub energy: f64,
}

impl Default for Failed {
    fn default() -> Failed {
        Failed {
            relaxed: None,
            energy: f64::INFINITY,
        }
    }
}

/// Intervals of e_m solved at most, per branch, before the general search decides. Of the
/// 5,918 branches of the 3,000-case stress corpus that the convex route decides, 5,889 close
/// within 11 intervals (the zero branch is one), 29 within 26-292. Those that do not have their optimum next to a pole of
/// mu_max (the no-slip normal impulse vanishes), where the relaxation of its sign over an
/// interval tightens only in proportion to the width while the cost is nearly flat in e_m:
/// one such branch closes after 8,536 intervals (0.6 s) with the grid search's answer.
const MAX_NODES: usize = 300;

/// The relative gap within which the free branch's branch-and-bound proves its optimum: an
/// interval closes once its lower bound is within this share of the best cost found.
const GAP: f64 = 1e-7;

/// An e_m interval and a lower bound of the cost over it (in the QP's value, cost - c0).
#[derive(Debug, Clone, Copy)]
struct Node {
    em: [f64; 2],
    bound: f64,
}

/// Solves a branch as the union of its sign patterns' QPs: in the zero branch one set of
/// patterns, exact; in the free branch a branch-and-bound over e_m intervals, whose patterns
/// relax the two ratios that depend on e_m to their range over the interval. A pattern's
/// optimum that passes the exact check is feasible; one that fails splits its interval at its
/// e_m, with its value as the children's lower bound, until no interval can beat the best.
pub(crate) fn solve(inner: &Inner, settings: &FitSettings, branch: MomentBranch) -> Verdict {
    if let Err(why) = inner.family.convex_route() {
        return Verdict::Search(why);
    }
    if !settings.search.convex {
        return Verdict::Search(Fallback::Disabled);
    }
    let form = match Formulation::new(inner, settings, branch) {
        Ok(form) => form,
        Err(why) => return Verdict::Search(why),
    };
    let mut queue: Vec<Node> = form
        .pieces(branch)
        .into_iter()
        .map(|em| Node {
            em,
            bound: form.common_bound,
        })
        .collect();
    let mut counts = Counts::default();
    let mut best: Option<(f64, At, Candidate)> = None;
    // The value a node must stay below to be worth solving: the incumbent less a relative
    // margin (none to beat while there is no incumbent; `inf - inf` would be NaN and close
    // every node).
    let cutoff = |f: f64| {
        if f.is_finite() {
            f - (GAP * (form.c0 + f).abs()).max(1e-10)
        } else {
            f64::INFINITY
        }
    };
    let mut nodes = 0;
    // The lowest pattern optimum that creates energy: the branch's optimum is proven only if
    // the best admissible point is at or below it.
    let mut energy = f64::INFINITY;
    while !queue.is_empty() {
        // Best-first.
        let i = (0..queue.len())
            .min_by(|&a, &b| queue[a].bound.total_cmp(&queue[b].bound))
            .unwrap_or(0);
        let node = queue.swap_remove(i);
        let incumbent = value(&best);
        if node.bound >= cutoff(incumbent) {
            continue;
        }
        nodes += 1;
        if nodes > MAX_NODES {
            return Verdict::Search(Fallback::NodeLimit);
        }
        let failed = match form.interval(inner, branch, node.em, &mut best, &mut counts) {
            Ok(failed) => failed,
            Err(why) => return Verdict::Search(why),
        };
        energy = energy.min(failed.energy);
        let incumbent = value(&best);
        if let Some((f, em)) = failed.relaxed.filter(|(f, _)| *f < cutoff(incumbent)) {
            // The relaxation is not exact here: split the interval (at the failing optimum's
            // e_m, unless that is next to an end).
            let [lo, hi] = node.em;
            let width = hi - lo;
            if branch == MomentBranch::Zero || width <= 1e-9 {
                return Verdict::Search(Fallback::ExactCheckFailed);
            }
            let cut = if em > lo + 0.05 * width && em < hi - 0.05 * width {
                em
            } else {
                0.5 * (lo + hi)
            };
            // A feasible point near the failing one, at its e_m held fixed (where the patterns
            // are exact), so that the incumbent follows an optimum approached towards an end
            // of the interval (a pole of mu_max) and the children can be closed.
            let probe = em.clamp(lo + 1e-9 * width, hi - 1e-9 * width);
            match form.interval(inner, branch, [probe, probe], &mut best, &mut counts) {
                Ok(failed) => energy = energy.min(failed.energy),
                Err(why) => return Verdict::Search(why),
            }
            queue.push(Node {
                em: [lo, cut],
                bound: f,
            });
            queue.push(Node {
                em: [cut, hi],
                bound: f,
            });
        }
    }
    counts.intervals = nodes;
    // A pattern whose optimum creates energy may still hold an admissible point below the
    // best one found; the grid search, which enforces the energy condition exactly, decides.
    if energy < cutoff(value(&best)) {
        return Verdict::Search(Fallback::ExactCheckFailed);
    }
    let Some((_, at, candidate)) = best else {
        return Verdict::Infeasible { counts };
    };
    // The answer is the coefficients: the forward model must carry the contact state to the
    // separation state with them. Next to a singular point of the six equations a round-off
    // in the coefficients moves the separation far (the grid search, which works through
    // the transfer matrix, reports a point it reproduces).
    let reproduced = inner.transfer(&at).is_some_and(|t| {
        let size = 1.0 + candidate.xf.amax().max(candidate.x.amax());
        (t * candidate.x - candidate.xf).amax() <= 1e-9 * size
    });
    if !reproduced {
        return Verdict::Search(Fallback::IllConditioned);
    }
    Verdict::Optimal {
        at,
        candidate,
        counts,
    }
}
