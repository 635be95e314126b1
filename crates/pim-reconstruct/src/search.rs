//! The search: the run-out inverse's candidates per count of turns, a bound per combination
//! of counts, and the refinement of the promising ones.

use crate::error::{NoPoint, Result};
use crate::outcome::{Contradiction, Found, Outcome, Status, Tried, TriedCounts};
use crate::point::{linearised, Lin, Point};
use crate::problem::{Reconstruction, Settings};
use crate::refine::{assemble, probe, refine_probe, FarFirst, Probe, RefineEnd, Refined};
use pim_runout::{Estimate, EstimateSettings};
use rayon::prelude::*;

/// Tolerance of the run-outs of the first search's scene-alone candidates.
const CANDIDATE_TOLERANCE: f64 = 1e-6;

/// The candidates of one scene vehicle from the run-out inverse.
fn candidates(
    r: &Reconstruction,
    settings: &Settings,
    vehicle: usize,
    scatter: bool,
    earlier: Option<&Outcome>,
) -> Result<Estimate> {
    let s = &r.scene[vehicle];
    // The road friction is held at its value in the reconstruction (its spread is drawn by an
    // uncertainty study), so the scene alone is searched with it held too.
    let evidence = pim_runout::Evidence {
        friction_sigma: None,
        ..s.evidence.clone()
    };
    // The candidates are starts of the refinement, which runs at full precision: the first
    // search's quick look searches them on run-outs of tolerance CANDIDATE_TOLERANCE; the
    // second, thorough one at the run-outs' own precision. A long steered or rolling run-out's
    // rest moves by tens of standard deviations per m/s, and its scene polished on run-outs of
    // 1e-6 can miss an exact solution the same search finds at 1e-10 (a braked, steered
    // vehicle's 68 m run-out: its true count's candidate at 10,130 against 0.20).
    let es = EstimateSettings {
        turns: settings.turns,
        runout: if scatter {
            settings.runout
        } else {
            settings.runout.no_finer_than(CANDIDATE_TOLERANCE)
        },
        scatter,
        // The first search looks quickly; the second (where the first answer fits worse than
        // its median) from every start and the scatter.
        quick: !scatter,
        starts: earlier.map_or_else(Vec::new, |e| answers_of(e, vehicle)),
        ..EstimateSettings::default()
    };
    Ok(pim_runout::estimate(&s.chassis, &s.pose, &evidence, &es)?)
}

