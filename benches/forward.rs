//! Forward solve with every derived result against a bare nalgebra 6x6 LU solve, and the
//! second impact model's forward solve with the same report.
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use nalgebra::{Matrix6, Vector6};
use pim_core::*;
use std::hint::black_box;

fn ricsac7() -> (Impact, Velocities, Coefficients) {
    let v = |mass, yaw_inertia, heading, d, phi| Vehicle {
        mass,
        yaw_inertia,
        heading,
        d,
        phi,
    };
    let impact = Impact::new(Collision {
        vehicle1: v(1955.0, 4723.0, 0.0, 1.8, 0.0),
        vehicle2: v(1197.0, 2279.0, 60.0, 0.9, -140.0),
        crush_angle: -30.0,
    })
    .unwrap();
    let x = Velocities {
        vehicle1: VehicleVelocity {
            vx: -13.01,
            vy: 0.0,
            omega: 0.0,
        },
        vehicle2: VehicleVelocity {
            vx: 6.505,
            vy: 11.267,
            omega: 0.0,
        },
    };
    (
        impact,
        x,
        Coefficients {
            e: 0.015,
            mu: 0.968,
            em: -0.774,
        },
    )
}

fn bench(c: &mut Criterion) {
    let (impact, x, coef) = ricsac7();
    let opts = SolveOptions::default();
    let sys = equations::assemble(&impact, &coef, FrictionSign::Positive, &opts);
    let f: Matrix6<f64> = sys.f;
    let rhs: Vector6<f64> = -(sys.g * x.to_vector());
    let mut g = c.benchmark_group("forward");
    g.bench_function("bare_lu_6x6", |b| {
        b.iter(|| black_box(black_box(f).lu().solve(black_box(&rhs))))
    });
    g.bench_function("separation_velocities", |b| {
        b.iter(|| {
            black_box(separation_velocities(
                black_box(&impact),
                black_box(&coef),
                black_box(&x),
                &opts,
            ))
        })
    });
    g.bench_function("solve_forward_with_report", |b| {
        b.iter(|| {
            black_box(solve_forward(
                black_box(&impact),
                black_box(&coef),
                black_box(&x),
                &opts,
            ))
        })
    });
    // The second model with the same report (slides here: sticking needs |Pt/Pn| = 1.29).
    let tc = TangentialCoefficients {
        e: 0.1,
        et: 0.0,
        friction: 0.8,
    };
    g.bench_function("solve_tangential_with_report", |b| {
        b.iter(|| {
            black_box(solve_tangential(
                black_box(&impact),
                black_box(&tc),
                black_box(&x),
            ))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
