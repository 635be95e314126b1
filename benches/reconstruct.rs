//! The three phases in one fit (pim-reconstruct): the example `reconstruction_us.toml` (two cars,
//! rest positions and headings, a mark each, a skid and an EDR speed) reconstructed from its
//! case, and 20 draws of its uncertainty study.
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use pim_case::case::Case;
use pim_core::MomentForm;
use pim_fit::{FitModel, MomentBranch};
use std::hint::black_box;

fn case() -> Case {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/cases/reconstruction_us.toml"
    );
    let text = std::fs::read_to_string(path).unwrap();
    Case::from_text(path, &text).unwrap()
}

fn reconstruction(c: &mut Criterion) {
    let case = case();
    let input = pim_studies::reconstruct::case_reconstruction(
        &case,
        FitModel::Pim,
        MomentForm::Corrected,
        MomentBranch::ALL.to_vec(),
    )
    .unwrap();
    let mut g = c.benchmark_group("reconstruct");
    g.sample_size(10);
    g.bench_function("reconstruction_us, whole search", |b| {
        b.iter(|| {
            pim_reconstruct::reconstruct(black_box(&input.reconstruction), &input.settings).unwrap()
        })
    });
    let nominal = pim_reconstruct::reconstruct(&input.reconstruction, &input.settings).unwrap();
    g.bench_function("reconstruction_us, one draw's refit", |b| {
        b.iter(|| {
            pim_reconstruct::redo(
                black_box(&input.reconstruction),
                &input.settings,
                &nominal,
                4.0,
            )
            .unwrap()
        })
    });
    g.bench_function("reconstruction_us, study of 20 draws", |b| {
        b.iter(|| {
            pim_studies::reconstruct_study::run(
                &case,
                FitModel::Pim,
                MomentForm::Corrected,
                MomentBranch::ALL.to_vec(),
                20,
                1,
                &pim_studies::watch::Unwatched,
            )
            .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, reconstruction);
criterion_main!(benches);
