//! A friction zone's friction as an assumption of the uncertainty study: with
//! `friction_sigma` the study draws it (the fit holds it as stated), and the SUV of the verge
//! example, which ends its run-out on the zone, leaves the impact with a wider spread of speeds.
use pim_case::case::Case;
use std::path::Path;

fn verge(sigma: Option<f64>) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/cases/reconstruction_verge_us.toml");
    let mut text = std::fs::read_to_string(&path).unwrap();
    if let Some(s) = sigma {
        text = text.replacen(
            "friction = 0.45 ",
            &format!("friction = 0.45\nfriction_sigma = {s} "),
            1,
        );
    }
    Case::from_text(&path.display().to_string(), &text).unwrap()
}

/// 40 draws of the study with and without a spread of 0.1 on the verge's friction (the same
/// seed): the verge's friction is among the inputs drawn, and the 90 % interval of the SUV's
/// speed at separation is wider with it.
#[test]
fn a_zones_friction_is_drawn_by_the_study() {
    let width = |case: &Case| {
        let done = pim_studies::reconstruct::reconstruct(
            case,
            pim_fit::FitModel::Pim,
            pim_core::MomentForm::Corrected,
            pim_fit::MomentBranch::ALL.to_vec(),
        )
        .unwrap();
        let study = pim_studies::reconstruct_study::run_around(
            case,
            &done,
            40,
            7,
            &pim_studies::watch::Unwatched,
        )
        .unwrap();
        let q = &study.quantities["vehicle2.speed_at_separation"];
        (study.inputs.clone(), q.p95 - q.p05)
    };
    let (inputs, spread) = width(&verge(Some(0.1)));
    let (plain_inputs, plain) = width(&verge(None));
    println!(
        "SUV at separation: 90 % width {spread:.3} m/s with the verge's spread, {plain:.3} without"
    );
    assert!(
        inputs.iter().any(|i| i == "grass verge friction"),
        "{inputs:?}"
    );
    assert!(
        !plain_inputs.iter().any(|i| i.contains("verge")),
        "{plain_inputs:?}"
    );
    assert!(spread > plain, "{spread} against {plain}");
    // A spread that is no spread is refused at its line.
    let bad = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/cases/reconstruction_verge_us.toml"),
    )
    .unwrap()
    .replacen(
        "friction = 0.45 ",
        "friction = 0.45\nfriction_sigma = -0.1 ",
        1,
    );
    let e = Case::from_text("verge.toml", &bad)
        .and_then(|c| c.scene_inputs().map(|_| ()))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("zones[0].friction_sigma") && e.contains("above 0"),
        "{e}"
    );
}
