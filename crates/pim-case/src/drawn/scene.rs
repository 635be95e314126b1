//! The scene's, the road friction's and the EDR's drawn inputs (in the file's units).

use super::input::Input;
use crate::case::Case;
use crate::spread::Spread;

/// The friction of each zone that gives its spread (`[[runout.zones]] friction_sigma`): the
/// centre of its prior drawn about the stated value (the fit fits it, as the road's).
pub(super) fn zone_inputs(case: &Case) -> Vec<Input> {
    let Some(r) = &case.content.runout else {
        return Vec::new();
    };
    r.zones
        .iter()
        .enumerate()
        .filter_map(|(k, z)| {
            let s = z.friction_sigma?;
            let name = z.display_name(k);
            Some(Input {
                name: format!("{name} friction"),
                spread: Spread::Normal(s),
                nominal: z.friction,
                apply: Box::new(move |case: &mut Case, x| {
                    if let Some(z) = case
                        .content
                        .runout
                        .as_mut()
                        .and_then(|r| r.zones.get_mut(k))
                    {
                        z.friction = x.clamp(0.05, 1.5);
                    }
                }),
            })
        })
        .collect()
}

/// Each point of each traced mark (`[scene.vehicleN] traces`), drawn by its trace's sigma (in
/// the file's units).
pub(super) fn trace_inputs(case: &Case) -> Vec<Input> {
    let Some(scene) = &case.content.scene else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for (n, v) in [(1usize, &scene.vehicle1), (2, &scene.vehicle2)] {
        let Some(v) = v else { continue };
        for (i, t) in v.traces.iter().enumerate() {
            for (j, p) in t.points.iter().enumerate() {
                for (axis, nominal) in [(0usize, p[0]), (1, p[1])] {
                    out.push(Input {
                        name: format!(
                            "vehicle{n} trace {} point {} {}",
                            i + 1,
                            j + 1,
                            ["x", "y"][axis]
                        ),
                        spread: Spread::Normal(t.sigma),
                        nominal,
                        apply: Box::new(move |c: &mut Case, x| {
                            let s = c.content.scene.as_mut().and_then(|s| {
                                if n == 1 {
                                    s.vehicle1.as_mut()
                                } else {
                                    s.vehicle2.as_mut()
                                }
                            });
                            if let Some(q) = s
                                .and_then(|s| s.traces.get_mut(i))
                                .and_then(|t| t.points.get_mut(j))
                            {
                                q[axis] = x;
                            }
                        }),
                    });
                }
            }
        }
    }
    out
}

/// The scene's, the friction's and the EDR's drawn inputs (in the file's units).
pub(super) fn scene_inputs(case: &Case) -> Vec<Input> {
    let mut out = friction_inputs(case);
    out.extend(scene_vehicle_inputs(case));
    out.extend(edr_inputs(case));
    out
}

/// The road friction and each vehicle's own, where the case gives them a spread.
fn friction_inputs(case: &Case) -> Vec<Input> {
    let mut out: Vec<Input> = Vec::new();
    let c = &case.content;
    if let Some(r) = &c.runout {
        if let (Some(s), Some(f)) = (r.friction_sigma, r.friction) {
            out.push(Input {
                name: "road friction".into(),
                spread: Spread::Normal(s),
                nominal: f,
                apply: Box::new(|case: &mut Case, x| {
                    if let Some(r) = case.content.runout.as_mut() {
                        r.friction = Some(x.clamp(0.05, 1.5));
                    }
                }),
            });
        }
        // A vehicle on a surface of its own: its friction drawn by the same spread.
        if let Some(s) = r.friction_sigma {
            type Own = fn(&mut Case) -> Option<&mut crate::scene_sections::RunoutVehicleSection>;
            let own: [(&str, Own, Option<f64>); 2] = [
                (
                    "vehicle1",
                    |c| c.content.runout.as_mut().and_then(|r| r.vehicle1.as_mut()),
                    r.vehicle1.as_ref().and_then(|v| v.friction),
                ),
                (
                    "vehicle2",
                    |c| c.content.runout.as_mut().and_then(|r| r.vehicle2.as_mut()),
                    r.vehicle2.as_ref().and_then(|v| v.friction),
                ),
            ];
            for (name, pick, value) in own {
                if let Some(f) = value {
                    out.push(Input {
                        name: format!("road friction under {name}"),
                        spread: Spread::Normal(s),
                        nominal: f,
                        apply: Box::new(move |case: &mut Case, x| {
                            if let Some(v) = pick(case) {
                                v.friction = Some(x.clamp(0.05, 1.5));
                            }
                        }),
                    });
                }
            }
        }
    }
    out
}

