//! The search: the run-out inverse's candidates per count of turns, one linearised impact fit
//! per combination of counts, and Gauss-Newton with the exact impact fit inside from the best.

use crate::error::Result;
use crate::outcome::{Found, Outcome, SceneFit, Status, Tried, TriedCounts};
use crate::problem::{Reconstruction, SceneVehicle, Settings};
use pim_core::Velocities;
use pim_fit::{
    fit, state_vector, Combination, FitProblem, Knowledge, MomentBranch, Solution,
    Status as FitStatus,
};
use pim_runout::{linearise, Estimate, EstimateSettings, Linearised, Motion};
use rayon::prelude::*;

/// The scene of one vehicle linearised at one separation state.
#[derive(Debug, Clone)]
pub(crate) struct Lin {
    /// Index of the vehicle in [`Reconstruction::scene`].
    pub(crate) vehicle: usize,
    /// Its count of turns (0 when the rest heading is not given).
    pub(crate) turns: i64,
    /// The separation velocity `(vx, vy, yaw_rate)` linearised at.
    pub(crate) at: [f64; 3],
    pub(crate) lin: Linearised,
}

/// A point of the search: an admissible impact and its scene.
#[derive(Debug, Clone)]
pub(crate) struct Point {
    pub(crate) branch: MomentBranch,
    pub(crate) solution: Solution,
    pub(crate) certificate: pim_fit::Certificate,
    pub(crate) contact: f64,
    pub(crate) scene: Vec<Lin>,
    pub(crate) total: f64,
}

/// The separation velocity of scene vehicle `v` in a state.
fn velocity_of(state: &Velocities, s: &SceneVehicle) -> [f64; 3] {
    let v = if s.id.index() == 0 {
        state.vehicle1
    } else {
        state.vehicle2
    };
    [v.vx, v.vy, v.omega]
}

fn linearised(
    r: &Reconstruction,
    settings: &Settings,
    vehicle: usize,
    turns: i64,
    at: [f64; 3],
    jacobian: bool,
) -> Result<Lin> {
    let s = &r.scene[vehicle];
    let start = Motion {
        vx: at[0],
        vy: at[1],
        yaw_rate: at[2],
        ..s.pose
    };
    let lin = linearise(
        &s.chassis,
        &start,
        &s.evidence,
        turns,
        &settings.runout,
        jacobian,
    )?;
    Ok(Lin {
        vehicle,
        turns,
        at,
        lin,
    })
}

/// The impact fit with each scene linearised (rows in chi-square units, weight 1 each) and,
/// with `damping`, Marquardt's rows that keep the separation state near the current one. Every
/// weight is scaled by one factor into (0, 1]; the fit's cost over that factor is the
/// chi-square of the linearised problem.
fn assemble(r: &Reconstruction, lins: &[Lin], damping: Option<(f64, &[Lin])>) -> (FitProblem, f64) {
    let unit = r.unit.unwrap_or(1.0);
    let mut problem = r.contact.clone();
    // Chi-square weights first.
    for c in problem.components.iter_mut() {
        if let Knowledge::Estimated { weight, .. } = c {
            *weight /= unit;
        }
    }
    for o in problem.observations.iter_mut() {
        o.weight /= unit;
    }
    for c in problem.combinations.iter_mut() {
        c.weight /= unit;
    }
    for l in lins {
        let base = 6 + 3 * r.scene[l.vehicle].id.index();
        let j = l
            .lin
            .jacobian
            .as_ref()
            .expect("linearised with its Jacobian");
        for i in 0..j.nrows() {
            let mut row = pim_fit::Vector12::zeros();
            let mut target = -l.lin.weighted[i];
            for c in 0..3 {
                row[base + c] = j[(i, c)];
                target += j[(i, c)] * l.at[c];
            }
            // A residual that no separation velocity moves adds only a constant.
            let norm = row.norm();
            if norm > 1e-12 {
                problem.combinations.push(Combination {
                    row: row / norm,
                    value: target / norm,
                    weight: norm * norm,
                });
            }
        }
    }
    if let Some((lambda, around)) = damping {
        for l in around {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            let j = l
                .lin
                .jacobian
                .as_ref()
                .expect("linearised with its Jacobian");
            let jtj = j.transpose() * j;
            let largest = (0..3).map(|c| jtj[(c, c)]).fold(0.0, f64::max).max(1e-12);
            for c in 0..3 {
                let mut row = pim_fit::Vector12::zeros();
                row[base + c] = 1.0;
                problem.combinations.push(Combination {
                    row,
                    value: l.at[c],
                    weight: lambda * jtj[(c, c)].max(1e-6 * largest),
                });
            }
        }
    }
    let largest = problem
        .components
        .iter()
        .filter_map(|c| match c {
            Knowledge::Estimated { weight, .. } => Some(*weight),
            _ => None,
        })
        .chain(problem.observations.iter().map(|o| o.weight))
        .chain(problem.combinations.iter().map(|c| c.weight))
        .fold(0.0, f64::max);
    let scale = if largest > 0.0 { 1.0 / largest } else { 1.0 };
    for c in problem.components.iter_mut() {
        if let Knowledge::Estimated { weight, .. } = c {
            *weight = (*weight * scale).max(f64::MIN_POSITIVE);
        }
    }
    for o in problem.observations.iter_mut() {
        o.weight = (o.weight * scale).max(f64::MIN_POSITIVE);
    }
    for c in problem.combinations.iter_mut() {
        c.weight = (c.weight * scale).max(f64::MIN_POSITIVE);
    }
    (problem, scale)
}

