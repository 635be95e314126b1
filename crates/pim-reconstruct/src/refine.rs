//! Gauss-Newton over the separation state of one combination of counts of turns, with the
//! exact impact fit inside.

use crate::error::NoPoint;
use crate::friction_step::FrictionStep;
use crate::point::{differentiated, linearised, velocity_of, Lin, Point};
use crate::problem::{Reconstruction, Settings};
use crate::work::Work;
use pim_fit::{
    fit, state_vector, Combination, FitProblem, MomentBranch, Solution, Status as FitStatus,
    Vector12,
};
use rayon::prelude::*;

/// An impact fit's work in run-out evaluations (a run-out's right-hand side: 0.7 us): each
/// branch on the convex route [`CONVEX_FIT_EVALUATIONS`], on the grid route one per operation
/// of its search (cost evaluation, exact solve, QP solve, grid point), plus one per elementary
/// operation of its inner problems (pim-fit's `Certificate::operations`: linear solves,
/// active-set steps, interior-point iterations). Measured over 450 fits of ordinary and hostile
/// scenes, an operation so counted takes 0.36 to 1.3 us whatever the problem, so the count
/// bounds the time within a small factor on a given machine; it does not time it.
fn fit_work(report: &pim_fit::FitReport) -> u64 {
    let search: u64 = report
        .branches
        .iter()
        .map(|b| {
            let c = &b.certificate;
            match c.method.route {
                pim_fit::Route::Convex => CONVEX_FIT_EVALUATIONS,
                pim_fit::Route::Grid => {
                    (c.evaluations + c.exact_solves + c.qp_solves + c.grid_points) as u64
                }
            }
        })
        .sum();
    // The operations are counted once for the whole fit (every branch).
    search
        + report
            .branches
            .first()
            .map_or(0, |b| b.certificate.operations)
}

/// An impact fit on the convex route, in run-out evaluations.
pub(crate) const CONVEX_FIT_EVALUATIONS: u64 = 150;

/// The scenes' count of data at `p` (their residuals).
pub(crate) fn scene_data(p: &Point) -> usize {
    p.scene.iter().map(|l| l.lin.weighted.len()).sum()
}

/// The impact fit with each scene linearised (rows in chi-square units, weight 1 each) and,
/// with `damping`, Marquardt's rows that keep the separation state near the current one. Every
/// weight is scaled by one factor into (0, 1]; the fit's cost over that factor is the
/// chi-square of the linearised problem. With fitted frictions, the scenes' rows and the
/// frictions' own rows are projected onto the complement of the frictions' columns: the
/// linearised cost minimised over the frictions for every velocity state (exact for a linear
/// model), and the [`FrictionStep`] that gives those frictions back.
pub(crate) fn assemble(
    r: &Reconstruction,
    lins: &[Lin],
    damping: Option<(f64, &[Lin])>,
    at: Option<&Vector12>,
) -> (FitProblem, f64, Option<FrictionStep>) {
    let unit = r.unit.unwrap_or(1.0);
    let mut problem = r.contact.clone();
    // Chi-square weights first.
    for w in problem.weights_mut() {
        *w /= unit;
    }
    // The nonlinear evidence linearised at the current state (none before the first).
    if let Some(u) = at {
        problem.combinations.extend(nonlinear_rows(r, u));
    }
    let step = if r.frictions.is_empty() {
        for l in lins {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            let j = l.jacobian();
            for i in 0..j.nrows() {
                let mut row = Vector12::zeros();
                let mut target = -l.lin.weighted[i];
                for c in 0..3 {
                    row[base + c] = j[(i, c)];
                    target += j[(i, c)] * l.at[c];
                }
                push_row(&mut problem, row, target);
            }
        }
        None
    } else {
        let step = FrictionStep::new(r, lins);
        let projected = step.projected();
        for k in 0..projected.0.nrows() {
            let row = Vector12::from_iterator(projected.0.row(k).iter().copied());
            push_row(&mut problem, row, row.dot(&step.at) - projected.1[k]);
        }
        Some(step)
    };
    if let Some((lambda, around)) = damping {
        for l in around {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            let j = l.jacobian();
            let jtj = j.transpose() * j;
            let largest = (0..3).map(|c| jtj[(c, c)]).fold(0.0, f64::max).max(1e-12);
            for c in 0..3 {
                let mut row = Vector12::zeros();
                row[base + c] = 1.0;
                problem.combinations.push(Combination {
                    row,
                    value: l.at[c],
                    weight: lambda * jtj[(c, c)].max(1e-6 * largest),
                });
            }
        }
    }
    let largest = problem.weights_mut().fold(0.0_f64, |m, w| m.max(*w));
    let scale = if largest > 0.0 { 1.0 / largest } else { 1.0 };
    for w in problem.weights_mut() {
        *w = (*w * scale).max(f64::MIN_POSITIVE);
    }
    (problem, scale, step)
}

