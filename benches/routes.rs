//! One fit per solver route: PIM's moment branches under Q1, Q2 and Q3 (RICSAC 9, each branch
//! alone, so that the route of each is timed on its own), the tangential model's fit, the fit
//! with the impact geometry as unknowns (RICSAC 6, five unknowns, Q2 and Q3, the proof over the
//! geometry box included), and one draw of
//! `pim uncertainty` (RICSAC 7, 200 draws on one thread, divided by 200 in the README).
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use pim_fit::*;
use pim_studies::fitcase::CostChoice;
use std::hint::black_box;

fn root(p: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(p)
}

fn ricsac(test: u32, cost: CostPreset) -> FitProblem {
    let tests = pim_case::ricsac::parse(
        "data/ricsac.csv",
        &std::fs::read_to_string(root("data/ricsac.csv")).expect("data/ricsac.csv"),
    )
    .expect("valid data");
    let t = tests.iter().find(|t| t.test == test).expect("test");
    FitProblem::from_preset(
        t.impact().unwrap(),
        cost,
        &t.initial(),
        &t.separation(),
        None,
    )
}

fn case(path: &str) -> pim_case::case::Case {
    let text = std::fs::read_to_string(root(path)).expect("case file");
    pim_case::case::Case::from_text(path, &text).expect("valid case")
}

fn settings(model: FitModel, branches: &[MomentBranch]) -> ValidSettings {
    FitSettings {
        model,
        branches: branches.to_vec(),
        ..FitSettings::default()
    }
    .check()
    .unwrap()
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("route");
    g.sample_size(30);
    for cost in CostPreset::ALL {
        let p = ricsac(9, cost);
        for branch in MomentBranch::ALL {
            let s = settings(FitModel::Pim, &[branch]);
            g.bench_function(format!("pim_{}_{}", cost.name(), branch.name()), |b| {
                b.iter(|| black_box(fit(black_box(&p), &s).unwrap()))
            });
        }
        let s = settings(FitModel::Tangential, &MomentBranch::ALL);
        g.bench_function(format!("tangential_{}", cost.name()), |b| {
            b.iter(|| black_box(fit(black_box(&p), &s).unwrap()))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("geometry");
    g.sample_size(10);
    let geo = case("examples/cases/ricsac6_geometry.toml");
    let s = pim_studies::fitcase::settings_from(&geo, FitSettings::default()).unwrap();
    // The whole geometry fit: grid, refinements, the proof over the box, the scans.
    for cost in [CostPreset::Q2, CostPreset::Q3] {
        let problem = pim_studies::fitcase::problem(&geo, CostChoice::Preset(cost)).unwrap();
        g.bench_function(format!("ricsac6_geometry_{}", cost.name()), |b| {
            b.iter(|| black_box(pim_studies::fitcase::fit(&geo, &problem, &s).unwrap()))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("uncertainty");
    g.sample_size(10);
    let unc_case = case("examples/cases/ricsac7_uncertainty.toml");
    let unc = unc_case.content.uncertainty.unwrap_or_default();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    for cost in CostPreset::ALL {
        g.bench_function(
            format!("ricsac7_{}_200_draws_one_thread", cost.name()),
            |b| {
                b.iter(|| {
                    pool.install(|| {
                        black_box(
                            pim_studies::uncertainty::run(
                                &unc_case,
                                &unc,
                                CostChoice::Preset(cost),
                                FitSettings::default(),
                                200,
                                1,
                                &pim_studies::watch::Unwatched,
                            )
                            .unwrap(),
                        )
                    })
                })
            },
        );
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
