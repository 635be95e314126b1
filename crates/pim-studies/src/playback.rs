//! The motion played back: each vehicle from where its braking before the impact began through
//! contact to rest, as the answer has it, for the editor's time slider and the animated
//! figure.
//!
//! Time is 0 at contact, negative before it, seconds. Before contact a vehicle that braked
//! (`[pre_impact.vehicleN] skid`) slides straight along its velocity at contact with the
//! constant deceleration that takes the answer's speed where the braking began, `v0`, to its
//! speed at contact, `vc`, over the skid's length `d`:
//! ```text
//! a = (v0^2 - vc^2) / (2 d),   T = 2 d / (v0 + vc),   s(tau) = vc tau + a tau^2 / 2
//! ```
//! (`tau = -t`, the time before contact, and `s` the distance back from the contact pose); its
//! heading is held at its heading at contact (the impact model's vehicles track). A vehicle
//! without a skid is shown for [`APPROACH`] before contact at its contact velocity. The impact
//! itself takes no time (the positions at separation are those at contact), and from contact
//! each vehicle follows the answer's own fitted run-out ([`crate::runout::fitted`]) to rest:
//! no run-out is simulated again here.

use crate::reconstruct::Reconstructed;
use crate::runout::RunoutResult;
use pim_core::VehicleId;
use pim_reconstruct::Found;
use pim_runout::Motion;

/// How long a vehicle without a skid is shown before contact, s.
pub const APPROACH: f64 = 1.0;

/// One vehicle's motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    /// Which vehicle.
    pub vehicle: VehicleId,
    /// Its index among the fitted run-out's vehicles (`RunoutResult::inputs`), for its outline.
    pub index: usize,
    /// Whether it braked before contact (else it approached at its contact velocity).
    pub braking: bool,
    /// Its poses and velocities in time order, SI and the natural frame: the first where its
    /// braking began (or [`APPROACH`] before contact), one at time 0 (the pose at contact, the
    /// velocities at separation), the last at rest.
    pub poses: Vec<(f64, Motion)>,
}

/// How a vehicle came to contact in the answer: its speed there and the braking before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeadIn {
    /// Its velocity at contact (m/s, natural frame).
    pub velocity: pim_core::VehicleVelocity,
    /// Its speed at contact, m/s.
    pub speed: f64,
    /// How long before contact its braking began (a skid), else [`APPROACH`], s.
    pub duration: f64,
    /// Its deceleration over that time, m/s^2 (0 without a skid).
    pub deceleration: f64,
    /// Whether it braked before contact (`[pre_impact.vehicleN] skid`).
    pub braking: bool,
}

impl LeadIn {
    /// Its speed `tau` seconds before contact (m/s): braking, `vc + a tau` back to where the
    /// braking began and the speed there before it; else its speed at contact.
    pub fn speed_before(&self, tau: f64) -> f64 {
        self.speed + self.deceleration * tau.clamp(0.0, self.duration)
    }
}

/// The lead-in of vehicle `id` in the answer `best` of `done` (see the module's docs).
pub fn lead_in(done: &Reconstructed, best: &Found, id: VehicleId) -> LeadIn {
    let velocity = if id == VehicleId::One {
        best.solution.initial.vehicle1
    } else {
        best.solution.initial.vehicle2
    };
    let speed = velocity.vx.hypot(velocity.vy);
    let before = best
        .phases
        .iter()
        .find(|p| p.vehicle == id)
        .and_then(|p| p.before_braking);
    let skid = done.input.reconstruction.skids[id.index()].as_ref();
    let (duration, deceleration, braking) = match (before, skid) {
        (Some(v0), Some(s)) if s.distance > 0.0 && v0 + speed > 1e-9 => (
            2.0 * s.distance / (v0 + speed),
            (v0 * v0 - speed * speed) / (2.0 * s.distance),
            true,
        ),
        _ => (APPROACH, 0.0, false),
    };
    LeadIn {
        velocity,
        speed,
        duration,
        deceleration,
        braking,
    }
}

/// Each vehicle of the fitted run-outs `fitted` (of the answer `best` of `done`) sampled every
/// `dt` seconds (times before contact counted back from it, so that 0 is always a sample), the
/// rest its last sample.
pub fn tracks(done: &Reconstructed, best: &Found, fitted: &RunoutResult, dt: f64) -> Vec<Track> {
    let dt = if dt.is_finite() && dt > 0.0 { dt } else { 0.05 };
    fitted
        .inputs
        .iter()
        .zip(&fitted.runouts)
        .enumerate()
        .map(|(index, (input, run))| {
            let id = input.id;
            let lead = lead_in(done, best, id);
            let (speed, v) = (lead.speed, lead.velocity);
            let u = if speed > 1e-9 {
                [v.vx / speed, v.vy / speed]
            } else {
                [run.start.heading.cos(), run.start.heading.sin()]
            };
            let (duration, a, braking) = (lead.duration, lead.deceleration, lead.braking);
            let at = |tau: f64| {
                let s = speed * tau + 0.5 * a * tau * tau;
                let now = speed + a * tau;
                Motion {
                    x: run.start.x - s * u[0],
                    y: run.start.y - s * u[1],
                    heading: run.start.heading,
                    vx: now * u[0],
                    vy: now * u[1],
                    yaw_rate: 0.0,
                }
            };
            let steps = (duration / dt).ceil() as usize;
            let mut poses: Vec<(f64, Motion)> = (1..=steps)
                .rev()
                .map(|i| {
                    let tau = (i as f64 * dt).min(duration);
                    (-tau, at(tau))
                })
                .collect();
            poses.extend(run.sample(dt));
            Track {
                vehicle: id,
                index,
                braking,
                poses,
            }
        })
        .collect()
}

/// The pose of `track` at time `t` (linear between its samples; before its first, its first;
/// after its last, at rest).
pub fn pose_at(track: &Track, t: f64) -> Motion {
    let p = &track.poses;
    let Some(first) = p.first() else {
        return Motion::default();
    };
    if t <= first.0 {
        return first.1;
    }
    let k = p.partition_point(|(s, _)| *s <= t);
    if k >= p.len() {
        return p[p.len() - 1].1;
    }
    let ((t0, a), (t1, b)) = (p[k - 1], p[k]);
    let w = if t1 > t0 { (t - t0) / (t1 - t0) } else { 1.0 };
    let mix = |x: f64, y: f64| x + w * (y - x);
    Motion {
        x: mix(a.x, b.x),
        y: mix(a.y, b.y),
        heading: mix(a.heading, b.heading),
        vx: mix(a.vx, b.vx),
        vy: mix(a.vy, b.vy),
        yaw_rate: mix(a.yaw_rate, b.yaw_rate),
    }
}
