//! The forms a user may write a crash in, reduced to the one form the rest of the program reads.
//!
//! - Velocities: `{ vx, vy }` in the case's fixed frame, `{ speed, direction }` (direction in
//!   degrees in that frame), or `{ forward, lateral }` in the vehicle's own frame (lateral
//!   towards +90 deg from the nose: to the left in the natural form, to the right in SAE's).
//! - The impact centre: in each vehicle's frame (`impact_point`, or `d` and `phi`), or once in
//!   the fixed frame (`[impact] centre`) with each vehicle's CG `position`.
//! - The crush surface: `crush_angle` from the fixed x axis, or `crush_angle_from_vehicle1` from
//!   vehicle 1's nose.
//! - `convention = "sae"` (x forward, y right, angles and yaw clockwise): mirrored into the
//!   natural form (every y, angle and yaw rate changes sign; a lateral observation too).
//!
//! Each form is exact: the same crash in any of them loads to the same numbers (to round-off).
//! The reduction runs in the file's units, before the conversion to SI (directions are degrees
//! whatever the units).

use crate::case::Case;
use crate::error::Result;
use crate::sections::{PartialState, PartialStates, PartialVelocity, PointSection, StateSection};
use crate::spread::Spread;
use pim_core::{wrap_degrees, Convention, VehicleId};

/// `(cos, sin)` of an angle in degrees.
fn unit(deg: f64) -> [f64; 2] {
    let r = deg.to_radians();
    [r.cos(), r.sin()]
}

/// Reduces a velocity written as `{ speed, direction }` or `{ forward, lateral }` to `vx`, `vy`,
/// given the direction the vehicle's nose points (degrees in the file's frame), and clears the
/// alternative fields. An error text when a form is half-given or two are mixed.
fn resolve_velocity(v: &mut PartialVelocity, nose: f64) -> std::result::Result<(), String> {
    let cartesian = v.vx.is_some() || v.vy.is_some();
    let polar = v.speed.is_some() || v.direction.is_some();
    let body = v.forward.is_some() || v.lateral.is_some();
    if usize::from(cartesian) + usize::from(polar) + usize::from(body) > 1 {
        return Err(
            "give the velocity in one form: { vx, vy }, { speed, direction } or \
                    { forward, lateral }, not two"
                .to_string(),
        );
    }
    let both = |a: Option<f64>, b: Option<f64>, names: &str| match (a, b) {
        (Some(a), Some(b)) => Ok((a, b)),
        _ => Err(format!("give both {names}")),
    };
    if polar {
        let (s, d) = both(v.speed, v.direction, "speed and direction")?;
        let [c, n] = unit(d);
        (v.vx, v.vy) = (Some(s * c), Some(s * n));
    } else if body {
        let (f, l) = both(v.forward, v.lateral, "forward and lateral")?;
        let [c, n] = unit(nose);
        (v.vx, v.vy) = (Some(f * c - l * n), Some(f * n + l * c));
    }
    *v = PartialVelocity {
        vx: v.vx,
        vy: v.vy,
        omega: v.omega,
        ..PartialVelocity::default()
    };
    Ok(())
}

/// Negates and swaps a `[low, high]` range (a mirrored angle or coordinate).
fn mirror_range(r: &mut Option<[f64; 2]>) {
    if let Some([lo, hi]) = *r {
        *r = Some([-hi, -lo]);
    }
}

/// Mirrors a spread of a signed quantity: a standard deviation keeps, a range mirrors.
fn mirror_spread(s: &mut Option<Spread>) {
    if let Some(Spread::Uniform { uniform: [lo, hi] }) = *s {
        *s = Some(Spread::Uniform {
            uniform: [-hi, -lo],
        });
    }
}

impl Case {
    /// The direction each vehicle's nose points, degrees in the file's frame (0 for a barrier).
    fn noses(&self) -> [f64; 2] {
        [VehicleId::One, VehicleId::Two].map(|id| {
            let v = self.content.vehicle(id.index());
            if v.barrier {
                0.0
            } else {
                self.written.nose(id, v.heading)
            }
        })
    }

    /// Reduces every alternative form to `{ vx, vy }`, the impact centre to each vehicle's
    /// frame, the crush angle to the fixed frame, and an SAE case to the natural form.
    pub(crate) fn resolve_forms(&mut self) -> Result<()> {
        self.resolve_crush_angle()?;
        let noses = self.noses();
        self.resolve_centre(noses)?;
        self.resolve_velocities(noses)?;
        if self.written == Convention::Sae {
            self.mirror_sae();
        }
        Ok(())
    }