/// One impact fit of the linearised problem: the best optimal branch, or why there is none.
fn fit_once(
    r: &Reconstruction,
    settings: &Settings,
    lins: &[Lin],
    damping: Option<(f64, &[Lin])>,
) -> std::result::Result<(MomentBranch, Solution, pim_fit::Certificate, f64), String> {
    let (problem, scale) = assemble(r, lins, damping);
    let report = fit(&problem, &settings.fit).map_err(|e| e.to_string())?;
    let best = report.best_branch().ok_or_else(|| {
        report
            .branches
            .iter()
            .find_map(|b| b.reason.as_ref().map(|x| x.to_string()))
            .unwrap_or_else(|| "no admissible impact".into())
    })?;
    match (&best.status, &best.solution) {
        (FitStatus::Optimal, Some(s)) => Ok((
            best.moment,
            s.clone(),
            best.certificate.clone(),
            s.cost / scale,
        )),
        _ => Err(format!("the impact fit ended {:?}", best.status)),
    }
}

/// Evaluates the true cost of a fit's answer: the contact evidence and each scene's run-out.
fn evaluate(
    r: &Reconstruction,
    settings: &Settings,
    counts: &[i64],
    branch: MomentBranch,
    solution: Solution,
    certificate: pim_fit::Certificate,
) -> Option<Point> {
    let u = state_vector(&solution.initial, &solution.separation);
    let contact = r.contact_chi_square(&u);
    let scene: Option<Vec<Lin>> = r
        .scene
        .par_iter()
        .enumerate()
        .map(|(i, s)| {
            linearised(
                r,
                settings,
                i,
                counts[i],
                velocity_of(&solution.separation, s),
                false,
            )
            .ok()
        })
        .collect();
    let scene = scene?;
    let total = contact + scene.iter().map(|l| l.lin.cost).sum::<f64>();
    Some(Point {
        branch,
        solution,
        certificate,
        contact,
        scene,
        total,
    })
}