/// A separation state the refinement may start from: a scene's candidate for a count of
/// turns, or another local minimum of that count's scene ([`pim_runout::Alternative`]).
struct Start {
    turns: Option<i64>,
    at: [f64; 3],
    /// The scene's cost there.
    cost: f64,
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
fn counts_first<K: PartialEq>(order: Vec<usize>, counts_of: impl Fn(usize) -> K) -> Vec<usize> {
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

/// At most this many of an earlier search's refined combinations give the scenes' inverse
/// starts from the impact's side (the lowest).
const ANSWER_STARTS: usize = 3;

/// Scene vehicle `v`'s separation states where an earlier search's lowest refinements ended,
/// with their counts of turns: starts of the scene's inverse from the impact's side.
fn answers_of(earlier: &Outcome, v: usize) -> Vec<(Option<i64>, [f64; 3])> {
    let mut refined: Vec<(f64, &TriedCounts)> = earlier
        .tried
        .iter()
        .filter_map(|t| match (&t.state, &t.end) {
            (Tried::Refined { cost, .. }, Some(_)) => Some((*cost, t)),
            _ => None,
        })
        .collect();
    refined.sort_by(|a, b| a.0.total_cmp(&b.0));
    refined
        .iter()
        .take(ANSWER_STARTS)
        .filter_map(|(_, t)| Some((t.counts[v], *t.end.as_ref()?.velocities.get(v)?)))
        .collect()
}

/// A refusal says what was searched: it rests on a search, not a proof.
pub(crate) fn searched(r: &Reconstruction, mut out: Outcome) -> Outcome {
    let refined = out
        .tried
        .iter()
        .filter(|t| matches!(t.state, Tried::Refined { .. }))
        .count();
    let what = format!(
        " (searched: {} combinations of counts of turns, {refined} refined{}; a search, not a \
         proof that no state reaches it)",
        out.tried.len(),
        if out.scattered {
            ", and again from each scene's rest curve"
        } else {
            ""
        }
    );
    if let Some(c) = out.contradiction.as_mut() {
        c.statement.push_str(&what);
        out.reason = Some(c.describe(|t| Contradiction::default_name(r, t)));
    }
    out
}

/// Where a search stands when it comes to a combination: what decides whether it is refined.
struct Gate {
    /// The second search (from the scatter).
    scatter: bool,
    /// The best chi-square found so far (infinite before the first).
    lowest_best: f64,
    /// Whether the best found fits (a chi-square no larger than its count of data).
    best_fits: bool,
    /// Combinations refined so far whose refinement ended within the margin of its bound.
    refined: usize,
}

impl Gate {
    /// Why a combination with momentum bound `bound` and scenes alone costing `scene_bound`
    /// is not refined, or `None`: it is.
    fn not_refined(
        &self,
        settings: &Settings,
        work: &crate::work::Work,
        (bound, scene_bound): (f64, f64),
    ) -> Option<String> {
        if scene_bound >= self.lowest_best {
            return Some(format!(
                "excluded: its scenes alone cost {scene_bound:.3}, not below the best found"
            ));
        }
        // The momentum bound is one of the linearised problem: where the best found does not
        // fit (a chi-square above its count of data), it is not trusted in the second search
        // (a scene whose states meeting the rest form a long curved valley is far from linear
        // over it) and the combination is refined, within the budget of work.
        let trusted = !self.scatter || self.best_fits;
        if trusted && bound > self.lowest_best + settings.refine_margin {
            return Some(format!(
                "not refined: its momentum bound {bound:.3} lies more than {} above the best \
                 found",
                settings.refine_margin
            ));
        }
        if work.exhausted() {
            return Some(format!(
                "not refined: the refinements before it spent their budget of work ({} \
                 run-out evaluations or their equivalent; Settings::refine_work)",
                settings.refine_work
            ));
        }
        (self.refined >= settings.max_refined).then(|| {
            format!(
                "not refined: {} combinations with lower bounds were, each ending within the \
                 margin of its bound",
                settings.max_refined
            )
        })
    }
}

/// A combination without a point to refine: why, in words.
fn no_impact(e: &NoPoint) -> Tried {
    Tried::NoImpact {
        reason: e.to_string(),
    }
}

/// One search: the scenes' candidates (from a scatter too, with `scatter`), the bounds, the
/// refinements.
pub(crate) fn search(
    r: &Reconstruction,
    settings: &Settings,
    (scatter, earlier): (bool, Option<&Outcome>),
    work: &crate::work::Work,
) -> Result<Outcome> {
    let estimates: Vec<Estimate> = (0..r.scene.len())
        .into_par_iter()
        .map(|i| candidates(r, settings, i, scatter, earlier))
        .collect::<Result<_>>()?;
    let mut runouts: usize = estimates
        .iter()
        .flat_map(|e| e.candidates.iter().map(|c| c.runouts))
        .sum();
    let starts = starts_of(&estimates);
    let mus = crate::point::stated_frictions(r);
    // Each start linearised once (shared by every combination it is part of).
    let lins: Vec<Vec<Option<Lin>>> = starts
        .iter()
        .enumerate()
        .map(|(i, e)| {
            e.par_iter()
                .map(|c| linearised(r, settings, i, c.turns.unwrap_or(0), c.at, true, &mus).ok())
                .collect()
        })
        .collect();
    runouts += lins
        .iter()
        .flatten()
        .flatten()
        .map(|l| l.lin.runouts)
        .sum::<usize>();
    // 1. Each combination's bound: the linearised problem under the momentum balance alone.
    let combos = combinations(&starts);
    let first: Vec<(Vec<usize>, std::result::Result<f64, NoPoint>)> = combos
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
    let mut fits = 0;
    let bound_of = |i: usize| *first[i].1.as_ref().expect("filtered");
    let counts_of = |i: usize| counts(&first[i].0, &starts);
    let mut order: Vec<usize> = (0..first.len()).filter(|&i| first[i].1.is_ok()).collect();
    order.sort_by(|&a, &b| bound_of(a).total_cmp(&bound_of(b)));
    let order = counts_first(order, counts_of);
    let scene_bound_of = |i: usize| -> f64 {
        first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| starts[v][k].cost)
            .sum()
    };
    let mut refined: Vec<Option<RefineEnd>> = vec![None; first.len()];
    let mut skipped_reason: Vec<Option<String>> = vec![None; first.len()];
    // 2. Each combination's first point (the impact fitted to its scenes linearised at their
    //    starts, the run-outs simulated), from the lowest bound, while the bound could still
    //    beat the lowest first point (a cost evaluated: an upper bound of the best) and within
    //    half the budget left.
    let mut probes: Vec<Option<Probe>> = (0..first.len()).map(|_| None).collect();
    let probe_limit = work.spent() + work.left() / 2;
    // The lowest first point's chi-square, and whether it fits.
    let mut lowest: (f64, bool) = (f64::INFINITY, false);
    for &i in &order {
        let gate = Gate {
            scatter,
            lowest_best: lowest.0,
            best_fits: lowest.1,
            refined: 0,
        };
        if let Some(why) = gate.not_refined(settings, work, (bound_of(i), scene_bound_of(i))) {
            skipped_reason[i] = Some(why);
            continue;
        }
        if work.spent() > probe_limit {
            skipped_reason[i] = Some(format!(
                "not refined: the first points of the combinations with lower bounds spent \
                 half the budget of work left ({} run-out evaluations or their equivalent; \
                 Settings::refine_work)",
                settings.refine_work
            ));
            continue;
        }
        let start: Vec<Lin> = first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| lins[v][k].clone().expect("linearised"))
            .collect();
        match probe(r, settings, start, None, work) {
            Ok(p) => {
                fits += 1;
                runouts += p.point.scene.iter().map(|l| l.lin.runouts).sum::<usize>();
                if p.point.total < lowest.0 {
                    lowest = (p.point.total, fits_its_data(r, &p.point));
                }
                probes[i] = Some(p);
            }
            Err(e) => refined[i] = Some(Err(e)),
        }
    }
    // 3. Refined from the lowest first point, one at a time (each knows the best found before
    //    it), while they could still beat the best.
    let mut by_probe: Vec<usize> = (0..first.len()).filter(|&i| probes[i].is_some()).collect();
    by_probe.sort_by(|&a, &b| {
        let cost = |i: usize| probes[i].as_ref().map_or(f64::INFINITY, |p| p.point.total);
        cost(a).total_cmp(&cost(b))
    });
    if let Some(&lowest_bound) = order.iter().find(|&&i| probes[i].is_some()) {
        by_probe.retain(|&i| i != lowest_bound);
        by_probe.insert(0, lowest_bound);
    }
    let by_probe = counts_first(by_probe, counts_of);
    let mut best: Option<(usize, Point, usize, bool)> = None;
    let mut ends: Vec<Option<crate::outcome::End>> = vec![None; first.len()];
    let mut count = 0;
    for i in by_probe {
        let p = probes[i].take().expect("probed");
        let lowest_best = best.as_ref().map_or(f64::INFINITY, |b| b.1.total);
        let bound = bound_of(i);
        let best_fits = best.as_ref().is_some_and(|b| fits_its_data(r, &b.1));
        let gate = Gate {
            scatter,
            lowest_best,
            best_fits,
            refined: count,
        };
        // The lowest first point is refined whatever the budget left (at least its first
        // point is then the search's answer).
        if best.is_some() {
            if let Some(why) = gate.not_refined(settings, work, (bound, scene_bound_of(i))) {
                skipped_reason[i] = Some(format!(
                    "{why} (its first point's chi-square: {:.3})",
                    p.point.total
                ));
                continue;
            }
        }
        // A first point far from its linearisation: refined on (restarted from the impact's
        // side) while nothing is found, so that every search has an answer; then, in the first
        // search (a quick look, followed by the second where its answer does not fit) set
        // aside; in the second, refined on while the best found does not fit (a chi-square
        // above its count of data), else set aside where far above the best.
        let far = if best.is_none() {
            FarFirst::RefineOn
        } else if !scatter {
            FarFirst::SetAside
        } else if best_fits {
            FarFirst::AboveBest
        } else {
            FarFirst::RefineOn
        };
        let share = work.share();
        let x = refine_probe(r, settings, p, (lowest_best, far), &share);
        work.add(share.spent());
        // Only a refinement whose bound held (it ended within the margin of it) counts towards
        // the cap: where the linearisation that ordered the combinations does not hold (short,
        // slow, spinning run-outs), the order says nothing of the combinations after it, and
        // they are refined too (within the budget of work).
        if x.point.total <= bound + settings.refine_margin {
            count += 1;
        }
        fits += x.fits - 1;
        runouts += x.point.scene.iter().map(|l| l.lin.runouts).sum::<usize>() * (x.iterations - 1);
        refined[i] = Some(Ok((x.point.total, x.iterations, x.converged, x.abandoned)));
        ends[i] = Some(crate::outcome::End::of(&x.point));
        if best.as_ref().is_none_or(|b| x.point.total < b.1.total) {
            best = Some((i, x.point, x.iterations, x.converged));
        }
    }
    let all: Vec<TriedCounts> = first
        .iter()
        .enumerate()
        .map(|(i, (c, lin))| {
            let counts = counts_of(i);
            let scene_alone = c.iter().enumerate().map(|(v, &k)| starts[v][k].cost).sum();
            let state = match (&refined[i], lin) {
                (Some(Ok((cost, iterations, converged, abandoned))), _) => Tried::Refined {
                    cost: *cost,
                    iterations: *iterations,
                    converged: *converged,
                    abandoned: *abandoned,
                },
                (Some(Err(e)), _) | (None, Err(e)) => no_impact(e),
                (None, Ok(_)) => Tried::NotRefined {
                    reason: skipped_reason[i].clone().unwrap_or_default(),
                },
            };
            TriedCounts {
                counts,
                scene_alone,
                momentum_bound: lin.as_ref().ok().copied(),
                state,
                end: ends[i].clone(),
            }
        })
        .collect();
    let tried = one_per_counts(all);
    let counted = Counted {
        runouts,
        fits,
        work: work.spent(),
    };
    Ok(outcome_of(
        r,
        best.map(|(_, p, i, c)| (p, i, c)),
        (tried, estimates),
        counted,
        scatter,
    ))
}

