//! The run-out and the scene of a case: `[runout]` (road friction, its zones and, per vehicle,
//! its wheels) and `[scene.vehicleN]` (rest position and heading, marks), read into
//! pim-runout's inputs.
//!
//! ```toml
//! [runout]
//! friction = 0.7                # road friction (default 0.7, dry asphalt)
//! friction_sigma = 0.05         # optional: estimate the friction around it with this sd
//! duration = 0.5                # optional: follow each run-out this long, s (not to rest)
//!
//! [runout.vehicle1]
//! wheelbase = 2.8               # length unit
//! track = 1.55
//! cg_to_front_axle = 1.25
//! cg_height = 0.55              # optional: load transfer
//! wheels = "locked"             # "locked", "rolling", a braking share 0-1, or per wheel:
//! # wheels = { front_left = "locked", front_right = "rolling", rear_left = 0.3, rear_right = "rolling" }
//! braking = 0.0                 # braking share of the wheels given as "rolling"
//! steer = 0.0                   # deg, front wheels (counter-clockwise; SAE: clockwise), or
//! # steer = { front_left = 6.1, front_right = 4.4 }   # each front wheel, or
//! # steering_wheel = 90.0       # deg, with steer_ratio = 16.0: the Ackermann angles of 90/16
//! # inputs = [ { at = 0.8, braking = 0.9, build_up = 0.25 } ]   # the driver's inputs in time
//! #                             # (see the scene_inputs module)
//!
//! [scene.vehicle1]
//! rest = { x = 14.2, y = 3.1, heading = 215.0 }
//! rest_sigma = { x = 0.1, y = 0.1, heading = 2.0 }
//! marks = [ { x = 6.0, y = 1.2, sigma = 0.15 } ]   # points the CG passed (heading optional)
//! turns = 1                     # optional: the count of full turns, when known
//! ```
//!
//! Positions are in the case's fixed frame and length unit (the frame of `[impact] centre` and
//! the vehicles' `position`s; with neither, the impact centre is the origin), headings and
//! angles in degrees, in the case's convention (an SAE case gives y to the right and angles
//! clockwise).

use crate::case::{error_at, Case};
use crate::error::{InputError, Result};
use crate::scene_sections::{
    MarkPoint, RunoutVehicleSection, SceneVehicleSection, SteerWritten, WheelWritten, WheelsWritten,
};
use pim_core::{Convention, VehicleId};
use pim_runout::{Chassis, Evidence, Mark, Motion, Rest, RunoutError, WheelState};

/// One vehicle's run-out inputs, SI, natural frame, radians.
#[derive(Debug, Clone)]
pub struct VehicleRunout {
    /// Which vehicle.
    pub id: VehicleId,
    /// Its wheels and the road.
    pub chassis: Chassis,
    /// Position and heading at separation (those at contact; velocities 0), or a motion
    /// case's stated start (with its velocities).
    pub start: Motion,
    /// The scene's evidence, when the case gives any.
    pub evidence: Option<Evidence>,
    /// The tyre contact points measured at rest (`rest_tyres`), m: what the evidence's rest
    /// stands for, for drawing.
    pub rest_tyres: Vec<[f64; 2]>,
}

/// The run-out inputs of a case.
#[derive(Debug, Clone)]
pub struct SceneInputs {
    /// The vehicles with a `[runout.vehicleN]` section (a barrier has none).
    pub vehicles: Vec<VehicleRunout>,
    /// The time limit, s (the duration when one is stated).
    pub time_limit: f64,
    /// `[runout] duration`, s: each run-out followed for this long, its end the state then.
    pub duration: Option<f64>,
}

impl Case {
    /// True when the case has a `[runout]` or a `[scene]` section.
    pub fn has_runout(&self) -> bool {
        self.content.runout.is_some() || self.content.scene.is_some()
    }

    /// The contact velocities the case estimates (`[estimates.initial]`, all six given), in
    /// the natural frame and SI.
    pub fn estimated_contact(&self) -> Option<pim_core::Velocities> {
        let est = self.content.estimates?.initial?.components();
        let v: Option<Vec<f64>> = est.iter().copied().collect();
        v.map(|v| {
            pim_core::Velocities::from_vector(&nalgebra::Vector6::new(
                v[0], v[1], v[2], v[3], v[4], v[5],
            ))
        })
    }

