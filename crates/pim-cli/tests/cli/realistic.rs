//! A reconstructionist's own case (a police-style brief: a sedan locked, an SUV rolling with
//! its right front wheel jammed by the crush, an EDR, a skid, a post-impact mark, total-station
//! rests), answered where it once was refused: `main_oak.toml` with no count of turns stated,
//! and two variants whose vehicle 2 at contact differs by 0.1 ft (`main_oak_turns_a.toml` and
//! `_b.toml`), which must answer alike.
use crate::common;
use common::*;

fn case(name: &str) -> String {
    repo()
        .join("crates/pim-cli/tests/cases")
        .join(name)
        .display()
        .to_string()
}

fn fit(name: &str) -> (Option<i32>, serde_json::Value) {
    let out = pim(&["fit", &case(name), "--format", "json"]);
    let doc = serde_json::from_slice(&out.stdout).unwrap_or(serde_json::Value::Null);
    (out.status.code(), doc)
}

fn chi_square(doc: &serde_json::Value) -> f64 {
    doc["best"]["chi_square"].as_f64().unwrap()
}

fn speeds(doc: &serde_json::Value) -> [f64; 2] {
    let v = doc["best"]["vehicles"].as_array().unwrap();
    [0, 1].map(|k| v[k]["speed_at_contact"].as_f64().unwrap() / 0.44704)
}

/// No count of turns stated: the combination of no full turn for either car was once set
/// aside after one step (its first point, at a chi-square of 5,530, far from what the scenes'
/// linearisation predicted) and a sedan spinning -328 deg in 10 ft answered at 115.9, refused.
/// Refined on from where the impact put it, it answers at 6.11 (4 degrees of freedom).
#[test]
fn the_case_without_turns_answers() {
    let (code, doc) = fit("main_oak.toml");
    assert_eq!(code, Some(0), "{doc}");
    let c = chi_square(&doc);
    assert!(c <= 6.2, "chi-square {c}");
    assert_eq!(doc["status"], "found");
    let [s1, s2] = speeds(&doc);
    assert!(
        (s1 - 31.4).abs() < 0.5 && (s2 - 30.4).abs() < 0.5,
        "{s1} {s2}"
    );
}

/// 0.1 ft apart at contact: once 31.2 against 5,977 (vehicle 2's rest missed by 37 ft). The
/// refused one is searched again by continuation (the scene's standard deviations widened and
/// narrowed back): both answer within a chi-square of 1, their speeds within 0.5 mph.
#[test]
fn a_tenth_of_a_foot_changes_the_answer_a_little() {
    let (code_a, a) = fit("main_oak_turns_a.toml");
    let (code_b, b) = fit("main_oak_turns_b.toml");
    assert_eq!((code_a, code_b), (Some(0), Some(0)), "{a}\n{b}");
    let (ca, cb) = (chi_square(&a), chi_square(&b));
    assert!((ca - cb).abs() < 1.0, "{ca} {cb}");
    let (sa, sb) = (speeds(&a), speeds(&b));
    for k in 0..2 {
        assert!((sa[k] - sb[k]).abs() < 0.5, "{sa:?} {sb:?}");
    }
}
