//! `data/ricsac.csv` checked cell by cell against its sources, its derived impact-centre distances
//! recomputed, and each test solved forwards with Brach 1984 Table 1B.
use crate::common;
use common::*;
use pim_case::ricsac::RicsacTest;
use pim_core::outline::{impact_centre_distance, Outline};
use pim_core::*;

fn tests() -> Vec<RicsacTest> {
    ricsac_tests()
}

fn by_test(rows: &[Row], t: u32) -> &Row {
    rows.iter()
        .find(|r| r.text("test") == t.to_string())
        .unwrap_or_else(|| panic!("no row for test {t}"))
}

#[test]
fn eleven_tests_in_order() {
    let ids: Vec<u32> = tests().iter().map(|t| t.test).collect();
    assert_eq!(ids, vec![1, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12]);
}

#[test]
fn velocities_and_angles_are_vossou2018_tables_1_and_2_as_printed() {
    let t1 = read_reference("data/reference/vossou2018_table1.csv");
    let t2 = read_reference("data/reference/vossou2018_table2.csv");
    for t in tests() {
        let r1 = by_test(&t1, t.test);
        let r2 = by_test(&t2, t.test);
        let pairs = [
            (t.vi1x_mps, r1.num("vi1x")),
            (t.vi1y_mps, r1.num("vi1y")),
            (t.wi1_radps, r1.num("wi1")),
            (t.vi2x_mps, r1.num("vi2x")),
            (t.vi2y_mps, r1.num("vi2y")),
            (t.wi2_radps, r1.num("wi2")),
            (t.vf1x_mps, r1.num("vf1x")),
            (t.vf1y_mps, r1.num("vf1y")),
            (t.wf1_radps, r1.num("wf1")),
            (t.vf2x_mps, r1.num("vf2x")),
            (t.vf2y_mps, r1.num("vf2y")),
            (t.wf2_radps, r1.num("wf2")),
            (t.crush_angle_deg, r2.num("crush_angle")),
            (t.heading1_deg, r2.num("theta1")),
            (t.heading2_deg, r2.num("theta2")),
            (t.phi1_deg, r2.num("phi1")),
            (t.phi2_deg, r2.num("phi2")),
        ];
        for (k, (got, want)) in pairs.iter().enumerate() {
            assert!(
                (got - want).abs() < 1e-12,
                "test {} value {k}: {got} vs {want}",
                t.test
            );
        }
    }
}

#[test]
fn masses_and_inertias_come_from_the_stated_sources() {
    let veh = read_reference("data/ricsac_vehicles.csv");
    for t in tests() {
        let (m1, i1, m2, i2) = match t.test {
            // Brach 1983 Table 1 (Neades' row 7.2, 771 kg, is implausible for a test car).
            7 => (1955.0, 4723.0, 1197.0, 2279.0),
            9 => (1036.0, 1348.0, 2189.0, 5287.0),
            n => {
                let v = |k: &str| {
                    veh.iter()
                        .find(|r| r.text("test") == n.to_string() && r.text("vehicle") == k)
                        .unwrap()
                };
                (
                    v("1").num("mass_kg"),
                    v("1").num("yaw_inertia_kgm2"),
                    v("2").num("mass_kg"),
                    v("2").num("yaw_inertia_kgm2"),
                )
            }
        };
        assert_eq!(
            [
                t.mass1_kg,
                t.yaw_inertia1_kgm2,
                t.mass2_kg,
                t.yaw_inertia2_kgm2
            ]
            .map(|x| x.to_bits()),
            [m1, i1, m2, i2].map(|x: f64| x.to_bits()),
            "test {}",
            t.test
        );
    }
}

/// d by the rule of `pim_core::outline` from the vehicle file.
fn derived_d(veh: &[Row], test: u32, vehicle: u32, phi: f64) -> f64 {
    let v = veh
        .iter()
        .find(|r| r.text("test") == test.to_string() && r.text("vehicle") == vehicle.to_string())
        .unwrap();
    let outline = Outline {
        cg_to_front: v.num("cg_to_front_cm") / 100.0,
        cg_to_rear: v.num("cg_to_rear_cm") / 100.0,
        width: v.num("width_cm") / 100.0,
    };
    let crush = ["c1_cm", "c2_cm", "c3_cm", "c4_cm", "c5_cm", "c6_cm"]
        .iter()
        .map(|c| v.num(c))
        .sum::<f64>()
        / 6.0
        / 100.0;
    impact_centre_distance(&outline, phi, crush).0
}

