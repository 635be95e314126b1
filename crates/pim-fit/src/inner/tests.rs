//! Tests of the inner problem: profiles along e against dense scans.
use super::constraints::Intervals;
use super::*;
use crate::problem::CostPreset;
use crate::problem::FitProblem;
use crate::report::Violation;
use crate::settings::FitSettings;
use nalgebra::Vector6;
use pim_core::{Coefficients, Impact, TangentialCondition};
use pim_core::{Collision, SolveOptions, Vehicle, Velocities};

fn problem(preset: CostPreset) -> FitProblem {
    let v = |mass, yaw_inertia, heading, d, phi| Vehicle {
        mass,
        yaw_inertia,
        heading,
        d,
        phi,
    };
    let impact = Impact::new(Collision {
        vehicle1: v(1500.0, 2500.0, 0.0, 1.6, 10.0),
        vehicle2: v(1200.0, 1900.0, 80.0, 1.3, -150.0),
        crush_angle: 10.0,
    })
    .expect("valid impact");
    // Separation states of the model, disturbed so that no coefficients reproduce them.
    let initial = Velocities::from_vector(&Vector6::new(-12.0, 1.0, 0.2, 0.5, 8.0, -0.1));
    let truth = Coefficients {
        e: 0.1,
        mu: 0.3,
        em: -0.5,
    };
    let sep = pim_core::solve_forward(&impact, &truth, &initial, &SolveOptions::default())
        .expect("forward solve")
        .separation
        .to_vector()
        + Vector6::new(0.3, -0.2, 0.1, -0.25, 0.15, -0.05);
    let separation = Velocities::from_vector(&sep);
    FitProblem::from_preset(impact, preset, &initial, &separation, None)
}

fn quadratic_roots_ok(c: [f64; 3], lo: f64, hi: f64) {
    let pieces = Intervals::single(lo, hi).quadratic_nonpositive(c);
    let n = 20_000;
    for i in 0..=n {
        let t = lo + (hi - lo) * i as f64 / n as f64;
        let inside = pieces.0.iter().any(|(p, q)| t >= *p && t <= *q);
        let value = c[0] + c[1] * t + c[2] * t * t;
        if inside {
            assert!(value <= 1e-9, "t = {t}: {value} in {pieces:?}");
        } else {
            // Outside the pieces only where the condition fails or within the margin.
            let near = pieces
                .0
                .iter()
                .any(|(p, q)| (t - p).abs() < 1e-9 || (t - q).abs() < 1e-9);
            assert!(value > 0.0 || near, "t = {t}: {value} outside {pieces:?}");
        }
    }
}

/// The pieces of a quadratic condition: convex, concave, linear, no root.
#[test]
fn quadratic_pieces_are_the_admissible_set() {
    quadratic_roots_ok([-0.25, 0.0, 1.0], -1.0, 1.0); // [-0.5, 0.5]
    quadratic_roots_ok([0.25, 0.0, -1.0], -1.0, 1.0); // two rays
    quadratic_roots_ok([-1.0, 2.0, 0.0], -1.0, 1.0); // t <= 0.5
    quadratic_roots_ok([-1.0, -2.0, 0.0], -1.0, 1.0); // t >= -0.5
    quadratic_roots_ok([1.0, 0.0, 1.0], -1.0, 1.0); // never
    quadratic_roots_ok([-1.0, 0.0, -1.0], -1.0, 1.0); // always
    let two = Intervals::single(-1.0, 1.0).quadratic_nonpositive([0.25, 0.0, -1.0]);
    assert_eq!(two.0.len(), 2);
    assert!(Intervals::single(-1.0, 1.0)
        .quadratic_nonpositive([1.0, 0.0, 1.0])
        .is_empty());
}

/// With e fixed at 0, separation velocities that still approach at C admit no contact state:
/// the profile says so instead of reporting a bound.
#[test]
fn profile_with_e_zero_backwards_is_inconsistent() {
    let settings = FitSettings {
        e: [0.0, 0.0],
        ..FitSettings::default()
    };
    let prep = Inner::new(&problem(CostPreset::Q1), &settings);
    for &sign in prep.signs() {
        let at = LineAt {
            e_range: settings.e,
            mu: 0.3,
            em: -0.5,
            mode: TangentialCondition::Sliding,
            sign,
        };
        let (_, eval) = prep.evaluate_profile(&at);
        assert_eq!(eval, Eval::Infeasible(Violation::Inconsistent));
    }
}

