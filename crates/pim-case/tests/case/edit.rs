//! Editing a case file in place: a round trip with no edit gives the file back byte for byte; an
//! edit changes the one value and nothing else (comments, order, spacing and the formatting of
//! every other number kept); an SI value is written in the file's units and reads back as that
//! SI value; an edit that breaks the case is caught by the same checks as `pim`.

use pim_case::case::Case;
use pim_case::edit::{CaseEdit, NewValue, Quantity};
use pim_case::units::FOOT;
use std::path::PathBuf;

fn examples() -> Vec<PathBuf> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&root)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 15, "examples found: {}", files.len());
    files
}

fn read(name: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/cases")
        .join(name);
    std::fs::read_to_string(p).unwrap()
}

/// The lines of `b` that differ from those of `a` (same count of lines required).
fn changed_lines(a: &str, b: &str) -> Vec<(String, String)> {
    let (la, lb): (Vec<_>, Vec<_>) = (a.lines().collect(), b.lines().collect());
    assert_eq!(la.len(), lb.len(), "an edit added or removed lines:\n{b}");
    la.iter()
        .zip(&lb)
        .filter(|(x, y)| x != y)
        .map(|(x, y)| (x.to_string(), y.to_string()))
        .collect()
}

#[test]
fn every_example_round_trips_byte_for_byte() {
    for path in examples() {
        let text = std::fs::read_to_string(&path).unwrap();
        let edit = CaseEdit::new(&path.display().to_string(), &text).unwrap();
        assert_eq!(edit.text(), text, "{}", path.display());
        edit.check().unwrap();
    }
}

#[test]
fn a_rest_position_dragged_in_metres_is_written_in_feet() {
    let text = read("reconstruction_us.toml");
    let mut edit = CaseEdit::new("reconstruction_us.toml", &text).unwrap();
    // 12 ft dragged on a plan that works in metres.
    edit.set(
        "scene.vehicle1.rest.x",
        NewValue::Si(12.0 * FOOT, Quantity::Length),
    )
    .unwrap();
    assert_eq!(edit.get("scene.vehicle1.rest.x").as_deref(), Some("12.0"));
    let changed = changed_lines(&text, &edit.text());
    assert_eq!(
        changed,
        vec![(
            "rest = { x = 11.9, y = 2.9, heading = 144.0 }     # ft, ft, deg clockwise".to_string(),
            "rest = { x = 12.0, y = 2.9, heading = 144.0 }     # ft, ft, deg clockwise".to_string()
        )]
    );
    // The edited file reads as the file typed by hand with 12.0.
    let by_hand = text.replace("x = 11.9, y = 2.9", "x = 12.0, y = 2.9");
    let (a, b) = (
        edit.check().unwrap().scene_inputs().unwrap(),
        Case::from_text("by_hand.toml", &by_hand)
            .unwrap()
            .scene_inputs()
            .unwrap(),
    );
    let rest = |s: &pim_case::scene::SceneInputs| {
        let r = s.vehicles[0].evidence.as_ref().unwrap().rest.unwrap();
        format!("{r:?}")
    };
    assert_eq!(rest(&a), rest(&b));
}

#[test]
fn a_heading_in_radians_is_written_in_degrees_and_a_speed_in_mph() {
    let text = read("reconstruction_us.toml");
    let mut edit = CaseEdit::new("reconstruction_us.toml", &text).unwrap();
    edit.set(
        "scene.vehicle2.rest.heading",
        NewValue::Si(250f64.to_radians(), Quantity::Angle),
    )
    .unwrap();
    edit.set(
        "pre_impact.vehicle2.edr.0.speed",
        NewValue::Si(30.0 * 0.447_04, Quantity::Speed),
    )
    .unwrap();
    assert_eq!(
        edit.get("scene.vehicle2.rest.heading").as_deref(),
        Some("250.0")
    );
    assert_eq!(
        edit.get("pre_impact.vehicle2.edr[0].speed").as_deref(),
        Some("30.0")
    );
    assert_eq!(changed_lines(&text, &edit.text()).len(), 2);
    edit.check().unwrap();
}

#[test]
fn a_sigma_and_a_wheel_state_keep_their_comments() {
    let text = read("reconstruction_us.toml");
    let mut edit = CaseEdit::new("reconstruction_us.toml", &text).unwrap();
    edit.set("observations[0].sigma", NewValue::Written(2.5))
        .unwrap();
    edit.set(
        "runout.vehicle1.wheels.front_right",
        NewValue::Text("locked".into()),
    )
    .unwrap();
    edit.set("runout.friction_sigma", NewValue::Written(0.08))
        .unwrap();
    let changed = changed_lines(&text, &edit.text());
    let after: Vec<&str> = changed.iter().map(|(_, b)| b.as_str()).collect();
    assert_eq!(
        after,
        vec![
            "sigma = 2.5                         # mph",
            "friction_sigma = 0.08               # its spread, drawn by `pim uncertainty`",
            "wheels = { front_left = \"locked\", front_right = \"locked\", rear_left = \"rolling\", rear_right = \"rolling\" }",
        ]
    );
    let case = edit.check().unwrap();
    // Read in SI: 2.5 mph.
    let sigma = case.content.observations[0].sigma.unwrap();
    assert!((sigma - 2.5 * 0.447_04).abs() < 1e-12, "{sigma}");
}

