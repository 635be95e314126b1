//! The inputs an uncertainty study draws: each one's name, its spread, its nominal value (in
//! the units the case holds it in: SI and the natural frame for what the file's `[units]`
//! converts, the file's own units for the damage's and the measured inputs' spreads, as their
//! sections say) and how a drawn value is written into a copy of the case. The one place above
//! the raw sections that knows where each drawn input lives in the file; a study draws, writes
//! with [`Input::apply`] and resolves the copy again.

mod damage;
mod input;
mod measured;
mod scene;

pub use input::{Apply, Input};

use crate::case::Case;
use crate::spread::{Spread, UncertaintySection, VehicleSpread};
use crate::{InputError, Result};

/// The inputs of a reconstruction's study: the fit's ([`fit_inputs`] with the case's
/// `[uncertainty]`), then the road friction and each vehicle's own, every rest, rest tyre and
/// mark, every EDR speed, each friction zone's friction, each point of each traced mark, the
/// measured inputs `[uncertainty.vehicleN]` gives a spread and the wheel states' alternatives,
/// in that order (the order of the draws' random numbers).
///
/// # Errors
/// A located error for a spread that is no spread or of a value the case does not give.
pub fn reconstruction_inputs(case: &Case) -> Result<Vec<Input>> {
    let unc = case.spreads();
    let mut all = fit_inputs(case, &unc)?;
    all.extend(scene::scene_inputs(case));
    all.extend(scene::zone_inputs(case));
    all.extend(scene::trace_inputs(case));
    all.extend(measured::measured_inputs(case)?);
    all.extend(measured::wheel_alternatives(case)?);
    Ok(all)
}

/// The draws of vehicle `id`'s impact point, each coordinate by its own spread (`p`), in the
/// vehicle's body axes; a draw moves the impact centre on the vehicle.
///
/// # Errors
/// A located error for a spread that is no spread (a range upside down, a sigma not above 0).
fn impact_point_inputs(
    case: &Case,
    id: usize,
    p: crate::spread::PointSpread,
) -> Result<Vec<Input>> {
    let name = ["vehicle1", "vehicle2"][id];
    let v = if id == 0 {
        &case.content.vehicle1
    } else {
        &case.content.vehicle2
    };
    let (x0, y0) = pim_core::impact_point_cartesian(v.d(), v.phi());
    // A range of y is written in the file's frame (SAE: to the right); the point is held in
    // the natural frame (to the left).
    let sae = case.written.mirrors();
    let y = p.y.map(|sp| match sp {
        Spread::Uniform { uniform: [a, b] } if sae => Spread::Uniform { uniform: [-b, -a] },
        other => other,
    });
    let mut out = Vec::new();
    for (axis, spread, nominal) in [("x", p.x, x0), ("y", y, y0)] {
        let Some(spread) = spread else { continue };
        spread.check_own().map_err(|why| {
            case.error_at(&format!("uncertainty.{name}.impact_point.{axis}"), why)
        })?;
        out.push(Input {
            name: format!("{name}.impact_point.{axis}"),
            spread,
            nominal,
            apply: Box::new(move |case: &mut Case, value| {
                let v = case.content.vehicle_mut(id);
                let (mut x, mut y) = pim_core::impact_point_cartesian(v.d(), v.phi());
                if axis == "x" {
                    x = value
                } else {
                    y = value
                }
                let (d, phi) = pim_core::impact_point_polar(x, y);
                v.d = Some(d);
                v.phi = Some(phi);
            }),
        });
    }
    Ok(out)
}

