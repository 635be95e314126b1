//! Simulated crashes with a known truth: random admissible impacts, both vehicles run out to
//! rest, the scene as a reconstructionist has it.
#![allow(dead_code)]

use super::impact::random_impact_with;
use super::runout::{random_chassis, Kind};
use pim_core::{solve_forward, VehicleId, Velocities};
use pim_fit::{CostPreset, FitProblem, FitSettings, Knowledge, Observation, ObservationKind};
use pim_reconstruct::{Reconstruction, SceneVehicle, Settings};
use pim_runout::{simulate, Evidence, Mark, Motion, Rest, Runout, Settings as RunoutSettings};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::f64::consts::TAU;

/// A simulated crash: the reconstruction's input and the truth.
pub struct Crash {
    pub recon: Reconstruction,
    pub contact: Velocities,
    pub separation: Velocities,
    pub runouts: Vec<Runout>,
}

pub const SIGMA_REST: f64 = 0.05;
pub const SIGMA_HEADING_DEG: f64 = 1.0;
pub const SIGMA_MARK: f64 = 0.05;
pub const SIGMA_LATERAL: f64 = 0.3;
pub const SIGMA_YAW: f64 = 0.1;

pub fn crash(seed: u64, noise: f64) -> Option<Crash> {
    crash_with(seed, noise, 4.0..18.0)
}

/// The simulated crashes of seeds 1, 2, ... (the seeds that draw no admissible crash left
/// out), with their seeds.
pub fn crashes(noise: f64) -> impl Iterator<Item = (u64, Crash)> {
    (1..).filter_map(move |seed| crash(seed, noise).map(|c| (seed, c)))
}

impl Crash {
    /// The larger error of the two impact speeds of a found answer against the truth, m/s.
    pub fn speed_error(&self, found: &pim_reconstruct::Found) -> f64 {
        let s = &found.solution;
        (s.initial.vehicle1.speed() - self.contact.vehicle1.speed())
            .abs()
            .max((s.initial.vehicle2.speed() - self.contact.vehicle2.speed()).abs())
    }
}

