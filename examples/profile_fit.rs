//! Profiling helper (not documented as an example): repeats one fit.
fn main() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("data/ricsac.csv");
    let tests = pim_cli::ricsac::load(&path).unwrap();
    let t = tests.iter().find(|t| t.test == 5).unwrap();
    let p = pim_fit::FitProblem::from_preset(
        t.impact().unwrap(),
        pim_fit::CostPreset::Q1,
        &t.initial(),
        &t.separation(),
        None,
    );
    let s = pim_fit::FitSettings {
        branches: vec![pim_fit::MomentBranch::Free],
        ..Default::default()
    }
    .check()
    .unwrap();
    for _ in 0..300 {
        std::hint::black_box(pim_fit::fit(&p, &s).unwrap());
    }
}
