//! `[[runout.zones]]`: read into each vehicle's chassis in SI and the natural frame, refused at
//! the line of the field at fault, and appended by an edit with every other byte kept.
use pim_case::case::Case;
use pim_case::edit::{CaseEdit, NewValue};
use std::path::Path;

fn example() -> (String, String) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/cases/reconstruction_verge_us.toml");
    (
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    )
}

/// The verge of the example (SAE, feet): each run-out's chassis carries it, its corners in
/// metres with y turned to the left.
#[test]
fn a_zone_is_read_in_si_and_the_natural_frame() {
    let (file, text) = example();
    let inputs = Case::from_text(&file, &text)
        .unwrap()
        .scene_inputs()
        .unwrap();
    assert_eq!(inputs.vehicles.len(), 2);
    for v in &inputs.vehicles {
        let z = &v.chassis.zones;
        assert_eq!(z.len(), 1);
        assert!((z[0].friction - 0.45).abs() < 1e-15);
        let expected = [[-50.0, 60.0], [150.0, 60.0], [150.0, 150.0], [-50.0, 150.0]];
        for (c, e) in z[0].corners.iter().zip(expected) {
            assert!((c[0] - e[0] * 0.3048).abs() < 1e-12 && (c[1] + e[1] * 0.3048).abs() < 1e-12);
        }
    }
}

/// A friction out of range, too few corners, corners on one line, a friction at or below the
/// rolling resistance: each refused at its line, naming the zone's field.
#[test]
fn a_bad_zone_is_refused_at_its_line() {
    let (file, text) = example();
    let line_of = |needle: &str| text.lines().position(|l| l.starts_with(needle)).unwrap() + 1;
    let cases = [
        (
            "friction = 0.45 ",
            "friction = 2.0 ",
            "friction",
            line_of("friction = 0.45 "),
        ),
        (
            "corners = [ [-50.0, 60.0], [150.0, 60.0], [150.0, 150.0], [-50.0, 150.0] ]",
            "corners = [ [-50.0, 60.0], [150.0, 60.0] ]",
            "at least three",
            line_of("corners = "),
        ),
        (
            "corners = [ [-50.0, 60.0], [150.0, 60.0], [150.0, 150.0], [-50.0, 150.0] ]",
            "corners = [ [0.0, 0.0], [1.0, 1.0], [2.0, 2.0] ]",
            "no area",
            line_of("corners = "),
        ),
    ];
    for (from, to, says, line) in cases {
        let bad = text.replacen(from, to, 1);
        let e = Case::from_text(&file, &bad)
            .and_then(|c| c.scene_inputs().map(|_| ()))
            .unwrap_err()
            .to_string();
        println!("{e}");
        assert!(
            e.contains(&format!(":{line}:")) && e.contains("zones") && e.contains(says),
            "{e}"
        );
    }
    let slippery = text.replacen("friction = 0.45 ", "friction = 0.01 ", 1);
    let e = Case::from_text(&file, &slippery)
        .and_then(|c| c.scene_inputs().map(|_| ()))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("zone 1") && e.contains("rolling resistance"),
        "{e}"
    );
}

/// An edit appends a zone as `[[runout.zones]]` at the end of the file: the text before it
/// byte for byte, the case reads it.
#[test]
fn a_zone_is_appended_with_every_other_byte_kept() {
    let (file, text) = example();
    let mut edit = CaseEdit::new(&file, &text).unwrap();
    edit.push_table(
        "runout.zones",
        &[
            ("name", NewValue::Text("gravel".into())),
            ("friction", NewValue::Written(0.55)),
            (
                "corners",
                NewValue::Points(vec![[0.0, -20.0], [10.0, -20.0], [10.0, -10.0]]),
            ),
        ],
    )
    .unwrap();
    let out = edit.text();
    assert!(out.starts_with(&text));
    assert_eq!(
        &out[text.len()..],
        "\n[[runout.zones]]\nname = \"gravel\"\nfriction = 0.55\ncorners = [[0.0, -20.0], [10.0, -20.0], [10.0, -10.0]]\n"
    );
    let case = edit.check().unwrap();
    assert_eq!(
        case.scene_inputs().unwrap().vehicles[0].chassis.zones.len(),
        2
    );
}
