//! The driver's inputs of a run-out (`[runout.vehicleN] inputs`), read into pim-runout's
//! [`Input`]s: SI, natural frame, radians.
//!
//! ```toml
//! [runout.vehicle1]
//! wheels = "rolling"            # the wheels at separation
//! steer_ratio = 16.0            # for inputs that give a steering-wheel angle
//! inputs = [
//!   { at = 0.8, braking = 0.9, build_up = 0.25 },   # the driver brakes 0.8 s after the impact
//!   { at = 1.5, steering_wheel = -90.0, build_up = 0.4 },
//!   { at = 3.0, braking = 0.0 },                     # and lets go of the brake
//! ]
//! ```
//!
//! Each input starts `at` seconds after separation and moves its values linearly, over
//! `build_up` seconds (default 0), from what they were to what it gives: `braking`, the braking
//! share (0 to 1) of every wheel that is not locked (0 is a free-rolling wheel; a locked wheel
//! stays locked), or shares per axle and wheel (`{ front = 0.9, rear = 0.5 }`, `{ front_left =
//! 0.9 }`; a wheel named itself takes precedence over its axle, a wheel not named keeps its
//! share); `steer`, the front wheels' angles (one for both, or `{ front_left,
//! front_right }`, degrees, counter-clockwise in the natural frame and clockwise in SAE's, as
//! `steer`), or `steering_wheel`, a steering-wheel angle turned into Ackermann angles with the
//! vehicle's `steer_ratio`. A value an input does not give keeps what it was. Times must be in
//! order. An input with `distance` (the case's length unit) starts once the CG has travelled that
//! far since separation, and not before its `at` (default 0 then) nor before the input before
//! it (PC-Crash's sequences by distance).

use crate::case::Case;
use crate::error::Result;
use crate::scene_sections::{BrakingWritten, RunoutVehicleSection, SteerWritten};
use pim_runout::Input;

impl Case {
    /// The inputs of `[runout.{name}]`, in the natural frame (`flip` -1 for an SAE case).
    pub(crate) fn inputs_of(
        &self,
        name: &str,
        w: &RunoutVehicleSection,
        flip: f64,
    ) -> Result<Vec<Input>> {
        let Some(written) = &w.inputs else {
            return Ok(Vec::new());
        };
        let length = self.written_units.length.to_si();
        let mut out = Vec::with_capacity(written.len());
        for (k, i) in written.iter().enumerate() {
            let at = |key: &str| format!("runout.{name}.inputs.{k}.{key}");
            let steer = match (i.steer, i.steering_wheel) {
                (Some(_), Some(_)) => {
                    return Err(self.error_at(
                        &at("steering_wheel"),
                        "give either steer (the wheels' angles) or steering_wheel, not both",
                    ))
                }
                (Some(SteerWritten::Both(a)), None) => Some([a; 2].map(|a| flip * a.to_radians())),
                (Some(SteerWritten::Each(f)), None) => {
                    Some([f.front_left, f.front_right].map(|a| flip * a.to_radians()))
                }
                (None, Some(sw)) => {
                    let Some(ratio) = w.steer_ratio.filter(|r| r.is_finite() && *r >= 1.0) else {
                        return Err(self.error_at(
                            &at("steering_wheel"),
                            format!(
                                "needs the vehicle's steer_ratio (runout.{name}.steer_ratio, at \
                                 least 1; about 16 for a car)"
                            ),
                        ));
                    };
                    let delta = flip * (sw / ratio).to_radians();
                    let angles =
                        pim_runout::ackermann(delta, w.wheelbase * length, w.track * length)
                            .ok_or_else(|| {
                                self.error_at(
                                    &at("steering_wheel"),
                                    format!(
                                        "{sw} deg over a ratio of {ratio} turns the inner wheel \
                                         90 deg or more for this wheelbase and track"
                                    ),
                                )
                            })?;
                    Some(angles)
                }
                (None, None) => None,
            };
            let braking = self.braking_of(&at("braking"), i.braking.as_ref())?;
            if braking.iter().all(Option::is_none) && steer.is_none() {
                return Err(self.error_at(
                    &at("at"),
                    "gives neither braking nor steer (or steering_wheel): nothing changes",
                ));
            }
            if i.at.is_none() && i.distance.is_none() {
                return Err(self.error_at(
                    &format!("runout.{name}.inputs.{k}"),
                    "give when it starts: at (seconds after separation) or distance (travelled \
                     since separation, the length unit)",
                ));
            }
            let input = Input {
                at: i.at.unwrap_or(0.0),
                braking,
                steer,
                build_up: i.build_up.unwrap_or(0.0),
                distance: i.distance.map(|d| d * length),
            };
            if let Err((key, why)) = input.check() {
                return Err(self.error_at(&at(key), why));
            }
            let by_distance = written.iter().any(|i| i.distance.is_some());
            if !by_distance && out.last().is_some_and(|p: &Input| input.at < p.at) {
                return Err(self.error_at(
                    &at("at"),
                    format!(
                        "{} s: the inputs must be written in the order of their times",
                        input.at
                    ),
                ));
            }
            out.push(input);
        }
        Ok(out)
    }

    /// An input's braking shares per wheel (front left, front right, rear left, rear right):
    /// one share for all, or by axle and wheel, a wheel named itself taking precedence over
    /// its axle. `path` is the field, for messages.
    fn braking_of(&self, path: &str, b: Option<&BrakingWritten>) -> Result<[Option<f64>; 4]> {
        let share = |at: &str, b: f64| {
            if b.is_finite() && (0.0..=1.0).contains(&b) {
                Ok(b)
            } else {
                Err(self.error_at(at, format!("braking share {b} must lie between 0 and 1")))
            }
        };
        match b {
            None => Ok([None; 4]),
            Some(BrakingWritten::All(b)) => Ok([Some(share(path, *b)?); 4]),
            Some(BrakingWritten::Each(map)) => {
                let mut out = [None; 4];
                for (key, wheels) in [("front", [0, 1]), ("rear", [2, 3])] {
                    if let Some(&b) = map.get(key) {
                        let b = share(&format!("{path}.{key}"), b)?;
                        wheels.iter().for_each(|&w| out[w] = Some(b));
                    }
                }
                for (w, name) in pim_runout::WHEEL_NAMES.iter().enumerate() {
                    if let Some(&b) = map.get(*name) {
                        out[w] = Some(share(&format!("{path}.{name}"), b)?);
                    }
                }
                if let Some(unknown) = map.keys().find(|k| {
                    !(k.as_str() == "front"
                        || k.as_str() == "rear"
                        || pim_runout::WHEEL_NAMES.contains(&k.as_str()))
                }) {
                    return Err(self.error_at(
                        &format!("{path}.{unknown}"),
                        format!(
                            "not an axle or a wheel; give front, rear or a wheel ({})",
                            pim_runout::WHEEL_NAMES.join(", ")
                        ),
                    ));
                }
                Ok(out)
            }
        }
    }
}
