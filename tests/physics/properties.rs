//! Property tests of the forward solver over random valid inputs (seeded, reproducible).
use crate::common;
use common::*;
use pim_core::*;
use proptest::prelude::*;
use proptest::strategy::ValueTree;

fn runner(cases: u32) -> proptest::test_runner::TestRunner {
    seeded_runner(cases, 7)
}

prop_compose! {
    fn arb_vehicle()(mass in 600.0..3000.0, inertia in 500.0..6000.0, heading in -180.0..180.0,
                     d in 0.2..3.0, phi in -180.0..180.0) -> Vehicle {
        vehicle(mass, inertia, heading, d, phi)
    }
}

prop_compose! {
    fn arb_collision()(v1 in arb_vehicle(), v2 in arb_vehicle(), g in -90.0..90.0) -> Collision {
        Collision { vehicle1: v1, vehicle2: v2, crush_angle: g }
    }
}

prop_compose! {
    fn arb_state()(v in prop::array::uniform6(-20.0..20.0f64), w1 in -2.0..2.0, w2 in -2.0..2.0)
        -> Velocities {
        state([v[0], v[1], w1, v[3], v[4], w2])
    }
}

fn arb_em() -> impl Strategy<Value = f64> {
    prop_oneof![Just(1.0), -1.0..0.0]
}

/// A collision, an approaching contact state and coefficients with 0 <= mu/mu_max <= 1.
fn arb_case() -> impl Strategy<Value = (Impact, Velocities, Coefficients)> {
    (
        arb_collision(),
        arb_state(),
        0.0..1.0f64,
        0.0..1.0f64,
        arb_em(),
    )
        .prop_filter_map(
            "vehicles must approach and the system be regular",
            |(c, x, e, frac, em)| {
                let impact = Impact::new(c).ok()?;
                impact.check_approach(&x).ok()?;
                let probe = Coefficients { e, mu: 0.0, em };
                let mu_max =
                    critical_friction(&impact, &probe, &x, &SolveOptions::default()).ok()??;
                Some((
                    impact,
                    x,
                    Coefficients {
                        e,
                        mu: frac * mu_max,
                        em,
                    },
                ))
            },
        )
}

#[test]
fn momentum_and_angular_momentum_hold_to_round_off() {
    runner(2000)
        .run(&arb_case(), |(impact, x, c)| {
            let r = solve_forward(&impact, &c, &x, &SolveOptions::default()).unwrap();
            let [m1, m2] = impact.masses();
            let xf = &r.separation;
            let px = m1 * (xf.vehicle1.vx - x.vehicle1.vx) + m2 * (xf.vehicle2.vx - x.vehicle2.vx);
            let py = m1 * (xf.vehicle1.vy - x.vehicle1.vy) + m2 * (xf.vehicle2.vy - x.vehicle2.vy);
            let scale = m1 * x.vehicle1.speed() + m2 * x.vehicle2.speed();
            prop_assert!(px.abs() <= 1e-11 * scale, "px residual {px}");
            prop_assert!(py.abs() <= 1e-11 * scale, "py residual {py}");
            // Every equation, angular momentum included, holds to round-off relative to its terms.
            let res = r.residuals(&impact);
            prop_assert!(res.max_relative() <= 1e-10, "{:?}", res);
            Ok(())
        })
        .unwrap();
}

