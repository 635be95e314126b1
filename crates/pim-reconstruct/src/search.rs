//! The search: the run-out inverse's candidates per count of turns, a bound per combination
//! of counts, and the refinement of the promising ones.

use crate::error::Result;
use crate::outcome::{Contradiction, Found, Outcome, Status, Tried, TriedCounts};
use crate::point::{linearised, Lin, Point};
use crate::problem::{Reconstruction, Settings};
use crate::refine::{assemble, refine, FarFirst, RefineEnd, Refined};
use pim_runout::{Estimate, EstimateSettings};
use rayon::prelude::*;

/// Tolerance of the run-outs of the scene-alone candidates.
const CANDIDATE_TOLERANCE: f64 = 1e-6;

/// The candidates of one scene vehicle from the run-out inverse.
fn candidates(
    r: &Reconstruction,
    settings: &Settings,
    vehicle: usize,
    scatter: bool,
) -> Result<Estimate> {
    let s = &r.scene[vehicle];
    // The road friction is held at its value in the reconstruction (its spread is drawn by an
    // uncertainty study), so the scene alone is searched with it held too.
    let evidence = pim_runout::Evidence {
        friction_sigma: None,
        ..s.evidence.clone()
    };
    // The candidates are starts of the refinement, which runs at full precision: they are
    // searched on run-outs of tolerance CANDIDATE_TOLERANCE.
    let es = EstimateSettings {
        turns: settings.turns,
        runout: pim_runout::Settings {
            rtol: CANDIDATE_TOLERANCE.max(settings.runout.rtol),
            atol: CANDIDATE_TOLERANCE.max(settings.runout.atol),
            ..settings.runout
        },
        scatter,
        // The first search looks quickly; the second (where the first answer fits worse than
        // its median) from every start and the scatter.
        quick: !scatter,
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

/// Reconstructs the collision: see the crate docs.
///
/// # Errors
/// Input the search cannot use ([`crate::ReconstructError`]). A scene no admissible impact
/// reaches is an [`Outcome`] with [`Status::NoSolution`].
pub fn reconstruct(r: &Reconstruction, settings: &Settings) -> Result<Outcome> {
    r.check()?;
    // One budget of work for both searches. The first may spend half of it: a first search
    // that refines many combinations far from their scenes (each one's run-outs long and
    // slow) must not leave the second, from the scatter, nothing; where the first answer
    // fits, the second is not needed.
    let work = crate::refine::Work::new(settings.refine_work / 2);
    let first = search(r, settings, false, &work)?;
    let fits_well = first.best.as_ref().is_some_and(|b| {
        pim_fit::ChiSquare::p_value_of(b.degrees_of_freedom, b.chi_square)
            .is_some_and(|p| p >= settings.scatter_below_p)
    });
    if fits_well {
        return Ok(searched(r, first));
    }
    // The second search refines with at most as much work again as the first spent (and at
    // least a quarter of the budget), within what is left: a bound of its time on evidence
    // whose impact fits or run-outs are slow.
    let spent = work.spent();
    let limit = (spent + spent.max(settings.refine_work / 4)).min(settings.refine_work);
    let work = crate::refine::Work::new(limit);
    work.add(spent);
    let second = search(r, settings, true, &work)?;
    let cost = |o: &Outcome| o.best.as_ref().map_or(f64::INFINITY, |b| b.chi_square);
    let (runouts, fits, work) = (
        first.runouts + second.runouts,
        first.fits + second.fits,
        work.spent(),
    );
    let mut out = if cost(&second) <= cost(&first) {
        second
    } else {
        first
    };
    out.runouts = runouts;
    out.fits = fits;
    out.work = work;
    out.first_work = spent;
    out.scattered = true;
    if out.status == Status::Inconsistent {
        continue_best(r, settings, &mut out);
    }
    Ok(searched(r, out))
}

/// The scene's standard deviations widened `k` times (rest positions, headings and marks).
fn widened(r: &Reconstruction, k: f64) -> Reconstruction {
    let mut w = r.clone();
    for s in &mut w.scene {
        if let Some(rest) = s.evidence.rest.as_mut() {
            rest.sigma_xy = rest.sigma_xy.map(|x| x * k);
            rest.sigma_heading *= k;
        }
        for m in &mut s.evidence.marks {
            m.sigma *= k;
        }
    }
    w
}

/// The widenings of the scene's standard deviations a continuation passes through, the last
/// the evidence as given.
const CONTINUATION: [f64; 5] = [16.0, 8.0, 4.0, 2.0, 1.0];

/// A refused answer searched once more before it is refused: the best combination of counts
/// refined by continuation, from its end, first with the scene's standard deviations widened
/// sixteen times (the impact and the contact evidence lead, the scene only pulls), then
/// narrowed step by step to the evidence as given, each stage refined from the one before. A
/// refinement that crawled in a curved valley of the full evidence, or stopped in a basin the
/// contact evidence does not want, is led around it. The lower of the two answers is kept.
fn continue_best(r: &Reconstruction, settings: &Settings, out: &mut Outcome) {
    let Some(best) = out.best.as_ref() else {
        return;
    };
    let Some(i) = out.tried.iter().position(|t| {
        matches!(t.state, Tried::Refined { cost, .. } if (cost - best.chi_square).abs() <= 1e-9 * (1.0 + cost))
    }) else {
        return;
    };
    let (Some(end), counts) = (out.tried[i].end.clone(), out.tried[i].counts.clone()) else {
        return;
    };
    // What the two searches left of the one budget of work.
    let work = crate::refine::Work::new(settings.refine_work.saturating_sub(out.work));
    if work.exhausted() {
        return;
    }
    let mut at = end;
    let mut last = None;
    for k in CONTINUATION {
        let rk = widened(r, k);
        let mus = crate::point::stated_frictions(&rk);
        let start: Result<Vec<Lin>> = at
            .iter()
            .enumerate()
            .map(|(v, a)| linearised(&rk, settings, v, counts[v].unwrap_or(0), *a, true, &mus))
            .collect();
        let Ok(start) = start else { return };
        let Ok(x) = refine(
            &rk,
            settings,
            start,
            (f64::INFINITY, FarFirst::RefineOn),
            &work,
        ) else {
            return;
        };
        at = x.point.scene.iter().map(|l| l.at).collect();
        out.fits += x.fits;
        // Narrowing the scene's deviations only raises the minimum (each scene term's weight
        // grows, the others stay): a stage already refused cannot lead to an answer.
        if Found::new(&rk, x.point.clone(), x.iterations, x.converged).refused() {
            out.work += work.spent();
            return;
        }
        // The last stage is the evidence as given.
        last = Some(x);
    }
    out.work += work.spent();
    let Some(x) = last else { return };
    if x.point.total >= best.chi_square {
        return;
    }
    out.tried[i].state = Tried::Refined {
        cost: x.point.total,
        iterations: x.iterations,
        converged: x.converged,
        abandoned: false,
    };
    out.tried[i].end = Some(x.point.scene.iter().map(|l| l.at).collect());
    answered(r, out, Found::new(r, x.point, x.iterations, x.converged));
}

/// A refusal says what was searched: it rests on a search, not a proof.
fn searched(r: &Reconstruction, mut out: Outcome) -> Outcome {
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

/// One search: the scenes' candidates (from a scatter too, with `scatter`), the bounds, the
/// refinements.
fn search(
    r: &Reconstruction,
    settings: &Settings,
    scatter: bool,
    work: &crate::refine::Work,
) -> Result<Outcome> {
    let estimates: Vec<Estimate> = (0..r.scene.len())
        .into_par_iter()
        .map(|i| candidates(r, settings, i, scatter))
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
    let first: Vec<(Vec<usize>, std::result::Result<f64, String>)> = combos
        .into_iter()
        .map(|c| {
            let start: Option<Vec<Lin>> = c
                .iter()
                .enumerate()
                .map(|(v, &k)| lins[v][k].clone())
                .collect();
            let out = match start {
                None => Err("a candidate's run-out could not be linearised".to_string()),
                Some(start) => {
                    let (problem, scale, _) = assemble(r, &start, None, None);
                    Ok(crate::relax::momentum_bound(&problem) / scale)
                }
            };
            (c, out)
        })
        .collect();
    let mut fits = 0;
    let mut order: Vec<usize> = (0..first.len()).filter(|&i| first[i].1.is_ok()).collect();
    order.sort_by(|&a, &b| {
        let cost = |i: usize| *first[i].1.as_ref().expect("filtered");
        cost(a).total_cmp(&cost(b))
    });
    // 2. Refined from the lowest bound, one at a time (each knows the best found before it),
    //    while they could still beat the best.
    let mut best: Option<(usize, Point, usize, bool)> = None;
    let mut ends: Vec<Option<Vec<[f64; 3]>>> = vec![None; first.len()];
    let mut refined: Vec<Option<RefineEnd>> = vec![None; first.len()];
    let mut skipped_reason: Vec<Option<String>> = vec![None; first.len()];
    let mut count = 0;
    for &i in &order {
        let lowest_best = best.as_ref().map_or(f64::INFINITY, |b| b.1.total);
        let bound = *first[i].1.as_ref().expect("filtered");
        let scene_bound: f64 = first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| starts[v][k].cost)
            .sum();
        if scene_bound >= lowest_best {
            skipped_reason[i] = Some(format!(
                "excluded: its scenes alone cost {scene_bound:.3}, not below the best found"
            ));
            continue;
        }
        if bound > lowest_best + settings.refine_margin {
            skipped_reason[i] = Some(format!(
                "not refined: its momentum bound {bound:.3} lies more than {} above the best \
                 found",
                settings.refine_margin
            ));
            continue;
        }
        if work.exhausted() {
            skipped_reason[i] = Some(format!(
                "not refined: the refinements before it spent their budget of work ({} \
                 run-out evaluations or their equivalent; Settings::refine_work)",
                settings.refine_work
            ));
            continue;
        }
        if count >= settings.max_refined {
            skipped_reason[i] = Some(format!(
                "not refined: {} combinations with lower bounds were, each ending within the \
                 margin of its bound",
                settings.max_refined
            ));
            continue;
        }
        let start: Vec<Lin> = first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| lins[v][k].clone().expect("linearised"))
            .collect();
        // A first point far from its linearisation: refined on (restarted from the impact's
        // side) while nothing is found, so that every search has an answer; then, in the first
        // search (a quick look, followed by the second where its answer does not fit) set
        // aside; in the second, refined on while the best found does not fit (a chi-square
        // above its count of data), else set aside where far above the best.
        let fitting = |b: &(usize, Point, usize, bool)| {
            b.1.total <= (r.contact_data() + crate::refine::scene_data(Some(&b.1))) as f64
        };
        let far = if best.is_none() {
            FarFirst::RefineOn
        } else if !scatter {
            FarFirst::SetAside
        } else if best.as_ref().is_some_and(fitting) {
            FarFirst::AboveBest
        } else {
            FarFirst::RefineOn
        };
        match refine(r, settings, start, (lowest_best, far), work) {
            Ok(x) => {
                // Only a refinement whose bound held (it ended within the margin of it) counts
                // towards the cap: where the linearisation that ordered the combinations does
                // not hold (short, slow, spinning run-outs), the order says nothing of the
                // combinations after it, and they are refined too (within the budget of work).
                if x.point.total <= bound + settings.refine_margin {
                    count += 1;
                }
                fits += x.fits;
                runouts +=
                    x.point.scene.iter().map(|l| l.lin.runouts).sum::<usize>() * x.iterations;
                refined[i] = Some(Ok((x.point.total, x.iterations, x.converged, x.abandoned)));
                ends[i] = Some(x.point.scene.iter().map(|l| l.at).collect());
                if best.as_ref().is_none_or(|b| x.point.total < b.1.total) {
                    best = Some((i, x.point, x.iterations, x.converged));
                }
            }
            Err(e) => refined[i] = Some(Err(e)),
        }
    }
    let all: Vec<TriedCounts> = first
        .iter()
        .enumerate()
        .map(|(i, (c, lin))| {
            let counts = c
                .iter()
                .enumerate()
                .map(|(v, &k)| starts[v][k].turns)
                .collect();
            let scene_alone = c.iter().enumerate().map(|(v, &k)| starts[v][k].cost).sum();
            let state = match (&refined[i], lin) {
                (Some(Ok((cost, iterations, converged, abandoned))), _) => Tried::Refined {
                    cost: *cost,
                    iterations: *iterations,
                    converged: *converged,
                    abandoned: *abandoned,
                },
                (Some(Err(e)), _) | (None, Err(e)) => Tried::NoImpact { reason: e.clone() },
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
    let Some((_, point, iterations, converged)) = best else {
        let reason = tried
            .iter()
            .find_map(|t| match &t.state {
                Tried::NoImpact { reason } => Some(reason.clone()),
                _ => None,
            })
            .unwrap_or_else(|| "no combination of counts of turns was searched".into());
        return Ok(Outcome {
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
            work: work.spent(),
            first_work: work.spent(),
            scattered: scatter,
        });
    };
    let found = Found::new(r, point, iterations, converged);
    let contradiction = crate::outcome::contradiction(r, &found);
    let status = if contradiction.is_some() {
        Status::Inconsistent
    } else {
        Status::Found
    };
    Ok(Outcome {
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
        work: work.spent(),
        first_work: work.spent(),
        scattered: scatter,
    })
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
    let work = crate::refine::Work::new(settings.refine_work);
    for t in &nominal.tried {
        let (Tried::Refined { cost, .. }, Some(end)) = (&t.state, &t.end) else {
            continue;
        };
        if *cost > best.chi_square + margin {
            continue;
        }
        let start: std::result::Result<Vec<Lin>, _> = end
            .iter()
            .enumerate()
            .map(|(v, at)| {
                linearised(
                    r,
                    settings,
                    v,
                    t.counts[v].unwrap_or(0),
                    *at,
                    true,
                    &crate::point::stated_frictions(r),
                )
            })
            .collect();
        let Ok(start) = start else { continue };
        let lowest = found.as_ref().map_or(f64::INFINITY, |f| f.point.total);
        if let Ok(x) = refine(r, settings, start, (lowest, FarFirst::AboveBest), &work) {
            if x.point.total < lowest {
                found = Some(x);
            }
        }
    }
    Ok(found.map(|x| Found::new(r, x.point, x.iterations, x.converged)))
}

/// The reconstruction of evidence a little changed from that of `previous` (a rest position
/// dragged on the plan): the combinations `previous` refined to within
/// [`Settings::refine_margin`] of its best are refined again from where they ended ([`redo`]),
/// the lowest kept; the scenes are not searched again, and the outcome keeps `previous`'s list
/// of the combinations compared. A fast answer to follow a change with (a few Gauss-Newton
/// steps), not a search: where none of them refines, the whole search runs.
///
/// # Errors
/// Input the search cannot use.
pub fn follow(r: &Reconstruction, settings: &Settings, previous: &Outcome) -> Result<Outcome> {
    match refined_from(r, settings, previous)? {
        Some(out) => Ok(out),
        None => reconstruct(r, settings),
    }
}

/// [`follow`] without its fallback: `previous`'s outcome with the answer its combinations give
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
fn answered(r: &Reconstruction, out: &mut Outcome, found: Found) {
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