/// The inputs of a fit's study: each estimate and observation with a standard deviation, the
/// vehicles' inputs and the impact's that `unc` gives a spread, and the damage's (see
/// [`damage`]).
///
/// # Errors
/// A located error for a spread that is no spread, or one of a barrier's inputs.
pub fn fit_inputs(case: &Case, unc: &UncertaintySection) -> Result<Vec<Input>> {
    let mut out: Vec<Input> = Vec::new();
    let c = &case.content;
    let est = c.estimates.unwrap_or_default().components();
    let sig = c.sigma.unwrap_or_default().components();
    for k in 0..12 {
        if let (Some(v), Some(s)) = (est[k], sig[k]) {
            out.push(Input {
                name: format!("estimate {}", pim_fit::COMPONENT_NAMES[k]),
                spread: Spread::Normal(s),
                nominal: v,
                apply: Box::new(move |case: &mut Case, x| set_estimate(case, k, x)),
            });
        }
    }
    for (i, o) in c.observations.iter().enumerate() {
        if let Some(s) = o.sigma {
            out.push(Input {
                name: case.observation_label(i),
                spread: Spread::Normal(s),
                nominal: o.value,
                apply: Box::new(move |case: &mut Case, x| case.content.observations[i].value = x),
            });
        }
    }
    if case.is_barrier() && unc.vehicle2 != VehicleSpread::default() {
        return Err(InputError::new(
            &case.file,
            "[uncertainty] vehicle2: vehicle 2 is a fixed barrier; it has no mass, inertia, \
             heading or impact centre to be uncertain (the barrier face's angle is [uncertainty] \
             impact.crush_angle)",
        ));
    }
    for (id, spread) in [(0usize, unc.vehicle1), (1, unc.vehicle2)] {
        let name = ["vehicle1", "vehicle2"][id];
        let v = if id == 0 { &c.vehicle1 } else { &c.vehicle2 };
        type Setter = fn(&mut crate::case::VehicleSection, f64);
        let fields: [(&str, Option<Spread>, f64, Setter); 5] = [
            ("mass", spread.mass, v.mass, |s, x| s.mass = x),
            ("yaw_inertia", spread.yaw_inertia, v.yaw_inertia, |s, x| {
                s.yaw_inertia = x
            }),
            ("heading", spread.heading, v.heading, |s, x| s.heading = x),
            ("d", spread.d, v.d(), |s, x| s.d = Some(x)),
            ("phi", spread.phi, v.phi(), |s, x| s.phi = Some(x)),
        ];
        for (field, sp, nominal, set) in fields {
            if let Some(sp) = sp {
                let positive = !matches!(field, "heading" | "phi");
                sp.check_against(&format!("{name}.{field}"), nominal, positive)
                    .map_err(|why| case.error_at(&format!("uncertainty.{name}.{field}"), why))?;
                out.push(Input {
                    name: format!("{name}.{field}"),
                    spread: sp,
                    nominal,
                    apply: Box::new(move |case: &mut Case, x| set(case.content.vehicle_mut(id), x)),
                });
            }
        }
        if let Some(p) = spread.impact_point {
            if spread.d.is_some() || spread.phi.is_some() {
                return Err(InputError::new(
                    &case.file,
                    format!("[uncertainty] {name}: give impact_point or d / phi, not both"),
                ));
            }
            out.extend(impact_point_inputs(case, id, p)?);
        }
    }
    out.extend(damage::inputs(case));
    if let Some(sp) = unc.impact.crush_angle {
        sp.check_against("impact.crush_angle", c.impact.crush_angle, false)
            .map_err(|why| case.error_at("uncertainty.impact.crush_angle", why))?;
        out.push(Input {
            name: "impact.crush_angle".into(),
            spread: sp,
            nominal: c.impact.crush_angle,
            apply: Box::new(|case: &mut Case, x| case.content.impact.crush_angle = x),
        });
    }
    Ok(out)
}

fn set_estimate(case: &mut Case, k: usize, x: f64) {
    let Some(est) = case.content.estimates.as_mut() else {
        return;
    };
    let state = if k < 6 {
        est.initial.as_mut()
    } else {
        est.final_.as_mut()
    };
    let Some(state) = state else { return };
    let v = if k % 6 < 3 {
        &mut state.vehicle1
    } else {
        &mut state.vehicle2
    };
    match k % 3 {
        0 => v.vx = Some(x),
        1 => v.vy = Some(x),
        _ => v.omega = Some(x),
    }
}
