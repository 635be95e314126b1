//! The case as forms: a section per table the file writes, a field per value (inline tables
//! and arrays of them flattened by key and index), the comment after a value as its help; a
//! field set from the page changes its value and nothing else.

use crate::{changed_lines, example};
use pim_serve::{form, set_field, AnswerError, FieldValue};

/// `text` with the field `key` set to `value` as typed in the page.
fn set_typed(file: &str, text: &str, key: &str, value: &str) -> Result<String, AnswerError> {
    set_field(file, text, key, &FieldValue::Typed(value.into()))
}

#[test]
fn every_section_and_value_of_the_example_is_a_field() {
    let text = example("reconstruction_us.toml");
    let sections = form("r.toml", &text).unwrap();
    let names: Vec<&str> = sections.iter().map(|s| s.name.as_str()).collect();
    for want in [
        "",
        "units",
        "vehicle1",
        "vehicle2",
        "impact",
        "estimates.initial",
        "observations.0",
        "observations.1",
        "pre_impact.vehicle1",
        "runout",
        "runout.vehicle1",
        "scene.vehicle2",
    ] {
        assert!(names.contains(&want), "{want} not in {names:?}");
    }
    let field = |key: &str| {
        sections
            .iter()
            .flat_map(|s| &s.fields)
            .find(|f| f.key == key)
            .unwrap_or_else(|| panic!("{key}"))
    };
    let mass = field("vehicle1.mass");
    assert_eq!((mass.kind, mass.value.as_str()), ("number", "3400.0"));
    assert_eq!(mass.comment.as_deref(), Some("lb, with driver"));
    assert_eq!(field("vehicle1.position.x").value, "-7.5");
    assert_eq!(field("observations.0.vehicle").kind, "integer");
    assert_eq!(field("runout.vehicle1.wheels.front_left").value, "locked");
    assert_eq!(field("scene.vehicle2.marks.0.sigma").value, "0.5");
    assert_eq!(field("convention").kind, "text");
    assert_eq!(field("pre_impact.vehicle2.edr.0.speed").value, "27.5");
    // Every field's key is one the file writes: setting it to its own value keeps the file.
    let every: usize = sections.iter().map(|s| s.fields.len()).sum();
    assert!(every > 60, "{every} fields");
}

#[test]
fn a_field_set_changes_its_value_only() {
    let text = example("reconstruction_us.toml");
    let changed = |new: &str| -> Vec<String> {
        changed_lines(new, &text)
            .into_iter()
            .map(str::to_string)
            .collect()
    };
    let t = set_typed("r.toml", &text, "vehicle1.mass", "3500").unwrap();
    assert_eq!(
        changed(&t),
        ["mass = 3500.0                       # lb, with driver"]
    );
    let t = set_typed("r.toml", &text, "observations.0.vehicle", "2").unwrap();
    assert_eq!(changed(&t), ["vehicle = 2"]);
    let t = set_typed("r.toml", &text, "runout.vehicle2.wheels", "locked").unwrap();
    assert_eq!(changed(&t), ["wheels = \"locked\""]);
    let t = set_typed("r.toml", &text, "scene.vehicle2.marks.0.x", "33.0").unwrap();
    assert_eq!(
        changed(&t),
        ["marks = [ { x = 33.0, y = 48.2, sigma = 0.5 } ]"]
    );
    // Refused: a number that is none, a key the file does not write, a whole number with a
    // fraction.
    let e = |key: &str, v: &str| set_typed("r.toml", &text, key, v).unwrap_err().to_string();
    assert!(e("vehicle1.mass", "heavy").contains("vehicle1.mass: \"heavy\" is not a number"));
    assert!(e("vehicle1.colour", "red").contains("the file writes no such value"));
    assert!(e("observations.0.vehicle", "1.5").contains("not a whole number"));
}