/// The level-set ends along e bracket every point of a dense scan whose cost is within the
/// limit, and lie within it themselves.
#[test]
fn level_ends_bracket_the_near_optimal_e() {
    let settings = FitSettings {
        e: [0.0, 0.4],
        ..FitSettings::default()
    };
    let mut checked = 0;
    for preset in [CostPreset::Q1, CostPreset::Q2] {
        let prep = Inner::new(&problem(preset), &settings);
        for &sign in prep.signs() {
            for (mu, em) in [(0.2, -0.6), (0.5, -0.2), (0.3, 1.0)] {
                let at = LineAt {
                    e_range: settings.e,
                    mu,
                    em,
                    mode: TangentialCondition::Sliding,
                    sign,
                };
                let Eval::Feasible(best) = prep.evaluate_profile(&at).1 else {
                    continue;
                };
                let limit = best.cost * 1.05 + 1e-6;
                let ends = prep.profile_level_ends(&at, limit);
                assert!(!ends.is_empty());
                let lo = ends.iter().map(|(t, _)| t.e).fold(f64::INFINITY, f64::min);
                let hi = ends
                    .iter()
                    .map(|(t, _)| t.e)
                    .fold(f64::NEG_INFINITY, f64::max);
                for (_, c) in &ends {
                    assert!(c.cost <= limit * (1.0 + 1e-9), "{} > {limit}", c.cost);
                }
                for i in 0..=4000 {
                    let e = 0.4 * i as f64 / 4000.0;
                    let th = At {
                        c: Coefficients { e, mu, em },
                        mode: TangentialCondition::Sliding,
                        sign,
                        et: 0.0,
                    };
                    if let Eval::Feasible(c) = prep.evaluate(&th, true, f64::INFINITY) {
                        if c.cost <= limit {
                            assert!(e >= lo - 1e-4 && e <= hi + 1e-4, "{e} outside [{lo}, {hi}]");
                        }
                    }
                }
                checked += 1;
            }
        }
    }
    assert!(checked >= 3, "only {checked} lines checked");
}

/// For fixed (mu, em), the profiled e is the best e: no point of a dense scan over e with
/// the plain evaluation is lower, and the scan's best is within its spacing of it.
#[test]
fn profile_is_the_minimum_over_e() {
    let settings = FitSettings {
        e: [0.0, 0.4],
        ..FitSettings::default()
    };
    let mut compared = 0;
    for preset in [CostPreset::Q1, CostPreset::Q2] {
        let prep = Inner::new(&problem(preset), &settings);
        assert!(prep.profiles());
        for mode in [TangentialCondition::Sliding, TangentialCondition::NoSlip] {
            for &sign in prep.signs() {
                for mu in [0.0, 0.2, 0.5, 0.9] {
                    for em in [-1.0, -0.6, -0.2, 0.0, 1.0] {
                        let at = LineAt {
                            e_range: settings.e,
                            mu,
                            em,
                            mode,
                            sign,
                        };
                        let (theta, eval) = prep.evaluate_profile(&at);
                        let profiled = match eval {
                            Eval::Feasible(c) => Some(c.cost),
                            _ => None,
                        };
                        let mut scan: Option<f64> = None;
                        for i in 0..=4000 {
                            let e = 0.4 * i as f64 / 4000.0;
                            let th = At {
                                c: Coefficients { e, mu, em },
                                mode,
                                sign,
                                et: 0.0,
                            };
                            if let Eval::Feasible(c) = prep.evaluate(&th, true, f64::INFINITY) {
                                scan = Some(scan.map_or(c.cost, |s: f64| s.min(c.cost)));
                            }
                        }
                        match (profiled, scan) {
                            (Some(p), Some(s)) => {
                                compared += 1;
                                assert!(p <= s + 1e-9 * (1.0 + s), "{theta:?} {p} > {s}");
                                assert!(s - p <= 1e-4 * (1.0 + p), "{theta:?} {p} vs {s}");
                                // The profiled point is an ordinary feasible point.
                                let again = prep.evaluate(
                                    &At {
                                        c: theta,
                                        mode,
                                        sign,
                                        et: 0.0,
                                    },
                                    true,
                                    f64::INFINITY,
                                );
                                assert!(
                                    matches!(again, Eval::Feasible(c) if (c.cost - p).abs() <= 1e-9 * (1.0 + p))
                                );
                            }
                            (None, Some(s)) => {
                                panic!("{preset:?} {mode:?} {sign:?} mu {mu} em {em}: scan finds {s}, profile none")
                            }
                            _ => {}
                        }
                    }
                }
            }
        }
    }
    assert!(compared >= 30, "only {compared} feasible lines compared");
}
