//! The measured inputs of a reconstruction that `[uncertainty.vehicleN]` can give a spread:
//! the pre-impact skid length, braking share and grade, the EDR's clock, the run-out's braking
//! share, and the chassis (wheelbase, track, CG to the front axle, CG height). Each is drawn in
//! the file's own units (lengths in its length unit, the grade in percent, times in seconds)
//! and applied to the field it names; a spread whose field the case does not give is refused
//! with its place, never dropped.

use crate::uncertainty::Input;
use pim_case::case::Case;
use pim_case::scene_sections::{PreImpactVehicleSection, RunoutVehicleSection};
use pim_case::spread::Spread;
use pim_case::Result;

fn pre_impact(c: &mut Case, k: usize) -> Option<&mut PreImpactVehicleSection> {
    let p = c.content.pre_impact.as_mut()?;
    if k == 0 {
        p.vehicle1.as_mut()
    } else {
        p.vehicle2.as_mut()
    }
}

fn runout(c: &mut Case, k: usize) -> Option<&mut RunoutVehicleSection> {
    let r = c.content.runout.as_mut()?;
    if k == 0 {
        r.vehicle1.as_mut()
    } else {
        r.vehicle2.as_mut()
    }
}

/// One drawn input: its key, the spread, how to read the nominal value and how to set a draw.
struct Field {
    key: &'static str,
    spread: Option<Spread>,
    get: fn(&mut Case, usize) -> Option<f64>,
    set: fn(&mut Case, usize, f64),
}

/// The drawn measured inputs of a case's reconstruction.
///
/// # Errors
/// A located error for a spread of a field the case does not give.
pub(crate) fn measured_inputs(case: &Case) -> Result<Vec<Input>> {
    let Some(unc) = case.content.uncertainty else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (k, v) in [unc.vehicle1, unc.vehicle2].into_iter().enumerate() {
        let fields = [
            Field {
                key: "skid",
                spread: v.skid,
                get: |c, k| pre_impact(c, k)?.skid,
                set: |c, k, x| {
                    if let Some(p) = pre_impact(c, k) {
                        p.skid = Some(x.max(0.0));
                    }
                },
            },
            Field {
                key: "skid_braking",
                spread: v.skid_braking,
                get: |c, k| {
                    pre_impact(c, k)
                        .filter(|p| p.skid.is_some())
                        .map(|p| p.braking.unwrap_or(1.0))
                },
                set: |c, k, x| {
                    if let Some(p) = pre_impact(c, k) {
                        p.braking = Some(x.clamp(0.0, 1.0));
                    }
                },
            },
            Field {
                key: "grade",
                spread: v.grade,
                get: |c, k| {
                    pre_impact(c, k)
                        .filter(|p| p.skid.is_some())
                        .map(|p| p.grade.unwrap_or(0.0))
                },
                set: |c, k, x| {
                    if let Some(p) = pre_impact(c, k) {
                        p.grade = Some(x);
                    }
                },
            },
            Field {
                key: "edr_time",
                spread: v.edr_time,
                // The offset of the EDR's clock, 0 nominally.
                get: |c, k| pre_impact(c, k).filter(|p| !p.edr.is_empty()).map(|_| 0.0),
                set: |c, k, x| {
                    if let Some(p) = pre_impact(c, k) {
                        for e in &mut p.edr {
                            e.time = (e.time + x).max(0.0);
                        }
                    }
                },
            },
            Field {
                key: "runout_braking",
                spread: v.runout_braking,
                get: |c, k| runout(c, k).map(|r| r.braking.unwrap_or(0.0)),
                set: |c, k, x| {
                    if let Some(r) = runout(c, k) {
                        r.braking = Some(x.clamp(0.0, 1.0));
                    }
                },
            },
            Field {
                key: "wheelbase",
                spread: v.wheelbase,
                get: |c, k| runout(c, k).map(|r| r.wheelbase),
                set: |c, k, x| {
                    if let Some(r) = runout(c, k) {
                        r.wheelbase = x.max(0.1 * r.wheelbase);
                    }
                },
            },
            Field {
                key: "track",
                spread: v.track,
                get: |c, k| runout(c, k).map(|r| r.track),
                set: |c, k, x| {
                    if let Some(r) = runout(c, k) {
                        r.track = x.max(0.1 * r.track);
                    }
                },
            },
            Field {
                key: "cg_to_front_axle",
                spread: v.cg_to_front_axle,
                get: |c, k| runout(c, k).map(|r| r.cg_to_front_axle.unwrap_or(0.5 * r.wheelbase)),
                set: |c, k, x| {
                    if let Some(r) = runout(c, k) {
                        r.cg_to_front_axle = Some(x.clamp(0.0, r.wheelbase));
                    }
                },
            },
            Field {
                key: "cg_height",
                spread: v.cg_height,
                get: |c, k| runout(c, k)?.cg_height,
                set: |c, k, x| {
                    if let Some(r) = runout(c, k) {
                        r.cg_height = Some(x.max(0.0));
                    }
                },
            },
        ];
        for f in fields {
            let Some(spread) = f.spread else { continue };
            let mut probe = case.clone();
            let Some(nominal) = (f.get)(&mut probe, k) else {
                let section = match f.key {
                    "skid" | "skid_braking" | "grade" => "[pre_impact.vehicleN] skid",
                    "edr_time" => "[pre_impact.vehicleN] edr",
                    "cg_height" => "[runout.vehicleN] cg_height",
                    _ => "[runout.vehicleN]",
                };
                return Err(case.error_at(
                    &format!("uncertainty.vehicle{}.{}", k + 1, f.key),
                    format!(
                        "a spread of a value the case does not give: it needs {}",
                        section.replace('N', &(k + 1).to_string())
                    ),
                ));
            };
            let set = f.set;
            out.push(Input {
                name: format!("vehicle{} {}", k + 1, f.key.replace('_', " ")),
                spread,
                nominal,
                apply: Box::new(move |c: &mut Case, x| set(c, k, x)),
            });
        }
    }
    Ok(out)
}