/// A linearised row `(row . U - target)^2` as a combination of the problem (a row that no
/// velocity moves adds only a constant and is left out).
fn push_row(problem: &mut FitProblem, row: Vector12, target: f64) {
    let norm = row.norm();
    if norm > 1e-12 {
        problem.combinations.push(Combination {
            row: row / norm,
            value: target / norm,
            weight: norm * norm,
        });
    }
}

/// Each piece of nonlinear evidence linearised at `u`, `z(U) ~ z(u) + g (U - u)` with `z` the
/// residual in standard deviations and `g` by forward differences over the free components:
/// a combination row in chi-square units.
fn nonlinear_rows(r: &Reconstruction, u: &Vector12) -> Vec<Combination> {
    let z = |v: &Vector12, t: &dyn crate::StateEvidence| t.residual(v).map(|(x, s)| x / s);
    let free: Vec<usize> = (0..12)
        .filter(|&k| !matches!(r.contact.components[k], pim_fit::Knowledge::Known { .. }))
        .collect();
    let mut rows = Vec::new();
    for t in &r.nonlinear.0 {
        let Some(z0) = z(u, t.as_ref()) else { continue };
        let mut g = Vector12::zeros();
        for &k in &free {
            let h = 1e-6 * (1.0 + u[k].abs());
            let mut v = *u;
            v[k] += h;
            if let Some(z1) = z(&v, t.as_ref()) {
                g[k] = (z1 - z0) / h;
            }
        }
        let norm = g.norm();
        if norm > 1e-300 {
            rows.push(Combination {
                row: g / norm,
                value: (g.dot(u) - z0) / norm,
                weight: norm * norm,
            });
        }
    }
    rows
}

/// An impact fit's answer: its branch, solution and certificate, and the frictions that go
/// with its velocities.
struct Fitted {
    branch: MomentBranch,
    solution: Solution,
    certificate: pim_fit::Certificate,
    mus: Vec<f64>,
    /// The linearised problem's chi-square at the fit (damping rows included).
    predicted: f64,
}

/// How an impact fit of the linearised problem may move the separation state.
#[derive(Clone, Copy)]
enum Step<'a> {
    /// Freely (Gauss-Newton's step).
    Free,
    /// Kept near the scenes' linearisation points by Marquardt's damping `lambda`.
    Damped(f64, &'a [Lin]),
    /// Not at all: held at the scenes' linearisation points (the impact fitted to them).
    Held,
}

