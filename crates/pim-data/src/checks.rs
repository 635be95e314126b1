//! The checks of a loaded case's numbers: every velocity a number, every number with a
//! physical range within it (in SI, see [`crate::ranges`]), the drawing dimensions.

use crate::case::{finite, Case};
use crate::error::Result;
use crate::sections::AT_REST;

impl Case {
    pub(crate) fn check_states(&self) -> Result<()> {
        // Every velocity the case gives is a number (its range is checked in SI, see
        // `check_ranges`).
        let mut given: Vec<(String, f64)> = Vec::new();
        for (name, s) in [
            ("initial", &self.content.initial),
            ("final", &self.content.final_),
        ] {
            if let Some(s) = s {
                let vehicle2 = s.vehicle2.unwrap_or(AT_REST);
                for (veh, v) in [("vehicle1", s.vehicle1), ("vehicle2", vehicle2)] {
                    for (field, x) in [("vx", v.vx), ("vy", v.vy), ("omega", v.omega)] {
                        given.push((format!("{name}.{veh}.{field}"), x));
                    }
                }
            }
        }
        for (name, s) in [
            ("estimates", &self.content.estimates),
            ("known", &self.content.known),
        ] {
            let Some(s) = s else { continue };
            for (state, st) in [("initial", &s.initial), ("final", &s.final_)] {
                let Some(st) = st else { continue };
                for (veh, v) in [("vehicle1", st.vehicle1), ("vehicle2", st.vehicle2)] {
                    for (field, x) in [("vx", v.vx), ("vy", v.vy), ("omega", v.omega)] {
                        if let Some(x) = x {
                            given.push((format!("{name}.{state}.{veh}.{field}"), x));
                        }
                    }
                }
            }
        }
        for (path, x) in given {
            finite(&self.file, &self.source, &path, x)?;
        }
        for (i, o) in self.content.observations.iter().enumerate() {
            finite(
                &self.file,
                &self.source,
                &format!("observations[{i}].value"),
                o.value,
            )?;
        }
        Ok(())
    }

    /// Checks every number with a physical range (in SI, after `[units]`; see
    /// [`crate::ranges`]): masses, yaw inertias, headings, impact centres, the crush angle and
    /// every velocity and observation.
    pub(crate) fn check_ranges(&self) -> Result<()> {
        use crate::ranges::{ANGLE, DISTANCE, MASS, SPEED, YAW_INERTIA, YAW_RATE};
        let c = &self.content;
        let mut checks: Vec<(String, f64, crate::ranges::Range)> = Vec::new();
        for (name, v) in [("vehicle1", &c.vehicle1), ("vehicle2", &c.vehicle2)] {
            if v.barrier {
                continue;
            }
            checks.push((format!("{name}.mass"), v.mass, MASS));
            checks.push((format!("{name}.yaw_inertia"), v.yaw_inertia, YAW_INERTIA));
            checks.push((format!("{name}.heading"), v.heading, ANGLE));
            if v.impact_point.is_some() {
                checks.push((format!("{name}.impact_point"), v.d(), DISTANCE));
            } else {
                checks.push((format!("{name}.d"), v.d(), DISTANCE));
                checks.push((format!("{name}.phi"), v.phi(), ANGLE));
            }
        }
        checks.push(("impact.crush_angle".into(), c.impact.crush_angle, ANGLE));
        for (name, s) in [("initial", &c.initial), ("final", &c.final_)] {
            let Some(s) = s else { continue };
            let vehicle2 = s.vehicle2.unwrap_or(AT_REST);
            for (veh, v) in [("vehicle1", s.vehicle1), ("vehicle2", vehicle2)] {
                checks.push((format!("{name}.{veh}.vx"), v.vx, SPEED));
                checks.push((format!("{name}.{veh}.vy"), v.vy, SPEED));
                checks.push((format!("{name}.{veh}.omega"), v.omega, YAW_RATE));
            }
        }
        for (name, s) in [("estimates", &c.estimates), ("known", &c.known)] {
            let Some(s) = s else { continue };
            for (state, st) in [("initial", &s.initial), ("final", &s.final_)] {
                let Some(st) = st else { continue };
                for (veh, v) in [("vehicle1", st.vehicle1), ("vehicle2", st.vehicle2)] {
                    for (field, x, range) in [
                        ("vx", v.vx, SPEED),
                        ("vy", v.vy, SPEED),
                        ("omega", v.omega, YAW_RATE),
                    ] {
                        if let Some(x) = x {
                            checks.push((format!("{name}.{state}.{veh}.{field}"), x, range));
                        }
                    }
                }
            }
        }
        for (i, o) in c.observations.iter().enumerate() {
            checks.push((format!("observations[{i}].value"), o.value, SPEED));
        }
        for (path, x, range) in checks {
            range.check(x).map_err(|why| {
                let si = if matches!(range.unit, "deg") {
                    ""
                } else {
                    " (in SI, after [units])"
                };
                let hint = if range.unit == "rad/s"
                    && self.written_units.yaw_rate == crate::units::YawRateUnit::RadiansPerSecond
                {
                    "; degrees per second meant? set [units] yaw_rate = \"deg/s\""
                } else {
                    ""
                };
                self.error_at(&path, format!("{why}{si}{hint}"))
            })?;
        }
        Ok(())
    }

    /// Checks the drawing dimensions (in SI) of both vehicles.
    pub(crate) fn check_outlines(&self) -> Result<()> {
        let c = &self.content;
        for (name, v) in [("vehicle1", &c.vehicle1), ("vehicle2", &c.vehicle2)] {
            v.check_outline()
                .map_err(|(field, what)| self.error_at(&format!("{name}.{field}"), what))?;
        }
        Ok(())
    }
}