/// Whether `p` fits: a chi-square no larger than its count of data.
fn fits_its_data(r: &Reconstruction, p: &Point) -> bool {
    p.total <= (r.contact_data() + crate::refine::scene_data(p)) as f64
}

/// What a search counted: run-outs, impact fits and work.
struct Counted {
    runouts: usize,
    fits: usize,
    work: u64,
}

/// A search's outcome from its best point (with its iterations and convergence), what it
/// tried and the scenes' estimates.
fn outcome_of(
    r: &Reconstruction,
    best: Option<(Point, usize, bool)>,
    (tried, estimates): (Vec<TriedCounts>, Vec<Estimate>),
    counted: Counted,
    scatter: bool,
) -> Outcome {
    let Counted {
        runouts,
        fits,
        work,
    } = counted;
    let Some((point, iterations, converged)) = best else {
        let reason = tried
            .iter()
            .find_map(|t| match &t.state {
                Tried::NoImpact { reason } => Some(reason.clone()),
                _ => None,
            })
            .unwrap_or_else(|| "no combination of counts of turns was searched".into());
        return Outcome {
            status: Status::NoSolution,
            reason: Some(format!(
                "none found: no impact fit from the scenes' own separation states was \
                 admissible for any of the {} combinations of counts of turns tried (a local \
                 search, not a proof that none exists); the first reason: {reason}",
                tried.len()
            )),
            contradiction: None,
            best: None,
            tried,
            estimates,
            runouts,
            fits,
            work,
            first_work: work,
            scattered: scatter,
        };
    };
    let found = Found::new(r, point, iterations, converged);
    let contradiction = crate::outcome::contradiction(r, &found);
    let status = if contradiction.is_some() {
        Status::Inconsistent
    } else {
        Status::Found
    };
    Outcome {
        status,
        reason: contradiction
            .as_ref()
            .map(|c| c.describe(|t| Contradiction::default_name(r, t))),
        contradiction,
        best: Some(found),
        tried,
        estimates,
        runouts,
        fits,
        work,
        first_work: work,
        scattered: scatter,
    }
}