    /// Where the impact centre lies in the case's fixed frame: natural axes, m (the case's
    /// `[impact] centre`, or the origin).
    pub fn impact_centre(&self) -> [f64; 2] {
        let (length, flip) = self.length_and_flip();
        self.content
            .impact
            .centre
            .as_ref()
            .map_or([0.0, 0.0], |p| [p.x * length, flip * p.y * length])
    }

    /// The written length unit, m, and the sign of the written y (SAE: y to the right, -1).
    pub fn length_and_flip(&self) -> (f64, f64) {
        let sae = self.written == Convention::Sae;
        (
            self.written_units.length.to_si(),
            if sae { -1.0 } else { 1.0 },
        )
    }

    /// The run-out inputs: the chassis of each vehicle with a `[runout.vehicleN]`, its pose at
    /// contact and its scene evidence, converted to SI and the natural frame.
    ///
    /// # Errors
    /// A located [`InputError`] for a missing section, a field the run-out model cannot use,
    /// or scene evidence without a `[runout]` section for its vehicle.
    pub fn scene_inputs(&self) -> Result<SceneInputs> {
        let c = &self.content;
        let Some(runout) = &c.runout else {
            return Err(InputError::new(
                &self.file,
                "[scene] needs [runout]: the road friction and, per vehicle, \
                 [runout.vehicleN] with wheelbase, track and the wheels' states (see `pim runout \
                 --help`)",
            ));
        };
        // A motion case states each start; a case with an impact starts at contact.
        let impact = if self.is_motion() {
            None
        } else {
            Some(self.impact()?)
        };
        // SAE: y to the right, angles clockwise; the natural frame: y left, counter-clockwise.
        let (length, flip) = self.length_and_flip();
        let centre = self.impact_centre();
        let cgs = impact.as_ref().map(pim_core::Impact::cg_positions);
        let zones = self.zones_of(&runout.zones, (length, flip))?;
        let mut vehicles = Vec::new();
        for (k, id) in [VehicleId::One, VehicleId::Two].into_iter().enumerate() {
            let name = format!("vehicle{}", k + 1);
            let section = if k == 0 {
                &runout.vehicle1
            } else {
                &runout.vehicle2
            };
            let scene = c
                .scene
                .as_ref()
                .and_then(|s| if k == 0 { &s.vehicle1 } else { &s.vehicle2 }.as_ref());
            let Some(w) = section else {
                if scene.is_some() {
                    return Err(self.error_at(
                        &format!("scene.{name}"),
                        format!(
                            "scene evidence of {name} needs [runout.{name}] (wheelbase, track, \
                             wheels) to simulate its run-out"
                        ),
                    ));
                }
                continue;
            };
            if c.vehicle(k).barrier {
                return Err(self.error_at(
                    &format!("runout.{name}"),
                    "a barrier does not move after the impact: leave out its run-out",
                ));
            }
            let chassis = self.chassis_of(k, w, (runout.friction, &zones), (length, flip))?;
            let start = match (&impact, cgs) {
                (Some(impact), Some(cgs)) => Motion {
                    x: centre[0] + cgs[k][0],
                    y: centre[1] + cgs[k][1],
                    heading: impact.nose_heading(id).to_radians(),
                    ..Motion::default()
                },
                _ => self.stated_start(k).ok_or_else(|| {
                    self.error_at(
                        &format!("start.{name}"),
                        "missing: where the vehicle starts",
                    )
                })??,
            };
            let evidence = match scene {
                Some(s) => Some(self.evidence_of(&name, s, &chassis, runout.friction_sigma)?),
                None => None,
            };
            let rest_tyres = match scene {
                Some(s) => self.tyre_points(&name, s, (length, flip))?,
                None => Vec::new(),
            };
            vehicles.push(VehicleRunout {
                id,
                chassis,
                start,
                evidence,
                rest_tyres: rest_tyres.into_iter().map(|t| t.1).collect(),
            });
        }
        if vehicles.is_empty() {
            return Err(self.error_at(
                "runout",
                "no vehicle to run out: give [runout.vehicle1] (and [runout.vehicle2]) with \
                 wheelbase, track and the wheels' states",
            ));
        }
        let time_limit = runout.time_limit.unwrap_or(60.0);
        if !(time_limit.is_finite() && time_limit > 0.0 && time_limit <= 3600.0) {
            return Err(self.error_at(
                "runout.time_limit",
                format!("{time_limit}: must be above 0 and at most 3600 s"),
            ));
        }
        let duration = runout.duration;
        if let Some(d) = duration {
            if runout.time_limit.is_some() {
                return Err(self.error_at(
                    "runout.duration",
                    "give a duration (the motion for that long) or a time limit (to rest, given \
                     up after it), not both",
                ));
            }
            if !(d.is_finite() && d > 0.0 && d <= 3600.0) {
                return Err(self.error_at(
                    "runout.duration",
                    format!("{d}: must be above 0 and at most 3600 s"),
                ));
            }
        }
        Ok(SceneInputs {
            vehicles,
            time_limit: duration.unwrap_or(time_limit),
            duration,
        })
    }

