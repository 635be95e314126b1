//! A survey imported from the page, drawn on the plan, and evidence dropped on its points:
//! written at the point's own coordinates with its id kept, the id dropped when the evidence
//! is moved off it again.
use crate::{changed_lines, example};
use pim_case::survey::Import;
use pim_case::units::{LengthUnit, UnitSystem};
use pim_serve::{import_survey, ContactChange, NewMark, SurveyImport};

const FILE: &str = "reconstruction_us.toml";
/// A survey in metres from a hydrant (point 1), its x along the case's north.
const CSV: &str = "id,x,y,code,description\n\
                   1,100.000,200.000,HYD,hydrant\n\
                   2,103.627,200.884,REST,SUV rest\n\
                   3,100.000,203.048,POI,gouge\n";

fn surveyed() -> String {
    let import = SurveyImport {
        csv: CSV.into(),
        source: Some("scene.csv".into()),
        placing: Import {
            unit: Some(LengthUnit::Metre),
            origin: Some("1".into()),
            rotation: 0.0,
        },
    };
    import_survey(FILE, &example(FILE), &import).unwrap()
}

/// The points are placed in the case's feet and SAE frame from the hydrant, written at the end
/// of the file, and drawn on the page where the frame puts them (an SAE plan is a map: x up).
#[test]
fn a_survey_is_imported_and_drawn() {
    let text = surveyed();
    let tail = text.split("[survey]").nth(1).unwrap();
    assert_eq!(
        tail,
        "\nsource = \"scene.csv\"\npoints = [\n  \
         { id = \"1\", x = 0.0, y = 0.0, code = \"HYD\", description = \"hydrant\" },\n  \
         { id = \"2\", x = 11.9, y = 2.9, code = \"REST\", description = \"SUV rest\" },\n  \
         { id = \"3\", x = 0.0, y = 10.0, code = \"POI\", description = \"gouge\" },\n]\n"
    );
    assert!(text.starts_with(example(FILE).trim_end()));
    let a = pim_serve::answer(FILE, &text).unwrap();
    let s = &a.plan.survey;
    assert_eq!(s.len(), 3);
    assert_eq!((s[1].id.as_str(), s[1].at), ("2", [2.9, 11.9]));
    assert_eq!(s[2].code.as_deref(), Some("POI"));
    // In metres on the page.
    let si = pim_serve::answer_in(FILE, &text, None, Some(UnitSystem::Si))
        .unwrap()
        .0;
    assert!((si.plan.survey[1].at[1] - 3.627).abs() < 1e-3);
    // A bad line is refused naming the CSV's line.
    let bad = SurveyImport {
        csv: "id,x,y\n1,2,x\n".into(),
        source: Some("scene.csv".into()),
        placing: Import::default(),
    };
    let e = import_survey(FILE, &example(FILE), &bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("scene.csv:2: y: expected a number"), "{e}");
}

/// A rest and a mark dropped on survey points are written at the points' coordinates with
/// their ids; moved off, the id goes; the impact centre too. A mark clicked on a point is
/// added there.
#[test]
fn evidence_dropped_on_a_survey_point_keeps_its_id() {
    let text = surveyed();
    let on = pim_serve::move_onto(FILE, &text, (1, None), ([0.0, 0.0], Some("2")), None).unwrap();
    assert_eq!(
        changed_lines(&on, &text),
        ["rest = { x = 11.9, y = 2.9, heading = 144.0, point = \"2\" }     # ft, ft, deg clockwise"]
    );
    let off = pim_serve::move_onto(FILE, &on, (1, None), ([3.0, 12.0], None), None).unwrap();
    assert_eq!(
        changed_lines(&off, &text),
        ["rest = { x = 12.0, y = 3.0, heading = 144.0 }     # ft, ft, deg clockwise"]
    );
    let mark =
        pim_serve::move_onto(FILE, &text, (2, Some(0)), ([0.0, 0.0], Some("3")), None).unwrap();
    assert_eq!(
        changed_lines(&mark, &text),
        ["marks = [ { x = 0.0, y = 10.0, sigma = 0.5, point = \"3\" } ]"]
    );
    let added = pim_serve::add_mark(
        FILE,
        &text,
        &NewMark {
            vehicle: 1,
            at: [0.0, 0.0],
            sigma: 0.5,
            wheel: Some("front_right".into()),
            point: Some("3".into()),
        },
        None,
    )
    .unwrap();
    assert!(added
        .contains("{ x = 0.0, y = 10.0, sigma = 0.5, wheel = \"front_right\", point = \"3\" }"));
    // The centre dropped on the gouge (0, 10): the vehicles' CGs stay, and their impact points
    // follow; moved off it, the id goes.
    let change = ContactChange {
        centre: Some([10.0, 0.0]),
        point: Some("3".into()),
        ..ContactChange::default()
    };
    let centre = pim_serve::edit_contact(FILE, &text, &change, None).unwrap();
    assert_eq!(
        changed_lines(&centre, &text),
        ["centre = { x = 0.0, y = 10.0, point = \"3\" }       # the impact area is the diagram's origin"]
    );
    let moved = ContactChange {
        centre: Some([10.0, 1.0]),
        ..ContactChange::default()
    };
    let away = pim_serve::edit_contact(FILE, &centre, &moved, None).unwrap();
    assert!(away.contains("centre = { x = 1.0, y = 10.0 }"), "{away}");
    // A point the survey does not have is refused.
    let e = pim_serve::move_onto(FILE, &text, (1, None), ([0.0, 0.0], Some("9")), None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("the survey has no point \"9\""), "{e}");
}
