//! The cost of one candidate: the residuals of a run-out against the evidence.

use super::evidence::{Evidence, Quantity, Residual, MAX_SEARCH_SPEED, MAX_SEARCH_YAW_RATE};
use crate::chassis::{Chassis, Motion};
use crate::error::{Result, RunoutError};
use crate::forces::Dynamics;
use crate::simulate::{hermite, replay, run, Runout, Settings};
use nalgebra::DVector;
use std::f64::consts::{PI, TAU};

/// The problem of one candidate.
pub(crate) struct Problem<'a> {
    pub(crate) chassis: &'a Chassis,
    pub(crate) start: Motion,
    pub(crate) evidence: &'a Evidence,
    /// Target heading at rest (unwrapped for this candidate), rad.
    pub(crate) heading: Option<f64>,
    pub(crate) settings: &'a Settings,
    pub(crate) estimate_friction: bool,
    /// Right-hand side evaluations of every run-out of this problem so far (failed ones too).
    pub(crate) work: std::sync::atomic::AtomicU64,
}

impl<'a> Problem<'a> {
    /// The same problem with its run-outs on `settings` (its own count of work).
    pub(crate) fn on<'b>(&self, settings: &'b Settings) -> Problem<'b>
    where
        'a: 'b,
    {
        Problem {
            chassis: self.chassis,
            start: self.start,
            evidence: self.evidence,
            heading: self.heading,
            settings,
            estimate_friction: self.estimate_friction,
            work: Default::default(),
        }
    }

    pub(crate) fn n(&self) -> usize {
        if self.estimate_friction {
            4
        } else {
            3
        }
    }

    pub(crate) fn runout(&self, theta: &[f64]) -> Result<Runout> {
        self.runout_through(theta, None)
            .expect("a run-out without a nominal is always simulated")
    }

    /// The run-out from `theta`: simulated, or with `nominal` integrated through its accepted
    /// steps ([`crate::simulate::replay`]; `None` when it cannot be).
    pub(crate) fn runout_through(
        &self,
        theta: &[f64],
        nominal: Option<&Runout>,
    ) -> Option<Result<Runout>> {
        if !(theta[0].hypot(theta[1]) <= MAX_SEARCH_SPEED && theta[2].abs() <= MAX_SEARCH_YAW_RATE)
        {
            return Some(Err(RunoutError::Input {
                field: "separation",
                reason: format!(
                    "the search left the separation states of a road crash (speed {:.1} m/s, \
                     yaw rate {:.1} rad/s)",
                    theta[0].hypot(theta[1]),
                    theta[2]
                ),
            }));
        }
        let mut chassis = self.chassis.clone();
        if self.estimate_friction {
            // The friction stays inside the model's range while searched.
            chassis.friction = theta[3].clamp(0.02, crate::chassis::MAX_FRICTION);
            chassis.rolling_resistance = chassis.rolling_resistance.min(0.5 * chassis.friction);
        }
        let start = Motion {
            vx: theta[0],
            vy: theta[1],
            yaw_rate: theta[2],
            ..self.start
        };
        let dynamics = Dynamics::new(&chassis);
        let r = match nominal {
            None => run(&dynamics, &start, self.settings),
            Some(n) => Ok(replay(&dynamics, &start, self.settings, n)?),
        };
        let spent = match &r {
            Ok(x) => u64::from(x.evaluations),
            Err(RunoutError::Integration { evaluations, .. }) => *evaluations,
            Err(_) => 1,
        };
        self.work
            .fetch_add(spent, std::sync::atomic::Ordering::Relaxed);
        Some(r)
    }

    /// The residuals (fitted minus given, and their sigmas) of a run-out.
    pub(crate) fn residuals(&self, theta: &[f64], r: &Runout) -> Vec<Residual> {
        let mut out = Vec::new();
        let res = |what: Quantity, value: f64, sigma: f64| Residual {
            what,
            name: what.name(),
            value,
            sigma,
        };
        if let Some(rest) = &self.evidence.rest {
            // The rest position of the point the scene gives (the CG, or tyres' centroid).
            let (x, y) = r.rest.point(rest.point);
            out.push(res(Quantity::RestX, x - rest.x, rest.sigma_xy[0]));
            out.push(res(Quantity::RestY, y - rest.y, rest.sigma_xy[1]));
            if let Some(h) = self.heading {
                out.push(res(
                    Quantity::RestHeading,
                    r.rest.heading - h,
                    rest.sigma_heading,
                ));
            }
        }
        for (i, m) in self.evidence.marks.iter().enumerate() {
            let (d, heading) = closest(r, m.x, m.y, m.point);
            out.push(res(Quantity::Mark { index: i }, d, m.sigma));
            if let Some((h, s)) = m.heading {
                let diff = wrap(heading - h);
                out.push(res(Quantity::MarkHeading { index: i }, diff, s));
            }
        }
        if let (true, Some(s)) = (self.estimate_friction, self.evidence.friction_sigma) {
            out.push(res(Quantity::Friction, theta[3] - self.chassis.friction, s));
        }
        out
    }

    pub(crate) fn weighted(&self, theta: &[f64]) -> Result<(DVector<f64>, Runout)> {
        let r = self.runout(theta)?;
        Ok((self.weigh(theta, &r), r))
    }

    /// The weighted residuals from `theta`, a state stepped from that of the run-out `nominal`
    /// (what a derivative differences): on the run-out integrated through `nominal`'s accepted
    /// steps where it can be replayed (internal numerical differentiation), else on a run-out
    /// with steps of its own.
    pub(crate) fn stepped(&self, theta: &[f64], nominal: &Runout) -> Result<DVector<f64>> {
        match self.runout_through(theta, Some(nominal)) {
            Some(r) => Ok(self.weigh(theta, &r?)),
            None => Ok(self.weighted(theta)?.0),
        }
    }

    /// The relative difference step of derivatives around the run-out `nominal`, as
    /// [`Problem::stepped`] integrates the stepped run-outs: [`INTERNAL_STEP`] through
    /// `nominal`'s steps, else the square root of the run-outs' tolerance (which keeps their
    /// noise and the truncation error alike small).
    pub(crate) fn difference_step(&self, nominal: &Runout) -> f64 {
        if self.can_replay(nominal) {
            INTERNAL_STEP
        } else {
            self.settings.rtol.sqrt()
        }
    }

    /// The change of the cost (the sum of the squared weighted residuals `r`, on the run-out
    /// `run`) that the run-outs' tolerance can resolve: a run-out integrated to the relative
    /// tolerance `rtol` carries errors of about `rtol` times the magnitude of each integrated
    /// quantity (the step control's scale), so each weighted residual carries about
    /// `d = rtol (1 + S) / sigma`, with `S` the distance travelled plus the start's distance
    /// from the origin for positions and the rotation plus the start's heading for headings;
    /// the cost then carries `sum 2 |r| d + d^2`. A gain below it cannot be told from the
    /// run-outs' noise (an order of magnitude, not a bound: the search stops trying there).
    pub(crate) fn noise(&self, r: &DVector<f64>, run: &Runout) -> f64 {
        let rtol = self.settings.rtol;
        let length = 1.0 + run.distance + self.start.x.hypot(self.start.y);
        let angle = 1.0 + run.rotation.abs() + self.start.heading.abs();
        let mut scales: Vec<f64> = Vec::with_capacity(r.len());
        if let Some(rest) = &self.evidence.rest {
            let arm = rest.point[0].hypot(rest.point[1]) * angle;
            scales.push((length + arm) / rest.sigma_xy[0]);
            scales.push((length + arm) / rest.sigma_xy[1]);
            if self.heading.is_some() {
                scales.push(angle / rest.sigma_heading);
            }
        }
        for m in &self.evidence.marks {
            scales.push((length + m.point[0].hypot(m.point[1]) * angle) / m.sigma);
            if let Some((_, s)) = m.heading {
                scales.push(angle / s);
            }
        }
        r.iter()
            .zip(scales.iter().chain(std::iter::repeat(&0.0)))
            .map(|(ri, scale)| {
                let d = rtol * scale;
                2.0 * ri.abs() * d + d * d
            })
            .sum()
    }

    /// Whether run-outs of this problem can be integrated through `nominal`'s steps.
    pub(crate) fn can_replay(&self, nominal: &Runout) -> bool {
        nominal.integrated.is_some() && !self.chassis.inputs.iter().any(|i| i.distance.is_some())
    }

    fn weigh(&self, theta: &[f64], r: &Runout) -> DVector<f64> {
        let res = self.residuals(theta, r);
        DVector::from_iterator(res.len(), res.iter().map(|x| x.value / x.sigma))
    }
}