    /// The chassis of vehicle `k` (0 or 1) from its `[runout.vehicleN]` section `w`, the road's
    /// friction `road` and its `zones` (lengths by `length`, angles mirrored by `flip`), checked.
    ///
    /// # Errors
    /// A located error for a field the run-out model cannot use.
    fn chassis_of(
        &self,
        k: usize,
        w: &RunoutVehicleSection,
        (road, zones): (Option<f64>, &[pim_runout::Zone]),
        (length, flip): (f64, f64),
    ) -> Result<Chassis> {
        let name = format!("vehicle{}", k + 1);
        let at = |field: &str| format!("runout.{name}.{field}");
        let vs = self.content.vehicle(k);
        let friction = w.friction.or(road).unwrap_or(pim_runout::DEFAULT_FRICTION);
        // One of three ways to give the linear tyre's slope (see RunoutVehicleSection).
        let given: Vec<&str> = [
            ("saturation_angle", w.saturation_angle.is_some()),
            ("cornering_stiffness", w.cornering_stiffness.is_some()),
            ("max_slip_angle", w.max_slip_angle.is_some()),
        ]
        .iter()
        .filter(|(_, g)| *g)
        .map(|(n, _)| *n)
        .collect();
        if given.len() > 1 {
            return Err(self.error_at(
                &at(given[1]),
                format!(
                    "give one of saturation_angle, cornering_stiffness and max_slip_angle \
                     (PC-Crash's), not {}",
                    given.join(" and ")
                ),
            ));
        }
        let positive = |key: &str, v: f64, unit: &str| {
            if v.is_finite() && v > 0.0 {
                Ok(v)
            } else {
                Err(self.error_at(&at(key), format!("{v}: must be above 0 ({unit})")))
            }
        };
        let saturation = if let Some(a) = w.saturation_angle {
            a.to_radians()
        } else if let Some(cs) = w.cornering_stiffness {
            let cs = positive("cornering_stiffness", cs, "per unit load, per degree")?;
            (friction / cs).to_radians()
        } else if let Some(m) = w.max_slip_angle {
            // PC-Crash: F/Fz = min(alpha / m, friction), so the force saturates at
            // friction x m.
            (friction * positive("max_slip_angle", m, "degrees")?).to_radians()
        } else {
            pim_runout::DEFAULT_SATURATION_ANGLE
        };
        let braking = w.braking.unwrap_or(0.0);
        let wheels =
            self.wheels_of(&format!("runout.{name}.wheels"), w.wheels.as_ref(), braking)?;
        let chassis = Chassis {
            mass: vs.mass,
            yaw_inertia: vs.yaw_inertia,
            wheelbase: w.wheelbase * length,
            cg_to_front_axle: w.cg_to_front_axle.unwrap_or(w.wheelbase / 2.0) * length,
            track: w.track * length,
            cg_height: w.cg_height.map(|h| h * length),
            wheels,
            steer: self.steer_of(&name, w, flip)?,
            friction,
            rolling_resistance: w
                .rolling_resistance
                .unwrap_or(pim_runout::DEFAULT_ROLLING_RESISTANCE),
            saturation_angle: saturation,
            length: vs.length,
            width: vs.width,
            cg_to_front: vs.cg_to_front,
            inputs: self.inputs_of(&name, w, flip)?,
            zones: zones.to_vec(),
        };
        chassis.check().map_err(|e| self.runout_error(&name, e))?;
        if let Some(b) = w.braking {
            if !(b.is_finite() && (0.0..=1.0).contains(&b)) {
                return Err(self.error_at(&at("braking"), format!("{b}: must lie between 0 and 1")));
            }
        }
        Ok(chassis)
    }

