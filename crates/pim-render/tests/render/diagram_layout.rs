//! Every plan view reads at a glance: parsed from its SVG, no two text boxes overlap, no text
//! box covers an arrowhead, and every text and shape lies inside the canvas. Checked on the
//! README's crash, every example case (drawn, solved and fitted) and every RICSAC test fitted.
//!
//! Text boxes are estimated from the font size and the characters (DejaVu Sans advance widths
//! by class of character), placed by `text-anchor` and the baseline shift `dy` that plotters
//! writes, and rotated with the text.

use crate::svg_layout;

use pim_case::case::Case;
use pim_studies::documents;
use std::path::Path;
use svg_layout::defects;

/// The repository root.
fn repo() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn load(path: &Path) -> Case {
    let text = std::fs::read_to_string(path).unwrap();
    Case::from_text(&path.display().to_string(), &text).unwrap()
}

/// The diagrams of a case: drawn, solved (when it can be) and fitted (when it can be).
fn diagrams(case: &Case) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let options = pim_core::SolveOptions::default();
    let d = pim_render::diagram::case_diagram(case, &options).unwrap();
    out.push((format!("{} (draw)", case.file), d.svg().unwrap()));
    if let Ok(s) = documents::solve(case, &options) {
        let d = pim_render::diagram::of_solve(case, &s);
        out.push((format!("{} (solve)", case.file), d.svg().unwrap()));
    }
    let cost = if case.content.known.is_some() || !case.content.observations.is_empty() {
        None
    } else {
        Some(pim_fit::CostPreset::Q3)
    };
    let fit = documents::fit(
        case,
        cost,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    );
    if let Ok(f) = fit {
        let d = pim_render::diagram::of_fit(case, &f, "q3").unwrap();
        out.push((format!("{} (fit)", case.file), d.svg().unwrap()));
    }
    out
}

#[test]
fn no_diagram_has_overlapping_labels_or_leaves_its_canvas() {
    let mut cases = Vec::new();
    let mut files: Vec<_> = std::fs::read_dir(repo().join("examples/cases"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 12);
    for f in &files {
        cases.push(load(f));
    }
    let data = std::fs::read_to_string(repo().join("data/ricsac.csv")).unwrap();
    let tests = pim_case::ricsac::parse("data/ricsac.csv", &data).unwrap();
    assert_eq!(tests.len(), 11);
    for t in &tests {
        cases.push(t.case(&format!("RICSAC test {}", t.test)).unwrap());
    }
    let mut bad = Vec::new();
    let mut drawn = 0;
    for c in &cases {
        for (name, svg) in diagrams(c) {
            drawn += 1;
            bad.extend(defects(&name, &svg));
        }
    }
    assert!(drawn >= 40, "{drawn} diagrams");
    assert!(bad.is_empty(), "{} defects:\n{}", bad.len(), bad.join("\n"));
}

#[test]
fn the_checker_sees_an_overlap_and_a_label_off_the_canvas() {
    let svg = r#"<svg width="100" height="50" xmlns="http://www.w3.org/2000/svg">
<text x="10" y="10" dy="0.76em" font-size="10">hello</text>
<text x="20" y="12" dy="0.76em" font-size="10">world</text>
<text x="90" y="30" dy="0.76em" font-size="10">outside</text>
<polygon points="12,12 14,18 16,12"/>
</svg>"#;
    let d = defects("probe", svg);
    assert!(d.iter().any(|x| x.contains("overlap")), "{d:?}");
    assert!(d.iter().any(|x| x.contains("leaves the canvas")), "{d:?}");
    assert!(d.iter().any(|x| x.contains("arrowhead")), "{d:?}");
}

/// A diagram that reached the drawing with a number that is not finite is refused with a typed
/// error naming what holds it, never handed to the plotting library.
#[test]
fn a_diagram_not_finite_is_refused_as_such() {
    let case = load(&repo().join("examples/cases/ricsac7_fit.toml"));
    let mut d =
        pim_render::diagram::case_diagram(&case, &pim_core::SolveOptions::default()).unwrap();
    d.vehicles[1].cg = [f64::NAN, 0.0];
    let e = d.svg().unwrap_err();
    assert!(matches!(e, pim_render::RenderError::NotFinite(_)), "{e:?}");
    assert_eq!(
        e.in_file("case.toml"),
        "case.toml: cannot draw: a dimension or velocity of the plan view (check length, width, \
         cg_to_front and the velocities) is not a finite number"
    );
}
