//! The three phases in one fit (pim-reconstruct): the example `reconstruction_us.toml` (two cars,
//! rest positions and headings, a mark each, a skid and an EDR speed) reconstructed from its
//! case, and 20 draws of its uncertainty study; and two realistic simulated crashes, whose whole
//! searches are the benchmarks of a realistic scene: `benches/data/realistic_100732.toml` (a
//! small car free rolling 98 m, the other on steered wheels; the median of the realistic
//! sweep's 200 by time) and `benches/data/realistic_100102.toml` (an ABS-braked sedan, an SUV
//! rolling 98 m on steered wheels; its first search ends in a wrong basin).
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use pim_case::case::Case;
use pim_core::MomentForm;
use pim_fit::{FitModel, MomentBranch};
use std::hint::black_box;

fn case_at(path: &str) -> Case {
    let text = std::fs::read_to_string(path).unwrap();
    Case::from_text(path, &text).unwrap()
}

fn case() -> Case {
    case_at(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/cases/reconstruction_us.toml"
    ))
}

/// The case's reconstruction as `pim fit` runs it (PIM, both moment branches).
fn input_of(case: &Case) -> pim_studies::reconstruct::CaseReconstruction {
    pim_studies::reconstruct::case_reconstruction(
        case,
        FitModel::Pim,
        MomentForm::Corrected,
        MomentBranch::ALL.to_vec(),
    )
    .unwrap()
}

fn reconstruction(c: &mut Criterion) {
    let case = case();
    let input = input_of(&case);
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

/// The whole search of two realistic crashes: the median of the 200 of the realistic sweep
/// (its first search answers), and one whose first search ends in a wrong basin, so that the
/// second, from the scatter, runs. Up to seconds per iteration, so ten samples of one iteration
/// each.
fn realistic(c: &mut Criterion) {
    let mut g = c.benchmark_group("realistic");
    g.sample_size(10)
        .measurement_time(std::time::Duration::from_secs(90));
    for (file, name) in [
        (
            "realistic_100732.toml",
            "crash 100732 (rolling 98 m / steered 31 m), whole search",
        ),
        (
            "realistic_100102.toml",
            "crash 100102 (ABS / steered 98 m), whole search",
        ),
    ] {
        let case = case_at(&format!(
            "{}/benches/data/{file}",
            env!("CARGO_MANIFEST_DIR")
        ));
        let input = input_of(&case);
        g.bench_function(name, |b| {
            b.iter(|| {
                pim_reconstruct::reconstruct(black_box(&input.reconstruction), &input.settings)
                    .unwrap()
            })
        });
    }
    g.finish();
}

criterion_group!(benches, reconstruction, realistic);
criterion_main!(benches);
