//! The road frictions of a case's reconstruction: which vehicles run out (and brake before the
//! impact) on which fitted friction, and what the scenes alone say of each.

use pim_case::case::Case;
use pim_core::VehicleId;
use pim_reconstruct::{Reconstruction, SceneVehicle};

/// The road frictions fitted with the velocities when `[runout] friction_sigma` is given: one
/// under every scene vehicle that runs out on `[runout] friction` (`road friction`), and one
/// of its own for a vehicle whose `[runout.vehicleN] friction` sets another surface (`road
/// friction under vehicleN`), each with that standard deviation. A skid before the impact
/// whose `friction` is not stated apart brakes on the shared road, at its fitted value.
pub(crate) fn frictions_of(
    case: &Case,
    scene: &[SceneVehicle],
    skids_on_road: [bool; 2],
) -> Vec<pim_reconstruct::RoadFriction> {
    let Some(runout) = &case.content.runout else {
        return Vec::new();
    };
    let Some(sigma) = runout.friction_sigma else {
        return Vec::new();
    };
    let own = |id: VehicleId| {
        let v = if id == VehicleId::One {
            &runout.vehicle1
        } else {
            &runout.vehicle2
        };
        v.as_ref().is_some_and(|v| v.friction.is_some())
    };
    let mut out: Vec<pim_reconstruct::RoadFriction> = Vec::new();
    let shared: Vec<usize> = (0..scene.len()).filter(|&i| !own(scene[i].id)).collect();
    if let Some(&first) = shared.first() {
        // A skid on the road of the run-outs (its friction not stated apart).
        let on_road: Vec<usize> = (0..2).filter(|&k| skids_on_road[k]).collect();
        out.push(pim_reconstruct::RoadFriction {
            name: "road friction".into(),
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
        .enumerate()
        .map(|(g, f)| {
            let mut info = 0.0;
            for &v in &f.vehicles {
                let s = &r.scene[v];
                let Some(fit) = found.scene.iter().find(|x| x.vehicle == s.id) else {
                    continue;
                };
                let mut chassis = s.chassis.clone();
                chassis.friction = found.frictions[g];
                let Ok(lin) = pim_runout::linearise_with_friction(
                    &chassis,
                    &fit.runout.start,
                    &s.evidence,
                    fit.turns.unwrap_or(0),
                    runout,
                ) else {
                    continue;
                };
                let (Some(j), Some(d)) = (&lin.jacobian, &lin.friction) else {
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
