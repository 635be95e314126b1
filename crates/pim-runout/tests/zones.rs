//! Friction zones in the run-out model: a sliding translation across an edge stops where the
//! work of the friction on each side says, and random run-outs crossing a zone agree with the
//! independent implementation (tests/common/runout.rs), which computes the friction under each
//! wheel on its own (a winding number for inside, not the crossing rule).
mod common;

use common::runout::{random_chassis, random_start, Reference, KINDS};
use pim_runout::{
    differentiate_zones, linearise_with_friction, simulate, Chassis, End, Evidence, Motion, Rest,
    Settings, WheelState, Zone, GRAVITY,
};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use rayon::prelude::*;

/// A rectangle `depth` deep and 200 m wide whose near edge passes through `at`, square to the
/// direction `dir` (a unit vector), lying beyond it.
fn across(at: [f64; 2], dir: [f64; 2], depth: f64, friction: f64) -> Zone {
    let n = [-dir[1], dir[0]];
    let corner = |along: f64, side: f64| {
        [
            at[0] + along * dir[0] + side * n[0],
            at[1] + along * dir[1] + side * n[1],
        ]
    };
    Zone {
        corners: vec![
            corner(0.0, -100.0),
            corner(depth, -100.0),
            corner(depth, 100.0),
            corner(0.0, 100.0),
        ],
        friction,
    }
}

/// Four locked wheels sliding straight ahead (no CG height, no yaw) from a road of friction
/// `mu1` onto a zone of `mu2`: every wheel does the work
/// `Fz_i (mu1 (xb - x_i) + mu2 (x_i + D - xb))` (the friction's change about the edge is
/// symmetric, so the work is a sharp edge's), and their sum is the kinetic energy, so the
/// run-out's length is
/// `D = (m v^2 / 2 - (mu1 - mu2) sum Fz_i (xb - x_i)) / (mu2 m g)`. Met to a micrometre, with
/// the wheels entering a zone of higher and of lower friction, the vehicle straight.
#[test]
fn a_sliding_translation_across_an_edge_stops_where_the_work_says() {
    for (mu1, mu2) in [(0.8, 0.3), (0.3, 0.9), (0.7, 0.69)] {
        let mut c = Chassis::new(1500.0, 2400.0, 2.7, 1.2, 1.55, WheelState::Locked);
        c.friction = mu1;
        let xb = 6.0;
        c.zones = vec![across([xb, 0.0], [1.0, 0.0], 500.0, mu2)];
        let v = 15.0;
        let start = Motion {
            vx: v,
            ..Motion::default()
        };
        let r = simulate(&c, &start, &Settings::default()).unwrap();
        let loads = c.static_loads();
        let before: f64 = (0..4)
            .map(|i| loads[i] * (xb - c.wheel_position(i)[0]))
            .sum();
        let d = (0.5 * c.mass * v * v - (mu1 - mu2) * before) / (mu2 * c.mass * GRAVITY);
        println!("{mu1} onto {mu2}: {:.6} m against {d:.6} m", r.rest.x);
        assert_eq!(r.end, End::Rest);
        assert!((r.rest.x - d).abs() < 1e-6, "{} against {d}", r.rest.x);
        assert!(r.rest.y.abs() < 1e-9 && r.rest.heading.abs() < 1e-9);
        assert!((r.tyre_work - r.initial_energy).abs() < 1e-6 * r.initial_energy);
    }
}

/// 100 random run-outs of each wheel state, each crossing a zone of a random friction laid
/// square across its path half way along (the rectangle 5 to 40 m deep): the rests agree with
/// the independent implementation to a centimetre and a tenth of a degree, the tyres' work is
/// the kinetic energy lost (1e-6), and a zone of the road's own friction changes nothing.
#[test]
fn run_outs_across_a_zone_agree_with_an_independent_implementation() {
    for kind in KINDS {
        let worst: Vec<(f64, f64, f64, f64)> = (0..100u64)
            .into_par_iter()
            .map(|seed| {
                let mut rng = StdRng::seed_from_u64(31_000 + seed);
                let mut c = random_chassis(&mut rng, kind);
                let start = random_start(&mut rng, 25.0);
                let s = Settings::default();
                let plain = simulate(&c, &start, &s).unwrap();
                let half = plain.at(plain.time / 2.0);
                let (dx, dy) = (plain.rest.x - start.x, plain.rest.y - start.y);
                let n = dx.hypot(dy).max(1e-9);
                let friction = rng
                    .random_range(0.1..1.0_f64)
                    .max(2.0 * c.rolling_resistance);
                let depth = rng.random_range(5.0..40.0);
                let zone = across([half.x, half.y], [dx / n, dy / n], depth, friction);
                // The road's own friction on the zone: the same run-out.
                c.zones = vec![Zone {
                    friction: c.friction,
                    ..zone.clone()
                }];
                let same = simulate(&c, &start, &s).unwrap();
                let unchanged = (same.rest.x - plain.rest.x).hypot(same.rest.y - plain.rest.y);
                c.zones = vec![zone];
                let r = simulate(&c, &start, &s).unwrap();
                let (rest, stopped) = Reference::new(&c).run(&start);
                assert_eq!(
                    stopped,
                    r.end == End::Rest,
                    "{kind:?} seed {seed}: ends differ"
                );
                let balance = if r.end == End::Rest {
                    (r.tyre_work - r.initial_energy).abs() / r.initial_energy
                } else {
                    0.0
                };
                (
                    (r.rest.x - rest[0]).hypot(r.rest.y - rest[1]),
                    (r.rest.heading - rest[2]).abs().to_degrees(),
                    balance,
                    unchanged,
                )
            })
            .collect();
        let max = |k: usize| {
            worst
                .iter()
                .map(|w| [w.0, w.1, w.2, w.3][k])
                .fold(0.0, f64::max)
        };
        println!(
            "{kind:?}: 100 run-outs across a zone, largest difference at rest {:.2e} m, {:.2e} \
             deg; energy balance {:.1e}; a zone of the road's friction moves the rest {:.1e} m",
            max(0),
            max(1),
            max(2),
            max(3)
        );
        assert!(max(0) < 0.01, "{kind:?}: {} m", max(0));
        assert!(max(1) < 0.1, "{kind:?}: {} deg", max(1));
        assert!(max(2) < 1e-6, "{kind:?}: {}", max(2));
        assert!(max(3) < 1e-12, "{kind:?}: {}", max(3));
    }
}

