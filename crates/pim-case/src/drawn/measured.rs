//! The measured inputs of a reconstruction that `[uncertainty.vehicleN]` can give a spread:
//! the pre-impact skid length, braking share and grade, the EDR's clock, the run-out's braking
//! share and rolling resistance, and the chassis (wheelbase, track, CG to the front axle, CG
//! height). Each is drawn in
//! the file's own units (lengths in its length unit, the grade in percent, times in seconds)
//! and applied to the field it names; a spread whose field the case does not give is refused
//! with its place, never dropped.

use super::input::Input;
use crate::case::Case;
use crate::scene_sections::{PreImpactVehicleSection, RunoutVehicleSection};
use crate::spread::{Spread, VehicleSpread};
use crate::Result;

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
pub(super) fn measured_inputs(case: &Case) -> Result<Vec<Input>> {
    let Some(unc) = case.content.uncertainty else {
        return Ok(Vec::new());
    };
    let mut out = Vec::new();
    for (k, v) in [unc.vehicle1, unc.vehicle2].into_iter().enumerate() {
        let [a, b, c, d] = pre_impact_fields(&v);
        let [e, f, g, h, i, j] = runout_fields(&v);
        let fields = [a, b, c, d, e, f, g, h, i, j];
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

/// The drawn fields of a vehicle's braking before the impact and its EDR, with `v`'s spreads.
fn pre_impact_fields(v: &VehicleSpread) -> [Field; 4] {
    [
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
    ]
}

/// The drawn fields of a vehicle's run-out, with `v`'s spreads.
fn runout_fields(v: &VehicleSpread) -> [Field; 6] {
    [
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
        Field {
            key: "rolling_resistance",
            spread: v.rolling_resistance,
            get: |c, k| {
                runout(c, k).map(|r| {
                    r.rolling_resistance
                        .unwrap_or(pim_runout::DEFAULT_ROLLING_RESISTANCE)
                })
            },
            // At least a trace (a rolling wheel must stop), at most half the road's
            // friction (the chassis refuses one at or above the friction).
            set: |c, k, x| {
                let road = c.road_friction();
                if let Some(r) = runout(c, k) {
                    let mu = r.friction.unwrap_or(road);
                    r.rolling_resistance = Some(x.clamp(1e-4, 0.5 * mu));
                }
            },
        },
    ]
}

/// The wheel states a run-out may have had instead of its stated ones
/// (`[runout.vehicleN] wheels_alternatives`), drawn by their probabilities: one uniform number
/// per draw in [0, 1), the stated wheels below the probability they keep (one less the
/// alternatives'), each alternative above by its own.
///
/// # Errors
/// A located error: a probability not above 0, probabilities that do not leave the stated
/// wheels some, or an alternative that is no wheel state.
pub(super) fn wheel_alternatives(case: &Case) -> Result<Vec<Input>> {
    let mut out = Vec::new();
    for k in 0..2 {
        let mut probe = case.clone();
        let Some(section) = runout(&mut probe, k) else {
            continue;
        };
        let (alternatives, braking) = (
            section.wheels_alternatives.clone(),
            section.braking.unwrap_or(0.0),
        );
        if alternatives.is_empty() {
            continue;
        }
        let at = format!("runout.vehicle{}.wheels_alternatives", k + 1);
        let total: f64 = alternatives.iter().map(|a| a.weight).sum();
        if alternatives
            .iter()
            .any(|a| !(a.weight.is_finite() && a.weight > 0.0))
            || total >= 1.0
        {
            return Err(case.error_at(
                &at,
                format!(
                    "probabilities {}: each above 0, together below 1 (the stated wheels keep                      the rest)",
                    alternatives
                        .iter()
                        .map(|a| a.weight.to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            ));
        }
        for (i, a) in alternatives.iter().enumerate() {
            case.wheels_of(&format!("{at}[{i}].wheels"), Some(&a.wheels), braking)?;
        }
        let stated = 1.0 - total;
        out.push(Input {
            name: format!("vehicle{} wheels", k + 1),
            spread: Spread::Uniform {
                uniform: [0.0, 1.0],
            },
            // Within the stated wheels' share: the nominal case.
            nominal: 0.5 * stated,
            apply: Box::new(move |c: &mut Case, x| {
                let mut edge = stated;
                if x < edge {
                    return;
                }
                let chosen = alternatives
                    .iter()
                    .find(|a| {
                        edge += a.weight;
                        x < edge
                    })
                    .or(alternatives.last());
                if let (Some(a), Some(r)) = (chosen, runout(c, k)) {
                    r.wheels = Some(a.wheels.clone());
                }
            }),
        });
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use crate::case::Case;
    use crate::spread::Spread;

    const FOOT: f64 = 0.3048;

    /// The newcomer's case (SAE, feet) with its spreads replaced by `spreads`.
    fn case(spreads: &str) -> Case {
        let path = concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../pim-cli/tests/cases/main_oak.toml"
        );
        let text = std::fs::read_to_string(path).unwrap();
        let at = text.find("[uncertainty.vehicle1]").unwrap();
        Case::from_text(path, &format!("{}{spreads}", &text[..at])).unwrap()
    }

    fn inputs(c: &Case) -> Vec<crate::drawn::Input> {
        let unc = c.spreads();
        let mut all = crate::drawn::fit_inputs(c, &unc).unwrap();
        all.extend(super::measured_inputs(c).unwrap());
        all
    }

    /// The impact point drawn over the range the damage allows (uniform, each coordinate on
    /// its own): the range of y, written to the right in an SAE case, is held to the left; a
    /// drawn value puts the point there.
    #[test]
    fn an_impact_point_is_drawn_over_a_uniform_range() {
        let c = case(
            "[uncertainty.vehicle2]\nimpact_point = { x = { uniform = [1.6, 4.7] }, y = { uniform = [2.0, 2.6] } }\n",
        );
        let all = inputs(&c);
        let x = all
            .iter()
            .find(|i| i.name == "vehicle2.impact_point.x")
            .unwrap();
        let y = all
            .iter()
            .find(|i| i.name == "vehicle2.impact_point.y")
            .unwrap();
        let near =
            |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12;
        assert!(
            matches!(x.spread, Spread::Uniform { uniform } if near(uniform, [1.6 * FOOT, 4.7 * FOOT]))
        );
        assert!(
            matches!(y.spread, Spread::Uniform { uniform } if near(uniform, [-2.6 * FOOT, -2.0 * FOOT]))
        );
        // The nominal point lies in the range as written: 3.0 ft ahead, 2.3 ft right.
        assert!(
            (x.nominal - 3.0 * FOOT).abs() < 1e-9 && (y.nominal + 2.3 * FOOT).abs() < 1e-9,
            "{} {}",
            x.nominal / FOOT,
            y.nominal / FOOT
        );
        let mut drawn = c.clone();
        (x.apply)(&mut drawn, 4.0 * FOOT);
        let v = drawn.content.vehicle(1);
        let (px, py) = pim_core::impact_point_cartesian(v.d(), v.phi());
        assert!(
            (px - 4.0 * FOOT).abs() < 1e-12 && (py - y.nominal).abs() < 1e-12,
            "{px} {py}"
        );
        // Only the coordinate given is drawn; a range upside down is refused at its line.
        let one = inputs(&case(
            "[uncertainty.vehicle2]\nimpact_point = { x = 0.8 }\n",
        ));
        assert!(one.iter().any(|i| i.name == "vehicle2.impact_point.x"));
        assert!(!one.iter().any(|i| i.name == "vehicle2.impact_point.y"));
        let bad = case("[uncertainty.vehicle2]\nimpact_point = { x = { uniform = [4.7, 1.6] } }\n");
        let unc = bad.spreads();
        let err = crate::drawn::fit_inputs(&bad, &unc)
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("uncertainty.vehicle2.impact_point.x"), "{err}");
    }

    /// The SUV's jammed wheel may have been free: its alternative drawn three times in ten,
    /// the stated wheels otherwise; probabilities that leave the stated wheels none, or an
    /// alternative that is no wheel state, are refused at their place.
    #[test]
    fn wheel_states_are_drawn_among_their_alternatives() {
        let with = |alt: &str| {
            let path = concat!(
                env!("CARGO_MANIFEST_DIR"),
                "/../pim-cli/tests/cases/main_oak.toml"
            );
            let text = std::fs::read_to_string(path).unwrap();
            let stated = "wheels = { front_left = \"rolling\", front_right = \"locked\", rear_left = \"rolling\", rear_right = \"rolling\" }";
            assert!(text.contains(stated));
            Case::from_text(
                path,
                &text.replace(stated, &format!("{stated}\nwheels_alternatives = {alt}")),
            )
            .unwrap()
        };
        let c = with("[ { wheels = \"rolling\", weight = 0.3 } ]");
        let all = super::wheel_alternatives(&c).unwrap();
        let w = all.iter().find(|i| i.name == "vehicle2 wheels").unwrap();
        let states = |c: &Case| c.scene_inputs().unwrap().vehicles[1].chassis.wheels;
        let (mut a, mut b) = (c.clone(), c.clone());
        (w.apply)(&mut a, 0.69);
        (w.apply)(&mut b, 0.71);
        assert_eq!(states(&a), states(&c));
        assert_eq!(states(&b), [pim_runout::WheelState::Rolling; 4]);
        assert_ne!(states(&c)[1], pim_runout::WheelState::Rolling);
        for (alt, at) in [
            (
                "[ { wheels = \"rolling\", weight = 1.0 } ]",
                "wheels_alternatives",
            ),
            (
                "[ { wheels = \"jammed\", weight = 0.2 } ]",
                "wheels_alternatives[0].wheels",
            ),
        ] {
            let err = super::wheel_alternatives(&with(alt))
                .err()
                .unwrap()
                .to_string();
            assert!(err.contains(&format!("runout.vehicle2.{at}")), "{err}");
        }
    }

    /// The run-out's rolling resistance carries a spread: drawn about the section's value (the
    /// default without one), and a draw stays a rolling resistance of that road (above 0, at
    /// most half its friction).
    #[test]
    fn the_rolling_resistance_is_drawn() {
        let c = case("[uncertainty.vehicle2]\nrolling_resistance = 0.005\n");
        let all = inputs(&c);
        let rr = all
            .iter()
            .find(|i| i.name == "vehicle2 rolling resistance")
            .unwrap();
        assert!(matches!(rr.spread, Spread::Normal(s) if (s - 0.005).abs() < 1e-15));
        let mut drawn = c.clone();
        (rr.apply)(&mut drawn, 0.02);
        let section = |c: &Case| c.content.runout.as_ref().unwrap().vehicle2.clone().unwrap();
        assert_eq!(section(&drawn).rolling_resistance, Some(0.02));
        (rr.apply)(&mut drawn, -0.01);
        assert_eq!(section(&drawn).rolling_resistance, Some(1e-4));
        drawn.scene_inputs().unwrap();
        (rr.apply)(&mut drawn, 3.0);
        let mu = drawn.scene_inputs().unwrap().vehicles[1].chassis.friction;
        assert_eq!(section(&drawn).rolling_resistance, Some(0.5 * mu));
    }
}