    /// An error of pim-runout about vehicle `name`, placed at its field in the case.
    pub fn runout_error(&self, name: &str, e: RunoutError) -> InputError {
        match e {
            RunoutError::Input { field, reason } => {
                let section = match field {
                    f if f.starts_with("rest") || f.starts_with("marks") || f == "turns" => "scene",
                    "mass" | "yaw_inertia" => {
                        return self.error_at(&format!("{name}.{field}"), reason)
                    }
                    "friction_sigma" => return self.error_at("runout.friction_sigma", reason),
                    "zones" => return self.error_at("runout.zones", reason),
                    "friction" => {
                        let at = self
                            .written_friction_at(name)
                            .unwrap_or_else(|| "runout.friction".to_string());
                        return self.error_at(&at, reason);
                    }
                    "x" | "y" | "heading" | "vx" | "vy" | "yaw_rate" => {
                        return InputError::new(
                            &self.file,
                            format!("{name}: separation {field}: {reason}"),
                        )
                    }
                    _ => "runout",
                };
                self.error_at(&format!("{section}.{name}.{field}"), reason)
            }
            other => InputError::new(&self.file, format!("{name}: {other}")),
        }
    }

    fn written_friction_at(&self, name: &str) -> Option<String> {
        let r = self.content.runout.as_ref()?;
        let v = if name == "vehicle1" {
            &r.vehicle1
        } else {
            &r.vehicle2
        };
        if v.as_ref()?.friction.is_some() {
            Some(format!("runout.{name}.friction"))
        } else {
            None
        }
    }

    /// The front wheels' steer angles (left, right; rad, natural frame) of `[runout.vehicleN]`:
    /// `steer` (one angle or one per wheel), or `steering_wheel / steer_ratio` through
    /// Ackermann geometry (pim-runout's `ackermann`).
    fn steer_of(&self, name: &str, w: &RunoutVehicleSection, flip: f64) -> Result<[f64; 2]> {
        let at = |k: &str| format!("runout.{name}.{k}");
        // A ratio for the inputs' steering-wheel angles alone stands without a steering wheel.
        let for_inputs = w.steering_wheel.is_none()
            && w.inputs
                .as_ref()
                .is_some_and(|v| v.iter().any(|i| i.steering_wheel.is_some()));
        let ratio = if for_inputs { None } else { w.steer_ratio };
        let degrees =
            match (w.steer, w.steering_wheel, ratio) {
                (Some(_), Some(_), _) => return Err(self.error_at(
                    &at("steering_wheel"),
                    "give either steer (the wheels' angles) or steering_wheel with steer_ratio, \
                     not both",
                )),
                (_, Some(_), None) => return Err(self.error_at(
                    &at("steering_wheel"),
                    "needs steer_ratio (steering-wheel degrees per degree of the wheels, about \
                     16 for a car)",
                )),
                (_, None, Some(_)) => {
                    return Err(self.error_at(
                        &at("steer_ratio"),
                        "goes with steering_wheel (the steering-wheel angle, degrees)",
                    ))
                }
                (None, None, None) => [0.0; 2],
                (Some(SteerWritten::Both(a)), None, None) => [a; 2],
                (Some(SteerWritten::Each(f)), None, None) => [f.front_left, f.front_right],
                (None, Some(sw), Some(ratio)) => {
                    if !(ratio.is_finite() && ratio >= 1.0) {
                        return Err(self.error_at(
                            &at("steer_ratio"),
                            format!("{ratio}: must be at least 1 (about 16 for a car)"),
                        ));
                    }
                    let track = w.track * self.written_units.length.to_si();
                    let wheelbase = w.wheelbase * self.written_units.length.to_si();
                    let delta = flip * (sw / ratio).to_radians();
                    let angles =
                        pim_runout::ackermann(delta, wheelbase, track).ok_or_else(|| {
                            self.error_at(
                                &at("steering_wheel"),
                                format!(
                            "{sw} deg over a ratio of {ratio} turns the inner wheel 90 deg or \
                             more for this wheelbase and track"
                        ),
                            )
                        })?;
                    // Already in the natural frame.
                    return Ok(angles);
                }
            };
        if let Some(a) = degrees.iter().find(|a| !(a.is_finite() && a.abs() < 90.0)) {
            return Err(self.error_at(
                &at("steer"),
                format!("{a}: must lie between -90 and 90 deg"),
            ));
        }
        Ok(degrees.map(|a| flip * a.to_radians()))
    }

