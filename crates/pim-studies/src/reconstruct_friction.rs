//! The road frictions of a case's reconstruction: which vehicles run out (and brake before the
//! impact) on which fitted friction, and what the scenes alone say of each.

use pim_case::case::Case;
use pim_core::VehicleId;
use pim_reconstruct::{Reconstruction, SceneVehicle};

/// The frictions fitted with the velocities. When `[runout] friction_sigma` is given: one
/// under every scene vehicle that runs out on `[runout] friction` (`road friction`), and one
/// of its own for a vehicle whose `[runout.vehicleN] friction` sets another surface (`road
/// friction under vehicleN`), each with that standard deviation. A skid before the impact
/// whose `friction` is not stated apart brakes on the shared road, at its fitted value. Then
/// each friction zone that gives its `friction_sigma` (`NAME friction`, under every scene
/// vehicle).
pub(crate) fn frictions_of(
    case: &Case,
    scene: &[SceneVehicle],
    skids_on_road: [bool; 2],
) -> Vec<pim_reconstruct::RoadFriction> {
    let mut out = road_frictions(case, scene, skids_on_road);
    if !scene.is_empty() {
        for z in case.zone_frictions() {
            if let Some(sigma) = z.sigma {
                out.push(pim_reconstruct::RoadFriction {
                    name: format!("{} friction", z.name),
                    zone: Some(z.zone),
                    value: z.friction,
                    sigma,
                    vehicles: (0..scene.len()).collect(),
                    skids: Vec::new(),
                });
            }
        }
    }
    out
}

/// The road's fitted frictions (`[runout] friction_sigma`), as [`frictions_of`] gives them.
fn road_frictions(
    case: &Case,
    scene: &[SceneVehicle],
    skids_on_road: [bool; 2],
) -> Vec<pim_reconstruct::RoadFriction> {
    let Some(sigma) = case.road_friction_sigma() else {
        return Vec::new();
    };
    let own = |id: VehicleId| case.runs_on_own_surface(id.index());
    let mut out: Vec<pim_reconstruct::RoadFriction> = Vec::new();
    let shared: Vec<usize> = (0..scene.len()).filter(|&i| !own(scene[i].id)).collect();
    if let Some(&first) = shared.first() {
        // A skid on the road of the run-outs (its friction not stated apart).
        let on_road: Vec<usize> = (0..2).filter(|&k| skids_on_road[k]).collect();
        out.push(pim_reconstruct::RoadFriction {
            name: "road friction".into(),
            zone: None,
            value: scene[first].chassis.friction,
            sigma,
            vehicles: shared,
            skids: on_road,
        });
    }
    for (i, v) in scene.iter().enumerate() {
        if own(v.id) {
            out.push(pim_reconstruct::RoadFriction {
                name: format!("road friction under {}", v.id),
                zone: None,
                value: v.chassis.friction,
                sigma,
                vehicles: vec![i],
                skids: Vec::new(),
            });
        }
    }
    out
}

/// What the scenes alone say of each fitted friction at the answer: the share of its stated
/// standard deviation's information they add (`F^T (I - J J^+) F sigma^2`, the friction's
/// derivatives with the separation velocities profiled out). Below 0.1 the scenes cannot
/// separate the speeds from the friction.
pub(crate) fn scene_information(
    r: &Reconstruction,
    runout: &pim_runout::Settings,
    found: &pim_reconstruct::Found,
) -> Vec<f64> {
    r.frictions
        .iter()
        .map(|f| {
            let mut info = 0.0;
            for &v in &f.vehicles {
                let s = &r.scene[v];
                let Some(fit) = found.scene.iter().find(|x| x.vehicle == s.id) else {
                    continue;
                };
                // The chassis the fitted run-out ran on.
                let mut chassis = s.chassis.clone();
                fit.ground(&mut chassis);
                let turns = fit.turns.unwrap_or(0);
                let start = &fit.runout.start;
                let Ok(lin) = (match f.zone {
                    None => pim_runout::linearise_with_friction(
                        &chassis,
                        start,
                        &s.evidence,
                        turns,
                        runout,
                    ),
                    Some(_) => {
                        pim_runout::linearise(&chassis, start, &s.evidence, turns, runout, true)
                            .and_then(|l| {
                                pim_runout::differentiate_zones(
                                    l,
                                    &chassis,
                                    start,
                                    &s.evidence,
                                    turns,
                                    runout,
                                )
                            })
                    }
                }) else {
                    continue;
                };
                let d = match f.zone {
                    None => lin.friction.as_ref(),
                    Some(k) => lin.zones.get(k),
                };
                let (Some(j), Some(d)) = (&lin.jacobian, d) else {
                    continue;
                };
                let jtj = j.transpose() * j;
                let Some(inv) = jtj.pseudo_inverse(1e-12).ok() else {
                    continue;
                };
                let profiled = d - j * (&inv * (j.transpose() * d));
                info += profiled.norm_squared();
            }
            info * f.sigma * f.sigma
        })
        .collect()
}

/// What the answer leaves open of the road friction: held at its value (no `friction_sigma`),
/// or fitted where the scenes alone cannot separate it from the speeds.
pub(crate) fn notes(
    r: &Reconstruction,
    runout: &pim_runout::Settings,
    best: Option<&pim_reconstruct::Found>,
) -> Vec<String> {
    if r.frictions.is_empty() {
        return vec![
            "the road friction is taken as given in the fit; its spread enters through `pim \
             uncertainty` (give [runout] friction_sigma to fit it with the speeds)"
                .into(),
        ];
    }
    let Some(b) = best else {
        return Vec::new();
    };
    r.frictions
        .iter()
        .zip(scene_information(r, runout, b))
        .filter(|(_, share)| *share < 0.1)
        .map(|(f, share)| {
            format!(
                "the {}: the scenes alone cannot separate it from the speeds (along speed ~ \
                 sqrt(friction) the run-outs end alike; they add {:.0} % of its stated standard \
                 deviation's information): it is fitted near its stated value, which with the \
                 impact's evidence decides it",
                f.name,
                100.0 * share
            )
        })
        .collect()
}