/// Each vehicle's rest, rest tyres and marks.
fn scene_vehicle_inputs(case: &Case) -> Vec<Input> {
    let mut out: Vec<Input> = Vec::new();
    type Pick = fn(&mut Case) -> Option<&mut crate::scene_sections::SceneVehicleSection>;
    let picks: [(usize, Pick); 2] = [
        (1, |c| {
            c.content.scene.as_mut().and_then(|s| s.vehicle1.as_mut())
        }),
        (2, |c| {
            c.content.scene.as_mut().and_then(|s| s.vehicle2.as_mut())
        }),
    ];
    for (n, pick) in picks {
        let mut probe = case.clone();
        let Some(v) = pick(&mut probe) else { continue };
        if let (Some(rest), Some(sd)) = (&v.rest, v.rest_sigma) {
            out.push(Input {
                name: format!("vehicle{n} rest.x"),
                spread: Spread::Normal(sd.x),
                nominal: rest.x,
                apply: Box::new(move |c: &mut Case, x| {
                    if let Some(r) = pick(c).and_then(|v| v.rest.as_mut()) {
                        r.x = x;
                    }
                }),
            });
            out.push(Input {
                name: format!("vehicle{n} rest.y"),
                spread: Spread::Normal(sd.y),
                nominal: rest.y,
                apply: Box::new(move |c: &mut Case, x| {
                    if let Some(r) = pick(c).and_then(|v| v.rest.as_mut()) {
                        r.y = x;
                    }
                }),
            });
            if let (Some(h), Some(sh)) = (rest.heading, sd.heading) {
                out.push(Input {
                    name: format!("vehicle{n} rest.heading"),
                    spread: Spread::Normal(sh),
                    nominal: h,
                    apply: Box::new(move |c: &mut Case, x| {
                        if let Some(r) = pick(c).and_then(|v| v.rest.as_mut()) {
                            r.heading = Some(x);
                        }
                    }),
                });
            }
        }
        for (i, t) in v.rest_tyres.iter().enumerate() {
            for (axis, nominal) in [("x", t.x), ("y", t.y)] {
                out.push(Input {
                    name: format!("vehicle{n} rest tyre {} {axis}", i + 1),
                    spread: Spread::Normal(t.sigma),
                    nominal,
                    apply: Box::new(move |c: &mut Case, x| {
                        if let Some(t) = pick(c).and_then(|v| v.rest_tyres.get_mut(i)) {
                            if axis == "x" {
                                t.x = x;
                            } else {
                                t.y = x;
                            }
                        }
                    }),
                });
            }
        }
        for (i, m) in v.marks.iter().enumerate() {
            for (axis, nominal) in [("x", m.x), ("y", m.y)] {
                out.push(Input {
                    name: format!("vehicle{n} mark {} {axis}", i + 1),
                    spread: Spread::Normal(m.sigma),
                    nominal,
                    apply: Box::new(move |c: &mut Case, x| {
                        if let Some(m) = pick(c).and_then(|v| v.marks.get_mut(i)) {
                            if axis == "x" {
                                m.x = x;
                            } else {
                                m.y = x;
                            }
                        }
                    }),
                });
            }
        }
    }
    out
}

/// Each EDR speed.
fn edr_inputs(case: &Case) -> Vec<Input> {
    let mut out: Vec<Input> = Vec::new();
    let c = &case.content;
    if let Some(p) = &c.pre_impact {
        for (n, v) in [(1usize, &p.vehicle1), (2, &p.vehicle2)] {
            let Some(v) = v else { continue };
            for (i, e) in v.edr.iter().enumerate() {
                out.push(Input {
                    name: format!("vehicle{n} EDR speed {:.1} s before contact", e.time),
                    spread: Spread::Normal(e.sigma),
                    nominal: e.speed,
                    apply: Box::new(move |c: &mut Case, x| {
                        let p = c.content.pre_impact.as_mut().and_then(|p| {
                            if n == 1 {
                                p.vehicle1.as_mut()
                            } else {
                                p.vehicle2.as_mut()
                            }
                        });
                        if let Some(e) = p.and_then(|p| p.edr.get_mut(i)) {
                            e.speed = x.max(0.0);
                        }
                    }),
                });
            }
        }
    }
    out
}
