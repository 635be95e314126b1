//! Damped least squares: the one Levenberg-Marquardt iteration of the workspace.
//!
//! Every iterative least-squares fit of the toolkit (the run-out inverse of `pim-runout`, the
//! nonlinear impact fit of `pim-fit`, the refinement of a combination of counts of turns and
//! the fit of the pose at contact in `pim-reconstruct`) minimises a cost `F(x) = |r(x)|^2` by
//! steps from a linearisation of `r` about the current point, damped by Marquardt's `lambda`:
//!
//! ```text
//! (J^T J + lambda D) dx = -J^T r        D a positive diagonal (each problem's own scaling)
//! ```
//!
//! A problem ([`Damped`]) forms the step and evaluates its trial point; [`minimise`] owns the
//! iteration: which point is current, when it is linearised again, how `lambda` moves, and
//! why the iteration ends ([`Termination`]). The moves of `lambda` are the problem's
//! [`Rules`], checked once ([`Rules::checked`]):
//!
//! - a trial whose cost is below the current point's is accepted, and `lambda` is lowered
//!   ([`Lower`]: reset to 0, divided by a factor down to a floor, or by Nielsen's rule
//!   `max(1/3, 1 - (2 rho - 1)^3)`, `rho` the gain over the gain the linearisation predicted);
//! - otherwise `lambda` is raised (from 0 to [`Rules::first`], else times [`Rules::raise`]);
//!   above [`Rules::most`] no damping lowers the cost: the current point is a (local) minimum
//!   to the precision of the cost;
//! - a problem whose linearisation is only approximate (a Broyden update) is linearised
//!   exactly before a failure or a negligible step ends the iteration ([`Damped::exact`]).
//!
//! The iteration ends at the first of: a verdict of the problem after a step
//! ([`Verdict::Converged`], [`Verdict::Stop`]), the limit of [`Rules::limit`] (trials or
//! linearisations), a point that cannot be linearised, a step the linearisation predicts to gain
//! nothing worth a trial, or the damping's limit. Each step is reported to the problem's
//! [`Damped::observe`] first, which may stop the iteration (a budget spent, a study
//! cancelled).

/// How `lambda` is lowered after an accepted step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Lower {
    /// Back to 0 (undamped Gauss-Newton steps until one fails).
    Reset,
    /// Divided by the factor, never below the floor.
    Divide {
        /// The factor (above 1).
        by: f64,
        /// The least `lambda`.
        floor: f64,
    },
    /// Nielsen's rule (1999): times `max(1/3, 1 - (2 rho - 1)^3)`, `rho` the gain over the
    /// predicted gain; a `lambda` of 0 stays 0.
    Nielsen,
}

/// What the iteration's limit counts.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Limit {
    /// Trial steps (failed ones included).
    Trials(usize),
    /// Linearisations (the start's included).
    Linearisations(usize),
}

/// The moves of Marquardt's `lambda` and the iteration's limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rules {
    /// `lambda` of the first step (0: undamped).
    pub start: f64,
    /// `lambda` after a failed undamped step.
    pub first: f64,
    /// The factor on `lambda` after a failed step (above 1).
    pub raise: f64,
    /// How `lambda` is lowered after an accepted step.
    pub lower: Lower,
    /// Above this `lambda` no step is tried: the point is a (local) minimum.
    pub most: f64,
    /// The most failed steps from one linearisation (`None`: as many as `most` allows).
    pub tries: Option<usize>,
    /// The iteration's limit.
    pub limit: Limit,
}

/// Rules that cannot drive an iteration.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RulesError {
    /// A damping or factor out of its range.
    #[error("damped least squares: {0}")]
    Range(&'static str),
}

/// Rules checked once ([`Rules::checked`]): what [`minimise`] takes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Checked(Rules);

impl Rules {
    /// The classical moves (Press et al., Numerical Recipes; Madsen, Nielsen and Tingleff): from
    /// `lambda` 1e-3, four times more after a failed step, a third after a success down to
    /// `floor`; no step above 1e12; at most `limit`.
    pub fn classic(floor: f64, limit: Limit) -> Rules {
        Rules {
            start: 1e-3,
            first: 1e-3,
            raise: 4.0,
            lower: Lower::Divide { by: 3.0, floor },
            most: 1e12,
            tries: None,
            limit,
        }
    }