/// The pose at contact's priors (`[contact_sigma]`) are a form like any section: a deviation set
/// from the page writes its value only, and the page's answer fits the pose with it (the
/// prior's deviation in the answer's rows, the answer as `pim fit` gives it for the text).
#[test]
fn the_priors_of_the_pose_at_contact_are_a_form() {
    let text = example("reconstruction_pose_us.toml");
    let sections = form("p.toml", &text).unwrap();
    let fields: Vec<(&str, &str)> = sections
        .iter()
        .filter(|s| s.name == "contact_sigma")
        .flat_map(|s| &s.fields)
        .map(|f| (f.key.as_str(), f.value.as_str()))
        .collect();
    assert_eq!(
        fields,
        [
            ("contact_sigma.vehicle1.heading", "3.0"),
            ("contact_sigma.vehicle1.position.x", "1.0"),
            ("contact_sigma.vehicle1.position.y", "1.0"),
            ("contact_sigma.vehicle2.heading", "3.0"),
            ("contact_sigma.vehicle2.impact_point.x", "0.8"),
        ]
    );
    let t = set_typed(
        "p.toml",
        &text,
        "contact_sigma.vehicle2.impact_point.x",
        "0.3",
    )
    .unwrap();
    assert_eq!(
        changed_lines(&t, &text),
        ["vehicle2 = { heading = 3.0, impact_point = { x = 0.3 } }   # along its side, from the crush"]
    );
    let prior = |text: &str| {
        let a = pim_serve::answer("p.toml", text).unwrap();
        let rows = a.document["best"]["contact_pose"]
            .as_array()
            .unwrap()
            .clone();
        let row = rows
            .iter()
            .find(|r| r["name"] == "vehicle2.impact_point.x")
            .unwrap()
            .clone();
        (
            row["prior_sigma"].as_f64().unwrap(),
            row["sigma"].as_f64().unwrap(),
        )
    };
    let (before, fitted_before) = prior(&text);
    let (after, fitted_after) = prior(&t);
    assert!((before - 0.8 * 0.3048).abs() < 1e-9, "{before}");
    assert!((after - 0.3 * 0.3048).abs() < 1e-9, "{after}");
    // A tighter prior: the impact point is known better after the fit too.
    assert!(
        fitted_after < fitted_before,
        "{fitted_after} {fitted_before}"
    );
    // Switched off on the page (as the consistency table leaves it out): the value is still
    // fitted, its prior is no row of the evidence, and the chi-square does not rise.
    let name = "vehicle2.impact_point.x at contact (prior)";
    let chi = |d: &serde_json::Value| d["best"]["chi_square"].as_f64().unwrap();
    let on = pim_serve::answer("p.toml", &t).unwrap();
    assert!(on.pieces.iter().any(|p| p.name == name));
    let (off, _) =
        pim_serve::answer_without("p.toml", &t, None, None, &[name.to_string()]).unwrap();
    let evidence = off.document["best"]["evidence"].as_array().unwrap();
    assert!(evidence.iter().all(|e| e["name"] != name), "{evidence:?}");
    let rows = off.document["best"]["contact_pose"].as_array().unwrap();
    assert!(rows.iter().any(|r| r["name"] == "vehicle2.impact_point.x"));
    assert!(chi(&off.document) <= chi(&on.document) + 1e-9);
    let dof = |d: &serde_json::Value| d["best"]["degrees_of_freedom"].as_u64().unwrap();
    assert_eq!(dof(&off.document) + 1, dof(&on.document));
}

/// A vehicle that writes its length and width has a yaw inertia field whatever the file says:
/// not written, it is offered empty with the case's estimate as its help; typed, the value is
/// written after the mass; emptied again, it is removed and the estimate comes back.
#[test]
fn a_yaw_inertia_not_given_is_offered_with_its_estimate() {
    let text = example("reconstruction_us.toml");
    let line = "yaw_inertia = 1900.0                # slug ft^2\n";
    assert!(text.contains(line));
    let without = text.replacen(line, "", 1);
    let field = |text: &str, key: &str| {
        form("r.toml", text)
            .unwrap()
            .into_iter()
            .flat_map(|s| s.fields)
            .find(|f| f.key == key)
    };
    let offered = field(&without, "vehicle1.yaw_inertia").expect("offered");
    assert_eq!((offered.kind, offered.value.as_str()), ("number", ""));
    assert!(offered.optional);
    assert!(
        offered
            .comment
            .as_deref()
            .unwrap()
            .starts_with("estimated as 2314 slug ft^2 from mass 3400 lb"),
        "{:?}",
        offered.comment
    );
    // Written (at the end of its section), then removed by an empty value.
    let typed = set_typed("r.toml", &without, "vehicle1.yaw_inertia", "1900").unwrap();
    assert_eq!(typed.replacen("yaw_inertia = 1900.0\n", "", 1), without);
    let written = field(&typed, "vehicle1.yaw_inertia").unwrap();
    assert_eq!(written.value, "1900.0");
    assert!(written.optional);
    let emptied = set_typed("r.toml", &typed, "vehicle1.yaw_inertia", " ").unwrap();
    assert_eq!(emptied, without);
    // A written inertia emptied goes back to the estimate too; vehicle 2 keeps its own.
    let back = set_typed("r.toml", &text, "vehicle1.yaw_inertia", "").unwrap();
    assert_eq!(back, without);
    assert_eq!(
        field(&text, "vehicle2.yaw_inertia").unwrap().value,
        "2400.0"
    );
    // A field that is not optional is not removed by an empty value.
    assert!(set_typed("r.toml", &text, "vehicle1.mass", "").is_err());
}