#[test]
fn every_derived_d_is_recomputed_from_dimensions_and_crush() {
    let veh = read_reference("data/ricsac_vehicles.csv");
    let mut derived = 0;
    for t in tests() {
        for (k, d, src, phi) in [
            (1, t.d1_m, &t.d1_source, t.phi1_deg),
            (2, t.d2_m, &t.d2_source, t.phi2_deg),
        ] {
            let rule = derived_d(&veh, t.test, k, phi);
            if src.starts_with("derived") {
                derived += 1;
                // The file stores d to the millimetre.
                assert!(
                    (d - rule).abs() <= 0.0005,
                    "test {} d{k}: file {d}, rule {rule:.4}",
                    t.test
                );
            } else {
                let published = match (t.test, k) {
                    (6, 1) => 2.56,
                    (6, 2) => 0.61,
                    (9, 1) => 1.4,
                    (9, 2) => 1.6,
                    _ => panic!("test {} d{k}: unknown published source {src}", t.test),
                };
                assert!((d - published).abs() < 1e-12);
                println!(
                    "test {} d{k}: published {d} m, rule gives {rule:.3} m",
                    t.test
                );
            }
        }
    }
    assert_eq!(derived, 18);
    // The rule against Brach 1984 Table 2 (RICSAC 6): 2.60 / 0.53 m against 2.56 / 0.61 m.
    assert!((derived_d(&veh, 6, 1, -17.9) - 2.56).abs() < 0.05);
    assert!((derived_d(&veh, 6, 2, -90.0) - 0.61).abs() < 0.10);
}

#[test]
fn measured_delta_v_against_table_1_with_the_known_mismatches() {
    let t7 = read_reference("data/reference/vossou2018_table7.csv");
    let mut mismatches = Vec::new();
    for t in tests() {
        let r = by_test(&t7, t.test);
        assert_eq!(t.dv1_measured_mps.to_bits(), r.num("dv1").to_bits());
        assert_eq!(t.dv2_measured_mps.to_bits(), r.num("dv2").to_bits());
        let (x, xf) = (t.initial(), t.separation());
        let dv1 = (xf.vehicle1.vx - x.vehicle1.vx).hypot(xf.vehicle1.vy - x.vehicle1.vy);
        let dv2 = (xf.vehicle2.vx - x.vehicle2.vx).hypot(xf.vehicle2.vy - x.vehicle2.vy);
        for (veh, from_table1, measured) in
            [(1, dv1, t.dv1_measured_mps), (2, dv2, t.dv2_measured_mps)]
        {
            let diff = from_table1 - measured;
            if diff.abs() > 0.011 {
                println!(
                    "test {} vehicle {veh}: Table 1 gives {from_table1:.2}, Table 7 {measured}",
                    t.test
                );
                mismatches.push((t.test, veh, (from_table1 * 100.0).round() / 100.0));
            }
        }
    }
    // Known and documented in data/README.md: test 10 vehicle 2 (5.62 from Table 1 vs 5.81) and
    // test 12 vehicle 1 (19.45 vs 18.75; Table 1's initial speed 15.41 m/s against 13.6 measured).
    assert_eq!(mismatches, vec![(10, 2, 5.62), (12, 1, 19.45)]);
}

fn no_slip_loss(c: Collision, x: &Velocities, e: f64) -> (f64, f64) {
    let impact = Impact::new(c).unwrap();
    let opts = SolveOptions {
        tangential: TangentialCondition::NoSlip,
        ..Default::default()
    };
    let r = solve_forward(
        &impact,
        &Coefficients {
            e,
            mu: 0.0,
            em: 1.0,
        },
        x,
        &opts,
    )
    .unwrap();
    (r.energy.loss_percent, r.mu_max.unwrap())
}