    /// The wheel states `written` (at `base` in the file) with the rolling wheels' braking
    /// share `braking`: checked, each wheel's path named in a refusal.
    ///
    /// # Errors
    /// A located error: a word that is no wheel state, a share outside 0-1, a wheel missing or
    /// unknown.
    pub fn wheels_of(
        &self,
        base: &str,
        written: Option<&WheelsWritten>,
        braking: f64,
    ) -> Result<[WheelState; 4]> {
        let one = |w: &WheelWritten, path: &str| -> Result<WheelState> {
            match w {
                WheelWritten::Word(s) => match s.to_ascii_lowercase().as_str() {
                    "locked" | "sliding" | "damaged" => Ok(WheelState::Locked),
                    "rolling" | "free" => Ok(if braking > 0.0 {
                        WheelState::Braked(braking)
                    } else {
                        WheelState::Rolling
                    }),
                    _ => Err(error_at(
                        &self.file,
                        &self.source,
                        path,
                        format!(
                            "{s:?} is not a wheel state; accepted: \"locked\" (also \"sliding\", \
                             \"damaged\"), \"rolling\" (also \"free\"), or a braking share from \
                             0 to 1"
                        ),
                    )),
                },
                WheelWritten::Share(b) => {
                    if b.is_finite() && (0.0..=1.0).contains(b) {
                        Ok(if *b > 0.0 {
                            WheelState::Braked(*b)
                        } else {
                            WheelState::Rolling
                        })
                    } else {
                        Err(error_at(
                            &self.file,
                            &self.source,
                            path,
                            format!("braking share {b}: must lie between 0 and 1"),
                        ))
                    }
                }
            }
        };
        match written {
            None => Ok([WheelState::Locked; 4]),
            Some(WheelsWritten::All(w)) => Ok([one(w, base)?; 4]),
            Some(WheelsWritten::Each(map)) => {
                if let Some(unknown) = map
                    .keys()
                    .find(|k| !pim_runout::WHEEL_NAMES.contains(&k.as_str()))
                {
                    return Err(self.error_at(
                        &format!("{base}.{unknown}"),
                        format!(
                            "not a wheel; the wheels are {}",
                            pim_runout::WHEEL_NAMES.join(", ")
                        ),
                    ));
                }
                let mut out = [WheelState::Locked; 4];
                for (i, wheel) in pim_runout::WHEEL_NAMES.iter().enumerate() {
                    match map.get(*wheel) {
                        Some(w) => out[i] = one(w, &format!("{base}.{wheel}"))?,
                        None => {
                            return Err(self.error_at(
                                base,
                                format!(
                                    "{wheel} missing: give all four wheels ({}), or one state \
                                     for all",
                                    pim_runout::WHEEL_NAMES.join(", ")
                                ),
                            ))
                        }
                    }
                }
                Ok(out)
            }
        }
    }

