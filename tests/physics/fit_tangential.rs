//! Fitting the tangential-restitution model: noise-free data from its own forward solve are
//! fitted back (e, et and the friction limit recovered, cost zero) under Q1, Q2 and Q3, in both
//! contact modes; and every fitted answer is the model's own forward solution.

use crate::common;

use pim_core::{solve_tangential, ContactMode, Impact, TangentialCoefficients, Velocities};
use pim_fit::{fit, CostPreset, FitModel, FitProblem, FitSettings, MomentBranch, Quantity};

/// RICSAC 7 as in Brach 1983 Table 1.
fn impact() -> Impact {
    Impact::new(common::brach1983_ricsac7().0).unwrap()
}

fn initial() -> Velocities {
    common::brach1983_ricsac7().1
}

fn settings() -> pim_fit::ValidSettings {
    FitSettings {
        model: FitModel::Tangential,
        ..FitSettings::default()
    }
    .check()
    .unwrap()
}

#[test]
fn sticking_data_give_back_e_and_et() {
    let truth = TangentialCoefficients {
        e: 0.08,
        et: 0.35,
        friction: 1.2,
    };
    let t = solve_tangential(&impact(), &truth, &initial()).unwrap();
    assert_eq!(t.mode, ContactMode::Stick);
    for preset in [CostPreset::Q1, CostPreset::Q2, CostPreset::Q3] {
        let problem =
            FitProblem::from_preset(impact(), preset, &initial(), &t.report.separation, None);
        let report = fit(&problem, &settings()).unwrap();
        assert_eq!(report.branches.len(), 1, "{preset:?}");
        let b = &report.branches[0];
        assert_eq!(b.moment, MomentBranch::Zero);
        let s = b.solution.as_ref().expect("solved");
        let tf = s.tangential.as_ref().expect("tangential reading");
        assert!(s.cost < 1e-8, "{preset:?}: cost {}", s.cost);
        assert!((s.e - 0.08).abs() < 1e-3, "{preset:?}: e {}", s.e);
        // The impulse ratio is determined. Sticking at et and sliding at a friction limit equal
        // to that ratio give the same answer (Routh's rule slides there for any et whose
        // sticking impulse needs more), so the data cannot tell the two readings apart.
        assert!(
            (tf.impulse_ratio - t.impulse_ratio).abs() < 1e-3,
            "{preset:?}"
        );
        match tf.mode {
            ContactMode::Stick => {
                assert!((tf.et - 0.35).abs() < 1e-3, "{preset:?}: et {}", tf.et);
                assert!((tf.friction - t.impulse_ratio.abs()).abs() < 1e-3);
                assert!((tf.friction_max - 1.2).abs() < 1e-12);
            }
            ContactMode::Slide => {
                assert!((tf.friction - t.impulse_ratio.abs()).abs() < 1e-3);
                assert!(tf.stick_ratio.abs() >= tf.friction * (1.0 - 1e-9));
            }
        }
        // Either way the friction limit is at least the impulse ratio, and may be anything up
        // to the bound.
        let f = b
            .identifiability
            .iter()
            .find(|i| i.coefficient == Quantity::Friction)
            .unwrap();
        // (within the 1 % cost tolerance of the ranges)
        let r = t.impulse_ratio.abs();
        assert!((f.low - r).abs() < 0.01 * r, "{preset:?}: {f:?} {r}");
        assert!((f.high - 1.2).abs() < 1e-9, "{preset:?}: {f:?}");
        let sep = (s.separation.to_vector() - t.report.separation.to_vector()).amax();
        assert!(sep < 1e-3, "{preset:?}: separation off by {sep}");
        assert!(s.max_residual < 1e-8 && s.admissible, "{preset:?}");
    }
}