/// Brach 1984 Table 1B (em = 1, mu = mu_max): solving each test forwards from its initial
/// velocities with Brach's e and the no-slip condition gives Brach's fitted separation state,
/// so its energy loss should land near the published one when the inputs agree with Brach's.
#[test]
fn energy_loss_with_brach1984_table1b_coefficients() {
    let b = read_reference("data/reference/brach1984_table1.csv");
    let mut report = Vec::new();
    for t in tests() {
        let row = b
            .iter()
            .find(|r| r.text("branch") == "B" && r.text("test") == t.test.to_string())
            .unwrap();
        let (loss, mu_max) = no_slip_loss(t.collision(), &t.initial(), row.num("e"));
        let published = row.num("energy_loss_percent");
        let diff = loss - published;
        report.push(format!(
            "test {:>2}: loss {loss:5.1} % vs {published:5.1} % ({diff:+5.1}); mu_max {mu_max:+.3} vs Brach's mu {:+.3}",
            t.test,
            row.num("mu")
        ));
        // Near: within 1.2 points. Far, each explained below: 7, 10, 12.
        let tol = match t.test {
            7 | 10 | 12 => f64::INFINITY,
            _ => 1.2,
        };
        assert!(
            diff.abs() <= tol,
            "test {}: {loss:.2} vs {published}",
            t.test
        );
    }
    println!("{}", report.join("\n"));
    let data = tests();
    let get = |n: u32| data.iter().find(|t| t.test == n).unwrap();

    // Test 7 (65.4 % vs 48.8 %): Vossou prints phi1 = +17.9 deg, test 6 (same configuration, same
    // vehicles) -17.9 deg. With -17.9 deg the loss is within a point of Brach's.
    let t7 = get(7);
    let (as_printed, _) = no_slip_loss(t7.collision(), &t7.initial(), 0.0);
    assert!(as_printed > 60.0);
    let mut c = t7.collision();
    c.vehicle1.phi = -17.9;
    let (fixed, _) = no_slip_loss(c, &t7.initial(), 0.0);
    assert!((fixed - 48.8).abs() < 1.0, "{fixed}");

    // Test 12 (94.7 % vs 91.9 %): Table 1's initial speed of vehicle 1 is 15.41 m/s, 13.6 m/s was
    // measured; at 13.6 m/s the loss moves to within a point.
    let t12 = get(12);
    let mut x = t12.initial();
    let k = 13.6 / x.vehicle1.speed();
    x.vehicle1.vx *= k;
    x.vehicle1.vy *= k;
    let (slow, _) = no_slip_loss(t12.collision(), &x, 0.100);
    assert!((slow - 91.9).abs() < 1.0, "{slow}");

    // Test 10 (24.9 % vs 31.0 %): d is derived (no published value) and Brach placed the impact
    // centre nearer the CGs; with both d at 60 % of the rule's the loss is 32.1 %.
    let t10 = get(10);
    let mut c = t10.collision();
    c.vehicle1.d *= 0.6;
    c.vehicle2.d *= 0.6;
    let (near, _) = no_slip_loss(c, &t10.initial(), 0.419);
    assert!((near - 31.0).abs() < 1.5, "{near}");

    // The sign of mu_max: negative for tests 3 and 4 as in Brach's fits. Test 5 comes out positive
    // because Vossou prints phi2 = -168 deg (tests 3 and 4: +171.4, +171.7); with +168 deg it is
    // negative like Brach's -0.090.
    for n in [3, 4] {
        let t = get(n);
        assert!(
            no_slip_loss(t.collision(), &t.initial(), 0.1).1 < 0.0,
            "test {n}"
        );
    }
    let t5 = get(5);
    assert!(no_slip_loss(t5.collision(), &t5.initial(), 0.053).1 > 0.0);
    let mut c = t5.collision();
    c.vehicle2.phi = 168.0;
    let (_, mm) = no_slip_loss(c, &t5.initial(), 0.053);
    assert!((mm + 0.090).abs() < 0.02, "{mm}");
}