    /// The rules if they can drive an iteration: dampings finite and not negative, `first`
    /// above 0, `raise` above 1, a lowering that lowers, `most` above `first`, a limit above 0.
    ///
    /// # Errors
    /// [`RulesError::Range`] naming the rule out of its range.
    pub fn checked(self) -> Result<Checked, RulesError> {
        let ok = |x: f64| x.is_finite() && x >= 0.0;
        if !ok(self.start) {
            return Err(RulesError::Range(
                "the first damping must be finite and not negative",
            ));
        }
        if !(ok(self.first) && self.first > 0.0) {
            return Err(RulesError::Range(
                "the damping after a failed step must be above 0",
            ));
        }
        if !(self.raise.is_finite() && self.raise > 1.0) {
            return Err(RulesError::Range(
                "the raise after a failed step must be above 1",
            ));
        }
        if let Lower::Divide { by, floor } = self.lower {
            if !(by.is_finite() && by > 1.0 && ok(floor)) {
                return Err(RulesError::Range(
                    "a lowering divides by more than 1 down to a floor not below 0",
                ));
            }
        }
        if self.most.is_nan() || self.most <= self.first.max(self.start) {
            return Err(RulesError::Range(
                "the most damping must lie above the first ones",
            ));
        }
        let limit = match self.limit {
            Limit::Trials(n) | Limit::Linearisations(n) => n,
        };
        if limit == 0 || self.tries == Some(0) {
            return Err(RulesError::Range("the limits must allow a step"));
        }
        Ok(Checked(self))
    }
}

impl Checked {
    /// The rules.
    pub fn rules(&self) -> &Rules {
        &self.0
    }
}

/// A linearisation's outcome.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Linearised {
    /// Steps can be formed from it.
    Ready,
    /// The point is stationary (gradient or cost nil): converged there.
    Stationary,
    /// The point cannot be linearised: the iteration ends there.
    Impossible,
}

/// A step from the current point.
#[derive(Debug, Clone, PartialEq)]
pub enum Step<P> {
    /// The trial point, evaluated, and the cost the linearisation predicted for it (NaN where
    /// the problem does not predict one).
    Trial {
        /// The trial point.
        point: P,
        /// Its cost as the linearisation predicts it.
        predicted: f64,
    },
    /// The damped system is singular at this `lambda`: damped more, no trial made.
    Singular,
    /// The linearisation predicts less gain than is worth a trial.
    Negligible,
    /// The trial point could not be evaluated (a failed step).
    Failed,
    /// No step can be formed at this point: the iteration ends.
    Unavailable,
}

/// The problem's verdict after a step.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict<R> {
    /// Go on.
    Continue,
    /// Converged (a gain or a step below the problem's tolerance).
    Converged,
    /// Stopped for the problem's own reason.
    Stop(R),
}

/// Why an iteration ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Termination<R> {
    /// The problem's verdict: a gain or step below its tolerance.
    Converged,
    /// The point is stationary where it was linearised.
    Stationary,
    /// The linearisation predicts less gain than is worth a trial.
    Negligible,
    /// No damping up to the most lowers the cost: a (local) minimum.
    NoDescent,
    /// The most failed steps from one exact linearisation.
    Tries,
    /// The limit of trials or linearisations.
    Limit,
    /// The current point cannot be linearised, or no step formed there.
    Undifferentiable,
    /// The problem stopped the iteration for its own reason.
    Stopped(R),
}

impl<R> Termination<R> {
    /// Whether the end is a minimum to the problem's precision (converged, stationary, nothing
    /// left to gain, or no damping that lowers the cost).
    pub fn converged(&self) -> bool {
        matches!(
            self,
            Self::Converged | Self::Stationary | Self::Negligible | Self::NoDescent
        )
    }
}

/// Where the iteration stands, as the problem's hooks see it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress {
    /// Trial steps so far (this one included in the hooks after a step).
    pub trials: usize,
    /// Linearisations so far.
    pub linearisations: usize,
    /// The current damping.
    pub lambda: f64,
}

/// A least-squares problem driven by [`minimise`].
pub trait Damped {
    /// A point of the iteration (its parameters and whatever its evaluation keeps).
    type Point;
    /// Why the problem stops an iteration of its own accord.
    type Reason;
    /// An error that ends the iteration and is returned.
    type Error;

