//! The damage as evidence: the fit of `examples/cases/ricsac7_damage.toml` (Q2) without the
//! crush, the Gauss-Newton fit with the crush energy on top of it, and the crush of all eleven
//! RICSAC tests beside their Q2 fits (`pim batch --damage`'s work).
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use pim_case::case::Case;
use pim_core::MomentForm;
use pim_fit::{CostPreset, FitModel, MomentBranch};
use std::hint::black_box;

fn read(path: &str) -> String {
    std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn damage(c: &mut Criterion) {
    let case = Case::from_text(
        "ricsac7_damage.toml",
        &read("examples/cases/ricsac7_damage.toml"),
    )
    .unwrap();
    let damage = pim_case::damage::Damage::of(&case).unwrap().unwrap();
    let problem = pim_studies::fitcase::problem(
        &case,
        pim_studies::fitcase::CostChoice::Preset(CostPreset::Q2),
    )
    .unwrap();
    let settings = pim_studies::fitcase::settings(
        &case,
        FitModel::Pim,
        MomentForm::Corrected,
        MomentBranch::ALL.to_vec(),
    )
    .unwrap();
    let mut g = c.benchmark_group("damage");
    g.bench_function("ricsac7 q2 fit, without the crush", |b| {
        b.iter(|| pim_fit::fit(black_box(&problem), &settings).unwrap())
    });
    let base = pim_fit::fit(&problem, &settings).unwrap();
    g.bench_function("ricsac7 q2, the crush energy fitted on top", |b| {
        b.iter(|| {
            pim_studies::damage_fit::fit_damage_of(
                black_box(&damage),
                &problem,
                &base,
                &settings,
                None,
            )
            .unwrap()
        })
    });
    let tests = pim_case::ricsac::parse("data/ricsac.csv", &read("data/ricsac.csv")).unwrap();
    let crush = pim_studies::ricsac_damage::parse_crush(&read("data/ricsac_vehicles.csv")).unwrap();
    let measured =
        pim_studies::ricsac_damage::parse_measured(&read("data/reference/neades2011_table5_3.csv"))
            .unwrap();
    let plan = pim_fit::FitSettings {
        velocity_bound: 20.0,
        yaw_rate_bound: 5.0,
        ..pim_fit::FitSettings::default()
    };
    g.sample_size(20);
    g.bench_function("ricsac, 11 tests with their crush", |b| {
        b.iter(|| {
            pim_studies::ricsac_damage::damage_records(black_box(&tests), &crush, &measured, &plan)
        })
    });
    g.finish();
}

criterion_group!(benches, damage);
criterion_main!(benches);
