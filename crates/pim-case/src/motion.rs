//! A motion case: one vehicle (or two, each on its own) on its four tyres from a stated state,
//! without an impact, as PC-Crash simulates a vehicle from a position, heading and velocity.
//!
//! ```toml
//! title = "A 2004 Chevrolet Malibu braking from 30 mph"
//! [units]
//! speed = "mph"
//! length = "ft"
//! mass = "lb"
//! yaw_inertia = "slug ft^2"
//!
//! [vehicle1]
//! description = "2004 Chevrolet Malibu"
//! mass = 3298.0
//! yaw_inertia = 2040.0
//!
//! [start.vehicle1]
//! x = 0.0                     # CG position, length unit
//! y = 0.0
//! heading = 0.0               # deg, where the nose points
//! speed = 30.0                # along the heading (or vx, vy in the fixed frame)
//! omega = 0.0                 # yaw rate, the yaw-rate unit (default 0)
//!
//! [runout]
//! friction = 0.76
//! duration = 3.0              # optional: the state after 3 s instead of to rest
//!
//! [runout.vehicle1]
//! wheelbase = 8.833
//! track = 5.0
//! cg_to_front_axle = 3.175
//! wheels = "rolling"
//! inputs = [ { at = 0.0, braking = 1.0, build_up = 0.2 } ]
//! ```
//!
//! The file is a case file without `[impact]`: `[vehicleN]` gives only what the run-out needs
//! (mass, yaw inertia, and the outline for drawings), `[start.vehicleN]` where and how each
//! vehicle starts, and `[runout]` with `[runout.vehicleN]` the road and the wheels exactly as
//! in a case with an impact. Loaded by [`Case::motion_from_text`]; `pim runout` reads either
//! kind.

use crate::case::{error_at, Case, CaseFile};
use crate::error::{InputError, Result};
use crate::parse::{parse_toml, printable};
use crate::scene_sections::RunoutSection;
pub use crate::scene_sections::{is_motion, StartSection, StartWritten};
use crate::sections::{ImpactSection, VehicleSection};
use crate::units::UnitsSection;
use pim_core::Convention;
use pim_runout::Motion;
use serde::Deserialize;

/// A motion case as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct MotionFile {
    #[serde(default)]
    title: Option<String>,
    #[serde(default)]
    convention: Convention,
    #[serde(default)]
    units: UnitsSection,
    vehicle1: MotionVehicle,
    #[serde(default)]
    vehicle2: Option<MotionVehicle>,
    start: StartSection,
    runout: RunoutSection,
}

/// `[vehicleN]` of a motion case: what the run-out needs.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
struct MotionVehicle {
    #[serde(default)]
    description: Option<String>,
    mass: f64,
    yaw_inertia: f64,
    #[serde(default)]
    length: Option<f64>,
    #[serde(default)]
    width: Option<f64>,
    #[serde(default)]
    cg_to_front: Option<f64>,
}

/// The sections a motion case does not have (they belong to an impact).
const IMPACT_ONLY: [&str; 15] = [
    "impact",
    "coefficients",
    "initial",
    "final",
    "estimates",
    "weights",
    "sigma",
    "known",
    "bounds",
    "observations",
    "uncertainty",
    "scene",
    "pre_impact",
    "contact_sigma",
    "damage",
];

impl Case {
    /// Parses a motion case (see the [module](crate::motion)): a case whose content holds the
    /// vehicles, `[start]` and `[runout]` (in SI after loading), used by the run-out alone.
    /// Vehicle 2, when the file has none, is a placeholder barrier without a run-out.
    ///
    /// # Errors
    /// A located [`InputError`] for bad input, or a section that belongs to an impact.
    pub fn motion_from_text(file: &str, text: &str) -> Result<Self> {
        if let Ok(table) = text.parse::<toml::Table>() {
            if let Some(key) = IMPACT_ONLY.iter().find(|k| table.contains_key(**k)) {
                return Err(error_at(
                    file,
                    text,
                    key,
                    "a motion case ([start]: the vehicles from a stated state, no impact) has \
                     no impact sections; leave it out, or leave out [start] for a case with an \
                     impact",
                ));
            }
        }
        let m: MotionFile = parse_toml(file, text)?;
        if m.convention == Convention::Brach {
            return Err(error_at(
                file,
                text,
                "convention",
                "a motion case gives headings where the noses point: \"natural\" or \"sae\"",
            ));
        }
        let u = m.units;
        let length = u.length.to_si();
        let vehicle = |v: &MotionVehicle, heading: f64| VehicleSection {
            description: v.description.as_deref().map(printable),
            barrier: false,
            mass: v.mass * u.mass.to_si(),
            yaw_inertia: v.yaw_inertia * u.yaw_inertia.to_si(),
            heading,
            d: None,
            phi: None,
            impact_point: None,
            position: None,
            length: v.length.map(|x| x * length),
            width: v.width.map(|x| x * length),
            cg_to_front: v.cg_to_front.map(|x| x * length),
            yaw_inertia_source: Default::default(),
        };
        let flip = if m.convention == Convention::Sae {
            -1.0
        } else {
            1.0
        };
        // In the natural frame, as a loaded case's headings are.
        let heading = |s: Option<StartWritten>| s.map_or(f64::NAN, |s| flip * s.heading);
        let vehicle2 = match &m.vehicle2 {
            Some(v) => vehicle(v, heading(m.start.vehicle2)),
            None => VehicleSection {
                description: None,
                barrier: true,
                mass: f64::INFINITY,
                yaw_inertia: f64::INFINITY,
                heading: 0.0,
                d: None,
                phi: None,
                impact_point: None,
                position: None,
                length: None,
                width: None,
                cg_to_front: None,
                yaw_inertia_source: Default::default(),
            },
        };
        let content = CaseFile {
            title: m.title.as_deref().map(printable),
            convention: m.convention,
            units: UnitsSection::default(),
            vehicle1: vehicle(&m.vehicle1, heading(m.start.vehicle1)),
            vehicle2,
            impact: ImpactSection {
                crush_angle: f64::NAN,
                crush_angle_from_vehicle1: None,
                centre: None,
                vehicle1_side: None,
            },
            coefficients: None,
            initial: None,
            final_: None,
            estimates: None,
            weights: None,
            sigma: None,
            known: None,
            bounds: None,
            observations: Vec::new(),
            uncertainty: None,
            runout: Some(m.runout),
            scene: None,
            pre_impact: None,
            contact_sigma: None,
            damage: None,
            background: None,
            survey: None,
            start: Some(m.start),
        };
        let case = Case {
            file: file.to_string(),
            content,
            source: text.to_string(),
            written: m.convention,
            written_units: u,
        };
        case.check_motion(m.vehicle2.is_some())?;
        // The wheels, the road and the inputs, checked now: a motion case is nothing else.
        case.scene_inputs()?;
        Ok(case)
    }

