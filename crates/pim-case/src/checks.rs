//! The checks of a loaded case's numbers: every velocity a number, every number with a
//! physical range within it (in SI, see [`crate::ranges`]), the drawing dimensions; a case
//! file's vehicles by number.

use crate::case::{finite, Case, CaseFile};
use crate::error::Result;
use crate::ranges::{Range, ANGLE, DISTANCE, FRICTION, MASS, SPEED, YAW_INERTIA, YAW_RATE};
use crate::sections::{VehicleSection, AT_REST};

impl Case {
    /// Every velocity component the case gives (its states, estimates and known components)
    /// and every observation value, with its path and its physical range.
    fn velocities(&self) -> Vec<(String, f64, Range)> {
        let c = &self.content;
        let range = |field: &str| if field == "omega" { YAW_RATE } else { SPEED };
        let mut out = Vec::new();
        for (name, s) in [("initial", &c.initial), ("final", &c.final_)] {
            let Some(s) = s else { continue };
            let vehicle2 = s.vehicle2.unwrap_or(AT_REST);
            for (veh, v) in [("vehicle1", s.vehicle1), ("vehicle2", vehicle2)] {
                for (field, x) in [("vx", v.vx), ("vy", v.vy), ("omega", v.omega)] {
                    out.push((format!("{name}.{veh}.{field}"), x, range(field)));
                }
            }
        }
        for (name, s) in [("estimates", &c.estimates), ("known", &c.known)] {
            let Some(s) = s else { continue };
            for (state, st) in [("initial", &s.initial), ("final", &s.final_)] {
                let Some(st) = st else { continue };
                for (veh, v) in [("vehicle1", st.vehicle1), ("vehicle2", st.vehicle2)] {
                    for (field, x) in [("vx", v.vx), ("vy", v.vy), ("omega", v.omega)] {
                        if let Some(x) = x {
                            out.push((format!("{name}.{state}.{veh}.{field}"), x, range(field)));
                        }
                    }
                }
            }
        }
        for (i, o) in c.observations.iter().enumerate() {
            out.push((format!("observations[{i}].value"), o.value, SPEED));
        }
        out
    }

    /// Every velocity the case gives is a number (its range is checked in SI, see
    /// `check_ranges`).
    pub(crate) fn check_states(&self) -> Result<()> {
        for (path, x, _) in self.velocities() {
            finite(&self.file, &self.source, &path, x)?;
        }
        Ok(())
    }

    /// Checks every number with a physical range (in SI, after `[units]`; see
    /// [`crate::ranges`]): masses, yaw inertias, headings, impact centres, the crush angle and
    /// every velocity and observation.
    pub(crate) fn check_ranges(&self) -> Result<()> {
        let c = &self.content;
        let mut checks: Vec<(String, f64, Range)> = Vec::new();
        for (name, v) in [("vehicle1", &c.vehicle1), ("vehicle2", &c.vehicle2)] {
            if v.barrier {
                continue;
            }
            checks.push((format!("{name}.mass"), v.mass, MASS));
            // An estimated inertia is checked with the outline it comes from.
            if v.yaw_inertia_source == crate::sections::InertiaSource::Stated {
                checks.push((format!("{name}.yaw_inertia"), v.yaw_inertia, YAW_INERTIA));
            }
            checks.push((format!("{name}.heading"), v.heading, ANGLE));
            if v.impact_point.is_some() {
                checks.push((format!("{name}.impact_point"), v.d(), DISTANCE));
            } else {
                checks.push((format!("{name}.d"), v.d(), DISTANCE));
                checks.push((format!("{name}.phi"), v.phi(), ANGLE));
            }
        }
        checks.push(("impact.crush_angle".into(), c.impact.crush_angle, ANGLE));
        // Every friction the case writes, where it writes it (a skid's and a vehicle's default
        // to the road's, so a bad road friction is named as the road's).
        if let Some(r) = &c.runout {
            checks.extend(r.friction.map(|f| ("runout.friction".into(), f, FRICTION)));
            for (name, v) in [("vehicle1", &r.vehicle1), ("vehicle2", &r.vehicle2)] {
                if let Some(f) = v.as_ref().and_then(|v| v.friction) {
                    checks.push((format!("runout.{name}.friction"), f, FRICTION));
                }
            }
        }
        if let Some(p) = &c.pre_impact {
            for (name, v) in [("vehicle1", &p.vehicle1), ("vehicle2", &p.vehicle2)] {
                if let Some(f) = v.as_ref().and_then(|v| v.friction) {
                    checks.push((format!("pre_impact.{name}.friction"), f, FRICTION));
                }
            }
        }
        checks.extend(self.velocities());
        for (path, x, range) in checks {
            range.check(x).map_err(|why| {
                let si = if matches!(range.unit, "deg" | "") {
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
            if v.yaw_inertia_source == crate::sections::InertiaSource::Outline {
                YAW_INERTIA.check(v.yaw_inertia).map_err(|why| {
                    self.error_at(
                        &format!("{name}.yaw_inertia"),
                        format!(
                            "estimated from the mass, length and width: {why}; give the yaw \
                             inertia"
                        ),
                    )
                })?;
            }
        }
        Ok(())
    }
}

impl CaseFile {
    /// Vehicle `k` (0 or 1).
    pub fn vehicle(&self, k: usize) -> &VehicleSection {
        if k == 0 {
            &self.vehicle1
        } else {
            &self.vehicle2
        }
    }

    /// Vehicle `k`'s (0 or 1) `[pre_impact.vehicleN]`, if the case writes one.
    pub fn pre_impact(&self, k: usize) -> Option<&crate::scene_sections::PreImpactVehicleSection> {
        let p = self.pre_impact.as_ref()?;
        if k == 0 {
            p.vehicle1.as_ref()
        } else {
            p.vehicle2.as_ref()
        }
    }

    /// Vehicle `k` (0 or 1), to change.
    pub fn vehicle_mut(&mut self, k: usize) -> &mut VehicleSection {
        if k == 0 {
            &mut self.vehicle1
        } else {
            &mut self.vehicle2
        }
    }
}