impl<'a> Step<'a> {
    /// Marquardt's damping `lambda` about `around` (none at 0).
    fn marquardt(lambda: f64, around: &'a [Lin]) -> Step<'a> {
        if lambda > 0.0 {
            Step::Damped(lambda, around)
        } else {
            Step::Free
        }
    }
}

/// One impact fit of the linearised problem: the best optimal branch, or why there is none.
fn fit_once(
    r: &Reconstruction,
    settings: &Settings,
    lins: &[Lin],
    step: Step<'_>,
    at: Option<&Vector12>,
    work: &Work,
) -> std::result::Result<Fitted, NoPoint> {
    let damping = match step {
        Step::Damped(lambda, around) => Some((lambda, around)),
        Step::Free | Step::Held => None,
    };
    let (mut problem, scale, frictions) = assemble(r, lins, damping, at);
    if matches!(step, Step::Held) {
        for l in lins {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            for c in 0..3 {
                problem.components[base + c] = pim_fit::Knowledge::Known { value: l.at[c] };
            }
        }
    }
    let report = fit(&problem, &settings.fit)?;
    work.add(fit_work(&report));
    let best = report.best_branch().ok_or_else(|| {
        NoPoint::NoImpact(
            report
                .branches
                .iter()
                .find_map(|b| b.reason.as_ref().map(|x| x.to_string()))
                .unwrap_or_else(|| "no admissible impact".into()),
        )
    })?;
    match (&best.status, &best.solution) {
        (FitStatus::Optimal, Some(s)) => {
            let mus = frictions.map_or_else(Vec::new, |st| {
                st.frictions_at(&state_vector(&s.initial, &s.separation))
            });
            Ok(Fitted {
                branch: best.moment,
                solution: s.clone(),
                certificate: best.certificate.clone(),
                mus,
                predicted: s.cost / scale,
            })
        }
        _ => Err(NoPoint::Ended(best.status)),
    }
}

/// Evaluates the true cost of a fit's answer: the contact evidence and each scene's run-out.
fn evaluate(
    r: &Reconstruction,
    settings: &Settings,
    counts: &[i64],
    fitted: Fitted,
    work: &Work,
) -> Option<Point> {
    let Fitted {
        branch,
        solution,
        certificate,
        mus,
        ..
    } = fitted;
    let u = state_vector(&solution.initial, &solution.separation);
    if !r.nonlinear_defined(&u) {
        return None;
    }
    let contact = r.contact_chi_square(&u);
    let scene: Option<Vec<Lin>> = r
        .scene
        .par_iter()
        .enumerate()
        .map(|(i, s)| {
            work.charge(linearised(
                r,
                settings,
                i,
                counts[i],
                velocity_of(&solution.separation, s),
                false,
                &mus,
            ))
            .ok()
        })
        .collect();
    let scene = scene?;
    let frictions: f64 = r.friction_z(&mus).iter().map(|z| z * z).sum();
    let total = contact + frictions + scene.iter().map(|l| l.lin.cost).sum::<f64>();
    Some(Point {
        branch,
        solution,
        certificate,
        contact,
        scene,
        mus,
        total,
    })
}

/// A combination's first point: the impact fitted to the scenes linearised at its start, its
/// run-outs simulated (their true cost), and what the linearisation predicted there. Probed
/// before any is refined, so that the refinements go in the order of costs that were
/// evaluated, not of bounds that were only linearised.
#[derive(Clone)]
pub(crate) struct Probe {
    pub(crate) point: Point,
    /// The linearised problem's chi-square at the fit.
    pub(crate) predicted: f64,
    /// The scenes linearised at the start (those the first fit was made on).
    lins: Vec<Lin>,
    /// Where the nonlinear contact evidence was linearised.
    contact: Option<Vector12>,
}

impl Probe {
    /// Whether the first point lies more than the margin above what its linearisation
    /// predicted: the scenes' candidates are then far from the separation state the impact
    /// gives, and the linearisation (its bound included) says nothing of the combination.
    pub(crate) fn far(&self, settings: &Settings) -> bool {
        self.point.total > self.predicted + settings.refine_margin
    }

    /// The scenes' chi-square at the start (a lower bound of [`Probe::held_point`]:
    /// the separation state held there meets the scenes as the start does).
    pub(crate) fn start_cost(&self) -> f64 {
        self.lins.iter().map(|l| l.lin.cost).sum()
    }

    /// Where the undamped step overshot ([`Probe::far`]): the start itself, the impact fitted
    /// with the separation state held there, where it is lower than this probe's point. A start
    /// near an answer (a scene's candidate near the truth, an earlier answer) whose
    /// linearisation is poor along a weakly determined direction (a long rolling run-out's
    /// speed against its turn) is otherwise thrown into another basin by its first step.
    fn held_point(&self, r: &Reconstruction, settings: &Settings, work: &Work) -> Option<Point> {
        if !self.far(settings) {
            return None;
        }
        let counts: Vec<i64> = self.lins.iter().map(|l| l.turns).collect();
        fit_once(
            r,
            settings,
            &self.lins,
            Step::Held,
            self.contact.as_ref(),
            work,
        )
        .ok()
        .and_then(|f| evaluate(r, settings, &counts, f, work))
        .filter(|h| h.total < self.point.total)
    }