    /// The cost of a point.
    fn cost(&self, p: &Self::Point) -> f64;
    /// Linearises the problem at `at` (the start, each accepted point before its first step,
    /// and exactly where an approximate linearisation failed). `exact`: an approximation
    /// (an update) will not do.
    ///
    /// # Errors
    /// The problem's, ending the iteration.
    fn linearise(&mut self, at: &Self::Point, exact: bool) -> Result<Linearised, Self::Error>;
    /// Whether the current linearisation is exact (not an update): only then do a failure or
    /// a negligible step end the iteration.
    fn exact(&self) -> bool {
        true
    }
    /// The step from `at` damped by `lambda`, its trial point evaluated.
    ///
    /// # Errors
    /// The problem's, ending the iteration.
    fn step(&mut self, at: &Self::Point, lambda: f64) -> Result<Step<Self::Point>, Self::Error>;
    /// Before each step: the problem may stop the iteration (a budget, a cancellation).
    fn observe(&mut self, _progress: &Progress) -> Option<Self::Reason> {
        None
    }
    /// After an accepted step from `from` to `to`: converged, stopped or on.
    fn accepted(
        &mut self,
        _from: &Self::Point,
        _to: &Self::Point,
        _progress: &Progress,
    ) -> Verdict<Self::Reason> {
        Verdict::Continue
    }
    /// After a failed step from `at` (`trial`: the trial point where it was evaluated, its cost
    /// not below `at`'s), before `lambda` is raised.
    fn failed(
        &mut self,
        _at: &Self::Point,
        _trial: Option<&Self::Point>,
        _progress: &Progress,
    ) -> Verdict<Self::Reason> {
        Verdict::Continue
    }
}

/// The end of an iteration.
#[derive(Debug, Clone, PartialEq)]
pub struct Minimised<P, R> {
    /// The last accepted point (the start if none was).
    pub point: P,
    /// Why it ended.
    pub termination: Termination<R>,
    /// Trial steps made.
    pub trials: usize,
    /// Linearisations made.
    pub linearisations: usize,
    /// The damping at the end.
    pub lambda: f64,
}

/// Minimises `problem` from `start` under `rules` (see the module's text).
///
/// # Errors
/// The problem's own, from [`Damped::linearise`] or [`Damped::step`].
pub fn minimise<D: Damped>(
    problem: &mut D,
    start: D::Point,
    rules: &Checked,
) -> Result<Minimised<D::Point, D::Reason>, D::Error> {
    let r = rules.0;
    let mut at = start;
    let mut p = Progress {
        trials: 0,
        linearisations: 0,
        lambda: r.start,
    };
    let mut stale = true;
    let mut exact = false;
    let mut tries = 0;
    let end = |at, termination, p: Progress| {
        Ok(Minimised {
            point: at,
            termination,
            trials: p.trials,
            linearisations: p.linearisations,
            lambda: p.lambda,
        })
    };
    loop {
        if let Limit::Trials(n) = r.limit {
            if p.trials >= n {
                return end(at, Termination::Limit, p);
            }
        }
        if let Some(why) = problem.observe(&p) {
            return end(at, Termination::Stopped(why), p);
        }
        if stale {
            if let Limit::Linearisations(n) = r.limit {
                if p.linearisations >= n {
                    return end(at, Termination::Limit, p);
                }
            }
            p.linearisations += 1;
            match problem.linearise(&at, exact)? {
                Linearised::Ready => {}
                Linearised::Stationary => return end(at, Termination::Stationary, p),
                Linearised::Impossible => return end(at, Termination::Undifferentiable, p),
            }
            (stale, exact, tries) = (false, false, 0);
        }
        p.trials += 1;
        let trial = match problem.step(&at, p.lambda)? {
            Step::Trial { point, predicted } => Some((point, predicted)),
            Step::Failed => None,
            Step::Singular => {
                tries += 1;
                if let Some(t) = rejected(&r, &mut p, tries, problem, &mut stale, &mut exact) {
                    return end(at, t, p);
                }
                continue;
            }
            Step::Negligible => {
                if problem.exact() {
                    return end(at, Termination::Negligible, p);
                }
                (stale, exact) = (true, true);
                continue;
            }
            Step::Unavailable => return end(at, Termination::Undifferentiable, p),
        };
        let before = problem.cost(&at);
        match trial {
            Some((point, predicted)) if problem.cost(&point) < before => {
                let gain = before - problem.cost(&point);
                p.lambda = lowered(&r, p.lambda, gain, before - predicted);
                let verdict = problem.accepted(&at, &point, &p);
                at = point;
                stale = true;
                if let Some(t) = ending(verdict) {
                    return end(at, t, p);
                }
            }
            trial => {
                if let Some(t) = ending(problem.failed(&at, trial.as_ref().map(|t| &t.0), &p)) {
                    return end(at, t, p);
                }
                tries += 1;
                if let Some(t) = rejected(&r, &mut p, tries, problem, &mut stale, &mut exact) {
                    return end(at, t, p);
                }
            }
        }
    }
}

