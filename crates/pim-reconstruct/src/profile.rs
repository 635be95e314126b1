//! Profile intervals of the speeds at contact.
//!
//! The profile chi-square of a vehicle's forward speed at contact `g` is the lowest
//! chi-square of the whole reconstruction with that speed held:
//! `P(g0) = min { chi2(theta) : g(theta) = g0 }`. Its 90 % interval is the set of speeds whose
//! profile lies within `chi2_1(0.90) = 2.7055` of the answer's chi-square (Wilks): in a linear
//! model with Gaussian errors it is exactly the answer plus or minus 1.645 standard deviations,
//! and where the run-outs bend the chi-square it follows the chi-square, not a straight line
//! through the answer, so it is as wide on each side as the evidence allows there.
//!
//! Each point of the profile is found by a penalty: the reconstruction refitted
//! ([`crate::redo`], the answer's combinations of counts from where they ended) with one more
//! observation, the forward speed `v` at unit weight. Its minimiser `theta_v` is the
//! constrained minimiser at the speed it reaches, `g(theta_v)` (a Lagrange multiplier's
//! argument), so `P(g(theta_v)) = chi2(theta_v) - w (g(theta_v) - v)^2` exactly, whatever the
//! weight. The ends are where `sqrt(P - chi2_min)` (about linear in the speed) crosses
//! `sqrt(2.7055)`: found by steps out from the answer, then regula falsi (Illinois) in `v`.
//!
//! The interval is that of the evidence in the chi-square: a measured input drawn without
//! being evidence (a braking share's spread, say) widens only the study's draws.

use crate::{redo, Outcome, Reconstruction, Result, Settings};
use pim_core::VehicleId;
use pim_fit::{Observation, ObservationKind};
use statrs::distribution::{ChiSquared, ContinuousCDF};

/// The level of the profile intervals (the study's intervals are its draws' 5th to 95th
/// percentiles: the same level).
pub const PROFILE_LEVEL: f64 = 0.90;

/// Counts of turns whose answer lies within this chi-square of the best are refitted at every
/// point of the profile (as in a study's draw).
const COUNTS_MARGIN: f64 = 4.0;

/// Refits per end at most.
const MAX_REFITS: usize = 12;

/// The first step out from the answer, m/s.
const FIRST_STEP: f64 = 0.5;

/// An end is taken once `sqrt(P - chi2_min)` is within this of its target (a chi-square
/// within about 0.1 of the rise at 2.7).
const CLOSE: f64 = 0.03;

/// One end of a profile interval.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct ProfileEnd {
    /// The speed at contact there, m/s (the last speed tried where the end was not reached).
    pub speed: f64,
    /// The profile rose by the interval's chi-square there; `false`: it had not risen that
    /// far at the last speed tried (the evidence does not bound the speed on this side within
    /// the refits allowed, or no refit answered).
    pub reached: bool,
    /// Refits of the reconstruction made for this end.
    pub refits: usize,
}

/// A vehicle's 90 % profile interval of its speed at contact.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct ProfileInterval {
    /// The lower end.
    pub lower: ProfileEnd,
    /// The upper end.
    pub upper: ProfileEnd,
}

/// The chi-square's rise that bounds an interval of `level` of one quantity (`2.7055` for
/// 0.90).
pub fn profile_rise(level: f64) -> f64 {
    ChiSquared::new(1.0).map_or(f64::NAN, |c| c.inverse_cdf(level))
}

/// A point of the profile: the pull's target, the forward speed reached, `sqrt(P - chi2_min)`,
/// the speed at contact.
#[derive(Debug, Clone, Copy)]
struct Point {
    pull: f64,
    forward: f64,
    height: f64,
    speed: f64,
}

/// A point of a profile, as [`profile_point`] gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfilePoint {
    /// The vehicle's forward speed at contact reached, m/s.
    pub forward: f64,
    /// Its speed at contact there, m/s.
    pub speed: f64,
    /// The profile chi-square there: the lowest chi-square of the reconstruction with that
    /// forward speed.
    pub chi_square: f64,
}

/// The forward speed at contact of `vehicle` in `found`.
fn forward(r: &Reconstruction, found: &crate::Found, vehicle: VehicleId) -> f64 {
    let a = r.contact.impact.forward_axis(vehicle);
    let u = found.solution.initial.vehicle(vehicle);
    u.vx * a[0] + u.vy * a[1]
}

/// The profile at the forward speed that `nominal`'s answer, refitted with `vehicle`'s forward
/// speed at contact pulled toward `pull` (m/s, at unit weight), reaches. `None` where no
/// combination refits.
///
/// # Errors
/// Input the search cannot use.
pub fn profile_point(
    r: &Reconstruction,
    settings: &Settings,
    nominal: &Outcome,
    vehicle: VehicleId,
    pull: f64,
) -> Result<Option<ProfilePoint>> {
    let mut pulled = r.clone();
    pulled.contact.observations.push(Observation {
        kind: ObservationKind::SpeedAlongHeading,
        vehicle,
        value: pull,
        weight: 1.0,
    });
    let unit = pulled.unit.unwrap_or(1.0);
    let Some(found) = redo(&pulled, settings, nominal, COUNTS_MARGIN)? else {
        return Ok(None);
    };
    let g = forward(r, &found, vehicle);
    let Some(phase) = found.phases.iter().find(|p| p.vehicle == vehicle) else {
        return Ok(None);
    };
    Ok(Some(ProfilePoint {
        forward: g,
        speed: phase.contact,
        chi_square: found.chi_square - (g - pull).powi(2) / unit,
    }))
}

