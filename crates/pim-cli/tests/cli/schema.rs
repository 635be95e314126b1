//! Every document the command writes validates against its committed JSON Schema
//! (`docs/schema/`): every example by `solve`, `fit`, `sensitivity`, `runout` and `uncertainty`,
//! the RICSAC batch, a batch of case files (each JSON line), the damage batch and `predict-dv`.
use crate::common;
use common::*;

fn schema(file: &str) -> jsonschema::Validator {
    let text = std::fs::read_to_string(repo().join("docs/schema").join(file)).unwrap();
    let value: serde_json::Value = serde_json::from_str(&text).unwrap();
    jsonschema::validator_for(&value).unwrap_or_else(|e| panic!("{file}: {e}"))
}

fn check(validator: &jsonschema::Validator, what: &str, doc: &serde_json::Value) {
    let errors: Vec<String> = validator
        .iter_errors(doc)
        .take(5)
        .map(|e| format!("{} at {}", e, e.instance_path()))
        .collect();
    assert!(errors.is_empty(), "{what}: {errors:#?}");
}

fn document(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

fn examples() -> Vec<(String, bool)> {
    let mut v: Vec<(String, bool)> = std::fs::read_dir(repo().join("examples/cases"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            let scene = text.contains("[scene.");
            (
                format!(
                    "examples/cases/{}",
                    p.file_name().unwrap().to_string_lossy()
                ),
                scene,
            )
        })
        .collect();
    v.sort();
    v
}

#[test]
fn every_example_validates_by_every_command() {
    let (solve, sens, fit, rec, runout) = (
        schema("solve.schema.json"),
        schema("sensitivity.schema.json"),
        schema("fit.schema.json"),
        schema("reconstruction.schema.json"),
        schema("runout.schema.json"),
    );
    let (mut solved, mut studied, mut fitted, mut reconstructed, mut ran_out) = (0, 0, 0, 0, 0);
    for (case, scene) in examples() {
        let out = pim(&["solve", &case, "--format", "json"]);
        if out.status.success() {
            check(&solve, &format!("pim solve {case}"), &document(&out));
            solved += 1;
        }
        // The sensitivity study takes PIM's coefficients only.
        let out = pim(&["sensitivity", &case, "--format", "json"]);
        if out.status.success() {
            check(&sens, &format!("pim sensitivity {case}"), &document(&out));
            studied += 1;
        }
        let out = pim(&["fit", &case, "--format", "json"]);
        if out.status.success() {
            if scene {
                check(&rec, &format!("pim fit {case}"), &document(&out));
                reconstructed += 1;
            } else {
                check(&fit, &format!("pim fit {case}"), &document(&out));
                fitted += 1;
            }
        }
        let out = pim(&["runout", &case, "--format", "json"]);
        if out.status.success() {
            check(&runout, &format!("pim runout {case}"), &document(&out));
            ran_out += 1;
        }
    }
    // What the examples hold today: 10 solve, 8 take the sensitivity study, 6 fit, 2 are
    // scenes and 3 run out.
    assert!(solved >= 10, "solved {solved}");
    assert!(studied >= 8, "studied {studied}");
    assert!(fitted >= 6, "fitted {fitted}");
    assert!(reconstructed >= 2, "reconstructed {reconstructed}");
    assert!(ran_out >= 3, "ran out {ran_out}");
}

#[test]
fn uncertainty_studies_validate() {
    let out = pim_ok(&[
        "uncertainty",
        "examples/cases/ricsac7_uncertainty.toml",
        "--draws",
        "40",
        "--format",
        "json",
    ]);
    check(
        &schema("uncertainty.schema.json"),
        "impact study",
        &document(&out),
    );
    let out = pim_ok(&[
        "uncertainty",
        "examples/cases/reconstruction_us.toml",
        "--draws",
        "12",
        "--format",
        "json",
    ]);
    check(
        &schema("reconstruction-uncertainty.schema.json"),
        "reconstruction study",
        &document(&out),
    );
}

#[test]
fn batches_and_predictions_validate() {
    let out = pim_ok(&["batch", "data/ricsac.csv", "--format", "json"]);
    check(
        &schema("batch-data.schema.json"),
        "RICSAC batch",
        &document(&out),
    );
    let out = pim_ok(&["predict-dv", "data/ricsac.csv", "--format", "json"]);
    check(
        &schema("predict-dv.schema.json"),
        "predict-dv",
        &document(&out),
    );
    let dir = scratch_dir("schema", "damage");
    pim_ok(&[
        "batch",
        "data/ricsac.csv",
        "--damage",
        "data/ricsac_vehicles.csv",
        "--out",
        &dir.display().to_string(),
    ]);
    let damage: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("damage.json")).unwrap()).unwrap();
    check(&schema("damage-batch.schema.json"), "damage.json", &damage);
    let records: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("records.json")).unwrap()).unwrap();
    check(&schema("batch-data.schema.json"), "records.json", &records);

    let record = schema("batch-case-record.schema.json");
    let out = pim(&["batch", "examples/cases", "--format", "json"]);
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = 0;
    for line in text.lines() {
        let v: serde_json::Value = serde_json::from_str(line).unwrap();
        check(&record, &format!("record of {}", v["case"]), &v);
        lines += 1;
    }
    assert!(lines >= 15, "{lines} records");
}

#[test]
fn a_runout_with_its_wheels_validates() {
    let out = pim_ok(&[
        "runout",
        "examples/cases/runout_spin.toml",
        "--format",
        "json",
        "--wheels",
    ]);
    let doc = document(&out);
    check(&schema("runout.schema.json"), "runout --wheels", &doc);
    let first = &doc["vehicles"][0]["path"][0]["wheels"];
    assert_eq!(first.as_array().map(Vec::len), Some(4), "{first}");
}