/// The end a verdict gives, if any.
fn ending<R>(verdict: Verdict<R>) -> Option<Termination<R>> {
    match verdict {
        Verdict::Continue => None,
        Verdict::Converged => Some(Termination::Converged),
        Verdict::Stop(why) => Some(Termination::Stopped(why)),
    }
}

/// After a failed or singular step (the `tries`-th from this linearisation): the damping
/// raised, and the end where it passes its ceiling; where the tries from one linearisation are
/// spent, the end (an exact linearisation) or an exact linearisation asked for.
fn rejected<D: Damped>(
    r: &Rules,
    p: &mut Progress,
    tries: usize,
    problem: &D,
    stale: &mut bool,
    exact: &mut bool,
) -> Option<Termination<D::Reason>> {
    p.lambda = raised(r, p.lambda);
    if p.lambda > r.most {
        return Some(Termination::NoDescent);
    }
    if r.tries.is_some_and(|most| tries >= most) {
        if problem.exact() {
            return Some(Termination::Tries);
        }
        (*stale, *exact) = (true, true);
    }
    None
}

/// `lambda` after a failed step.
fn raised(r: &Rules, lambda: f64) -> f64 {
    if lambda == 0.0 {
        r.first
    } else {
        lambda * r.raise
    }
}

/// `lambda` after an accepted step that gained `gain` where the linearisation predicted
/// `predicted_gain`.
fn lowered(r: &Rules, lambda: f64, gain: f64, predicted_gain: f64) -> f64 {
    match r.lower {
        Lower::Reset => 0.0,
        Lower::Divide { by, floor } => (lambda / by).max(floor),
        Lower::Nielsen if lambda > 0.0 => lambda * nielsen(gain, predicted_gain),
        Lower::Nielsen => 0.0,
    }
}

