//! `[survey]`: a survey's CSV placed in the case (unit, origin, turn), written into the text
//! with every other byte kept, and evidence that names a survey point checked to lie on it.
use pim_case::case::Case;
use pim_case::survey::{read_csv, with_survey, Placing, SurveyPoint};
use pim_core::Convention;
use std::path::Path;

fn example() -> (String, String) {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases/reconstruction_us.toml");
    (
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    )
}

const CSV: &str = "\
point,x,y,code,description
100,5000.00,2000.00,HYD,fire hydrant
101,5010.00,2000.00,LF,sedan left front
102,5000.00,2020.50,,
";

fn placing(origin: Option<&str>, rotation: f64, convention: Convention) -> Placing {
    Placing {
        scale: 1.0,
        origin: origin.map(str::to_string),
        rotation,
        convention,
    }
}

/// A header names the columns; the origin point goes to (0, 0); a quarter turn
/// counter-clockwise on the plan turns +x to +y in a natural frame and to -y in an SAE one
/// (its plan is the map, x up); the scale converts the unit.
#[test]
fn a_survey_is_placed_by_its_origin_turn_and_unit() {
    let p = read_csv(
        "s.csv",
        CSV,
        &placing(Some("100"), 0.0, Convention::Natural),
    )
    .unwrap();
    assert_eq!(p.len(), 3);
    assert_eq!((p[0].x, p[0].y), (0.0, 0.0));
    assert_eq!((p[1].x, p[1].y), (10.0, 0.0));
    assert_eq!((p[2].x, p[2].y), (0.0, 20.5));
    assert_eq!(p[0].code.as_deref(), Some("HYD"));
    assert_eq!(p[0].description.as_deref(), Some("fire hydrant"));
    assert_eq!((p[2].code.clone(), p[2].description.clone()), (None, None));
    let turned = read_csv(
        "s.csv",
        CSV,
        &placing(Some("100"), 90.0, Convention::Natural),
    )
    .unwrap();
    assert_eq!((turned[1].x, turned[1].y), (0.0, 10.0));
    let sae = read_csv("s.csv", CSV, &placing(Some("100"), 90.0, Convention::Sae)).unwrap();
    assert_eq!((sae[1].x, sae[1].y), (0.0, -10.0));
    let metres = Placing {
        scale: 0.3048,
        ..placing(Some("100"), 0.0, Convention::Natural)
    };
    let m = read_csv("s.csv", CSV, &metres).unwrap();
    assert_eq!((m[1].x, m[2].y), (3.048, 6.248));
    // No header: id, x, y in that order; no origin: the survey's own.
    let bare = read_csv(
        "s.csv",
        "A,1.5,2.25\nB,3,4",
        &placing(None, 0.0, Convention::Natural),
    )
    .unwrap();
    assert_eq!(
        bare[1],
        SurveyPoint {
            id: "B".into(),
            x: 3.0,
            y: 4.0,
            code: None,
            description: None
        }
    );
}

/// A bad line is refused naming the file, the line and the column.
#[test]
fn a_bad_survey_line_is_refused_at_its_line() {
    let flat = placing(None, 0.0, Convention::Natural);
    let cases = [
        (
            "id,x,y\nA,1,2\nB,one,2\n",
            "s.csv:3: x: expected a number, got \"one\"",
        ),
        (
            "id,x,y\nA,1,2\nA,3,4\n",
            "s.csv:3: id: \"A\" is given twice (first on line 2)",
        ),
        ("id,x,y\n,1,2\n", "s.csv:2: id: every point needs its id"),
        (
            "name,east,north\nA,1,2\n",
            "s.csv:1: the header has no column \"x\"",
        ),
        ("id,x,y\n", "s.csv: no points"),
    ];
    for (text, expected) in cases {
        let e = read_csv("s.csv", text, &flat).unwrap_err().to_string();
        assert!(
            e.starts_with(expected),
            "{e:?} does not start with {expected:?}"
        );
    }
    let e = read_csv("s.csv", CSV, &placing(Some("9"), 0.0, Convention::Natural))
        .unwrap_err()
        .to_string();
    assert_eq!(e, "s.csv: origin: the survey has no point \"9\"");
}

/// The survey is written at the end with every other byte kept, replaced when imported again;
/// a mark that names a point must lie on it, and one the survey no longer has is refused at
/// its line.
#[test]
fn evidence_on_a_survey_point_is_checked_against_it() {
    let (file, text) = example();
    let points = read_csv("s.csv", CSV, &placing(Some("100"), 0.0, Convention::Sae)).unwrap();
    let with = with_survey(&file, &text, Some("s.csv"), &points).unwrap();
    assert!(with.starts_with(text.trim_end()));
    assert!(with.contains("[survey]\nsource = \"s.csv\"\npoints = [\n  { id = \"100\", x = 0.0, y = 0.0, code = \"HYD\", description = \"fire hydrant\" },\n"));
    let case = Case::from_text(&file, &with).unwrap();
    assert_eq!(case.content.survey.unwrap().points, points);
    // Imported again: one [survey], the new one.
    let again = with_survey(&file, &with, None, &points[..1]).unwrap();
    assert_eq!(again.matches("[survey]").count(), 1);
    assert!(!again.contains("source"));

    // Vehicle 1's mark placed on point 101 (10, 0).
    let on = with.replace(
        "marks = [ { x = 10.6, y = 2.7, sigma = 0.5 } ]",
        "marks = [ { x = 10.0, y = 0.0, sigma = 0.5, point = \"101\" } ]",
    );
    assert_ne!(on, with);
    let case = Case::from_text(&file, &on).unwrap();
    let marks = &case.content.scene.unwrap().vehicle1.unwrap().marks;
    assert_eq!(marks[0].point.as_deref(), Some("101"));
    let off = on.replace("x = 10.0, y = 0.0, sigma", "x = 10.2, y = 0.0, sigma");
    let e = Case::from_text(&file, &off).unwrap_err().to_string();
    assert!(
        e.contains(":97:")
            && e.contains("scene.vehicle1.marks.0.point")
            && e.contains("survey point \"101\" is at (10, 0), this at (10.2, 0)"),
        "{e}"
    );
    let gone = with_survey(&file, &on, None, &points[..1]).unwrap();
    let e = Case::from_text(&file, &gone).unwrap_err().to_string();
    assert!(e.contains("\"101\": [survey] has no such point"), "{e}");
    let none = on.split("[survey]").next().unwrap().to_string();
    let e = Case::from_text(&file, &none).unwrap_err().to_string();
    assert!(e.contains("\"101\": the case has no [survey]"), "{e}");
}
