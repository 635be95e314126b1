//! EDR-style reconstruction (as `examples/fit_edr.rs`): the pre-impact speed of car 1 and the
//! delta-V of both cars along and across their axes, both cars driving straight.
use crate::common;
use common::*;
use pim_core::*;
use pim_fit::*;

fn scenario(crush_angle: f64) -> (FitProblem, [f64; 2]) {
    let impact = Impact::new(Collision {
        vehicle1: vehicle(1955.0, 4723.0, 0.0, 1.8, 0.0),
        vehicle2: vehicle(1197.0, 2279.0, 60.0, 0.9, -140.0),
        crush_angle,
    })
    .unwrap();
    let h = 60f64.to_radians();
    let truth = state([-13.0, 0.0, 0.0, 11.0 * h.cos(), 11.0 * h.sin(), 0.0]);
    let crash = solve_forward(
        &impact,
        &Coefficients {
            e: 0.05,
            mu: 0.5,
            em: 1.0,
        },
        &truth,
        &SolveOptions::default(),
    )
    .unwrap();
    assert!(crash.admissibility.admissible);
    let mut observations = vec![Observation {
        kind: ObservationKind::SpeedAlongHeading,
        vehicle: VehicleId::One,
        value: 13.0,
        weight: 1.0,
    }];
    for v in [VehicleId::One, VehicleId::Two] {
        let f = forward_axis(&impact, v);
        let dv = &crash.delta_v[v.index()];
        for (kind, value) in [
            (
                ObservationKind::DeltaVLongitudinal,
                dv.dvx * f[0] + dv.dvy * f[1],
            ),
            (
                ObservationKind::DeltaVLateral,
                -dv.dvx * f[1] + dv.dvy * f[0],
            ),
        ] {
            observations.push(Observation {
                kind,
                vehicle: v,
                value,
                weight: 1.0,
            });
        }
    }
    observations.push(Observation {
        kind: ObservationKind::LateralVelocity,
        vehicle: VehicleId::Two,
        value: 0.0,
        weight: 1.0,
    });
    let mut components = [Knowledge::Unknown; 12];
    for k in [1, 2, 5] {
        components[k] = Knowledge::Known { value: 0.0 };
    }
    (
        FitProblem {
            impact,
            components,
            observations,
            combinations: Vec::new(),
        },
        [13.0, 11.0],
    )
}

fn ident<'a>(b: &'a BranchReport, name: &str) -> &'a Identifiability {
    b.identifiability
        .iter()
        .find(|i| i.coefficient.to_string() == name)
        .unwrap()
}

#[test]
fn with_restitution_assumed_both_impact_speeds_and_the_coefficients_are_returned() {
    let (problem, [s1, s2]) = scenario(-10.0);
    let settings = FitSettings {
        e: [0.05, 0.05],
        ..Default::default()
    }
    .check()
    .unwrap();
    let report = fit(&problem, &settings).unwrap();
    assert_eq!(report.best, Some(MomentBranch::Zero));
    let b = report.best_branch().unwrap();
    let s = b.solution.as_ref().unwrap();
    assert!(s.cost < 1e-8, "{}", s.cost);
    assert!((s.initial.vehicle1.speed() - s1).abs() < 0.01);
    assert!(
        (s.initial.vehicle2.speed() - s2).abs() < 0.01,
        "{}",
        s.initial.vehicle2.speed()
    );
    assert!((s.mu - 0.5).abs() < 0.005 && (s.em - 1.0).abs() < 1e-12);
    assert!(ident(b, "speed2").identifiable);
}

#[test]
fn with_restitution_free_the_trade_off_is_reported_not_hidden() {
    // Delta-V fixes the impulse, where restitution and approach speed trade off, (1 + e) vn:
    // the fit must say that car 2's speed is not pinned down, and the truth must lie in the
    // range it reports.
    let (problem, [s1, s2]) = scenario(-10.0);
    let report = fit(&problem, &FitSettings::default().check().unwrap()).unwrap();
    let b = report.best_branch().unwrap();
    let s = b.solution.as_ref().unwrap();
    assert!(s.cost < 1e-8);
    assert!((s.initial.vehicle1.speed() - s1).abs() < 0.01);
    let sp = ident(b, "speed2");
    assert!(!sp.identifiable, "{sp:?}");
    assert!(sp.low - 0.2 <= s2 && s2 <= sp.high + 0.2, "{sp:?}");
    assert!(sp.high - sp.low > 2.0, "{sp:?}");
    assert!(!ident(b, "e").identifiable, "{:?} {:?}", ident(b, "e"), s);
    assert!(ident(b, "mu").identifiable && ident(b, "speed1").identifiable);
}

#[test]
fn a_velocity_the_data_cannot_see_is_named() {
    // RICSAC 7's own crush angle: car 2 moves along the crush surface, so its speed enters only
    // the sliding, on which sliding friction does not depend. With e fixed, car 2's speed along
    // its heading is a flat direction of the cost at every admissible sliding solution.
    let (problem, _) = scenario(-30.0);
    let settings = FitSettings {
        e: [0.05, 0.05],
        branches: vec![MomentBranch::Zero],
        ..Default::default()
    }
    .check()
    .unwrap();
    let report = fit(&problem, &settings).unwrap();
    let b = &report.branches[0];
    let s = b.solution.as_ref().unwrap();
    assert!(s.cost < 1e-8, "{}", s.cost);
    let sp = ident(b, "speed2");
    assert!(!sp.identifiable && sp.open_ended, "{sp:?}");
    assert!(sp.low <= 11.0 + 0.2, "{sp:?}");
}