/// Nielsen's factor on `lambda` after a success: `max(1/3, 1 - (2 rho - 1)^3)`, `rho` the gain
/// over the predicted gain (a third where `rho` is not a positive number): down to a third
/// where the linearisation predicted the gain well, up to twice where it did not, so that a
/// valley the linearisation overshoots is not crossed again and again by undamped steps.
pub fn nielsen(gain: f64, predicted_gain: f64) -> f64 {
    let rho = gain / predicted_gain;
    if rho.is_finite() && rho > 0.0 {
        (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0)
    } else {
        1.0 / 3.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rosenbrock's valley as least squares: `r = (10 (y - x^2), 1 - x)`, minimum 0 at (1, 1).
    struct Rosenbrock {
        j: [[f64; 2]; 2],
        r: [f64; 2],
        evaluations: usize,
    }

    fn residuals(p: &[f64; 2]) -> [f64; 2] {
        [10.0 * (p[1] - p[0] * p[0]), 1.0 - p[0]]
    }

    fn cost(p: &[f64; 2]) -> f64 {
        let r = residuals(p);
        r[0] * r[0] + r[1] * r[1]
    }

    impl Damped for Rosenbrock {
        type Point = [f64; 2];
        type Reason = &'static str;
        type Error = ();

        fn cost(&self, p: &[f64; 2]) -> f64 {
            cost(p)
        }

        fn linearise(&mut self, at: &[f64; 2], _: bool) -> Result<Linearised, ()> {
            self.r = residuals(at);
            self.j = [[-20.0 * at[0], 10.0], [-1.0, 0.0]];
            Ok(if cost(at) < 1e-30 {
                Linearised::Stationary
            } else {
                Linearised::Ready
            })
        }

        fn step(&mut self, at: &[f64; 2], lambda: f64) -> Result<Step<[f64; 2]>, ()> {
            let j = self.j;
            // A = J^T J (1 + lambda on the diagonal), g = J^T r.
            let a = |i: usize, k: usize| j[0][i] * j[0][k] + j[1][i] * j[1][k];
            let g = [
                j[0][0] * self.r[0] + j[1][0] * self.r[1],
                j[0][1] * self.r[0] + j[1][1] * self.r[1],
            ];
            let (a00, a11, a01) = (a(0, 0) * (1.0 + lambda), a(1, 1) * (1.0 + lambda), a(0, 1));
            let det = a00 * a11 - a01 * a01;
            if det.abs() < 1e-300 {
                return Ok(Step::Singular);
            }
            let dx = [
                (-g[0] * a11 + g[1] * a01) / det,
                (g[0] * a01 - g[1] * a00) / det,
            ];
            if dx[0].abs() + dx[1].abs() < 1e-15 {
                return Ok(Step::Negligible);
            }
            self.evaluations += 1;
            Ok(Step::Trial {
                point: [at[0] + dx[0], at[1] + dx[1]],
                predicted: f64::NAN,
            })
        }

        fn accepted(
            &mut self,
            from: &[f64; 2],
            to: &[f64; 2],
            _: &Progress,
        ) -> Verdict<&'static str> {
            if cost(from) - cost(to) < 1e-14 * (1.0 + cost(to)) {
                Verdict::Converged
            } else {
                Verdict::Continue
            }
        }
    }

    fn rules(limit: Limit) -> Checked {
        Rules::classic(1e-12, limit).checked().unwrap()
    }

    fn problem() -> Rosenbrock {
        Rosenbrock {
            j: [[0.0; 2]; 2],
            r: [0.0; 2],
            evaluations: 0,
        }
    }

    #[test]
    fn rosenbrock_is_minimised_from_its_classic_start() {
        let mut p = problem();
        let end = minimise(&mut p, [-1.2, 1.0], &rules(Limit::Trials(200))).unwrap();
        assert!(end.termination.converged(), "{:?}", end.termination);
        assert!(
            (end.point[0] - 1.0).abs() < 1e-6 && (end.point[1] - 1.0).abs() < 1e-6,
            "{:?}",
            end.point
        );
        assert!(cost(&end.point) < 1e-12);
        assert_eq!(end.trials, p.evaluations);
    }

    #[test]
    fn every_accepted_step_lowers_the_cost() {
        // Run with ever larger limits: the cost at the end never rises with the limit.
        let mut last = f64::INFINITY;
        for n in 1..40 {
            let end = minimise(&mut problem(), [-1.2, 1.0], &rules(Limit::Trials(n))).unwrap();
            let c = cost(&end.point);
            assert!(c <= last, "{n} trials: {c} above {last}");
            last = c;
            if n < 5 {
                assert_eq!(end.termination, Termination::Limit);
                assert_eq!(end.trials, n);
            }
        }
    }

    #[test]
    fn linearisations_are_limited_when_they_are_counted() {
        let end = minimise(
            &mut problem(),
            [-1.2, 1.0],
            &rules(Limit::Linearisations(3)),
        )
        .unwrap();
        assert_eq!(end.termination, Termination::Limit);
        assert_eq!(end.linearisations, 3);
    }

    #[test]
    fn a_stationary_start_ends_at_once() {
        let end = minimise(&mut problem(), [1.0, 1.0], &rules(Limit::Trials(10))).unwrap();
        assert_eq!(end.termination, Termination::Stationary);
        assert_eq!((end.trials, end.linearisations), (0, 1));
    }

    #[test]
    fn rules_out_of_range_are_refused() {
        let good = *rules(Limit::Trials(5)).rules();
        for bad in [
            Rules { raise: 1.0, ..good },
            Rules { first: 0.0, ..good },
            Rules {
                start: -1.0,
                ..good
            },
            Rules { most: 1e-4, ..good },
            Rules {
                limit: Limit::Trials(0),
                ..good
            },
            Rules {
                tries: Some(0),
                ..good
            },
            Rules {
                lower: Lower::Divide {
                    by: 0.5,
                    floor: 0.0,
                },
                ..good
            },
        ] {
            assert!(bad.checked().is_err(), "{bad:?}");
        }
    }

    #[test]
    fn nielsens_factor_lies_between_a_third_and_two() {
        assert!((nielsen(1.0, 1.0) - 1.0 / 3.0).abs() < 1e-15);
        assert!((nielsen(0.0001, 1.0) - 2.0).abs() < 1e-3);
        assert!((nielsen(1.0, f64::NAN) - 1.0 / 3.0).abs() < 1e-15);
        for k in 0..100 {
            let f = nielsen(k as f64 / 50.0, 1.0);
            assert!((1.0 / 3.0..=2.0).contains(&f));
        }
    }
}
