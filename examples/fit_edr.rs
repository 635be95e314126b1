//! Reconstructing impact speeds from event-data-recorder style data:
//! `cargo run --release --example fit_edr`.
//!
//! Known: both cars drove straight (no lateral velocity, no yaw rate at contact). Observed:
//! the pre-impact speed of car 1 and the delta-V of both cars along and across their own axes.
//! The fit returns the contact velocities of both cars (so the unknown speed of car 2) and the
//! impact coefficients.
use pim_core::*;
use pim_fit::*;

fn main() -> std::result::Result<(), Box<dyn std::error::Error>> {
    // RICSAC 7 vehicles and headings (Brach 1983 Table 1) with a crush surface at -10 deg, so
    // that both speeds enter the normal approach velocity. (With RICSAC 7's own -30 deg, car 2
    // moves exactly along the crush surface: its speed then only enters the sliding, and sliding
    // friction does not depend on the sliding speed, so delta-V cannot tell it; the fit reports
    // that speed as not determined.)
    let vehicle = |mass, yaw_inertia, heading, d, phi| Vehicle {
        mass,
        yaw_inertia,
        heading,
        d,
        phi,
    };
    let impact = Impact::new(Collision {
        vehicle1: vehicle(1955.0, 4723.0, 0.0, 1.8, 0.0),
        vehicle2: vehicle(1197.0, 2279.0, 60.0, 0.9, -140.0),
        crush_angle: -10.0,
    })?;
    // What the recorders saw, generated here from a known impact so that the answer is known:
    // car 1 at 13.0 m/s, car 2 at 11.0 m/s, e = 0.05, mu = 0.5, em = 1.
    let h = 60f64.to_radians();
    let truth = Velocities::from_vector(&nalgebra::Vector6::new(
        -13.0,
        0.0,
        0.0,
        11.0 * h.cos(),
        11.0 * h.sin(),
        0.0,
    ));
    let coefficients = Coefficients {
        e: 0.05,
        mu: 0.5,
        em: 1.0,
    };
    let crash = solve_forward(&impact, &coefficients, &truth, &SolveOptions::default())?;
    println!(
        "the impact: mu_max {:.3}, admissible {}, energy loss {:.1} %",
        crash.mu_max.unwrap_or(f64::NAN),
        crash.admissibility.admissible,
        crash.energy.loss_percent
    );
    assert!(
        crash.admissibility.admissible,
        "the example impact must be physically admissible"
    );
    let edr = |kind, vehicle: VehicleId| {
        let f = forward_axis(&impact, vehicle);
        let dv = &crash.delta_v[vehicle.index()];
        let value = match kind {
            ObservationKind::DeltaVLongitudinal => dv.dvx * f[0] + dv.dvy * f[1],
            ObservationKind::DeltaVLateral => -dv.dvx * f[1] + dv.dvy * f[0],
            _ => unreachable!(),
        };
        Observation {
            kind,
            vehicle,
            value,
            weight: 1.0,
        }
    };
    let mut observations = vec![Observation {
        kind: ObservationKind::SpeedAlongHeading,
        vehicle: VehicleId::One,
        value: 13.0,
        weight: 1.0,
    }];
    for v in [VehicleId::One, VehicleId::Two] {
        observations.push(edr(ObservationKind::DeltaVLongitudinal, v));
        observations.push(edr(ObservationKind::DeltaVLateral, v));
    }
    for o in &observations {
        println!("observed {:?} of {}: {:.3} m/s", o.kind, o.vehicle, o.value);
    }
    // Driving straight: no yaw rate, and no lateral velocity (car 1 heads along -x, so v1y = 0;
    // car 2's lateral velocity is an observation with full weight).
    let mut components = [Knowledge::Unknown; 12];
    for k in [1, 2, 5] {
        components[k] = Knowledge::Known { value: 0.0 };
    }
    observations.push(Observation {
        kind: ObservationKind::LateralVelocity,
        vehicle: VehicleId::Two,
        value: 0.0,
        weight: 1.0,
    });
    let problem = FitProblem {
        impact,
        components,
        observations,
        combinations: Vec::new(),
    };
    println!("\n1. e free in [0, 0.2]:");
    report_fit(&problem, FitSettings::default())?;
    // Delta-V fixes the impulse, in which restitution and approach speed trade off ((1 + e) vn):
    // with e assumed, as reconstructionists usually must, both speeds are determined.
    println!("\n2. e assumed to be 0.05:");
    report_fit(
        &problem,
        FitSettings {
            e: [0.05, 0.05],
            ..Default::default()
        },
    )?;
    Ok(())
}

fn report_fit(
    problem: &FitProblem,
    settings: FitSettings,
) -> std::result::Result<(), Box<dyn std::error::Error>> {
    let report = fit(problem, &settings.check()?)?;
    for b in &report.branches {
        if let Some(s) = &b.solution {
            println!(
                "branch {:?}: car 1 at {:.2} m/s, car 2 at {:.2} m/s; e = {:.3}, mu = {:.3}, em = {:.3} (cost {:.1e})",
                b.moment,
                s.initial.vehicle1.speed(),
                s.initial.vehicle2.speed(),
                s.e,
                s.mu,
                s.em,
                s.cost
            );
        }
    }
    for note in &report.notes {
        println!("note: {note}");
    }
    for b in &report.branches {
        if let Some(r) = &b.reason {
            println!("branch {:?}: {r}", b.moment);
        }
    }
    let best = report.best_branch().ok_or("no admissible reconstruction")?;
    let s = best
        .solution
        .as_ref()
        .expect("optimal branch has a solution");
    println!(
        "best branch {:?}: car 1 at {:.2} m/s, car 2 at {:.2} m/s; e = {:.3}, mu = {:.3}, em = {:.3} (cost {:.1e})",
        best.moment,
        s.initial.vehicle1.speed(),
        s.initial.vehicle2.speed(),
        s.e,
        s.mu,
        s.em,
        s.cost
    );
    for i in &best.identifiability {
        println!(
            "  {}: within 1 % of the optimum for {:.3} .. {:.3}{}{}",
            i.coefficient,
            i.low,
            i.high,
            if i.open_ended { " and beyond" } else { "" },
            if i.identifiable {
                ""
            } else {
                "  (not pinned down by these data)"
            }
        );
    }
    Ok(())
}
