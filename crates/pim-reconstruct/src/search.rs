//! The search: the run-out inverse's candidates per count of turns, a bound per combination
//! of counts, and the refinement of the promising ones.

use crate::error::Result;
use crate::outcome::{Contradiction, Found, Outcome, Status, Tried, TriedCounts};
use crate::point::{linearised, Lin, Point};
use crate::problem::{Reconstruction, Settings};
use crate::refine::{assemble, refine, RefineEnd, Refined};
use pim_runout::{Estimate, EstimateSettings};
use rayon::prelude::*;

/// Tolerance of the run-outs of the scene-alone candidates.
const CANDIDATE_TOLERANCE: f64 = 1e-7;

/// The candidates of one scene vehicle from the run-out inverse.
fn candidates(r: &Reconstruction, settings: &Settings, vehicle: usize) -> Result<Estimate> {
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
        ..EstimateSettings::default()
    };
    Ok(pim_runout::estimate(&s.chassis, &s.pose, &evidence, &es)?)
}

/// Every combination of one candidate per vehicle.
fn combinations(estimates: &[Estimate]) -> Vec<Vec<usize>> {
    let mut out: Vec<Vec<usize>> = vec![Vec::new()];
    for e in estimates {
        out = out
            .into_iter()
            .flat_map(|c| {
                (0..e.candidates.len()).map(move |i| {
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
    let estimates: Vec<Estimate> = (0..r.scene.len())
        .into_par_iter()
        .map(|i| candidates(r, settings, i))
        .collect::<Result<_>>()?;
    let mut runouts: usize = estimates
        .iter()
        .flat_map(|e| e.candidates.iter().map(|c| c.runouts))
        .sum();
    // Each candidate linearised once (shared by every combination it is part of).
    let lins: Vec<Vec<Option<Lin>>> = estimates
        .par_iter()
        .enumerate()
        .map(|(i, e)| {
            e.candidates
                .iter()
                .map(|c| {
                    let s = &c.separation;
                    linearised(
                        r,
                        settings,
                        i,
                        c.turns.unwrap_or(0),
                        [s.vx, s.vy, s.yaw_rate],
                        true,
                    )
                    .ok()
                })
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
    let combos = combinations(&estimates);
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
                    let (problem, scale) = assemble(r, &start, None);
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
    let work = crate::refine::Work::new(settings.refine_work);
    for &i in &order {
        let lowest_best = best.as_ref().map_or(f64::INFINITY, |b| b.1.total);
        let bound = *first[i].1.as_ref().expect("filtered");
        let scene_bound: f64 = first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| estimates[v].candidates[k].cost)
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
                "not refined: {} combinations with lower bounds were",
                settings.max_refined
            ));
            continue;
        }
        count += 1;
        let start: Vec<Lin> = first[i]
            .0
            .iter()
            .enumerate()
            .map(|(v, &k)| lins[v][k].clone().expect("linearised"))
            .collect();
        match refine(r, settings, start, lowest_best, &work) {
            Ok(x) => {
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
    let tried: Vec<TriedCounts> = first
        .iter()
        .enumerate()
        .map(|(i, (c, lin))| {
            let counts = c
                .iter()
                .enumerate()
                .map(|(v, &k)| estimates[v].candidates[k].turns)
                .collect();
            let scene_alone = c
                .iter()
                .enumerate()
                .map(|(v, &k)| estimates[v].candidates[k].cost)
                .sum();
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
            .map(|(v, at)| linearised(r, settings, v, t.counts[v].unwrap_or(0), *at, true))
            .collect();
        let Ok(start) = start else { continue };
        let lowest = found.as_ref().map_or(f64::INFINITY, |f| f.point.total);
        if let Ok(x) = refine(r, settings, start, lowest, &work) {
            if x.point.total < lowest {
                found = Some(x);
            }
        }
    }
    Ok(found.map(|x| Found::new(r, x.point, x.iterations, x.converged)))
}
