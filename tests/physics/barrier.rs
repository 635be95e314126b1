//! A vehicle against a fixed rigid barrier: the equations' limit as vehicle 2's mass and inertia
//! grow without bound, checked against the closed-form rigid-body impact of one body, against a
//! very heavy second vehicle, and between the two models.
use crate::common;
use common::*;
use pim_core::*;
use proptest::prelude::*;
use proptest::strategy::ValueTree;

fn runner(cases: u32) -> proptest::test_runner::TestRunner {
    seeded_runner(cases, 11)
}

fn barrier_impact(v1: Vehicle, crush_angle: f64) -> Impact {
    Impact::new(Collision {
        vehicle1: v1,
        vehicle2: Vehicle::barrier(),
        crush_angle,
    })
    .unwrap()
}

fn moving(v: [f64; 3]) -> Velocities {
    state([v[0], v[1], v[2], 0.0, 0.0, 0.0])
}

/// Full frontal impact through the CG: vehicle 1 (Brach's heading 0: nose towards -x) hits a
/// wall normal to x at 15 m/s. It rebounds at e times its speed, does not turn, and loses the
/// fraction 1 - e^2 of its kinetic energy; delta-V is (1 + e) v. Nothing slides at contact and
/// the normal impulse through the CG makes nothing slide: mu_max = 0, so mu = 0 is the one
/// admissible friction, and any other mu is reported inadmissible (a tangential impulse that
/// sticking does not need).
#[test]
fn central_frontal_impact_rebounds_at_e() {
    let impact = barrier_impact(vehicle(1500.0, 2500.0, 0.0, 2.0, 0.0), 0.0);
    let x = moving([-15.0, 0.0, 0.0]);
    for e in [0.0, 0.1, 0.3] {
        let c = Coefficients {
            e,
            mu: 0.0,
            em: 1.0,
        };
        let too_much = Coefficients { mu: 0.5, ..c };
        let bad = solve_forward(&impact, &too_much, &x, &SolveOptions::default()).unwrap();
        assert!(bad.mu_max.unwrap().abs() < 1e-12, "{:?}", bad.mu_max);
        assert!(!bad.admissibility.friction_ok && !bad.admissibility.admissible);
        assert_eq!(bad.friction_basis, FrictionBasis::NoSlipImpulse);
        let r = solve_forward(&impact, &c, &x, &SolveOptions::default()).unwrap();
        let s = r.separation;
        assert!((s.vehicle1.vx - 15.0 * e).abs() < 1e-12, "{s:?}");
        assert!(s.vehicle1.vy.abs() < 1e-12 && s.vehicle1.omega.abs() < 1e-12);
        assert_eq!(
            s.vehicle2,
            VehicleVelocity {
                vx: 0.0,
                vy: 0.0,
                omega: 0.0
            }
        );
        assert!((r.vehicles[0].delta_v - 15.0 * (1.0 + e)).abs() < 1e-12);
        assert!((r.energy.loss_percent - 100.0 * (1.0 - e * e)).abs() < 1e-9);
        assert!((r.energy.initial - 0.5 * 1500.0 * 225.0).abs() < 1e-9);
        assert!(r.vehicles[1].delta_v.abs() < f64::MIN_POSITIVE);
        assert!(r.admissibility.admissible);
        // Delta-V along the vehicle's axis: slowed (negative), PDOF 12 o'clock.
        assert!((r.vehicles[0].delta_v_longitudinal + 15.0 * (1.0 + e)).abs() < 1e-12);
        assert_eq!(r.vehicles[0].clock, 12);
    }
}