    /// The scene's positions and headings of `[scene.name]` within their ranges, in the
    /// file's own words (degrees, its length unit), before conversion.
    fn check_places(&self, name: &str, s: &SceneVehicleSection, length: f64) -> Result<()> {
        let at = |field: &str| format!("scene.{name}.{field}");
        let unit = self.written_units.length;
        let reach = pim_runout::inverse::MAX_SCENE_DISTANCE / length;
        let mut places: Vec<(String, f64, bool)> = Vec::new();
        if let Some(r) = &s.rest {
            places.extend([(at("rest.x"), r.x, false), (at("rest.y"), r.y, false)]);
            if let Some(h) = r.heading {
                places.push((at("rest.heading"), h, true));
            }
        }
        for (i, m) in s.marks.iter().enumerate() {
            let mark = |f: &str| format!("scene.{name}.marks[{i}].{f}");
            places.extend([(mark("x"), m.x, false), (mark("y"), m.y, false)]);
            if let Some(h) = m.heading {
                places.push((mark("heading"), h, true));
            }
        }
        for (path, x, angle) in places {
            let (lim, what) = if angle {
                (360.0, "deg".to_string())
            } else {
                let u = match unit {
                    crate::units::LengthUnit::Metre => "m",
                    crate::units::LengthUnit::Foot => "ft",
                };
                (reach, format!("{u} (10 km)"))
            };
            if !(x.is_finite() && x.abs() <= lim) {
                return Err(self.error_at(
                    &path,
                    format!("{x}: must be a number from -{lim} to {lim} {what}"),
                ));
            }
        }
        Ok(())
    }

    fn evidence_of(
        &self,
        name: &str,
        s: &SceneVehicleSection,
        chassis: &Chassis,
        friction_sigma: Option<f64>,
    ) -> Result<Evidence> {
        let (length, flip) = self.length_and_flip();
        let at = |field: &str| format!("scene.{name}.{field}");
        self.check_places(name, s, length)?;
        let tyres = self.rest_of_tyres(name, s, chassis, (length, flip))?;
        let rest = match (s.rest.clone(), s.rest_sigma) {
            _ if tyres.is_some() => tyres.map(|t| t.rest),
            (None, None) => None,
            (None, Some(_)) => {
                return Err(self.error_at(&at("rest_sigma"), "rest_sigma without rest"));
            }
            (Some(_), None) => {
                return Err(self.error_at(
                    &at("rest"),
                    "the rest position needs its standard deviations: rest_sigma = { x = .., \
                     y = .., heading = .. }",
                ))
            }
            (Some(r), Some(sd)) => {
                let sigma_heading = match (r.heading, sd.heading) {
                    (Some(_), None) => {
                        return Err(self.error_at(
                            &at("rest_sigma"),
                            "the rest heading needs its standard deviation: rest_sigma.heading",
                        ))
                    }
                    (_, h) => h.unwrap_or(1.0).to_radians(),
                };
                Some(Rest {
                    x: r.x * length,
                    y: flip * r.y * length,
                    heading: r.heading.map(|h| flip * h.to_radians()),
                    sigma_xy: [sd.x * length, sd.y * length],
                    sigma_heading,
                    point: [0.0, 0.0],
                })
            }
        };
        let mut marks = Vec::new();
        for (i, m) in s.marks.iter().enumerate() {
            let heading = match (m.heading, m.heading_sigma) {
                (Some(h), Some(sd)) => Some((flip * h.to_radians(), sd.to_radians())),
                (None, None) => None,
                _ => {
                    return Err(self.error_at(
                        &format!("scene.{name}.marks[{i}]"),
                        "a mark's heading and heading_sigma come together",
                    ))
                }
            };
            // A wheel's contact point in the vehicle's frame (ahead of the CG, to its left):
            // the wheels are physical, the frame's y axis only a direction of writing.
            let point = m
                .wheel
                .and_then(MarkPoint::wheel)
                .map_or([0.0, 0.0], |w| chassis.wheel_position(w));
            marks.push(Mark {
                x: m.x * length,
                y: flip * m.y * length,
                sigma: m.sigma * length,
                heading,
                point,
            });
        }
        marks.extend(self.trace_marks(name, s, chassis, (length, flip))?);
        let evidence = Evidence {
            rest,
            marks,
            turns: s.turns.map(|t| if flip < 0.0 { -t } else { t }),
            friction_sigma,
        };
        evidence.check().map_err(|e| match e {
            RunoutError::Input { field, reason } => {
                let path = match field {
                    "friction_sigma" => "runout.friction_sigma".to_string(),
                    f if f.starts_with("marks") => at("marks"),
                    f => at(f),
                };
                self.error_at(&path, reason)
            }
            other => InputError::new(&self.file, format!("{name}: {other}")),
        })?;
        Ok(evidence)
    }
}
