//! The figures of `pim batch` (both models) and of `pim uncertainty` read cleanly: parsed from
//! their SVG, no two text boxes overlap, every text and shape lies inside the canvas, and no
//! rectangle has zero area (a value too small for a bar is drawn as a line on the axis).

use crate::svg_layout;

use pim_fit::{CostPreset, FitModel, MomentBranch};
use pim_studies::batch::{self, BatchPlan};
use std::path::Path;
use svg_layout::defects;

fn repo() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn batch_and_uncertainty_figures_keep_their_text_apart_and_inside() {
    let path = repo().join("data/ricsac.csv");
    let text = std::fs::read_to_string(&path).unwrap();
    let tests = pim_case::ricsac::parse("data/ricsac.csv", &text).unwrap();
    let costs = [CostPreset::Q1, CostPreset::Q2, CostPreset::Q3];
    let plan = BatchPlan::new(
        &costs,
        &[MomentBranch::Free, MomentBranch::Zero],
        pim_fit::DEFAULT_E_RANGE[1],
        pim_core::MomentForm::Corrected,
    )
    .unwrap()
    .with_models(&[FitModel::Pim, FitModel::Tangential]);
    let records = batch::run(&tests, &plan, &pim_studies::watch::Unwatched);
    let pim: Vec<_> = records
        .iter()
        .filter(|r| r.model == FitModel::Pim)
        .cloned()
        .collect();
    let mut figures = pim_render::figures::all(&pim, &costs, &plan.settings).unwrap();
    figures.push(
        pim_render::figures::models(&records, &costs, &[FitModel::Pim, FitModel::Tangential])
            .unwrap(),
    );

    let case_path = repo().join("examples/cases/tbone_sae_us.toml");
    let case = pim_case::case::Case::from_text(
        "tbone_sae_us.toml",
        &std::fs::read_to_string(&case_path).unwrap(),
    )
    .unwrap();
    let unc = case.spreads();
    let study = pim_studies::uncertainty::run(
        &case,
        &unc,
        pim_studies::fitcase::CostChoice::Custom,
        pim_fit::FitSettings::default(),
        60,
        1,
        &pim_studies::watch::Unwatched,
    )
    .unwrap();
    figures.extend(
        pim_render::uncertainty_figures::figures(&study, pim_case::units::UnitSystem::Us).unwrap(),
    );

    let names: Vec<&str> = figures.iter().map(|f| f.name.as_str()).collect();
    assert!(names.len() >= 7, "figures checked: {names:?}");
    let bad: Vec<String> = figures
        .iter()
        .flat_map(|f| defects(&f.name, &f.svg))
        .collect();
    assert!(bad.is_empty(), "{} defects:\n{}", bad.len(), bad.join("\n"));
}