/// The impulse of one rigid body against a wall, from its 2x2 collision matrix at C
/// (`K = I/m + rp rp' / I`), written here without pim-core's equations: normal restitution,
/// and a tangential impulse `mu'` times the normal one.
fn one_body(v: &Vehicle, r1: [f64; 2], n: [f64; 2], x: [f64; 3], e: f64, mu_s: f64) -> [f64; 3] {
    let t = [-n[1], n[0]];
    let rp = [-r1[1], r1[0]];
    let dot = |a: [f64; 2], b: [f64; 2]| a[0] * b[0] + a[1] * b[1];
    let k = |a, b| dot(a, b) / v.mass + dot(rp, a) * dot(rp, b) / v.yaw_inertia;
    let vc = [x[0] - x[2] * r1[1], x[1] + x[2] * r1[0]];
    let vn = dot(vc, n);
    let pn = -(1.0 + e) * vn / (k(n, n) + mu_s * k(n, t));
    let p = [pn * (n[0] + mu_s * t[0]), pn * (n[1] + mu_s * t[1])];
    [
        x[0] + p[0] / v.mass,
        x[1] + p[1] / v.mass,
        x[2] + (r1[0] * p[1] - r1[1] * p[0]) / v.yaw_inertia,
    ]
}

prop_compose! {
    fn arb_barrier_case()(mass in 700.0..2800.0, k2 in 1.0..3.5, heading in -180.0..180.0,
                          d in 0.3..2.8, phi in -180.0..180.0, g in -80.0..80.0,
                          v in prop::array::uniform2(-25.0..25.0f64), w in -1.5..1.5,
                          e in 0.0..0.6, frac in 0.0..1.0, em in prop_oneof![Just(1.0), -1.0..0.0])
        -> Option<(Impact, Velocities, Coefficients)> {
        let impact = barrier_impact(vehicle(mass, k2 * mass, heading, d, phi), g);
        let x = moving([v[0], v[1], w]);
        impact.check_approach(&x).ok()?;
        let probe = Coefficients { e, mu: 0.0, em };
        let mu_max = critical_friction(&impact, &probe, &x, &SolveOptions::default()).ok()??;
        Some((impact, x, Coefficients { e, mu: frac * mu_max, em }))
    }
}

/// The valid cases among `draws` draws of [`arb_barrier_case`] (same seeded stream each call).
fn barrier_cases(draws: usize) -> impl Iterator<Item = (Impact, Velocities, Coefficients)> {
    let mut tree_runner = runner(1);
    (0..draws).filter_map(move |_| {
        arb_barrier_case()
            .new_tree(&mut tree_runner)
            .unwrap()
            .current()
    })
}

/// Over random barrier impacts: the barrier never moves, every equation holds to round-off,
/// an admissible solution never creates energy, and with e_m = 1 (no moment impulse) the
/// solution is the one-body closed form.
#[test]
fn barrier_solutions_match_the_one_body_closed_form() {
    let mut checked = 0;
    for (impact, x, c) in barrier_cases(3000) {
        let opts = SolveOptions::default();
        let r = solve_forward(&impact, &c, &x, &opts).unwrap();
        let s = r.separation;
        assert_eq!(
            s.vehicle2,
            VehicleVelocity {
                vx: 0.0,
                vy: 0.0,
                omega: 0.0
            }
        );
        assert!(r.residuals(&impact).max_relative() <= 1e-10);
        if r.admissibility.admissible {
            assert!(r.energy.loss >= -1e-9 * r.energy.initial, "{:?}", r.energy);
        }
        if (c.em - 1.0).abs() < f64::EPSILON {
            let v1 = impact.collision().vehicle1;
            let [r1, _] = impact.lever_arms();
            let mu_s = c.mu * r.friction_sign.value();
            let xv = x.to_vector();
            let want = one_body(&v1, r1, impact.normal(), [xv[0], xv[1], xv[2]], c.e, mu_s);
            let got = [s.vehicle1.vx, s.vehicle1.vy, s.vehicle1.omega];
            for (a, b) in got.iter().zip(want) {
                assert!(
                    (a - b).abs() <= 1e-9 * (1.0 + b.abs()),
                    "{got:?} against {want:?}"
                );
            }
        }
        checked += 1;
    }
    assert!(checked > 1500, "only {checked} valid cases");
}