    /// [`Probe::held_point`] as a probe of its own (a second start of the combination; the
    /// step's own point is kept as well, since a scene's candidate far from the impact is often
    /// nearer an answer after it).
    pub(crate) fn start_itself(
        self,
        r: &Reconstruction,
        settings: &Settings,
        work: &Work,
    ) -> Option<Probe> {
        let held = self.held_point(r, settings, work)?;
        Some(Probe {
            point: held,
            ..self
        })
    }
}

/// The first point of the combination whose scenes are linearised at `start`, or why it has
/// none. The nonlinear contact evidence (an EDR's speed) is linearised at `contact`, the twelve
/// velocities of an earlier answer of the combination (a restart); without one, at the impact
/// fitted without it, and the impact fitted again.
pub(crate) fn probe(
    r: &Reconstruction,
    settings: &Settings,
    start: Vec<Lin>,
    contact: Option<Vector12>,
    work: &Work,
) -> std::result::Result<Probe, NoPoint> {
    let counts: Vec<i64> = start.iter().map(|l| l.turns).collect();
    let restart = contact.is_some();
    let contact = match contact {
        Some(u) => Some(u),
        None if !r.nonlinear.0.is_empty() => {
            let f = fit_once(r, settings, &start, Step::Free, None, work)?;
            Some(state_vector(&f.solution.initial, &f.solution.separation))
        }
        None => None,
    };
    let fitted = fit_once(r, settings, &start, Step::Free, contact.as_ref(), work)?;
    let predicted = fitted.predicted;
    let point = evaluate(r, settings, &counts, fitted, work).ok_or(NoPoint::Runout)?;
    let mut first = Probe {
        point,
        predicted,
        lins: start,
        contact,
    };
    if restart {
        // A restart from an answer whose undamped step overshot: the refinement goes on from
        // the start itself where it is lower. (A search's start is a scene's candidate, not an
        // answer: its refinement goes on from where the impact put it, and from the start
        // itself after every combination has had its first refinement.)
        if let Some(held) = first.held_point(r, settings, work) {
            first.point = held;
        }
    }
    Ok(first)
}

/// A combination refined from its scenes linearised at `start`, to the end (nothing to beat),
/// or why its first point has no impact.
pub(crate) fn refine_start(
    r: &Reconstruction,
    settings: &Settings,
    start: Vec<Lin>,
    contact: Option<Vector12>,
    work: &Work,
) -> std::result::Result<Refined, NoPoint> {
    let first = probe(r, settings, start, contact, work)?;
    Ok(refine(r, settings, first, f64::INFINITY, work))
}

/// What a refinement does with a first point far (more than the margin) above what its
/// linearisation predicted ([`Probe::far`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum FarFirst {
    /// Refined on from where the impact put it (a restart from the impact's side).
    RefineOn,
    /// Abandoned where it also lies more than the margin above the best found.
    AboveBest,
    /// Abandoned (a quick look, followed by a thorough search where it finds nothing that
    /// fits: its run-outs far from the scene are costly to follow).
    SetAside,
}

/// A combination refined on from its first point, or that point alone, abandoned, where it is
/// far from its linearisation and `far` sets it aside against `best_so_far`.
pub(crate) fn refine_probe(
    r: &Reconstruction,
    settings: &Settings,
    first: Probe,
    (best_so_far, far): (f64, FarFirst),
    work: &Work,
) -> Refined {
    let set_aside = match far {
        FarFirst::RefineOn => false,
        FarFirst::AboveBest => first.point.total > best_so_far + settings.refine_margin,
        FarFirst::SetAside => true,
    };
    if set_aside && first.far(settings) {
        return Refined {
            point: first.point,
            iterations: 1,
            converged: false,
            abandoned: true,
            fits: 1,
        };
    }
    refine(r, settings, first, best_so_far, work)
}

