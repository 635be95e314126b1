//! The run-out (pim-runout): one passenger car from 15 m/s and 3 rad/s to rest on each kind of
//! wheels, and the separation velocities of one vehicle from its rest position and heading
//! (with and without two marks).
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use pim_runout::{
    estimate, simulate, Chassis, EstimateSettings, Evidence, Mark, Motion, Rest, Settings,
    WheelState,
};
use std::hint::black_box;

fn car(wheels: WheelState) -> Chassis {
    let mut c = Chassis::new(1500.0, 2500.0, 2.7, 1.2, 1.55, wheels);
    c.friction = 0.75;
    c
}

fn start() -> Motion {
    Motion {
        vx: 15.0,
        yaw_rate: 3.0,
        ..Motion::default()
    }
}

fn runouts(c: &mut Criterion) {
    let s = Settings::default();
    for (name, wheels) in [
        ("locked", WheelState::Locked),
        ("braked 0.5", WheelState::Braked(0.5)),
        ("rolling", WheelState::Rolling),
    ] {
        let chassis = car(wheels);
        c.bench_function(&format!("runout 15 m/s 3 rad/s, {name}"), |b| {
            b.iter(|| simulate(black_box(&chassis), black_box(&start()), &s).unwrap())
        });
    }
    let mut with_height = car(WheelState::Locked);
    with_height.cg_height = Some(0.55);
    c.bench_function("runout 15 m/s 3 rad/s, locked, load transfer", |b| {
        b.iter(|| simulate(black_box(&with_height), black_box(&start()), &s).unwrap())
    });
}

fn inverse(c: &mut Criterion) {
    let chassis = car(WheelState::Locked);
    let truth = simulate(&chassis, &start(), &Settings::default()).unwrap();
    let rest = Rest {
        x: truth.rest.x,
        y: truth.rest.y,
        heading: Some(truth.rest.heading),
        sigma_xy: [0.1, 0.1],
        sigma_heading: 0.05,
        point: [0.0, 0.0],
    };
    let mark = |t: f64| {
        let m = truth.at(t);
        Mark {
            x: m.x,
            y: m.y,
            sigma: 0.1,
            heading: None,
            point: [0.0, 0.0],
        }
    };
    let pose = Motion::default();
    let settings = EstimateSettings::default();
    let mut group = c.benchmark_group("separation from the scene");
    group.sample_size(20);
    let rest_only = Evidence {
        rest: Some(rest),
        ..Evidence::default()
    };
    group.bench_function("rest, 7 counts of turns", |b| {
        b.iter(|| estimate(&chassis, &pose, black_box(&rest_only), &settings).unwrap())
    });
    let marks = Evidence {
        rest: Some(rest),
        marks: vec![mark(0.3 * truth.time), mark(0.6 * truth.time)],
        ..Evidence::default()
    };
    group.bench_function("rest and two marks, 7 counts of turns", |b| {
        b.iter(|| estimate(&chassis, &pose, black_box(&marks), &settings).unwrap())
    });
    let stated = Evidence {
        turns: Some(1),
        ..marks.clone()
    };
    group.bench_function("rest and two marks, the count stated", |b| {
        b.iter(|| estimate(&chassis, &pose, black_box(&stated), &settings).unwrap())
    });
    // The quick look the whole reconstruction's first search takes, at its run-out tolerance.
    let quick = EstimateSettings {
        quick: true,
        runout: pim_runout::Settings {
            rtol: 1e-6,
            atol: 1e-6,
            ..pim_runout::Settings::default()
        },
        ..settings
    };
    group.bench_function("rest, 7 counts of turns, quick look", |b| {
        b.iter(|| estimate(&chassis, &pose, black_box(&rest_only), &quick).unwrap())
    });
    group.bench_function("rest and two marks, 7 counts of turns, quick look", |b| {
        b.iter(|| estimate(&chassis, &pose, black_box(&marks), &quick).unwrap())
    });
    group.finish();
}

criterion_group!(benches, runouts, inverse);
criterion_main!(benches);