/// The barrier is the limit of a very heavy vehicle 2 (1e7 kg, 1e10 kg m^2, at rest): vehicle
/// 1's separation velocities agree to about m1 / m2 wherever the barrier solution is admissible
/// (inadmissible ones, which create energy, can amplify the difference).
#[test]
fn barrier_is_the_limit_of_a_heavy_vehicle() {
    let mut checked = 0;
    for (impact, x, c) in barrier_cases(1000) {
        let mut heavy = *impact.collision();
        heavy.vehicle2 = vehicle(1e7, 1e10, 30.0, 1.2, 40.0);
        let heavy = Impact::new(heavy).unwrap();
        let opts = SolveOptions::default();
        let a = solve_forward(&impact, &c, &x, &opts).unwrap();
        if !a.admissibility.admissible {
            continue;
        }
        let a = a.separation;
        // The heavy vehicle's own CG decides which side of the crush surface it is on, which
        // can make the same velocities a separation for it.
        let Ok(b) = solve_forward(&heavy, &c, &x, &opts) else {
            continue;
        };
        let b = b.separation;
        let d = (a.to_vector() - b.to_vector()).amax();
        assert!(
            d <= 1e-3 * (1.0 + x.to_vector().amax()),
            "{a:?} against {b:?}"
        );
        checked += 1;
    }
    assert!(checked > 200, "only {checked} valid cases");
}

/// Both models against the same barrier: the tangential-restitution model sliding at its
/// friction limit is PIM sliding with mu = friction and e_m = 1; sticking with et = 0 is PIM's
/// no-slip form.
/// The separation state of both models for the same barrier impact.
fn both(
    impact: &Impact,
    x: &Velocities,
    model: TangentialCoefficients,
    pim: Coefficients,
    tangential: TangentialCondition,
) -> (TangentialReport, f64) {
    let t = solve_tangential(impact, &model, x).unwrap();
    let opts = SolveOptions {
        tangential,
        ..SolveOptions::default()
    };
    let p = solve_forward(impact, &pim, x, &opts).unwrap();
    let d = (t.report.separation.to_vector() - p.separation.to_vector()).amax();
    (t, d)
}

/// Both models against the same barrier: the tangential-restitution model sliding at its
/// friction limit is PIM sliding with mu = friction on the no-slip impulse's side and e_m = 1;
/// sticking with et = 0 is PIM's no-slip form. Here the normal impulse alone reverses the
/// sliding (mu_max = -0.204): friction against the initial sliding (PIM's mu = +0.2) would
/// drive the sliding further past zero, and PIM rejects it; both models use mu = -0.2.
#[test]
fn both_models_agree_against_a_barrier() {
    let impact = barrier_impact(vehicle(1400.0, 2300.0, 20.0, 1.9, 35.0), 10.0);
    let x = moving([-14.0, 3.0, 0.2]);
    let model = |friction| TangentialCoefficients {
        e: 0.1,
        et: 0.0,
        friction,
    };
    let pim = |mu| Coefficients {
        e: 0.1,
        mu,
        em: 1.0,
    };
    let (slide, d) = both(
        &impact,
        &x,
        model(0.2),
        pim(-0.2),
        TangentialCondition::Sliding,
    );
    assert_eq!(slide.mode, ContactMode::Slide);
    assert!(d < 1e-10, "{d}");
    let mu_max = slide.report.mu_max.unwrap();
    assert!((mu_max + 0.2038).abs() < 1e-4, "{mu_max}");
    assert!((slide.report.coefficients.mu + 0.2).abs() < 1e-12);
    assert!(slide.report.admissibility.admissible);
    let against = solve_forward(&impact, &pim(0.2), &x, &SolveOptions::default()).unwrap();
    assert!(!against.admissibility.friction_ok);
    let (stick, d) = both(
        &impact,
        &x,
        model(5.0),
        pim(0.0),
        TangentialCondition::NoSlip,
    );
    assert_eq!(stick.mode, ContactMode::Stick);
    assert!(d < 1e-10, "{d}");
    let (_, vt) = impact.relative_velocity(&stick.report.separation);
    assert!(vt.abs() < 1e-10);
}