/// The reconstruction again with changed evidence or inputs (one draw of an uncertainty
/// study): each combination of counts that `nominal` refined to within `margin` of its best is
/// refined again from where it ended there, and the best is kept. No scene-alone search, no
/// other combinations: the counts of turns are those the nominal reconstruction found.
///
/// # Errors
/// Input the search cannot use.
pub fn redo(
    r: &Reconstruction,
    settings: &Settings,
    nominal: &Outcome,
    margin: f64,
) -> Result<Option<Found>> {
    r.check()?;
    let Some(best) = &nominal.best else {
        return Ok(None);
    };
    let mut found: Option<Refined> = None;
    let work = crate::work::Work::new(settings.refine_work);
    for t in &nominal.tried {
        let (Tried::Refined { cost, .. }, Some(end)) = (&t.state, &t.end) else {
            continue;
        };
        if *cost > best.chi_square + margin {
            continue;
        }
        let Ok(start) = end.linearised(r, settings, &t.counts) else {
            continue;
        };
        let lowest = found.as_ref().map_or(f64::INFINITY, |f| f.point.total);
        let Ok(first) = probe(r, settings, start, Some(end.state), &work) else {
            continue;
        };
        let x = refine_probe(r, settings, first, (lowest, FarFirst::AboveBest), &work);
        if x.point.total < lowest {
            found = Some(x);
        }
    }
    Ok(found.map(|x| Found::new(r, x.point, x.iterations, x.converged)))
}