    fn resolve_crush_angle(&mut self) -> Result<()> {
        let i = &self.content.impact;
        match (i.crush_angle.is_nan(), i.crush_angle_from_vehicle1) {
            (false, Some(_)) => Err(self.error_at(
                "impact.crush_angle_from_vehicle1",
                "give the crush angle once: crush_angle (from the fixed x axis) or \
                 crush_angle_from_vehicle1 (from vehicle 1's nose), not both",
            )),
            (true, None) => Err(self.error_at(
                "impact",
                "crush_angle: missing; give crush_angle (degrees from the fixed x axis) or \
                 crush_angle_from_vehicle1 (degrees from vehicle 1's nose)",
            )),
            (true, Some(rel)) => {
                let nose = self.noses()[0];
                if !(rel.is_finite() && nose.is_finite()) {
                    return Err(self.error_at(
                        "impact.crush_angle_from_vehicle1",
                        "must be a finite number, with vehicle 1's heading given",
                    ));
                }
                self.content.impact.crush_angle = wrap_degrees(nose + rel);
                Ok(())
            }
            (false, None) => Ok(()),
        }
    }

    /// `[impact] centre` with each vehicle's `position`: the impact centre in each vehicle's
    /// frame, `R(-nose) (C - P)`.
    fn resolve_centre(&mut self, noses: [f64; 2]) -> Result<()> {
        let centre = self.content.impact.centre.clone();
        for (k, name) in ["vehicle1", "vehicle2"].into_iter().enumerate() {
            let v = self.content.vehicle(k);
            if v.barrier {
                if v.position.is_some() {
                    return Err(self.error_at(
                        &format!("{name}.position"),
                        "a barrier has no position: the impact centre is on its face",
                    ));
                }
                continue;
            }
            let own = v.impact_point.is_some() || v.d.is_some() || v.phi.is_some();
            let point = match (&centre, v.position, own) {
                (Some(_), Some(_), true) => {
                    return Err(self.error_at(
                        &format!("{name}.position"),
                        "the impact centre is given twice: by [impact] centre with this \
                         position, and by this vehicle's impact_point or d and phi; give one",
                    ))
                }
                (Some(c), Some(p), false) => {
                    if ![c.x, c.y, p.x, p.y, noses[k]].iter().all(|x| x.is_finite()) {
                        return Err(self.error_at(
                            &format!("{name}.position"),
                            "the position, [impact] centre and the heading must be finite \
                             numbers",
                        ));
                    }
                    let [cos, sin] = unit(noses[k]);
                    let (dx, dy) = (c.x - p.x, c.y - p.y);
                    PointSection {
                        x: cos * dx + sin * dy,
                        y: -sin * dx + cos * dy,
                    }
                }
                (None, Some(_), _) => {
                    return Err(self.error_at(
                        &format!("{name}.position"),
                        "a CG position needs [impact] centre (the impact centre in the same \
                         fixed frame)",
                    ))
                }
                (Some(_), None, false) => {
                    return Err(self.error_at(
                        name,
                        "position: missing; [impact] centre needs each vehicle's CG position \
                         (or give this vehicle's impact_point)",
                    ))
                }
                _ => continue,
            };
            self.content.vehicle_mut(k).impact_point = Some(point);
        }
        Ok(())
    }

