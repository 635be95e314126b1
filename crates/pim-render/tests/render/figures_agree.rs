//! The figures of one crash put every point at one place: the plan view at contact (`pim
//! draw`) and the scene of the reconstruction (`pim fit --out`, the report) draw each vehicle's
//! outline at contact on the same page coordinates, in the case's frame and units; an SAE
//! scene lies as a map (x up, y to the right).

use pim_case::case::Case;
use pim_case::units::UnitSystem;
use std::path::Path;

fn load(name: &str) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/cases")
        .join(name);
    let text = std::fs::read_to_string(&path).unwrap();
    Case::from_text(&path.display().to_string(), &text).unwrap()
}

fn sorted(mut v: Vec<(f64, f64)>) -> Vec<(f64, f64)> {
    v.dedup_by(|a, b| (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9);
    if v.len() > 1 && v.first() == v.last() {
        v.pop();
    }
    v.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    v
}

/// Both figures of every scene example: the outlines at contact coincide to 1e-9 of the
/// display unit.
#[test]
fn plan_view_and_scene_put_every_point_at_one_place() {
    for name in ["reconstruction_us.toml", "runout_scene.toml"] {
        let case = load(name);
        let units = UnitSystem::of(&case.written_units);
        let diagram = pim_render::diagram::case_diagram(&case, &Default::default()).unwrap();
        let runouts = pim_studies::runout::runout(&case, None, None, 0.02, false);
        let Ok(runouts) = runouts else {
            // A case whose run-out needs the reconstruction's separation state.
            let done = pim_studies::reconstruct::reconstruct(
                &case,
                pim_fit::FitModel::Pim,
                pim_core::MomentForm::Corrected,
                pim_fit::MomentBranch::ALL.to_vec(),
            )
            .unwrap();
            let sep = done.outcome.best.unwrap().solution.separation;
            let r = pim_studies::runout::runout(&case, None, Some(sep), 0.02, false).unwrap();
            check(&case, &diagram, &r, units);
            continue;
        };
        check(&case, &diagram, &runouts, units);
    }
}

fn check(
    case: &Case,
    diagram: &pim_render::diagram::Diagram,
    r: &pim_studies::runout::RunoutResult,
    units: UnitSystem,
) {
    for (k, input) in r.inputs.iter().enumerate() {
        let v = input.id.index();
        let scene = sorted(pim_render::runout::start_outline_on_page(
            r,
            k,
            units,
            case.written,
        ));
        let plan = sorted(diagram.outline_on_page(v));
        assert_eq!(scene.len(), 4, "{}: {scene:?}", case.file);
        assert_eq!(plan.len(), 4, "{}: {plan:?}", case.file);
        for (a, b) in scene.iter().zip(&plan) {
            assert!(
                (a.0 - b.0).abs() < 1e-9 && (a.1 - b.1).abs() < 1e-9,
                "{}: vehicle {}: scene {scene:?} plan {plan:?}",
                case.file,
                v + 1
            );
        }
    }
}

/// The SAE example lies as a map: the northbound sedan's outline runs up the page, the
/// eastbound SUV's across it to the right, and the SUV's rest (x 50.1 ft, y +79.7 ft: east) is
/// drawn right of the origin and above it, where its axis labels read +80 and +50.
#[test]
fn an_sae_scene_is_read_as_a_map() {
    let case = load("reconstruction_us.toml");
    let units = UnitSystem::of(&case.written_units);
    let diagram = pim_render::diagram::case_diagram(&case, &Default::default()).unwrap();
    let span = |pts: &[(f64, f64)]| {
        let w = pts.iter().map(|p| p.0).fold(f64::MIN, f64::max)
            - pts.iter().map(|p| p.0).fold(f64::MAX, f64::min);
        let h = pts.iter().map(|p| p.1).fold(f64::MIN, f64::max)
            - pts.iter().map(|p| p.1).fold(f64::MAX, f64::min);
        (w, h)
    };
    let (w1, h1) = span(&diagram.outline_on_page(0));
    assert!(
        (h1 - 16.0).abs() < 1e-9 && (w1 - 6.0).abs() < 1e-9,
        "{w1} x {h1}"
    );
    let (w2, h2) = span(&diagram.outline_on_page(1));
    assert!(
        (w2 - 15.0).abs() < 1e-9 && (h2 - 6.2).abs() < 1e-9,
        "{w2} x {h2}"
    );
    let done = pim_studies::reconstruct::reconstruct(
        &case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    )
    .unwrap();
    let svg = pim_render::runout::reconstruction_scene(&case, &done, units)
        .unwrap()
        .unwrap();
    assert!(svg.contains("y [ft] (SAE: to the right of x)"));
    assert!(svg.contains("x [ft] (SAE)"));
    // The rest as reconstructed, on the page: (y, x) of the SAE scene.
    let rest = done.document.best.unwrap().vehicles[1].rest.unwrap();
    let page = pim_render::plan::Page::of(case.written)
        .point([units.length(rest.x), units.length(rest.y)]);
    assert!(
        (page[0] - 79.7).abs() < 1.0 && (page[1] - 50.1).abs() < 1.0,
        "{page:?}"
    );
}
