//! The search: the run-out inverse's candidates per count of turns, a bound per combination
//! of counts, and the refinement of the promising ones.

use crate::combos::{counts_first, Combos};
use crate::error::{NoPoint, Result};
pub(crate) use crate::looks::Look;
use crate::looks::{candidates, steered};
use crate::outcome::{Contradiction, Found, Outcome, Status, Tried, TriedCounts};
use crate::point::Point;
use crate::problem::{Reconstruction, Settings};
use crate::refine::{probe, refine_probe, FarFirst, Probe, RefineEnd, Refined};
use pim_runout::Estimate;
use rayon::prelude::*;

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

/// What became of each combination so far: refined (or no impact), why not, where it ended.
struct Fates {
    refined: Vec<Option<RefineEnd>>,
    skipped: Vec<Option<String>>,
    ends: Vec<Option<crate::outcome::End>>,
}

impl Fates {
    /// Combination `i` refined to `x`: where it ended.
    fn record(&mut self, i: usize, x: &Refined) {
        self.refined[i] = Some(Ok((x.point.total, x.iterations, x.converged, x.abandoned)));
        self.ends[i] = Some(crate::outcome::End::of(&x.point));
    }

    /// The chi-square combination `i` was refined to (infinite where it was not).
    fn cost(&self, i: usize) -> f64 {
        match &self.refined[i] {
            Some(Ok((cost, ..))) => *cost,
            _ => f64::INFINITY,
        }
    }
}

/// A search's best point: its combination, the point, iterations, converged.
type Best = Option<(usize, Point, usize, bool)>;

