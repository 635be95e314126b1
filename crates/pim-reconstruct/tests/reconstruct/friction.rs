//! The road friction fitted with the velocities: a datum of the chi-square (its stated value
//! and standard deviation) and an unknown of every run-out on it, on simulated crashes with a
//! known truth.
use crate::common;

use common::crash::{crashes, settings, Crash};
use pim_fit::{Knowledge, Vector12};
use pim_reconstruct::{reconstruct, RoadFriction, Status};

/// One friction under both vehicles, stated `off` standard deviations from the truth (sigma
/// `sigma`); the scenes keep the true friction of each (the crashes draw one per vehicle, so
/// both are set to the first's).
fn on_one_road(c: &mut Crash, off: f64, sigma: f64) -> f64 {
    let truth = c.recon.scene[0].chassis.friction;
    // Both vehicles ran out on the same road: the second's run-out again at the first's
    // friction (its rest and marks from that run-out).
    c.recon.scene[1].chassis.friction = truth;
    let v = &c.recon.scene[1];
    let start = pim_runout::Motion {
        vx: c.runouts[1].start.vx,
        vy: c.runouts[1].start.vy,
        yaw_rate: c.runouts[1].start.yaw_rate,
        ..v.pose
    };
    let run = pim_runout::simulate(&v.chassis, &start, &pim_runout::Settings::default()).unwrap();
    let e = &mut c.recon.scene[1].evidence;
    let rest = e.rest.as_mut().unwrap();
    rest.x = run.rest.x;
    rest.y = run.rest.y;
    rest.heading = Some(run.rest.heading.rem_euclid(std::f64::consts::TAU));
    for (m, f) in e.marks.iter_mut().zip([0.3, 0.6]) {
        let p = run.at(f * run.time);
        m.x = p.x;
        m.y = p.y;
    }
    c.runouts[1] = run;
    let stated = truth + off * sigma;
    for s in &mut c.recon.scene {
        s.chassis.friction = stated;
    }
    c.recon.frictions = vec![RoadFriction {
        name: "road friction".into(),
        zone: None,
        value: stated,
        sigma,
        vehicles: vec![0, 1],
        skids: Vec::new(),
    }];
    truth
}

/// Scenes without a speed (rest positions, marks, directions at contact) cannot tell the speed
/// from the friction (a sliding path keeps its shape when the friction scales by s and the
/// speeds by sqrt(s)): the truth with its friction one sigma off its stated value costs 1, and
/// the answer costs no more.
#[test]
fn the_friction_never_costs_more_than_the_truth() {
    for (seed, mut c) in crashes(0.0).take(4) {
        on_one_road(&mut c, 1.0, 0.05);
        let out = reconstruct(&c.recon, &settings()).unwrap();
        assert_eq!(out.status, Status::Found, "seed {seed}: {:?}", out.reason);
        let b = out.best.as_ref().unwrap();
        assert_eq!(b.frictions.len(), 1);
        assert!(
            b.chi_square <= 1.0 + 1e-6,
            "seed {seed}: chi-square {} against the truth's 1",
            b.chi_square
        );
    }
}

/// Vehicle 1's velocity at contact known to 0.05 m/s (an EDR): the scenes then fix the speed
/// and with it the friction.
fn speed_of_vehicle1_known(c: &mut Crash) {
    let unit = c.recon.unit.unwrap();
    let u: Vector12 = pim_fit::state_vector(&c.contact, &c.separation);
    for k in 0..2 {
        c.recon.contact.components[k] = Knowledge::Estimated {
            value: u[k],
            weight: unit / 0.05f64.powi(2),
        };
    }
}

/// With the speed at contact of vehicle 1 known (an EDR, 0.05 m/s), the scenes fix the speed
/// and with it the friction: stated two sigmas off, the friction is found back at the truth.
#[test]
fn a_known_speed_finds_the_friction_back() {
    for (seed, mut c) in crashes(0.0).take(3) {
        let truth = on_one_road(&mut c, 2.0, 0.1);
        speed_of_vehicle1_known(&mut c);
        let out = reconstruct(&c.recon, &settings()).unwrap();
        let Some(b) = out.best.as_ref() else {
            panic!("seed {seed}: {:?}", out.reason)
        };
        assert!(
            (b.frictions[0] - truth).abs() < 0.01,
            "seed {seed}: friction {} against the truth's {truth} (stated {})",
            b.frictions[0],
            truth + 0.2
        );
    }
}

/// An answer refined again from itself ([`pim_reconstruct::refine_earlier`], the start of
/// `pim fit --from` and of a pose fit's search) starts on the frictions its run-outs ran on:
/// with the friction fitted 0.2 from its stated value, it is at its minimum from the first
/// step (the same chi-square and friction, one iteration). Started on the stated friction
/// instead, each run-out ends elsewhere and the refinement has to find its way back.
#[test]
fn an_answer_refined_again_starts_on_its_fitted_friction() {
    for (seed, mut c) in crashes(0.0).take(2) {
        on_one_road(&mut c, 2.0, 0.1);
        speed_of_vehicle1_known(&mut c);
        let s = settings();
        let out = reconstruct(&c.recon, &s).unwrap();
        let b = out.best.as_ref().expect("an answer");
        let earlier = b.earlier();
        assert_eq!(earlier.frictions.as_deref(), Some(&b.frictions[..]));
        let again = pim_reconstruct::refine_earlier(&c.recon, &s, &earlier).expect("refined");
        let stated = pim_reconstruct::refine_earlier(
            &c.recon,
            &s,
            &pim_reconstruct::Earlier {
                frictions: None,
                ..earlier.clone()
            },
        );
        eprintln!(
            "seed {seed}: answer {:.6} (friction {:.4}); again {:.6} in {} iterations; from \
             the stated friction {:?}",
            b.chi_square,
            b.frictions[0],
            again.chi_square,
            again.iterations,
            stated.as_ref().map(|f| (f.chi_square, f.iterations))
        );
        assert!(
            (again.chi_square - b.chi_square).abs() <= 1e-6 * (1.0 + b.chi_square),
            "seed {seed}: {} against {}",
            again.chi_square,
            b.chi_square
        );
        assert!((again.frictions[0] - b.frictions[0]).abs() < 1e-4);
        assert!(again.iterations <= 2, "{}", again.iterations);
        let stated = stated.expect("refined from the stated friction");
        assert!(
            stated.iterations > again.iterations,
            "{}",
            stated.iterations
        );
    }
}