    /// True for a motion case (one loaded by [`Case::motion_from_text`]).
    pub fn is_motion(&self) -> bool {
        self.content.start.is_some()
    }

    fn check_motion(&self, has_vehicle2: bool) -> Result<()> {
        let c = &self.content;
        let start = c.start.unwrap_or_default();
        for (k, (given, st)) in [(true, start.vehicle1), (has_vehicle2, start.vehicle2)]
            .into_iter()
            .enumerate()
        {
            let name = format!("vehicle{}", k + 1);
            let runout = c
                .runout
                .as_ref()
                .and_then(|r| if k == 0 { &r.vehicle1 } else { &r.vehicle2 }.as_ref());
            match (given, st.is_some(), runout.is_some()) {
                (true, true, true) | (false, false, false) => {}
                (false, _, _) => {
                    let at = if st.is_some() { "start" } else { "runout" };
                    return Err(self.error_at(
                        &format!("{at}.{name}"),
                        format!("there is no [{name}]: give its mass and yaw inertia"),
                    ));
                }
                (true, false, _) => {
                    return Err(self.error_at(
                        &name,
                        format!(
                            "needs [start.{name}]: where it starts (x, y, heading) and its \
                             speed (or vx, vy) and yaw rate omega"
                        ),
                    ))
                }
                (true, true, false) => {
                    return Err(self.error_at(
                        &format!("start.{name}"),
                        format!("needs [runout.{name}]: wheelbase, track and the wheels' states"),
                    ))
                }
            }
            if !given {
                continue;
            }
            let v = c.vehicle(k);
            crate::ranges::MASS
                .check(v.mass)
                .map_err(|why| self.error_at(&format!("{name}.mass"), why))?;
            crate::ranges::YAW_INERTIA
                .check(v.yaw_inertia)
                .map_err(|why| self.error_at(&format!("{name}.yaw_inertia"), why))?;
            v.check_outline()
                .map_err(|(field, what)| self.error_at(&format!("{name}.{field}"), what))?;
            let Some(s) = st else { continue };
            let at = |f: &str| format!("start.{name}.{f}");
            for (f, x) in [("x", s.x), ("y", s.y)] {
                if !(x.is_finite() && x.abs() <= 1e5) {
                    return Err(self.error_at(&at(f), format!("{x}: must be a finite position")));
                }
            }
            crate::ranges::ANGLE
                .check(s.heading)
                .map_err(|why| self.error_at(&at("heading"), why))?;
            match (s.speed, s.vx, s.vy) {
                (Some(_), None, None) | (None, Some(_), Some(_)) => {}
                (Some(_), _, _) => {
                    return Err(self.error_at(
                        &at("speed"),
                        "give speed (along the heading) or vx and vy, not both",
                    ))
                }
                _ => {
                    return Err(self.error_at(
                        &format!("start.{name}"),
                        "give speed (along the heading) or both vx and vy",
                    ))
                }
            }
        }
        Ok(())
    }

    /// The stated start of vehicle `k` (0 or 1) of a motion case: SI, natural frame, radians.
    pub(crate) fn stated_start(&self, k: usize) -> Option<std::result::Result<Motion, InputError>> {
        let s = self.content.start?;
        let st = if k == 0 { s.vehicle1 } else { s.vehicle2 }?;
        let u = self.written_units;
        let (speed, rate) = (u.speed.to_si(), u.yaw_rate.to_si());
        let (length, flip) = self.length_and_flip();
        let heading = (flip * st.heading).to_radians();
        let (vx, vy) = match st.speed {
            Some(v) => (v * heading.cos(), v * heading.sin()),
            None => (st.vx.unwrap_or(0.0), flip * st.vy.unwrap_or(0.0)),
        };
        let m = Motion {
            x: st.x * length,
            y: flip * st.y * length,
            heading,
            vx: vx * speed,
            vy: vy * speed,
            yaw_rate: flip * st.omega.unwrap_or(0.0) * rate,
        };
        let name = format!("start.vehicle{}", k + 1);
        Some(m.check().map(|()| m).map_err(|e| match e {
            pim_runout::RunoutError::Input { field, reason } => {
                let key = match field {
                    "yaw_rate" => "omega",
                    "vx" | "vy" if st.speed.is_some() => "speed",
                    f => f,
                };
                self.error_at(&format!("{name}.{key}"), reason)
            }
            other => self.error_at(&name, other),
        }))
    }
}
