//! Gauss-Newton over the separation state of one combination of counts of turns, with the
//! exact impact fit inside.

use crate::error::NoPoint;
use crate::impact_fit::{fit_once, Fitted, Step};
use crate::point::{differentiated, linearised, velocity_of, Lin, Point};
use crate::problem::{Reconstruction, Settings};
use crate::work::Work;
use pim_core::damped::{
    self, Damped, Limit, Linearised, Lower, Progress, Rules, Step as DampedStep, Termination,
    Verdict,
};
use pim_fit::{state_vector, Vector12};
use rayon::prelude::*;

/// The scenes' count of data at `p` (their residuals).
pub(crate) fn scene_data(p: &Point) -> usize {
    p.scene.iter().map(|l| l.lin.weighted.len()).sum()
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

/// Why a refinement stopped before it converged.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ended {
    /// Far above the best found and no longer closing the gap.
    Abandoned,
    /// At the rate of its steps the iterations left could not bring the chi-square below 10
    /// per datum.
    Hopeless,
    /// The search's budget of work is spent.
    Exhausted,
}

/// One combination's refinement as a damped least-squares problem: each step is the exact
/// impact fit of the scenes linearised at the current point, with Marquardt's rows that keep
/// the separation states near it.
struct Refinement<'a> {
    r: &'a Reconstruction,
    settings: &'a Settings,
    work: &'a Work,
    counts: Vec<i64>,
    /// The scenes linearised at the current point.
    lins: Vec<Lin>,
    best_so_far: f64,
}

impl Damped for Refinement<'_> {
    type Point = Point;
    type Reason = Ended;
    type Error = std::convert::Infallible;

    fn cost(&self, p: &Point) -> f64 {
        p.total
    }

    /// Relinearised at the point accepted last: its run-outs with their derivatives (the
    /// run-outs not simulated again). A point that cannot be differentiated ends the
    /// refinement there.
    fn linearise(&mut self, at: &Point, _: bool) -> Result<Linearised, Self::Error> {
        Ok(match relinearised(self.r, self.settings, at, self.work) {
            Ok(next) => {
                self.lins = next;
                Linearised::Ready
            }
            Err(_) => Linearised::Impossible,
        })
    }

    fn step(&mut self, at: &Point, lambda: f64) -> Result<DampedStep<Point>, Self::Error> {
        let damping = Step::marquardt(lambda, &self.lins);
        let x = state_vector(&at.solution.initial, &at.solution.separation);
        let fitted = fit_once(
            self.r,
            self.settings,
            &self.lins,
            damping,
            Some(&x),
            self.work,
        );
        let Ok(fitted) = fitted else {
            return Ok(DampedStep::Failed);
        };
        let predicted = fitted.predicted;
        Ok(
            match evaluate(self.r, self.settings, &self.counts, fitted, self.work) {
                Some(point) => DampedStep::Trial { point, predicted },
                None => DampedStep::Failed,
            },
        )
    }

    fn observe(&mut self, _: &Progress) -> Option<Ended> {
        self.work.exhausted().then_some(Ended::Exhausted)
    }

    fn accepted(&mut self, from: &Point, to: &Point, progress: &Progress) -> Verdict<Ended> {
        let gain = from.total - to.total;
        let total = to.total;
        // The first point counts as an iteration.
        let iterations = progress.trials + 1;
        // A chi-square change of 1e-6 is far below any statistical meaning and near the
        // precision of the run-outs' forward differences.
        if gain < GAIN * (1.0 + total) || largest_step(to, from) < 1e-9 {
            return Verdict::Converged;
        }
        // Far above the best found and no longer closing the gap: abandoned.
        let excess = total - self.best_so_far - self.settings.refine_margin;
        if excess > 0.0 && (gain < 0.01 * excess || iterations >= 8) {
            return Verdict::Stop(Ended::Abandoned);
        }
        // Evidence far from every admissible impact and run-out: when, at the rate of this
        // step, the iterations left could not bring the chi-square below 10 per datum
        // (residuals of three standard deviations on average; the evidence is then refused
        // whatever its last digits), the refinement stops here, not converged, instead of
        // crawling on through long run-outs.
        let data = self.r.contact_data() + scene_data(to);
        let left = self.settings.max_iterations.saturating_sub(iterations) as i32;
        let projected = total * (1.0 - (gain / total).min(1.0)).powi(left);
        if iterations >= 4 && projected > 10.0 * data.max(1) as f64 {
            return Verdict::Stop(Ended::Hopeless);
        }
        Verdict::Continue
    }

    fn failed(&mut self, at: &Point, trial: Option<&Point>, _: &Progress) -> Verdict<Ended> {
        // A trial no worse than the current point by more than the convergence tolerance: the
        // step is lost in the run-outs' precision, and so is anything left to gain.
        if trial.is_some_and(|p| p.total - at.total < GAIN * (1.0 + at.total)) {
            return Verdict::Converged;
        }
        // Far above the best found, and the linearisation's step fails there: the
        // combination's scenes are not near what its linearised bound assumed.
        if at.total > self.best_so_far + self.settings.refine_margin {
            return Verdict::Stop(Ended::Abandoned);
        }
        Verdict::Continue
    }
}

/// Gauss-Newton (Levenberg-Marquardt on the separation state, `pim_core::damped`) for one
/// combination of counts, on from its first point, abandoned where it stays far above
/// `best_so_far`. Undamped until a step fails; then `lambda` from 1e-3, ten times more after
/// each failure (a minimum above 1e6), lowered by Nielsen's rule after a success (kept near
/// what the step needed, not dropped, so that a valley the linearisation overshoots is not
/// crossed again and again by undamped steps). At most `max_iterations` points, the first
/// included.
fn refine(
    r: &Reconstruction,
    settings: &Settings,
    first: Probe,
    best_so_far: f64,
    work: &Work,
) -> Refined {
    let Probe { point, lins, .. } = first;
    if settings.max_iterations < 2 {
        return Refined {
            point,
            iterations: 1,
            converged: false,
            abandoned: false,
            fits: 1,
        };
    }
    let rules = Rules {
        start: 0.0,
        first: 1e-3,
        raise: 10.0,
        lower: Lower::Nielsen,
        most: 1e6,
        tries: None,
        limit: Limit::Trials(settings.max_iterations - 1),
    }
    .checked()
    .expect("the refinement's damping rules are in range");
    let mut problem = Refinement {
        r,
        settings,
        work,
        counts: lins.iter().map(|l| l.turns).collect(),
        lins,
        best_so_far,
    };
    let end = match damped::minimise(&mut problem, point, &rules) {
        Ok(end) => end,
        Err(never) => match never {},
    };
    Refined {
        point: end.point,
        iterations: 1 + end.trials,
        converged: end.termination.converged(),
        abandoned: end.termination == Termination::Stopped(Ended::Abandoned),
        fits: 1 + end.trials,
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