#[test]
fn a_new_key_is_added_where_it_belongs_and_can_be_removed_again() {
    let text = read("reconstruction_us.toml");
    let mut edit = CaseEdit::new("reconstruction_us.toml", &text).unwrap();
    edit.set("scene.vehicle1.turns", NewValue::Written(0.0))
        .unwrap();
    assert!(edit.text().contains("[scene.vehicle1]\nrest = "));
    // A whole number typed for a count of turns is written as one, and read.
    assert_eq!(edit.get("scene.vehicle1.turns").as_deref(), Some("0"));
    edit.check().unwrap();
    // A fraction where the case wants a count of turns: the same message as `pim`.
    edit.set("scene.vehicle1.turns", NewValue::Written(0.5))
        .unwrap();
    let e = edit.check().unwrap_err().to_string();
    assert!(e.contains("scene.vehicle1.turns"), "{e}");
    assert!(edit.remove("scene.vehicle1.turns"));
    assert_eq!(edit.text(), text);
    assert!(!edit.remove("scene.vehicle1.turns"));
}

#[test]
fn bad_paths_and_values_are_refused_with_the_path() {
    let text = read("reconstruction_us.toml");
    let mut edit = CaseEdit::new("reconstruction_us.toml", &text).unwrap();
    let refused = |e: pim_case::InputError| e.to_string();
    let e = refused(
        edit.set("observations.7.sigma", NewValue::Written(1.0))
            .unwrap_err(),
    );
    assert!(
        e.contains("observations.7.sigma") && e.contains("has 2"),
        "{e}"
    );
    let e = refused(
        edit.set("scene.vehicle1", NewValue::Written(1.0))
            .unwrap_err(),
    );
    assert!(e.contains("is a table"), "{e}");
    let e = refused(edit.set("title.x", NewValue::Written(1.0)).unwrap_err());
    assert!(e.contains("title.x"), "{e}");
    let e = refused(
        edit.set("vehicle1.mass", NewValue::Si(f64::NAN, Quantity::Mass))
            .unwrap_err(),
    );
    assert!(e.contains("finite"), "{e}");
    assert_eq!(edit.text(), text, "a refused edit changes nothing");
    // An edit that breaks the case is caught by the case's own checks.
    edit.set("vehicle1.mass", NewValue::Written(-5.0)).unwrap();
    let e = edit.check().unwrap_err().to_string();
    assert!(
        e.starts_with("reconstruction_us.toml:") && e.contains("vehicle1.mass"),
        "{e}"
    );
    // Not TOML at all: the line and column.
    let e = CaseEdit::new("broken.toml", "a = 1\nb = = 2\n")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("broken.toml:2:"), "{e}");
}

#[test]
fn si_files_take_si_values_as_they_are() {
    let text = read("runout_scene.toml");
    let mut edit = CaseEdit::new("runout_scene.toml", &text).unwrap();
    let units = edit.units().unwrap();
    assert!((units.length.to_si() - 1.0).abs() < 1e-15);
    edit.set("vehicle1.mass", NewValue::Si(1234.5, Quantity::Mass))
        .unwrap();
    assert_eq!(edit.get("vehicle1.mass").as_deref(), Some("1234.5"));
    assert_eq!(changed_lines(&text, &edit.text()).len(), 1);
}

/// A mark added to a scene vehicle's marks: appended to its array on the same line (the
/// comment after it kept), written in the file's unit, read back as a mark; a vehicle without
/// marks gets its array; a path that is no array is refused.
#[test]
fn a_mark_is_appended_to_the_scene_and_the_rest_kept() {
    let text = read("reconstruction_us.toml");
    let mut e = CaseEdit::new("r.toml", &text).unwrap();
    let i = e
        .push(
            "scene.vehicle2.marks",
            &[
                ("x", NewValue::Si(12.0, Quantity::Length)),
                ("y", NewValue::Written(20.5)),
                ("sigma", NewValue::Written(0.5)),
            ],
        )
        .unwrap();
    assert_eq!(i, 1);
    let changed = changed_lines(&text, &e.text());
    assert_eq!(changed.len(), 1, "{changed:?}");
    assert_eq!(
        changed[0].1,
        "marks = [ { x = 32.6, y = 48.2, sigma = 0.5 }, { x = 39.3700787, y = 20.5, sigma = 0.5 } ]"
    );
    let case = e.check().unwrap();
    let marks = &case
        .content
        .scene
        .as_ref()
        .unwrap()
        .vehicle2
        .as_ref()
        .unwrap()
        .marks;
    assert_eq!(marks.len(), 2);

    // A vehicle whose scene has no marks yet.
    let no_marks = text.replace(
        "marks = [ { x = 10.6, y = 2.7, sigma = 0.5 } ]     # a yaw mark the CG passed\n",
        "",
    );
    assert_ne!(no_marks, text);
    let mut e = CaseEdit::new("r.toml", &no_marks).unwrap();
    assert_eq!(
        e.push(
            "scene.vehicle1.marks",
            &[
                ("x", NewValue::Written(1.0)),
                ("y", NewValue::Written(2.0)),
                ("sigma", NewValue::Written(0.5))
            ]
        )
        .unwrap(),
        0
    );
    assert!(
        e.text()
            .contains("marks = [ { x = 1.0, y = 2.0, sigma = 0.5 } ]"),
        "{}",
        e.text()
    );
    e.check().unwrap();
    // Not an array.
    let mut e = CaseEdit::new("r.toml", &text).unwrap();
    let err = e
        .push("scene.vehicle1.rest", &[("x", NewValue::Written(1.0))])
        .unwrap_err();
    assert!(
        err.to_string()
            .contains("scene.vehicle1.rest: is not an array"),
        "{err}"
    );
}