/// Gauss-Newton (Levenberg-Marquardt on the separation state) for one combination of counts,
/// on from its first point, abandoned where it stays far above `best_so_far`.
fn refine(
    r: &Reconstruction,
    settings: &Settings,
    first: Probe,
    best_so_far: f64,
    work: &Work,
) -> Refined {
    let Probe { point, lins, .. } = first;
    let counts: Vec<i64> = lins.iter().map(|l| l.turns).collect();
    let mut lins = lins;
    // `lins` are those of the point before the one accepted last (linearised again at the
    // accepted one before the next step).
    let mut stale = true;
    let mut current = point;
    let mut lambda = 0.0;
    let mut fits = 1;
    let mut iterations = 1;
    let mut converged = false;
    let mut abandoned = false;
    while iterations < settings.max_iterations {
        if work.exhausted() {
            break;
        }
        // Relinearised at the point accepted last: its run-outs with their derivatives (the
        // run-outs not simulated again).
        if stale {
            match relinearised(r, settings, &current, work) {
                Ok(next) => lins = next,
                // The point accepted last cannot be differentiated: the refinement ends there.
                Err(_) => break,
            }
            stale = false;
        }
        iterations += 1;
        let damping = Step::marquardt(lambda, &lins);
        fits += 1;
        let at = state_vector(&current.solution.initial, &current.solution.separation);
        let fitted = fit_once(r, settings, &lins, damping, Some(&at), work);
        let predicted = fitted.as_ref().map_or(f64::NAN, |f| f.predicted);
        let trial =
            fitted.and_then(|f| evaluate(r, settings, &counts, f, work).ok_or(NoPoint::Runout));
        let accepted = trial.as_ref().is_ok_and(|p| p.total < current.total);
        if accepted {
            let p = trial.expect("accepted");
            let gain = current.total - p.total;
            let step = largest_step(&p, &current);
            // Linearised at the accepted point (its derivatives added when the refinement goes
            // on from it).
            stale = true;
            let total = p.total;
            if lambda > 0.0 {
                lambda *= nielsen(gain, gain + total - predicted);
            }
            current = p;
            // A chi-square change of 1e-6 is far below any statistical meaning and near the
            // precision of the run-outs' forward differences.
            if gain < GAIN * (1.0 + total) || step < 1e-9 {
                converged = true;
                break;
            }
            // Far above the best found and no longer closing the gap: abandoned.
            let excess = total - best_so_far - settings.refine_margin;
            if excess > 0.0 && (gain < 0.01 * excess || iterations >= 8) {
                abandoned = true;
                break;
            }
            // Evidence far from every admissible impact and run-out: when, at the rate of
            // this step, the iterations left could not bring the chi-square below 10 per
            // datum (residuals of three standard deviations on average; the evidence is then
            // refused whatever its last digits), the refinement stops here, not converged,
            // instead of crawling on through long run-outs.
            let data = r.contact_data() + scene_data(&current);
            let left = settings.max_iterations.saturating_sub(iterations) as i32;
            let projected = total * (1.0 - (gain / total).min(1.0)).powi(left);
            if iterations >= 4 && projected > 10.0 * data.max(1) as f64 {
                break;
            }
        } else {
            // A trial no worse than the current point by more than the convergence tolerance:
            // the step is lost in the run-outs' precision, and so is anything left to gain.
            if let Ok(p) = &trial {
                if p.total - current.total < GAIN * (1.0 + current.total) {
                    converged = true;
                    break;
                }
            }
            // Far above the best found, and the linearisation's step fails there: the
            // combination's scenes are not near what its linearised bound assumed.
            if current.total > best_so_far + settings.refine_margin {
                abandoned = true;
                break;
            }
            lambda = if lambda == 0.0 { 1e-3 } else { lambda * 10.0 };
            if lambda > 1e6 {
                // No step lowers the cost: a (local) minimum to the run-outs' precision.
                converged = true;
                break;
            }
        }
    }
    Refined {
        point: current,
        iterations,
        converged,
        abandoned,
        fits,
    }
}

/// The point `c` linearised again, its run-outs differentiated where they stand (not simulated
/// again), the work counted.
fn relinearised(
    r: &Reconstruction,
    settings: &Settings,
    c: &Point,
    work: &Work,
) -> std::result::Result<Vec<Lin>, NoPoint> {
    c.scene
        .par_iter()
        .map(|l| {
            let spent = l.lin.evaluations;
            let d = differentiated(r, settings, l.clone(), &c.mus)?;
            work.add(d.lin.evaluations - spent);
            Ok(d)
        })
        .collect()
}

/// The largest change of any separation state's component from `b` to `a`.
fn largest_step(a: &Point, b: &Point) -> f64 {
    a.scene
        .iter()
        .zip(&b.scene)
        .map(|(a, b)| {
            (0..3)
                .map(|k| (a.at[k] - b.at[k]).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max)
}

/// Marquardt's damping after a success, the factor on `lambda`: kept near what the step needed
/// (Nielsen's rule `max(1/3, 1 - (2 rho - 1)^3)`, `rho` the gain over the linearised fit's
/// `predicted_gain`: down to a third where the linearisation predicted the gain well, up to
/// twice where it did not), not dropped, so that a valley the linearisation overshoots is not
/// crossed again and again by undamped steps.
fn nielsen(gain: f64, predicted_gain: f64) -> f64 {
    let rho = gain / predicted_gain;
    if rho.is_finite() && rho > 0.0 {
        (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0)
    } else {
        1.0 / 3.0
    }
}

/// A refinement has converged when a step gains less than this times (1 + its chi-square):
/// far below any statistical meaning and near the precision of the run-outs' forward
/// differences.
const GAIN: f64 = 1e-6;

/// A refinement's cost, iterations, convergence and abandonment, or why it failed.
pub(crate) type RefineEnd = std::result::Result<(f64, usize, bool, bool), NoPoint>;

/// The end of one combination's refinement.
pub(crate) struct Refined {
    pub(crate) point: Point,
    pub(crate) iterations: usize,
    pub(crate) converged: bool,
    /// Stopped far above the best found, no longer closing the gap.
    pub(crate) abandoned: bool,
    pub(crate) fits: usize,
}