/// [`crate::follow`] without its fallback: `previous`'s outcome with the answer its combinations give
/// refined again from where they ended ([`redo`]), or `None` where none of them refines (no
/// search is run then).
///
/// # Errors
/// Input the search cannot use.
pub fn refined_from(
    r: &Reconstruction,
    settings: &Settings,
    previous: &Outcome,
) -> Result<Option<Outcome>> {
    let Some(found) = redo(r, settings, previous, settings.refine_margin)? else {
        return Ok(None);
    };
    let mut out = previous.clone();
    answered(r, &mut out, found);
    Ok(Some(out))
}

/// `out` with `found` as its answer: its status, and the contradiction where the evidence
/// refuses it.
pub(crate) fn answered(r: &Reconstruction, out: &mut Outcome, found: Found) {
    let contradiction = crate::outcome::contradiction(r, &found);
    out.status = if contradiction.is_some() {
        Status::Inconsistent
    } else {
        Status::Found
    };
    out.reason = contradiction
        .as_ref()
        .map(|c| c.describe(|t| Contradiction::default_name(r, t)));
    out.contradiction = contradiction;
    out.best = Some(found);
}

/// One entry per combination of counts of turns, in the order they first appear: where several
/// starts of the same counts were tried, the one refined to the lowest cost (else the one with
/// the lowest momentum bound), its scene-alone cost the lowest of them.
fn one_per_counts(all: Vec<TriedCounts>) -> Vec<TriedCounts> {
    let rank = |t: &TriedCounts| match t.state {
        Tried::Refined { cost, .. } => (0, cost),
        Tried::NotRefined { .. } => (1, t.momentum_bound.unwrap_or(f64::INFINITY)),
        Tried::NoImpact { .. } => (2, f64::INFINITY),
    };
    let mut out: Vec<TriedCounts> = Vec::new();
    for t in all {
        match out.iter_mut().find(|o| o.counts == t.counts) {
            None => out.push(t),
            Some(o) => {
                let scene = o.scene_alone.min(t.scene_alone);
                let (a, b) = (rank(o), rank(&t));
                if b.0 < a.0 || (b.0 == a.0 && b.1 < a.1) {
                    *o = t;
                }
                o.scene_alone = scene;
            }
        }
    }
    out
}