#[test]
fn a_moving_barrier_is_refused() {
    let impact = barrier_impact(vehicle(1500.0, 2500.0, 0.0, 2.0, 0.0), 0.0);
    let x = state([-15.0, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let c = Coefficients {
        e: 0.1,
        mu: 0.2,
        em: 1.0,
    };
    let err = solve_forward(&impact, &c, &x, &SolveOptions::default()).unwrap_err();
    assert!(err.to_string().contains("fixed barrier"), "{err}");
    let err = solve_backward(&impact, &c, &x, &SolveOptions::default()).unwrap_err();
    assert!(err.to_string().contains("fixed barrier"), "{err}");
    let mut bad = Vehicle::barrier();
    bad.yaw_inertia = 5000.0;
    let e = Impact::new(Collision {
        vehicle1: vehicle(1500.0, 2500.0, 0.0, 2.0, 0.0),
        vehicle2: bad,
        crush_angle: 0.0,
    })
    .unwrap_err();
    assert!(e.to_string().contains("both mass and yaw inertia"), "{e}");
}

#[test]
fn backward_against_a_barrier_returns_the_start() {
    let impact = barrier_impact(vehicle(1200.0, 1900.0, -15.0, 2.1, 25.0), 5.0);
    let x = moving([-16.0, 2.0, 0.1]);
    let c = Coefficients {
        e: 0.12,
        mu: 0.1,
        em: -0.4,
    };
    let opts = SolveOptions::default();
    let fwd = solve_forward(&impact, &c, &x, &opts).unwrap();
    let back =
        solve_backward_with_sign(&impact, &c, &fwd.separation, &opts, fwd.friction_sign).unwrap();
    assert!((back.initial.to_vector() - x.to_vector()).amax() < 1e-9);
}

/// The fit against a barrier: noise-free separation velocities from known coefficients (Q2) or
/// every component (Q3) give the coefficients back in the zero branch; the barrier's components
/// are held at 0 by the fit itself.
#[test]
fn fit_recovers_barrier_coefficients() {
    use pim_fit::*;
    let impact = barrier_impact(vehicle(1400.0, 2300.0, 20.0, 1.9, 35.0), 10.0);
    let x = moving([-12.0, 2.5, 0.1]);
    let probe = Coefficients {
        e: 0.12,
        mu: 0.0,
        em: 1.0,
    };
    let mu_max = critical_friction(&impact, &probe, &x, &SolveOptions::default())
        .unwrap()
        .unwrap();
    let truth = Coefficients {
        e: 0.12,
        mu: 0.5 * mu_max,
        em: 1.0,
    };
    let sep = solve_forward(&impact, &truth, &x, &SolveOptions::default())
        .unwrap()
        .separation;
    for preset in [CostPreset::Q2, CostPreset::Q3] {
        let problem = FitProblem::from_preset(impact, preset, &x, &sep, None);
        let report = fit(&problem, &FitSettings::default().check().unwrap()).unwrap();
        let zero = report
            .branches
            .iter()
            .find(|b| b.moment == MomentBranch::Zero)
            .unwrap();
        let s = zero.solution.as_ref().unwrap();
        assert!(s.cost < 1e-10, "{preset:?}: cost {}", s.cost);
        assert!((s.e - truth.e).abs() < 1e-4, "{preset:?}: e {}", s.e);
        assert!((s.mu - truth.mu).abs() < 1e-4, "{preset:?}: mu {}", s.mu);
        assert_eq!(
            s.initial.vehicle2,
            VehicleVelocity {
                vx: 0.0,
                vy: 0.0,
                omega: 0.0
            }
        );
        assert!(
            s.separation.vehicle2.vx.abs() < 1e-12 && s.separation.vehicle2.omega.abs() < 1e-12
        );
    }
    // Data about the barrier are refused, with the component named.
    let mut problem = FitProblem::from_preset(impact, CostPreset::Q3, &x, &sep, None);
    problem.components[9] = Knowledge::Estimated {
        value: 0.5,
        weight: 1.0,
    };
    let err = fit(&problem, &FitSettings::default().check().unwrap()).unwrap_err();
    assert!(err.to_string().contains("barrier"), "{err}");
}
