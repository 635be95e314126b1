//! `pim edr`: an EDR's pre-crash table imported into a case (its rows and the one record they
//! give); refused at the table's line with the file left as it was; and the speeds before
//! contact drawn beside it by `pim fit --out` (speed_history.svg, in report.md and
//! report.html), for a vehicle with an EDR only.
use crate::common;
use common::*;

const CASE: &str = "examples/cases/reconstruction_us.toml";
const TABLE: &str = "examples/scene/suv_precrash.txt";
const MPH: f64 = 0.44704;

fn scratch_case(name: &str, text: &str) -> String {
    scratch_file("edr", name, text)
}

#[test]
fn a_table_is_imported_and_drawn_beside_the_answer() {
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap();
    let case = scratch_case("imported.toml", &text);
    let out = pim(&["edr", &case, TABLE, "--vehicle", "2", "--unit", "km/h"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(stderr(&out).contains("[pre_impact.vehicle2] edr_history from"));
    let written = std::fs::read_to_string(&case).unwrap();
    assert!(
        written.contains("  { speed = 27.34, time = 0.5, deceleration = 0.0, sigma = 1.01 },\n")
    );
    assert_eq!(written.matches("brake = false").count(), 5);

    let dir = scratch_dir("edr", "out");
    let out = pim(&[
        "fit",
        &case,
        "--out",
        dir.to_str().unwrap(),
        "--format",
        "json",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let svg = std::fs::read_to_string(dir.join("speed_history.svg")).unwrap();
    assert!(svg.contains("vehicle 2: speed before contact"));
    assert!(
        !svg.contains("vehicle 1: speed before contact"),
        "no EDR for vehicle 1"
    );
    // The five rows (open: brake off) and the answer's dot at contact.
    assert_eq!(svg.matches("<circle").count(), 6);
    assert!(std::fs::read_to_string(dir.join("report.md"))
        .unwrap()
        .contains("](speed_history.svg)"));
    assert!(std::fs::read_to_string(dir.join("report.html"))
        .unwrap()
        .contains("<h2>The speeds before contact: the answer and the EDR</h2>"));
    // The record is the evidence: its residual is the answer's speed at contact less 27.34
    // mph (no deceleration), as the figure draws it; the residual is of the speed along the
    // heading, the figure's of the speed, which differ by the side slip's cosine (1e-3 m/s).
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap();
    let best = &doc["best"];
    let v2 = best["vehicles"][1]["speed_at_contact"].as_f64().unwrap();
    let row = best["evidence"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["source"]["kind"] == "edr")
        .expect("the EDR's row");
    let residual = row["residual"].as_f64().unwrap();
    assert!(
        (residual - (v2 - 27.34 * MPH)).abs() < 1e-3,
        "{residual} vs {}",
        v2 - 27.34 * MPH
    );
}

#[test]
fn a_bad_table_is_refused_at_its_line_and_the_file_kept() {
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap();
    let case = scratch_case("kept.toml", &text);
    let table = scratch_file("edr", "bad.txt", "-1.0 30 off\n-0.5 30 maybe\n");
    let out = pim(&["edr", &case, &table, "--vehicle", "1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("bad.txt:2: brake: expected on or off, got \"maybe\""),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read_to_string(&case).unwrap(), text);
    // --no-record keeps the case's own record; a vehicle 3 is refused by the parser.
    let out = pim(&[
        "edr",
        &case,
        TABLE,
        "--vehicle",
        "2",
        "--no-record",
        "--dry-run",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(String::from_utf8_lossy(&out.stdout)
        .contains("edr = [ { speed = 27.5, time = 0.5, deceleration = 0.0, sigma = 1.5 } ]"));
    assert_eq!(
        pim(&["edr", &case, TABLE, "--vehicle", "3"]).status.code(),
        Some(2)
    );
}

#[test]
fn a_case_without_an_edr_has_no_speed_figure() {
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap();
    let line = "edr = [ { speed = 27.5, time = 0.5, deceleration = 0.0, sigma = 1.5 } ]   # mph, s before contact, g, mph\n";
    assert!(text.contains(line));
    let case = scratch_case("none.toml", &text.replacen(line, "", 1));
    let dir = scratch_dir("edr", "none");
    let out = pim(&["fit", &case, "--out", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    assert!(dir.join("scene.svg").exists());
    assert!(!dir.join("speed_history.svg").exists());
}