/// A zone is checked: too few corners, no area, or a friction at or below the rolling
/// resistance is refused, naming the zone.
#[test]
fn a_bad_zone_names_itself() {
    let mut c = Chassis::new(1500.0, 2400.0, 2.7, 1.2, 1.55, WheelState::Rolling);
    let good = across([0.0, 0.0], [1.0, 0.0], 10.0, 0.5);
    c.zones = vec![
        good.clone(),
        Zone {
            friction: 0.01,
            ..good
        },
    ];
    let e = c.check().unwrap_err().to_string();
    assert!(
        e.contains("zone 2") && e.contains("rolling resistance"),
        "{e}"
    );
    c.zones[1].corners.truncate(2);
    let e = c.check().unwrap_err().to_string();
    assert!(e.contains("zone 2") && e.contains("three"), "{e}");
}

/// The derivative of a rest's residual with respect to a zone's friction
/// (`differentiate_zones`): for the sliding translation above, the run-out's length is
/// `D(mu2) = (m v^2/2 - (mu1 - mu2) B) / (mu2 m g)` with `B = sum Fz_i (xb - x_i)`, so
/// `dD/dmu2 = (B - D m g) / (mu2 m g)`, and the rest's x residual in deviations moves by that
/// over its sigma. Met to 1e-4 relative (a forward difference through the run-out's steps);
/// the road friction's column is the road's (`-B / (mu2 m g)`), and a zone the run-out never
/// reaches has a column of zeros (below 1e-6, the rounding of the stepped run-out's end).
#[test]
fn a_zones_friction_derivative_is_the_work_formulas() {
    let (mu1, mu2, v, xb) = (0.8, 0.4, 15.0, 6.0);
    let mut c = Chassis::new(1500.0, 2400.0, 2.7, 1.2, 1.55, WheelState::Locked);
    c.friction = mu1;
    c.zones = vec![
        across([xb, 0.0], [1.0, 0.0], 500.0, mu2),
        across([-50.0, 0.0], [-1.0, 0.0], 10.0, 0.2),
    ];
    let start = Motion {
        vx: v,
        ..Motion::default()
    };
    let w = c.mass * GRAVITY;
    let b: f64 = (0..4)
        .map(|i| c.static_loads()[i] * (xb - c.wheel_position(i)[0]))
        .sum();
    let d = (0.5 * c.mass * v * v - (mu1 - mu2) * b) / (mu2 * w);
    let sigma = 0.1;
    let ev = Evidence {
        rest: Some(Rest {
            x: d + 0.3,
            y: 0.0,
            heading: None,
            sigma_xy: [sigma, sigma],
            sigma_heading: 1.0,
            point: [0.0, 0.0],
        }),
        ..Evidence::default()
    };
    let s = Settings::default();
    let lin = linearise_with_friction(&c, &start, &ev, 0, &s).unwrap();
    let before = (lin.runouts, lin.evaluations);
    let lin = differentiate_zones(lin, &c, &start, &ev, 0, &s).unwrap();
    assert_eq!(lin.zones.len(), 2);
    assert_eq!(lin.runouts, before.0 + 2);
    let expected = (b - d * w) / (mu2 * w) / sigma;
    let got = lin.zones[0][0];
    println!("d(rest.x)/d(mu zone) {got:.6} against {expected:.6} per deviation");
    assert!((got - expected).abs() < 1e-4 * expected.abs(), "{got}");
    // The road's: dD/dmu1 = -B / (mu2 m g).
    let road = lin.friction.as_ref().unwrap()[0];
    let expected_road = -b / (mu2 * w) / sigma;
    assert!(
        (road - expected_road).abs() < 1e-4 * expected_road.abs(),
        "{road}"
    );
    assert!(
        lin.zones[1].iter().all(|x| x.abs() < 1e-6),
        "{:?}",
        lin.zones[1]
    );
    // Differentiated again: nothing more is run.
    let again = differentiate_zones(lin.clone(), &c, &start, &ev, 0, &s).unwrap();
    assert_eq!(again.runouts, lin.runouts);
}