/// One search: the scenes' candidates (from a scatter too, unless `look` is quick), the
/// bounds, the refinements.
pub(crate) fn search(
    r: &Reconstruction,
    settings: &Settings,
    (look, earlier): (Look, Option<&Outcome>),
    work: &crate::work::Work,
) -> Result<Outcome> {
    let scatter = look != Look::Quick;
    let estimates: Vec<Estimate> = (0..r.scene.len())
        .into_par_iter()
        .map(|i| match (look, earlier) {
            // The fine look searches again only the steered vehicles' scenes (see
            // `stages::looked_finely`); the others keep the search before's candidates.
            (Look::Fine, Some(e)) if !steered(&r.scene[i]) => Ok(e.estimates[i].clone()),
            _ => candidates(r, settings, i, (scatter, look == Look::Fine), earlier),
        })
        .collect::<Result<_>>()?;
    // 1. Each combination's bound: the linearised problem under the momentum balance alone.
    let combos = Combos::new(r, settings, &estimates);
    let mut runouts: usize = estimates
        .iter()
        .flat_map(|e| e.candidates.iter().map(|c| c.runouts))
        .sum::<usize>()
        + combos.runouts;
    let order = combos.order();
    let mut fates = Fates {
        refined: vec![None; combos.len()],
        skipped: vec![None; combos.len()],
        ends: vec![None; combos.len()],
    };
    let (probes, probed) =
        first_points(r, settings, (scatter, work), (&combos, &order), &mut fates);
    let (best, refined) = refine_each(
        r,
        settings,
        (scatter, work),
        (&combos, &order),
        probes,
        &mut fates,
    );
    runouts += probed.runouts + refined.runouts;
    let tried = one_per_counts(tried_of(&combos, &fates));
    let counted = Counted {
        runouts,
        fits: probed.fits + refined.fits,
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

/// 2. Each combination's first point (the impact fitted to its scenes linearised at their
///    starts, the run-outs simulated), from the lowest bound, while the bound could still beat
///    the lowest first point (a cost evaluated: an upper bound of the best) and within half the
///    budget left. The points, and the run-outs and fits spent.
fn first_points(
    r: &Reconstruction,
    settings: &Settings,
    (scatter, work): (bool, &crate::work::Work),
    (combos, order): (&Combos, &[usize]),
    fates: &mut Fates,
) -> (Vec<Option<Probe>>, Counted) {
    let mut spent = Counted::default();
    let mut probes: Vec<Option<Probe>> = (0..combos.len()).map(|_| None).collect();
    let probe_limit = work.spent() + work.left() / 2;
    // The lowest first point's chi-square, and whether it fits.
    let mut lowest: (f64, bool) = (f64::INFINITY, false);
    for &i in order {
        let gate = Gate {
            scatter,
            lowest_best: lowest.0,
            best_fits: lowest.1,
            refined: 0,
        };
        let bounds = (combos.bound(i), combos.scene_alone(i));
        if let Some(why) = gate.not_refined(settings, work, bounds) {
            fates.skipped[i] = Some(why);
            continue;
        }
        if work.spent() > probe_limit {
            fates.skipped[i] = Some(format!(
                "not refined: the first points of the combinations with lower bounds spent \
                 half the budget of work left ({} run-out evaluations or their equivalent; \
                 Settings::refine_work)",
                settings.refine_work
            ));
            continue;
        }
        match probe(r, settings, combos.start(i), None, work) {
            Ok(p) => {
                spent.fits += 1;
                spent.runouts += p.point.scene.iter().map(|l| l.lin.runouts).sum::<usize>();
                if p.point.total < lowest.0 {
                    lowest = (p.point.total, fits_its_data(r, &p.point));
                }
                probes[i] = Some(p);
            }
            Err(e) => fates.refined[i] = Some(Err(e)),
        }
    }
    (probes, spent)
}

/// 3. Refined from the lowest first point, one at a time (each knows the best found before
///    it), while they could still beat the best; then, where a first step overshot, from its
///    start itself (the impact fitted with the start's separation state held), while that
///    start could still be the answer. The best, and the run-outs and fits spent.
fn refine_each(
    r: &Reconstruction,
    settings: &Settings,
    (scatter, work): (bool, &crate::work::Work),
    (combos, order): (&Combos, &[usize]),
    mut probes: Vec<Option<Probe>>,
    fates: &mut Fates,
) -> (Best, Counted) {
    let mut spent = Counted::default();
    let mut by_probe: Vec<usize> = (0..combos.len()).filter(|&i| probes[i].is_some()).collect();
    by_probe.sort_by(|&a, &b| {
        let cost = |i: usize| probes[i].as_ref().map_or(f64::INFINITY, |p| p.point.total);
        cost(a).total_cmp(&cost(b))
    });
    if let Some(&lowest_bound) = order.iter().find(|&&i| probes[i].is_some()) {
        by_probe.retain(|&i| i != lowest_bound);
        by_probe.insert(0, lowest_bound);
    }
    let by_probe = counts_first(by_probe, |i| combos.counts(i));
    let mut best: Best = None;
    let mut count = 0;
    // Where a first step overshot, the start itself (`Probe::start_itself`): a second start of
    // its combination, refined once every combination has had its first, in the thorough
    // search (the quick look's budget is the thorough search's too).
    let mut second = Vec::new();
    for i in by_probe {
        let p = probes[i].take().expect("probed");
        if scatter && p.far(settings) {
            second.push((i, p.clone()));
        }
        let lowest_best = best.as_ref().map_or(f64::INFINITY, |b| b.1.total);
        let bound = combos.bound(i);
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
            if let Some(why) = gate.not_refined(settings, work, (bound, combos.scene_alone(i))) {
                fates.skipped[i] = Some(format!(
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
        spent.fits += x.fits - 1;
        spent.runouts +=
            x.point.scene.iter().map(|l| l.lin.runouts).sum::<usize>() * (x.iterations - 1);
        fates.record(i, &x);
        if best.as_ref().is_none_or(|b| x.point.total < b.1.total) {
            best = Some((i, x.point, x.iterations, x.converged));
        }
    }
    refine_starts(r, settings, work, second, fates, &mut best, &mut spent);
    (best, spent)
}

/// Refines each combination `i` again from its start itself ([`Probe::start_itself`], for the
/// probes in `second`, whose first steps overshot), where it could still be the answer: the
/// start lies within the margin of the best found, or the best found does not fit (a refusal
/// is not given while a start below it is left). The start is evaluated only where the
/// scenes' cost there (a lower bound of its point) passes that test. A lower end replaces the
/// combination's fate, and the best.
fn refine_starts(
    r: &Reconstruction,
    settings: &Settings,
    work: &crate::work::Work,
    second: Vec<(usize, Probe)>,
    fates: &mut Fates,
    best: &mut Best,
    spent: &mut Counted,
) {
    for (i, p) in second {
        if work.exhausted() {
            break;
        }
        let lowest_best = best.as_ref().map_or(f64::INFINITY, |b| b.1.total);
        let best_fits = best.as_ref().is_some_and(|b| fits_its_data(r, &b.1));
        let could = |cost: f64| !best_fits || cost <= lowest_best + settings.refine_margin;
        // The scenes' cost at the start bounds the start's own point from below.
        if !could(p.start_cost()) {
            continue;
        }
        let Some(p) = p.start_itself(r, settings, work) else {
            continue;
        };
        if !could(p.point.total) {
            continue;
        }
        let share = work.share();
        let x = refine_probe(r, settings, p, (lowest_best, FarFirst::RefineOn), &share);
        work.add(share.spent());
        spent.fits += x.fits;
        spent.runouts += x.point.scene.iter().map(|l| l.lin.runouts).sum::<usize>() * x.iterations;
        if x.point.total < fates.cost(i) {
            fates.record(i, &x);
        }
        if best.as_ref().is_none_or(|b| x.point.total < b.1.total) {
            *best = Some((i, x.point, x.iterations, x.converged));
        }
    }
}

/// What became of every combination, in their order.
fn tried_of(combos: &Combos, fates: &Fates) -> Vec<TriedCounts> {
    combos
        .first
        .iter()
        .enumerate()
        .map(|(i, (_, lin))| {
            let state = match (&fates.refined[i], lin) {
                (Some(Ok((cost, iterations, converged, abandoned))), _) => Tried::Refined {
                    cost: *cost,
                    iterations: *iterations,
                    converged: *converged,
                    abandoned: *abandoned,
                },
                (Some(Err(e)), _) | (None, Err(e)) => no_impact(e),
                (None, Ok(_)) => Tried::NotRefined {
                    reason: fates.skipped[i].clone().unwrap_or_default(),
                },
            };
            TriedCounts {
                counts: combos.counts(i),
                scene_alone: combos.scene_alone(i),
                momentum_bound: lin.as_ref().ok().copied(),
                state,
                end: fates.ends[i].clone(),
            }
        })
        .collect()
}

/// Whether `p` fits: a chi-square no larger than its count of data.
fn fits_its_data(r: &Reconstruction, p: &Point) -> bool {
    p.total <= (r.contact_data() + crate::refine::scene_data(p)) as f64
}

/// What a search counted: run-outs, impact fits and work.
#[derive(Default)]
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