#[test]
fn forward_then_backward_returns_the_start() {
    runner(1000)
        .run(&arb_case(), |(impact, x, mut c)| {
            // e = 0 or em = 0 make the backward problem singular (tested elsewhere).
            c.e = c.e.max(0.05);
            if c.em > -0.05 && c.em < 1.0 {
                c.em = -0.5;
            }
            let opts = SolveOptions::default();
            let fwd = solve_forward(&impact, &c, &x, &opts).unwrap();
            let back =
                solve_backward_with_sign(&impact, &c, &fwd.separation, &opts, fwd.friction_sign)
                    .unwrap();
            let d = (back.initial.to_vector() - x.to_vector()).amax();
            prop_assert!(
                d <= 1e-7 * (1.0 + x.to_vector().amax()),
                "start not recovered: {d}"
            );
            // From an admissible start, the automatic direction search finds that start, or says
            // the problem has two admissible answers.
            if !fwd.admissibility.admissible {
                return Ok(());
            }
            match solve_backward(&impact, &c, &fwd.separation, &opts) {
                Ok(b) => prop_assert!(
                    (b.initial.to_vector() - x.to_vector()).amax()
                        <= 1e-7 * (1.0 + x.to_vector().amax())
                ),
                Err(PimError::InconsistentSliding(msg)) => {
                    prop_assert!(msg.contains("both friction directions"))
                }
                Err(e) => prop_assert!(false, "unexpected {e}"),
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn point_mass_closed_form_agrees_with_the_6x6_solve() {
    let strat = (
        600.0..3000.0f64,
        600.0..3000.0f64,
        -90.0..90.0f64,
        prop::array::uniform4(-20.0..20.0f64),
        0.0..1.0f64,
        0.0..1.2f64,
        arb_em(),
    );
    runner(2000)
        .run(&strat, |(m1, m2, g, v, e, mu, em)| {
            let impact = Impact::new(Collision {
                vehicle1: vehicle(m1, 1000.0, 0.0, 0.0, 0.0),
                vehicle2: vehicle(m2, 1000.0, 0.0, 0.0, 0.0),
                crush_angle: g,
            })
            .unwrap();
            let x = state([v[0], v[1], 0.0, v[2], v[3], 0.0]);
            if impact.check_approach(&x).is_err() {
                return Ok(());
            }
            let c = Coefficients { e, mu, em };
            let pm = PointMassImpact {
                masses: [m1, m2],
                crush_angle: g,
                initial: [[v[0], v[1]], [v[2], v[3]]],
            };
            for tangential in [TangentialCondition::Sliding, TangentialCondition::NoSlip] {
                let opts = SolveOptions {
                    tangential,
                    ..Default::default()
                };
                let r = solve_forward(&impact, &c, &x, &opts).unwrap();
                let cf = solve_point_mass(&pm, &c, tangential).unwrap();
                let s = &r.separation;
                let got = [s.vehicle1.vx, s.vehicle1.vy, s.vehicle2.vx, s.vehicle2.vy];
                let want = [
                    cf.separation[0][0],
                    cf.separation[0][1],
                    cf.separation[1][0],
                    cf.separation[1][1],
                ];
                for k in 0..4 {
                    prop_assert!(
                        (got[k] - want[k]).abs() <= 1e-9 * 40.0,
                        "{tangential:?} {k}: {} vs {}",
                        got[k],
                        want[k]
                    );
                }
                prop_assert!(s.vehicle1.omega.abs() < 1e-12 && s.vehicle2.omega.abs() < 1e-12);
                // Energy loss from Brach 1984 eq. 10 and mu_max from eq. 11.
                prop_assert!(
                    (r.energy.loss - cf.energy_loss).abs() <= 1e-8 * r.energy.initial.max(1.0)
                );
                let mm = r.mu_max.unwrap();
                prop_assert!(
                    (mm - cf.mu_max).abs() <= 1e-9 * (1.0 + mm.abs()),
                    "mu_max {mm} vs {}",
                    cf.mu_max
                );
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn at_mu_max_the_tangential_velocity_at_separation_vanishes() {
    runner(2000)
        .run(&arb_case(), |(impact, x, mut c)| {
            let opts = SolveOptions::default();
            c.mu = critical_friction(&impact, &c, &x, &opts).unwrap().unwrap();
            let r = solve_forward(&impact, &c, &x, &opts).unwrap();
            let scale = x.max_speed() + x.vehicle1.omega.abs() * 3.0 + x.vehicle2.omega.abs() * 3.0;
            prop_assert!(
                r.relative.tangential_final.abs() <= 1e-9 * scale,
                "Vt = {}",
                r.relative.tangential_final
            );
            prop_assert_eq!(r.tangential, TangentialOutcome::Sticking);
            // And the no-slip form gives the same state.
            let ns = solve_forward(
                &impact,
                &c,
                &x,
                &SolveOptions {
                    tangential: TangentialCondition::NoSlip,
                    ..opts
                },
            )
            .unwrap();
            prop_assert!(
                (ns.separation.to_vector() - r.separation.to_vector()).amax()
                    <= 1e-8 * (1.0 + scale)
            );
            Ok(())
        })
        .unwrap();
}

/// Inside the friction domain the corrected moment equation still creates
/// kinetic energy in a sizeable share of random impacts with -1 < em < 0 (about 28 % of such
/// random impacts), less often with em = 1 or em = 0. The solver must flag every such case.
#[test]
fn energy_creation_inside_the_friction_domain_is_detected() {
    let mut rng = runner(1);
    let mut created = [0usize; 3];
    let mut total = [0usize; 3];
    let em_of = |k: usize, u: f64| match k {
        0 => -u.max(1e-3),
        1 => 1.0,
        _ => 0.0,
    };
    let strat = (
        arb_collision(),
        arb_state(),
        0.0..1.0f64,
        0.0..1.0f64,
        0.0..1.0f64,
    );
    while total.iter().sum::<usize>() < 6000 {
        let (col, x, e, frac, u) = strat.new_tree(&mut rng).unwrap().current();
        let Ok(impact) = Impact::new(col) else {
            continue;
        };
        if impact.check_approach(&x).is_err() {
            continue;
        }
        let k = total.iter().sum::<usize>() % 3;
        let mut c = Coefficients {
            e,
            mu: 0.0,
            em: em_of(k, u),
        };
        let Ok(Some(mm)) = critical_friction(&impact, &c, &x, &SolveOptions::default()) else {
            continue;
        };
        c.mu = frac * mm;
        let r = solve_forward(&impact, &c, &x, &SolveOptions::default()).unwrap();
        total[k] += 1;
        let creates = r.energy.final_ > r.energy.initial * (1.0 + REPORT_TOL);
        assert_eq!(r.admissibility.energy_ok, !creates);
        assert!(
            r.admissibility.friction_ok,
            "mu inside [0, mu_max] must pass the friction test"
        );
        if creates {
            created[k] += 1;
            assert!(!r.admissibility.admissible);
            assert!(r
                .inadmissibility_reasons()
                .iter()
                .any(|m| m.contains("creates kinetic energy")));
        } else {
            assert!(r.admissibility.admissible);
        }
    }
    let share = |k: usize| created[k] as f64 / total[k] as f64;
    println!(
        "energy created: em in (-1,0) {:.1} %, em = 1 {:.1} %, em = 0 {:.1} % of {} cases each",
        100.0 * share(0),
        100.0 * share(1),
        100.0 * share(2),
        total[0]
    );
    // The finding (measured here: 31.6 %, 4.4 %, 3.0 %): common with a free moment coefficient,
    // rare but present without one.
    assert!((0.20..0.45).contains(&share(0)), "{}", share(0));
    assert!((0.005..0.10).contains(&share(1)), "{}", share(1));
    assert!((0.005..0.10).contains(&share(2)), "{}", share(2));
}

#[test]
fn friction_beyond_mu_max_is_flagged_as_reversed_and_inadmissible() {
    let (c, x) = brach1983_ricsac9();
    let impact = Impact::new(c).unwrap();
    let mut coef = Coefficients {
        e: 0.467,
        mu: 0.0,
        em: 1.0,
    };
    let mm = critical_friction(&impact, &coef, &x, &SolveOptions::default())
        .unwrap()
        .unwrap();
    coef.mu = 1.2 * mm;
    let r = solve_forward(&impact, &coef, &x, &SolveOptions::default()).unwrap();
    assert_eq!(r.tangential, TangentialOutcome::Reversed);
    assert!(!r.admissibility.friction_ok);
    assert!(r.inadmissibility_reasons()[0].contains("reverses the sliding"));
    // The tangential relative velocity has changed sign.
    assert!(r.relative.tangential_final * r.relative.tangential_initial < 0.0);
}

/// A collision, an approaching contact state and coefficients of the tangential-restitution
/// model.
fn arb_tangential() -> impl Strategy<Value = (Impact, Velocities, TangentialCoefficients)> {
    (
        arb_collision(),
        arb_state(),
        0.0..1.0f64,
        -1.0..1.0f64,
        0.0..1.5f64,
    )
        .prop_filter_map(
            "vehicles must approach and slide at C",
            |(c, x, e, et, friction)| {
                let impact = Impact::new(c).ok()?;
                impact.check_approach(&x).ok()?;
                impact.sliding_sign(&x).is_some().then_some((
                    impact,
                    x,
                    TangentialCoefficients { e, et, friction },
                ))
            },
        )
}

#[test]
fn tangential_model_conserves_momentum_and_meets_its_conditions() {
    runner(2000)
        .run(&arb_tangential(), |(impact, x, c)| {
            let t = solve_tangential(&impact, &c, &x).unwrap();
            let r = &t.report;
            let [m1, m2] = impact.masses();
            let xf = &r.separation;
            let scale = m1 * x.vehicle1.speed() + m2 * x.vehicle2.speed();
            let px = m1 * (xf.vehicle1.vx - x.vehicle1.vx) + m2 * (xf.vehicle2.vx - x.vehicle2.vx);
            let py = m1 * (xf.vehicle1.vy - x.vehicle1.vy) + m2 * (xf.vehicle2.vy - x.vehicle2.vy);
            prop_assert!(px.abs() <= 1e-11 * scale && py.abs() <= 1e-11 * scale);
            // No moment impulse: PIM's six equations hold with the equivalent coefficients
            // (e, mu = the impulse ratio, em = 1).
            prop_assert!(r.impulse.moment.abs() <= 1e-9 * (1.0 + r.impulse.normal.abs()));
            prop_assert!(
                r.residuals(&impact).max_relative() <= 1e-9,
                "{:?}",
                r.residuals(&impact)
            );
            let (vn, vt) = impact.relative_velocity(&x);
            let (vn1, vt1) = impact.relative_velocity(xf);
            let tol = 1e-9 * (1.0 + vn.abs() + vt.abs());
            prop_assert!((vn1 + c.e * vn).abs() <= tol, "normal restitution");
            match t.mode {
                ContactMode::Stick => {
                    prop_assert!((vt1 - c.et * vt).abs() <= tol, "tangential restitution");
                    prop_assert!(t.impulse_ratio.abs() <= c.friction * (1.0 + 1e-9) + 1e-12);
                }
                ContactMode::Slide => {
                    prop_assert!(t.stick_ratio.abs() > c.friction);
                    prop_assert!((t.impulse_ratio.abs() - c.friction).abs() <= 1e-12);
                }
            }
            // The friction rule: the ratio between 0 and the sticking ratio.
            prop_assert!(
                t.impulse_ratio * t.stick_ratio >= 0.0
                    && t.impulse_ratio.abs() <= t.stick_ratio.abs() * (1.0 + 1e-12),
                "ratio {} sticking {}",
                t.impulse_ratio,
                t.stick_ratio
            );
            // The report's admissibility: the energy balance, with the normal impulse pushing
            // the vehicles apart (the friction rule holds by construction).
            prop_assert_eq!(
                r.admissibility.admissible,
                !creates_energy(r.energy.initial, r.energy.final_)
                    && r.impulse.normal * r.relative.normal_initial <= 0.0
            );
            Ok(())
        })
        .unwrap();
}

#[test]
fn tangential_model_is_pim_in_its_two_limits() {
    runner(1000)
        .run(&arb_tangential(), |(impact, x, c)| {
            // et = 0 and a friction limit that does not bind: PIM's no-slip form with em = 1.
            let stick = TangentialCoefficients {
                et: 0.0,
                friction: 100.0,
                ..c
            };
            let t = solve_tangential(&impact, &stick, &x).unwrap();
            let pim_c = Coefficients {
                e: c.e,
                mu: 0.0,
                em: 1.0,
            };
            let no_slip = SolveOptions {
                tangential: TangentialCondition::NoSlip,
                ..SolveOptions::default()
            };
            if let Ok(p) = solve_forward(&impact, &pim_c, &x, &no_slip) {
                if t.mode == ContactMode::Stick {
                    let d = (t.report.separation.to_vector() - p.separation.to_vector()).amax();
                    prop_assert!(d <= 1e-8 * (1.0 + x.to_vector().amax()), "no-slip: {d}");
                }
            }
            // A binding friction limit (PIM's sliding form on the sticking impulse's side):
            // tests/physics/friction_rule.rs, over 10,000 collisions.
            Ok(())
        })
        .unwrap();
}

/// Every number of two JSON values equal to `tol` relative to the largest of its kind.
fn json_close(
    a: &serde_json::Value,
    b: &serde_json::Value,
    path: &str,
    tol: f64,
) -> std::result::Result<(), String> {
    use serde_json::Value as V;
    match (a, b) {
        (V::Number(x), V::Number(y)) => {
            let (x, y) = (x.as_f64().unwrap(), y.as_f64().unwrap());
            if (x - y).abs() <= tol * x.abs().max(y.abs()).max(1.0) {
                Ok(())
            } else {
                Err(format!("{path}: {x} against {y}"))
            }
        }
        (V::Object(x), V::Object(y)) => x
            .iter()
            .try_for_each(|(k, v)| json_close(v, &y[k], &format!("{path}.{k}"), tol)),
        (V::Array(x), V::Array(y)) => x
            .iter()
            .zip(y)
            .enumerate()
            .try_for_each(|(i, (v, w))| json_close(v, w, &format!("{path}[{i}]"), tol)),
        _ if a == b => Ok(()),
        _ => Err(format!("{path}: {a} against {b}")),
    }
}

#[test]
fn the_mirrored_collision_has_the_mirrored_solution() {
    // Reflection (y, angles, rotations change sign) maps a solution to the solution of the
    // mirrored collision with the same coefficients: `ImpactReport::mirrored` states which
    // result changes sign (how an SAE case is answered in its own frame).
    runner(2000)
        .run(
            &(
                arb_collision(),
                arb_state(),
                0.0..1.0f64,
                -1.2..1.2f64,
                arb_em(),
            ),
            |(c, x, e, mu, em)| {
                let Ok(impact) = Impact::new(c) else {
                    return Ok(());
                };
                if impact.check_approach(&x).is_err() {
                    return Ok(());
                }
                let m = |v: Vehicle| Vehicle {
                    heading: -v.heading,
                    phi: -v.phi,
                    ..v
                };
                let mirror = Impact::new(Collision {
                    vehicle1: m(c.vehicle1),
                    vehicle2: m(c.vehicle2),
                    crush_angle: -c.crush_angle,
                })
                .unwrap();
                let coefficients = Coefficients { e, mu, em };
                let opts = SolveOptions::default();
                let (Ok(a), Ok(b)) = (
                    solve_forward(&impact, &coefficients, &x, &opts),
                    solve_forward(&mirror, &coefficients, &x.mirrored(), &opts),
                ) else {
                    return Ok(());
                };
                // The PDOF is stated clockwise from the nose in both frames, so it is a
                // physical direction: the mirror crash's PDOF is the mirror image of ours.
                let mut b = b;
                for v in &mut b.vehicles {
                    v.pdof = wrap_degrees(-v.pdof);
                    v.clock = if v.clock == 12 { 12 } else { 12 - v.clock };
                }
                let (a, b) = (
                    serde_json::to_value(a.mirrored()).unwrap(),
                    serde_json::to_value(&b).unwrap(),
                );
                json_close(&a, &b, "report", 1e-9).map_err(TestCaseError::fail)
            },
        )
        .unwrap();
}