/// A crash of contact speeds drawn from `speeds` (m/s).
pub fn crash_with(seed: u64, noise: f64, speeds: std::ops::Range<f64>) -> Option<Crash> {
    let mut rng = StdRng::seed_from_u64(seed);
    let ri = random_impact_with(&mut rng, speeds)?;
    let report = solve_forward(&ri.impact, &ri.truth, &ri.x, &ri.opts).ok()?;
    if !report.admissibility.admissible {
        return None;
    }
    let sep = report.separation;
    let cgs = ri.impact.cg_positions();
    let mut scene = Vec::new();
    let mut runouts = Vec::new();
    for id in [VehicleId::One, VehicleId::Two] {
        let k = id.index();
        let kind = if rng.random_bool(0.5) {
            Kind::Locked
        } else {
            Kind::Mixed
        };
        let mut chassis = random_chassis(&mut rng, kind);
        let c = ri.impact.collision();
        let vehicle = if k == 0 { &c.vehicle1 } else { &c.vehicle2 };
        chassis.mass = vehicle.mass;
        chassis.yaw_inertia = vehicle.yaw_inertia;
        chassis.friction = rng.random_range(0.4..0.9);
        let v = if k == 0 { sep.vehicle1 } else { sep.vehicle2 };
        let pose = Motion {
            x: cgs[k][0],
            y: cgs[k][1],
            heading: ri.impact.nose_heading(id).to_radians(),
            vx: 0.0,
            vy: 0.0,
            yaw_rate: 0.0,
        };
        let start = Motion {
            vx: v.vx,
            vy: v.vy,
            yaw_rate: v.omega,
            ..pose
        };
        let run = simulate(&chassis, &start, &RunoutSettings::default()).ok()?;
        if run.distance < 1.0 {
            return None;
        }
        let mut n = |s: f64| noise * s * common_normal(&mut rng);
        let marks = [0.3, 0.6]
            .iter()
            .map(|f| {
                let m = run.at(f * run.time);
                Mark {
                    x: m.x + n(SIGMA_MARK),
                    y: m.y + n(SIGMA_MARK),
                    sigma: SIGMA_MARK,
                    heading: None,
                    point: [0.0, 0.0],
                }
            })
            .collect();
        let evidence = Evidence {
            rest: Some(Rest {
                x: run.rest.x + n(SIGMA_REST),
                y: run.rest.y + n(SIGMA_REST),
                heading: Some(
                    (run.rest.heading + n(SIGMA_HEADING_DEG.to_radians())).rem_euclid(TAU),
                ),
                sigma_xy: [SIGMA_REST, SIGMA_REST],
                sigma_heading: SIGMA_HEADING_DEG.to_radians(),
                point: [0.0, 0.0],
            }),
            marks,
            turns: None,
            friction_sigma: None,
        };
        scene.push(SceneVehicle {
            id,
            chassis,
            pose,
            evidence,
        });
        runouts.push(run);
    }
    // Contact evidence: the lateral velocity and yaw rate (from the approach), not the speeds.
    let unit = SIGMA_YAW * SIGMA_YAW;
    let mut components = [Knowledge::Unknown; 12];
    let mut observations = Vec::new();
    for id in [VehicleId::One, VehicleId::Two] {
        let k = id.index();
        let v = if k == 0 { ri.x.vehicle1 } else { ri.x.vehicle2 };
        let f = ri.impact.forward_axis(id);
        let lateral = -v.vx * f[1] + v.vy * f[0];
        observations.push(Observation {
            kind: ObservationKind::LateralVelocity,
            vehicle: id,
            value: lateral + noise * SIGMA_LATERAL * common_normal(&mut rng),
            weight: unit / (SIGMA_LATERAL * SIGMA_LATERAL),
        });
        components[3 * k + 2] = Knowledge::Estimated {
            value: v.omega + noise * SIGMA_YAW * common_normal(&mut rng),
            weight: 1.0,
        };
    }
    let mut contact = FitProblem::from_preset(ri.impact, CostPreset::Q3, &ri.x, &sep, None);
    contact.components = components;
    contact.observations = observations;
    Some(Crash {
        recon: Reconstruction {
            contact,
            unit: Some(unit),
            scene,
            skids: [None, None],
            nonlinear: Default::default(),
            frictions: Vec::new(),
        },
        contact: ri.x,
        separation: sep,
        runouts,
    })
}

pub fn common_normal(rng: &mut StdRng) -> f64 {
    // Box-Muller.
    let u1: f64 = rng.random_range(f64::EPSILON..1.0);
    let u2: f64 = rng.random_range(0.0..1.0);
    (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
}

/// The fit's settings of a case file (bounds 100 m/s and 15 rad/s: a spinning car's yaw rate
/// at separation passes 5 rad/s).
pub fn settings() -> Settings {
    let fit = FitSettings {
        velocity_bound: 100.0,
        yaw_rate_bound: 15.0,
        ..FitSettings::default()
    };
    Settings::new(fit.check().unwrap())
}

/// The chi-square of the truth against the (noisy) evidence: the contact evidence at the true
/// contact state and each scene against the true run-out, with its true count of turns.
pub fn truth_cost(c: &Crash) -> f64 {
    let u = pim_fit::state_vector(&c.contact, &c.separation);
    let mut total = c.recon.contact_chi_square(&u);
    for (v, run) in c.recon.scene.iter().zip(&c.runouts) {
        let h = v.evidence.rest.and_then(|r| r.heading).unwrap();
        let nearest = h + TAU * ((v.pose.heading - h) / TAU).round();
        let turns = ((run.rest.heading - nearest) / TAU).round() as i64;
        let lin = pim_runout::linearise(
            &v.chassis,
            &run.start,
            &v.evidence,
            turns,
            &RunoutSettings::default(),
            false,
        )
        .unwrap();
        total += lin.cost;
    }
    total
}