    fn resolve_velocities(&mut self, noses: [f64; 2]) -> Result<()> {
        let file = self.file.clone();
        let source = self.source.clone();
        let at = |path: &str, what: String| crate::case::error_at(&file, &source, path, what);
        let c = &mut self.content;
        for (name, st) in [("initial", &mut c.initial), ("final", &mut c.final_)] {
            let Some(StateSection { vehicle1, vehicle2 }) = st else {
                continue;
            };
            for (k, v) in [Some(vehicle1), vehicle2.as_mut()].into_iter().enumerate() {
                let Some(v) = v else { continue };
                let path = format!("{name}.vehicle{}", k + 1);
                // Set (a barrier's rest), written in the file (a written `nan` is refused as
                // not finite later), or left out (NaN by default).
                let given = |field: &str, x: f64| {
                    (!x.is_nan()
                        || crate::parse::locate(&source, &format!("{path}.{field}")).is_some())
                    .then_some(x)
                };
                let mut p = PartialVelocity {
                    vx: given("vx", v.vx),
                    vy: given("vy", v.vy),
                    omega: Some(v.omega),
                    speed: v.speed,
                    direction: v.direction,
                    forward: v.forward,
                    lateral: v.lateral,
                };
                resolve_velocity(&mut p, noses[k]).map_err(|w| at(&path, w))?;
                let (Some(x), Some(y)) = (p.vx, p.vy) else {
                    let missing = if p.vx.is_none() { "vx" } else { "vy" };
                    return Err(at(
                        &path,
                        format!(
                            "{missing}: missing; give {{ vx, vy, omega }}, {{ speed, direction, \
                             omega }} or {{ forward, lateral, omega }}"
                        ),
                    ));
                };
                (v.vx, v.vy) = (x, y);
                (v.speed, v.direction, v.forward, v.lateral) = (None, None, None, None);
            }
        }
        for (name, states, forms) in [
            ("estimates", &mut c.estimates, true),
            ("known", &mut c.known, true),
            ("weights", &mut c.weights, false),
            ("sigma", &mut c.sigma, false),
        ] {
            let Some(PartialStates { initial, final_ }) = states else {
                continue;
            };
            for (when, st) in [("initial", initial), ("final", final_)] {
                let Some(PartialState { vehicle1, vehicle2 }) = st else {
                    continue;
                };
                for (k, v) in [vehicle1, vehicle2].into_iter().enumerate() {
                    let path = format!("{name}.{when}.vehicle{}", k + 1);
                    let alt = v.speed.is_some()
                        || v.direction.is_some()
                        || v.forward.is_some()
                        || v.lateral.is_some();
                    if alt && !forms {
                        return Err(at(
                            &path,
                            format!(
                                "[{name}] takes vx, vy and omega only (a weight or standard \
                                 deviation of each fixed-frame component)"
                            ),
                        ));
                    }
                    resolve_velocity(v, noses[k]).map_err(|w| at(&path, w))?;
                }
            }
        }
        Ok(())
    }

    /// Mirrors an SAE case (y right, angles clockwise) into the natural form (y left, angles
    /// counter-clockwise): every y coordinate, angle, yaw rate and lateral observation changes
    /// sign; magnitudes (weights, standard deviations, speeds) keep.
    fn mirror_sae(&mut self) {
        let c = &mut self.content;
        let flip = |x: &mut f64| *x = -*x;
        let flip_opt = |x: &mut Option<f64>| {
            if let Some(v) = x {
                *v = -*v
            }
        };
        for v in [&mut c.vehicle1, &mut c.vehicle2] {
            if v.barrier {
                continue;
            }
            v.heading = wrap_degrees(-v.heading);
            flip_opt(&mut v.phi);
            if let Some(p) = &mut v.impact_point {
                flip(&mut p.y);
            }
        }
        c.impact.crush_angle = wrap_degrees(-c.impact.crush_angle);
        for st in [&mut c.initial, &mut c.final_].into_iter().flatten() {
            for v in [Some(&mut st.vehicle1), st.vehicle2.as_mut()]
                .into_iter()
                .flatten()
            {
                flip(&mut v.vy);
                flip(&mut v.omega);
            }
        }
        for states in [&mut c.estimates, &mut c.known].into_iter().flatten() {
            for st in [&mut states.initial, &mut states.final_]
                .into_iter()
                .flatten()
            {
                for v in [&mut st.vehicle1, &mut st.vehicle2] {
                    flip_opt(&mut v.vy);
                    flip_opt(&mut v.omega);
                }
            }
        }
        for o in &mut c.observations {
            if o.kind.is_lateral() {
                flip(&mut o.value);
            }
        }
        if let Some(b) = &mut c.bounds {
            mirror_range(&mut b.crush_angle);
            for v in [&mut b.vehicle1, &mut b.vehicle2].into_iter().flatten() {
                mirror_range(&mut v.phi);
                if let Some(p) = &mut v.impact_point {
                    mirror_range(&mut p.y);
                }
            }
        }
        if let Some(u) = &mut c.uncertainty {
            for v in [&mut u.vehicle1, &mut u.vehicle2] {
                mirror_spread(&mut v.heading);
                mirror_spread(&mut v.phi);
            }
            mirror_spread(&mut u.impact.crush_angle);
        }
        c.convention = Convention::Natural;
    }
}