#[test]
fn sliding_data_give_back_e_and_the_friction_limit() {
    let truth = TangentialCoefficients {
        e: 0.12,
        et: 0.0,
        friction: 0.3,
    };
    let t = solve_tangential(&impact(), &truth, &initial()).unwrap();
    assert_eq!(t.mode, ContactMode::Slide);
    for preset in [CostPreset::Q2, CostPreset::Q3] {
        let problem =
            FitProblem::from_preset(impact(), preset, &initial(), &t.report.separation, None);
        let report = fit(&problem, &settings()).unwrap();
        let b = &report.branches[0];
        let s = b.solution.as_ref().expect("solved");
        let tf = s.tangential.as_ref().expect("tangential reading");
        assert!(s.cost < 1e-8, "{preset:?}: cost {}", s.cost);
        assert!((s.e - 0.12).abs() < 1e-3, "{preset:?}: e {}", s.e);
        assert!(
            (tf.friction - 0.3).abs() < 1e-3,
            "{preset:?}: {}",
            tf.friction
        );
        // et is not determined by sliding data: its range is wide.
        let et = b
            .identifiability
            .iter()
            .find(|i| i.coefficient == Quantity::Et)
            .unwrap();
        assert!(!et.identifiable && et.high - et.low > 0.5, "{et:?}");
    }
}

/// Q2 on every RICSAC test: the fit is never beaten by an independent search written with
/// pim-core's forward solver only (a dense grid over e, et and the friction limit, then a
/// compass search from its best point).
#[test]
fn q2_is_never_beaten_by_a_dense_search_of_the_model() {
    for t in common::ricsac_tests() {
        let impact = t.impact().unwrap();
        let (x, xf) = (t.initial(), t.separation());
        let problem = FitProblem::from_preset(impact, CostPreset::Q2, &x, &xf, None);
        let report = fit(&problem, &settings()).unwrap();
        let fitted = report.branches[0]
            .solution
            .as_ref()
            .map_or(f64::INFINITY, |s| s.cost);
        let best = common::tangential::q2_reference(
            &impact,
            &x,
            &xf,
            [[0.0, 0.2], [-1.0, 1.0], [0.0, 1.2]],
        );
        // Q2 keeps the measured contact state: every test has admissible answers.
        assert!(
            best.is_finite(),
            "test {}: no admissible grid point",
            t.test
        );
        assert!(
            fitted <= best * (1.0 + 1e-6) + 1e-9,
            "test {}: fit {fitted} > reference {best}",
            t.test
        );
        eprintln!("test {}: fit {fitted:.6} reference {best:.6}", t.test);
    }
}

/// The tangential model contains PIM's zero branch (PIM sliding is its sliding mode, PIM's
/// no-slip form its sticking mode with et = 0): on every RICSAC test, under Q2 and Q3, its
/// optimum is never above that branch's and exists wherever that branch has one.
#[test]
fn never_worse_than_pims_zero_branch_on_ricsac() {
    let pim = FitSettings {
        branches: vec![MomentBranch::Zero],
        ..FitSettings::default()
    }
    .check()
    .unwrap();
    let mut below = 0;
    for t in common::ricsac_tests() {
        let impact = t.impact().unwrap();
        for preset in [CostPreset::Q2, CostPreset::Q3] {
            let problem =
                FitProblem::from_preset(impact, preset, &t.initial(), &t.separation(), None);
            let cost = |s: &pim_fit::ValidSettings| {
                fit(&problem, s).unwrap().branches[0]
                    .solution
                    .as_ref()
                    .map(|s| s.cost)
            };
            let (Some(zero), tangential) = (cost(&pim), cost(&settings())) else {
                continue;
            };
            let tangential = tangential.unwrap_or_else(|| panic!("test {}: none", t.test));
            assert!(
                tangential <= zero * (1.0 + 1e-6) + 1e-9,
                "test {} {preset:?}: tangential {tangential} > PIM zero {zero}",
                t.test
            );
            if tangential < zero * (1.0 - 1e-6) {
                below += 1;
            }
        }
    }
    // et adds freedom the data use: below PIM's zero branch on 14 of the 22 fits.
    assert_eq!(below, 14);
}