/// [`profile_point`] as a height above the answer's chi-square `lowest`.
fn pulled(
    r: &Reconstruction,
    settings: &Settings,
    nominal: &Outcome,
    (vehicle, v): (VehicleId, f64),
    lowest: f64,
) -> Result<Option<Point>> {
    Ok(
        profile_point(r, settings, nominal, vehicle, v)?.map(|p| Point {
            pull: v,
            forward: p.forward,
            height: (p.chi_square - lowest).max(0.0).sqrt(),
            speed: p.speed,
        }),
    )
}

/// One end (`sign` -1: lower, +1: upper) of `vehicle`'s profile interval at `level` around
/// `nominal`'s answer. `None` where `nominal` has no answer.
///
/// # Errors
/// Input the search cannot use.
pub fn profile_end(
    r: &Reconstruction,
    settings: &Settings,
    nominal: &Outcome,
    vehicle: VehicleId,
    (level, sign): (f64, f64),
) -> Result<Option<ProfileEnd>> {
    let Some(best) = &nominal.best else {
        return Ok(None);
    };
    let Some(phase) = best.phases.iter().find(|p| p.vehicle == vehicle) else {
        return Ok(None);
    };
    let target = profile_rise(level).sqrt();
    let g0 = forward(r, best, vehicle);
    // The speed is the forward speed's magnitude (it is the speed itself in every crash that
    // drives forward): its lower end moves the forward speed toward zero, its upper end away,
    // and neither crosses zero (a reversed vehicle is another answer, not a slower one) nor the
    // search's velocity bound (past which no refit can follow the pull).
    let bound = settings.fit.get().velocity_bound;
    let toward = if g0 < 0.0 { -sign } else { sign };
    let range = if g0 < 0.0 {
        (-bound, 0.0)
    } else {
        (0.0, bound)
    };
    let mut inside = Point {
        pull: g0,
        forward: g0,
        height: 0.0,
        speed: phase.contact,
    };
    let mut outside: Option<Point> = None;
    // Regula falsi's values at the ends (height minus target); Illinois halves the value of
    // the end kept twice running.
    let (mut f_in, mut f_out) = (-target, 0.0);
    let mut last_replaced_inside: Option<bool> = None;
    let mut step = FIRST_STEP;
    let mut refits = 0;
    while refits < MAX_REFITS {
        let v = match outside {
            None => {
                let v = (inside.pull + toward * step).clamp(range.0, range.1);
                if (v - inside.pull).abs() < 1e-9 {
                    // At the edge of the range with the profile still inside: not reached.
                    break;
                }
                v
            }
            Some(o) => inside.pull + (o.pull - inside.pull) * f_in / (f_in - f_out),
        };
        refits += 1;
        let Some(p) = pulled(r, settings, nominal, (vehicle, v), best.chi_square)? else {
            step *= 0.5;
            continue;
        };
        if (p.height - target).abs() < CLOSE {
            return Ok(Some(ProfileEnd {
                speed: p.speed,
                reached: true,
                refits,
            }));
        }
        let replaces_inside = p.height < target;
        if replaces_inside {
            if outside.is_none() {
                // Out along the profile's slope so far: at least the last step, at most four
                // times it.
                let run = (p.forward - inside.forward).abs().max(1e-9);
                let slope = (p.height - inside.height) / run;
                let wanted = if slope > 0.0 {
                    1.1 * (target - p.height) / slope
                } else {
                    4.0 * step
                };
                step = wanted.clamp(step, 4.0 * step);
            } else if last_replaced_inside == Some(true) {
                f_out *= 0.5;
            }
            inside = p;
            f_in = p.height - target;
        } else {
            if last_replaced_inside == Some(false) {
                f_in *= 0.5;
            }
            outside = Some(p);
            f_out = p.height - target;
        }
        last_replaced_inside = outside.map(|_| replaces_inside);
        if outside.is_some_and(|o| (o.pull - inside.pull).abs() < 1e-3) {
            break;
        }
    }
    Ok(Some(match outside {
        Some(o) => {
            let t = ((target - inside.height) / (o.height - inside.height)).clamp(0.0, 1.0);
            ProfileEnd {
                speed: inside.speed + t * (o.speed - inside.speed),
                reached: true,
                refits,
            }
        }
        None => ProfileEnd {
            speed: inside.speed,
            reached: false,
            refits,
        },
    }))
}

/// Both ends of `vehicle`'s profile interval at `level` around `nominal`'s answer
/// ([`profile_end`] each). `None` where `nominal` has no answer.
///
/// # Errors
/// Input the search cannot use.
pub fn profile_interval(
    r: &Reconstruction,
    settings: &Settings,
    nominal: &Outcome,
    vehicle: VehicleId,
    level: f64,
) -> Result<Option<ProfileInterval>> {
    let end = |sign| profile_end(r, settings, nominal, vehicle, (level, sign));
    Ok(match (end(-1.0)?, end(1.0)?) {
        (Some(lower), Some(upper)) => Some(ProfileInterval { lower, upper }),
        _ => None,
    })
}
