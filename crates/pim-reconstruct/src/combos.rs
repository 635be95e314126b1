//! The combinations of one start per scene vehicle: each start linearised once, each
//! combination's momentum bound, its counts of turns and its scenes' cost alone.

use crate::error::NoPoint;
use crate::impact_fit::assemble;
use crate::point::{linearised, Lin};
use crate::problem::{Reconstruction, Settings};
use pim_runout::Estimate;
use rayon::prelude::*;

/// A separation state the refinement may start from: a scene's candidate for a count of
/// turns, or another local minimum of that count's scene ([`pim_runout::Alternative`]).
pub(crate) struct Start {
    pub(crate) turns: Option<i64>,
    pub(crate) at: [f64; 3],
    /// The scene's cost there.
    pub(crate) cost: f64,
}

/// Each vehicle's starts: every candidate, then its alternatives.
fn starts_of(estimates: &[Estimate]) -> Vec<Vec<Start>> {
    estimates
        .iter()
        .map(|e| {
            let mut out: Vec<Start> = e
                .candidates
                .iter()
                .map(|c| Start {
                    turns: c.turns,
                    at: [c.separation.vx, c.separation.vy, c.separation.yaw_rate],
                    cost: c.cost,
                })
                .collect();
            for c in &e.candidates {
                out.extend(c.alternatives.iter().map(|a| Start {
                    turns: c.turns,
                    at: a.velocity,
                    cost: a.cost,
                }));
            }
            out
        })
        .collect()
}

/// The counts of turns of a combination of starts (one per vehicle).
fn counts(combination: &[usize], starts: &[Vec<Start>]) -> Vec<Option<i64>> {
    combination
        .iter()
        .enumerate()
        .map(|(v, &k)| starts[v][k].turns)
        .collect()
}

/// Every combination of one start per vehicle.
fn combinations(starts: &[Vec<Start>]) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = vec![Vec::new()];
    for e in starts {
        out = out
            .into_iter()
            .flat_map(|c| {
                (0..e.len()).map(move |i| {
                    let mut c = c.clone();
                    c.push(i);
                    c
                })
            })
            .collect();
    }
    out
}

/// `order` with, for each combination of counts of turns, its first entry before every
/// second: a combination's further starts (its scenes' other minima for the same counts) come
/// after each other combination has had its turn, so that a scene with many exact solutions
/// cannot spend the budget of work before another combination is tried at all.
pub(crate) fn counts_first<K: PartialEq>(
    order: Vec<usize>,
    counts_of: impl Fn(usize) -> K,
) -> Vec<usize> {
    let mut seen: Vec<K> = Vec::new();
    let (mut firsts, mut rest) = (Vec::new(), Vec::new());
    for i in order {
        let k = counts_of(i);
        if seen.contains(&k) {
            rest.push(i);
        } else {
            seen.push(k);
            firsts.push(i);
        }
    }
    firsts.extend(rest);
    firsts
}

/// Every combination of the scenes' starts, with what the search orders and gates them by.
pub(crate) struct Combos {
    /// Each vehicle's starts.
    pub(crate) starts: Vec<Vec<Start>>,
    /// Each start linearised (shared by every combination it is part of).
    lins: Vec<Vec<Option<Lin>>>,
    /// Each combination (a start per vehicle) and its momentum bound, or why it has none.
    pub(crate) first: Vec<(Vec<usize>, std::result::Result<f64, NoPoint>)>,
    /// Run-outs the linearisations spent.
    pub(crate) runouts: usize,
}

impl Combos {
    /// The combinations of the scenes' `estimates`: each start linearised, each combination's
    /// bound (the linearised problem under the momentum balance alone).
    pub(crate) fn new(r: &Reconstruction, settings: &Settings, estimates: &[Estimate]) -> Combos {
        let starts = starts_of(estimates);
        let mus = crate::point::stated_frictions(r);
        let lins: Vec<Vec<Option<Lin>>> = starts
            .iter()
            .enumerate()
            .map(|(i, e)| {
                e.par_iter()
                    .map(|c| {
                        linearised(r, settings, i, c.turns.unwrap_or(0), c.at, true, &mus).ok()
                    })
                    .collect()
            })
            .collect();
        let runouts = lins
            .iter()
            .flatten()
            .flatten()
            .map(|l| l.lin.runouts)
            .sum::<usize>();
        let first = combinations(&starts)
            .into_iter()
            .map(|c| {
                let start: Option<Vec<Lin>> = c
                    .iter()
                    .enumerate()
                    .map(|(v, &k)| lins[v][k].clone())
                    .collect();
                let out = match start {
                    None => Err(NoPoint::Unlinearised),
                    Some(start) => {
                        let (problem, scale, _) = assemble(r, &start, None, None);
                        Ok(crate::relax::momentum_bound(&problem) / scale)
                    }
                };
                (c, out)
            })
            .collect();
        Combos {
            starts,
            lins,
            first,
            runouts,
        }
    }

    /// How many combinations.
    pub(crate) fn len(&self) -> usize {
        self.first.len()
    }

    /// Combination `i`'s momentum bound (one that has it).
    pub(crate) fn bound(&self, i: usize) -> f64 {
        *self.first[i].1.as_ref().expect("filtered")
    }

    /// Combination `i`'s counts of turns.
    pub(crate) fn counts(&self, i: usize) -> Vec<Option<i64>> {
        counts(&self.first[i].0, &self.starts)
    }

    /// The cost of combination `i`'s scenes alone at their starts.
    pub(crate) fn scene_alone(&self, i: usize) -> f64 {
        self.first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| self.starts[v][k].cost)
            .sum()
    }

    /// Combination `i`'s starts linearised (one that has a bound).
    pub(crate) fn start(&self, i: usize) -> Vec<Lin> {
        self.first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| self.lins[v][k].clone().expect("linearised"))
            .collect()
    }

    /// The combinations with a bound, the lowest first, each combination of counts' first
    /// before any second ([`counts_first`]).
    pub(crate) fn order(&self) -> Vec<usize> {
        let mut order: Vec<usize> = (0..self.len())
            .filter(|&i| self.first[i].1.is_ok())
            .collect();
        order.sort_by(|&a, &b| self.bound(a).total_cmp(&self.bound(b)));
        counts_first(order, |i| self.counts(i))
    }
}
