//! Certified fits: one (test, cost function) with both branches, and all 33 of RICSAC.
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use pim_fit::*;
use std::hint::black_box;

fn problems() -> Vec<(u32, CostPreset, FitProblem)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/ricsac.csv");
    let tests = pim_case::ricsac::parse(
        "data/ricsac.csv",
        &std::fs::read_to_string(&path).expect("data/ricsac.csv"),
    )
    .expect("valid data");
    let mut out = Vec::new();
    for t in &tests {
        for c in CostPreset::ALL {
            let p = FitProblem::from_preset(
                t.impact().unwrap(),
                c,
                &t.initial(),
                &t.separation(),
                None,
            );
            out.push((t.test, c, p));
        }
    }
    out
}

fn bench(c: &mut Criterion) {
    let settings = FitSettings::default().check().unwrap();
    let all = problems();
    let mut g = c.benchmark_group("fit");
    g.sample_size(20);
    for (test, cost) in [
        (9, CostPreset::Q2),
        (9, CostPreset::Q3),
        (7, CostPreset::Q3),
        (5, CostPreset::Q1),
    ] {
        let p = &all
            .iter()
            .find(|(t, c, _)| *t == test && *c == cost)
            .unwrap()
            .2;
        g.bench_function(format!("ricsac{test}_{}_both_branches", cost.name()), |b| {
            b.iter(|| black_box(fit(black_box(p), &settings).unwrap()))
        });
    }
    g.bench_function("all_33_sequential", |b| {
        b.iter(|| {
            for (_, _, p) in &all {
                black_box(fit(p, &settings).unwrap());
            }
        })
    });
    g.finish();

    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/ricsac.csv");
    let tests =
        pim_case::ricsac::parse("data/ricsac.csv", &std::fs::read_to_string(&path).unwrap())
            .unwrap();
    let plan = pim_studies::batch::BatchPlan {
        costs: CostPreset::ALL.to_vec(),
        branches: MomentBranch::ALL.to_vec(),
        models: vec![pim_fit::FitModel::Pim],
        settings: FitSettings::default(),
        timing: false,
        case_e_max: None,
    };
    let mut g = c.benchmark_group("batch");
    g.sample_size(20);
    g.bench_function("ricsac_66_records_all_threads", |b| {
        b.iter(|| {
            black_box(pim_studies::batch::run(
                &tests,
                &plan,
                &pim_studies::watch::Unwatched,
            ))
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