/// The residuals of `evidence` against a run-out computed elsewhere (from separation velocities
/// a solve or a fit gave): the rest heading is compared with the nearest of its full turns.
pub fn residuals_of(chassis: &Chassis, evidence: &Evidence, runout: &Runout) -> Vec<Residual> {
    let heading = evidence
        .rest
        .and_then(|r| r.heading)
        .map(|h| h + TAU * ((runout.rest.heading - h) / TAU).round());
    let settings = Settings::default();
    let p = Problem {
        chassis,
        start: runout.start,
        evidence,
        heading,
        settings: &settings,
        estimate_friction: false,
        work: Default::default(),
    };
    p.residuals(&[], runout)
}

/// The distance of `q` from the segment from `a` to `b`.
fn chord_distance(q: (f64, f64), a: (f64, f64), b: (f64, f64)) -> f64 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let len2 = dx * dx + dy * dy;
    let s = if len2 > 0.0 {
        (((q.0 - a.0) * dx + (q.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (q.0 - a.0 - s * dx).hypot(q.1 - a.1 - s * dy)
}

/// The relative difference step of a derivative by internal numerical differentiation: the
/// replayed run-outs differ from the nominal only through the unknown stepped (no step-size
/// control of their own, whose decisions would add the tolerance's noise), so the step is set by
/// the truncation error (of order the step) against the rounding of the nominal's step times
/// (of order 1e-13 of the residuals), not by the tolerance.
pub(crate) const INTERNAL_STEP: f64 = 1e-6;

/// Wraps an angle to (-pi, pi].
fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w > PI {
        w - TAU
    } else {
        w
    }
}

/// The signed distance of the point `(px, py)` from the path of the vehicle's point `at`
/// (metres ahead of the CG and to its left; `[0, 0]` the CG): positive to the left of that
/// point's direction of travel, the full distance when the closest point is an end of the
/// path; and the heading at the closest point.
fn closest(r: &Runout, px: f64, py: f64, at: [f64; 2]) -> (f64, f64) {
    let steps = &r.steps;
    // The point's position and velocity at a motion.
    let traced = |m: &Motion| {
        let (s, c) = m.heading.sin_cos();
        let (ox, oy) = (c * at[0] - s * at[1], s * at[0] + c * at[1]);
        (
            (m.x + ox, m.y + oy),
            (m.vx - m.yaw_rate * oy, m.vy + m.yaw_rate * ox),
        )
    };
    let dist2 = |m: &Motion| {
        let (p, _) = traced(m);
        (p.0 - px).powi(2) + (p.1 - py).powi(2)
    };
    if steps.len() < 2 {
        let m = r.rest;
        return (dist2(&m).sqrt(), m.heading);
    }
    // Coarse: eight points in every step; then Newton on (p(t) - q) . p'(t) = 0. A step none of
    // whose points can be nearer than the nearest step end is passed over (the same point is
    // found): the CG's cubic `p0 + h01 (p1 - p0) + h (h10 m0 + h11 m1)` lies within
    // `h (4/27) (|m0| + |m1|)` of the chord from p0 to p1 (`h01` in [0, 1], `|h10|, |h11|` at
    // most 4/27); a point at `|at|` from the CG moves at most `|at| |yaw rate|` faster, so
    // within twice the step's rotation times `|at|` more of its chord.
    let arm = at[0].hypot(at[1]);
    let nearest_end = steps
        .iter()
        .map(|s| dist2(&s.motion))
        .fold(f64::INFINITY, f64::min);
    let mut best = (f64::INFINITY, 0usize, 0.0);
    for k in 1..steps.len() {
        let (a, b) = (&steps[k - 1].motion, &steps[k].motion);
        let h = steps[k].time - steps[k - 1].time;
        let turn = (a.yaw_rate.abs() + b.yaw_rate.abs()) * h;
        let bulge = h * (4.0 / 27.0) * (a.vx.hypot(a.vy) + b.vx.hypot(b.vy)) + 2.0 * arm * turn;
        let (pa, pb) = (traced(a).0, traced(b).0);
        let below = chord_distance((px, py), pa, pb) - 1.001 * bulge - 1e-9;
        if below > 0.0 && below * below > nearest_end {
            continue;
        }
        for j in 0..=8 {
            let s = j as f64 / 8.0;
            let t = steps[k - 1].time + s * (steps[k].time - steps[k - 1].time);
            let d = dist2(&hermite(&steps[k - 1], &steps[k], t));
            if d < best.0 {
                best = (d, k, t);
            }
        }
    }
    let (_, k, mut t) = best;
    let (a, b) = (&steps[k - 1], &steps[k]);
    let h = 1e-7 * (b.time - a.time).max(1e-9);
    for _ in 0..20 {
        let f = |t: f64| {
            let (p, v) = traced(&hermite(a, b, t));
            (p.0 - px) * v.0 + (p.1 - py) * v.1
        };
        let (f0, f1) = (f(t), f(t + h));
        let df = (f1 - f0) / h;
        if df.abs() < 1e-300 {
            break;
        }
        let next = (t - f0 / df).clamp(a.time, b.time);
        let done = (next - t).abs() < 1e-13 * (1.0 + t.abs());
        t = next;
        if done {
            break;
        }
    }
    let m = hermite(a, b, t);
    let (p, v) = traced(&m);
    let (dx, dy) = (px - p.0, py - p.1);
    let speed = v.0.hypot(v.1);
    let interior = t > steps[0].time && t < r.time;
    if interior && speed > 1e-9 {
        ((v.0 * dy - v.1 * dx) / speed, m.heading)
    } else {
        (dx.hypot(dy), m.heading)
    }
}
