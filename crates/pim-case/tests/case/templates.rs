//! A case started from nothing and built section by section: each section written in the
//! case's own units with a comment per value, the text a valid case once the vehicles are in.
use pim_case::case::Case;
use pim_case::templates::{missing, new_case, with_section, SECTIONS};
use pim_case::units::UnitsSection;
use pim_core::Convention;

fn us() -> UnitsSection {
    toml::from_str(
        "speed = \"mph\"\nlength = \"ft\"\nmass = \"lb\"\nyaw_inertia = \"slug ft^2\"\nyaw_rate = \"deg/s\"",
    )
    .unwrap()
}

/// Every section added in turn to a new US case: each once, in feet, pounds and mph; the
/// whole a case that reads.
#[test]
fn a_case_is_built_from_nothing() {
    let mut text = new_case("Main and Oak", Convention::Sae, &us());
    assert!(text.starts_with("# SAE frame: x north, y east, headings clockwise.\ntitle = \"Main and Oak\"\nconvention = \"sae\"\n\n[units]\nspeed = \"mph\"\nlength = \"ft\""));
    assert_eq!(missing("new.toml", &text).unwrap().len(), SECTIONS.len());
    for s in SECTIONS {
        text = with_section("new.toml", &text, s.table).unwrap();
    }
    assert!(missing("new.toml", &text).unwrap().is_empty());
    assert!(text.contains("\n[vehicle1]\ndescription = \"vehicle 1\"  # what it is\nmass = 3310.0  # lb: with its occupants\n"), "{text}");
    assert!(
        text.contains("position = { x = -8.2, y = 0.0 }  # ft: its CG at contact\n"),
        "{text}"
    );
    assert!(
        text.contains("vehicle2 = { omega = 5.0 }  # deg/s\n"),
        "{text}"
    );
    assert!(
        text.contains(
            "edr = [ { speed = 29.1, time = 0.5, deceleration = 0.0, sigma = 1.57 } ]  # mph"
        ),
        "{text}"
    );
    let case = Case::from_text("new.toml", &text).unwrap();
    assert!((case.content.vehicle1.mass - 3310.0 * 0.45359237).abs() < 1e-9);
    std::fs::write(
        std::env::temp_dir().join("pim_built_from_nothing.toml"),
        &text,
    )
    .unwrap();
    // Added twice, or a name that is no section: refused.
    let e = with_section("new.toml", &text, "vehicle1")
        .unwrap_err()
        .to_string();
    assert_eq!(e, "new.toml: [vehicle1] is written already");
    let e = with_section("new.toml", &text, "vehicle3")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with(
            "new.toml: [vehicle3]: not a section that can be added (vehicle1, vehicle2, impact"
        ),
        "{e}"
    );
}

/// A section removed: a table, an entry of an array of tables, a nested table; every other
/// line kept; the top and [units] stay; a section not written is refused.
#[test]
fn a_section_is_removed_and_nothing_else() {
    use pim_case::templates::without_section;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text = std::fs::read_to_string(root.join("examples/cases/reconstruction_us.toml")).unwrap();
    for name in ["pre_impact.vehicle2", "observations.1", "scene.vehicle1"] {
        let out = without_section("r.toml", &text, name).unwrap();
        let edit = pim_case::edit::CaseEdit::new("r.toml", &out).unwrap();
        assert!(!edit.has(name), "{name}");
        // Every line of the result is a line of the original, in order.
        let mut lines = text.lines();
        for l in out.lines() {
            assert!(lines.any(|o| o == l), "{name}: {l:?} is new");
        }
    }
    let out = without_section("r.toml", &text, "observations.0").unwrap();
    assert_eq!(
        out.matches("[[observations]]").count(),
        text.matches("[[observations]]").count() - 1
    );
    for name in ["", "units"] {
        assert!(without_section("r.toml", &text, name).is_err());
    }
    let e = without_section("r.toml", &text, "pre_impact.vehicle3")
        .unwrap_err()
        .to_string();
    assert_eq!(
        e,
        "r.toml: [pre_impact.vehicle3]: the file writes no such section"
    );
}