/// A realistic random impact with the tangential model's coefficients whose forward solution is
/// admissible, within the fit's bounds, and slides at contact: (impact, contact state, truth).
fn arb_truth(
) -> impl proptest::strategy::Strategy<Value = (Impact, Velocities, TangentialCoefficients)> {
    use proptest::prelude::*;
    (
        (
            800.0..2500.0f64,
            1000.0..5000.0f64,
            0.8..2.5f64,
            -60.0..60.0f64,
        ),
        (
            800.0..2500.0f64,
            1000.0..5000.0f64,
            0.5..2.0f64,
            -120.0..-60.0f64,
        ),
        (30.0..150.0f64, -40.0..40.0f64),
        (6.0..15.0f64, 4.0..14.0f64),
        (0.02..0.18f64, -0.8..0.8f64, 0.1..1.1f64),
    )
        .prop_filter_map(
            "admissible truth",
            |(a, b, (h2, g), (s1, s2), (e, et, f))| {
                let impact = Impact::new(pim_core::Collision {
                    vehicle1: common::vehicle(a.0, a.1, 0.0, a.2, a.3),
                    vehicle2: common::vehicle(b.0, b.1, h2, b.2, b.3),
                    crush_angle: g,
                })
                .ok()?;
                let h = h2.to_radians();
                let x = common::state([-s1, 0.0, 0.0, s2 * h.cos(), s2 * h.sin(), 0.0]);
                let c = TangentialCoefficients { e, et, friction: f };
                let t = solve_tangential(&impact, &c, &x).ok()?;
                let within = t
                    .report
                    .separation
                    .to_vector()
                    .iter()
                    .enumerate()
                    .all(|(k, v)| v.abs() < if k % 3 == 2 { 4.5 } else { 19.0 });
                let (_, vt) = impact.relative_velocity(&x);
                (t.report.admissibility.admissible && within && vt.abs() > 0.5)
                    .then_some((impact, x, c))
            },
        )
}

/// Noise-free data of random collisions (both contact modes) are fitted back under Q2 and Q3:
/// zero cost, e and the impulse ratio recovered, and the answer is the model's own forward
/// solution (the fit's check passes: status optimal, residuals at round-off).
#[test]
fn random_collisions_are_fitted_back() {
    use proptest::strategy::{Strategy, ValueTree};
    let mut runner = common::seeded_runner(1, 23);
    let strat = arb_truth();
    let (mut sticks, mut slides) = (0, 0);
    for _ in 0..20 {
        let (impact, x, truth) = strat.new_tree(&mut runner).unwrap().current();
        let t = solve_tangential(&impact, &truth, &x).unwrap();
        match t.mode {
            ContactMode::Stick => sticks += 1,
            ContactMode::Slide => slides += 1,
        }
        for preset in [CostPreset::Q2, CostPreset::Q3] {
            let problem = FitProblem::from_preset(impact, preset, &x, &t.report.separation, None);
            let report = fit(&problem, &settings()).unwrap();
            let b = &report.branches[0];
            assert_eq!(b.status, pim_fit::Status::Optimal, "{preset:?} {truth:?}");
            let s = b.solution.as_ref().unwrap();
            let tf = s.tangential.as_ref().unwrap();
            assert!(s.cost < 1e-7, "{preset:?} {truth:?}: cost {}", s.cost);
            assert!(s.max_residual < 1e-8);
            assert!(
                (s.e - truth.e).abs() < 2e-3,
                "{preset:?} {truth:?}: e {}",
                s.e
            );
            assert!(
                (tf.impulse_ratio - t.impulse_ratio).abs() < 2e-3 * (1.0 + t.impulse_ratio.abs()),
                "{preset:?} {truth:?}: ratio {} vs {}",
                tf.impulse_ratio,
                t.impulse_ratio
            );
            if tf.mode == ContactMode::Stick && t.mode == ContactMode::Stick {
                assert!(
                    (tf.et - truth.et).abs() < 2e-3,
                    "{preset:?} {truth:?}: et {}",
                    tf.et
                );
            }
        }
    }
    // Both modes are exercised.
    assert!(sticks >= 3 && slides >= 3, "{sticks} stick, {slides} slide");
    eprintln!("{sticks} sticking and {slides} sliding truths fitted back");
}
