//! The scene editor's answers on the server (`pim serve`): a case solved from its coefficients
//! with both run-outs drawn (what an edit of a solved case costs before the page redraws it),
//! and a scene case's live answer while a rest is dragged and its whole answer on release.
#![allow(missing_docs)] // criterion_group! generates undocumented items
use criterion::{criterion_group, criterion_main, Criterion};
use std::hint::black_box;

fn text(path: &str) -> String {
    std::fs::read_to_string(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path))
        .expect("example")
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("serve");
    g.sample_size(20);
    // An edit of a solved case: car 1's speed changed, the solve, both run-outs to rest and
    // the plan (outlines every 0.5 s, paths, rests).
    let spin = text("examples/cases/runout_spin.toml");
    let edited = spin.replace("vx = 20.0, vy = 0.0", "vx = 21.5, vy = 0.0");
    assert_ne!(spin, edited);
    g.bench_function("runout_spin.toml edited: solve, run-outs and plan", |b| {
        b.iter(|| black_box(pim_serve::answer("runout_spin.toml", black_box(&edited)).unwrap()))
    });
    let file = "reconstruction_us.toml";
    let scene = text("examples/cases/reconstruction_us.toml");
    let (_, outcome) = pim_serve::answer_following(file, &scene, None).unwrap();
    let moved = pim_serve::move_rest(file, &scene, 2, [79.7 + 1.0, 50.1]).unwrap();
    g.bench_function("reconstruction_us.toml rest moved 1 ft: live answer", |b| {
        b.iter(|| {
            black_box(
                pim_serve::answer_following(file, black_box(&moved), outcome.as_ref()).unwrap(),
            )
        })
    });
    g.bench_function(
        "reconstruction_us.toml rest moved 1 ft: whole answer",
        |b| b.iter(|| black_box(pim_serve::answer(file, black_box(&moved)).unwrap())),
    );
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