/// Gauss-Newton (Levenberg-Marquardt on the separation state) for one combination of counts,
/// from the scene linearised at `start`.
pub(crate) fn refine(
    r: &Reconstruction,
    settings: &Settings,
    start: Vec<Lin>,
    best_so_far: f64,
) -> std::result::Result<Refined, String> {
    let counts: Vec<i64> = start.iter().map(|l| l.turns).collect();
    let mut lins = start;
    let mut current: Option<Point> = None;
    let mut lambda = 0.0;
    let mut fits = 0;
    let mut iterations = 0;
    let mut converged = false;
    let mut abandoned = false;
    while iterations < settings.max_iterations {
        iterations += 1;
        let damping = (current.is_some() && lambda > 0.0).then_some((lambda, lins.as_slice()));
        fits += 1;
        let trial = fit_once(r, settings, &lins, damping).and_then(|(b, s, c, _)| {
            evaluate(r, settings, &counts, b, s, c)
                .ok_or_else(|| "the run-out of the fitted separation state failed".to_string())
        });
        let accepted = match (&trial, &current) {
            (Ok(p), Some(c)) => p.total < c.total,
            (Ok(_), None) => true,
            (Err(e), None) => return Err(e.clone()),
            (Err(_), Some(_)) => false,
        };
        if accepted {
            let p = trial.expect("accepted");
            let gain = current
                .as_ref()
                .map_or(f64::INFINITY, |c| c.total - p.total);
            let step = current.as_ref().map_or(f64::INFINITY, |c| {
                p.scene
                    .iter()
                    .zip(&c.scene)
                    .map(|(a, b)| {
                        (0..3)
                            .map(|k| (a.at[k] - b.at[k]).abs())
                            .fold(0.0, f64::max)
                    })
                    .fold(0.0, f64::max)
            });
            // Relinearised, with the Jacobian, at the accepted point.
            let next: std::result::Result<Vec<Lin>, String> = p
                .scene
                .par_iter()
                .map(|l| {
                    linearised(r, settings, l.vehicle, l.turns, l.at, true)
                        .map_err(|e| e.to_string())
                })
                .collect();
            lins = next?;
            let total = p.total;
            current = Some(p);
            lambda = 0.0;
            // A chi-square change of 1e-6 is far below any statistical meaning and near the
            // precision of the run-outs' forward differences.
            if gain < 1e-6 * (1.0 + total) || step < 1e-9 {
                converged = true;
                break;
            }
            // Far above the best found and no longer closing the gap: abandoned.
            let excess = total - best_so_far - settings.refine_margin;
            if excess > 0.0 && (gain < 0.01 * excess || iterations >= 8) {
                abandoned = true;
                break;
            }
        } else {
            lambda = if lambda == 0.0 { 1e-3 } else { lambda * 10.0 };
            if lambda > 1e6 {
                // No step lowers the cost: a (local) minimum to the run-outs' precision.
                converged = true;
                break;
            }
        }
    }
    let point = current.expect("the first fit is accepted or returned");
    Ok(Refined {
        point,
        iterations,
        converged,
        abandoned,
        fits,
    })
}

/// A refinement's cost, iterations, convergence and abandonment, or why it failed.
type RefineEnd = std::result::Result<(f64, usize, bool, bool), String>;

/// The end of one combination's refinement.
pub(crate) struct Refined {
    pub(crate) point: Point,
    pub(crate) iterations: usize,
    pub(crate) converged: bool,
    /// Stopped far above the best found, no longer closing the gap.
    pub(crate) abandoned: bool,
    pub(crate) fits: usize,
}

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
        match refine(r, settings, start, lowest_best) {
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
                "no admissible impact reaches the scene's run-outs for any count of turns \
                 ({} combinations tried); the first reason: {reason}",
                tried.len()
            )),
            best: None,
            tried,
            estimates,
            runouts,
            fits,
        });
    };
    let found = Found::new(r, point, iterations, converged);
    let (status, reason) = match crate::outcome::contradiction(r, &found) {
        Some(why) => (Status::Inconsistent, Some(why)),
        None => (Status::Found, None),
    };
    Ok(Outcome {
        status,
        reason,
        best: Some(found),
        tried,
        estimates,
        runouts,
        fits,
    })
}

/// The scene fit of a point, for the outcome.
pub(crate) fn scene_fits(r: &Reconstruction, p: &Point) -> Vec<SceneFit> {
    p.scene
        .iter()
        .map(|l| SceneFit {
            vehicle: r.scene[l.vehicle].id,
            turns: r.scene[l.vehicle]
                .evidence
                .rest
                .and_then(|x| x.heading)
                .map(|_| l.turns),
            chi_square: l.lin.cost,
            residuals: l.lin.residuals.clone(),
            runout: l.lin.runout.clone(),
        })
        .collect()
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
        if let Ok(x) = refine(r, settings, start, lowest) {
            if x.point.total < lowest {
                found = Some(x);
            }
        }
    }
    Ok(found.map(|x| Found::new(r, x.point, x.iterations, x.converged)))
}
