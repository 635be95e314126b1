//! Fitting the second model through the command line: `pim fit --model tangential` and
//! `pim batch --model pim,tangential`.
use crate::common;
use common::*;
use serde_json::Value;

const CASE: &str = "examples/cases/ricsac7_fit.toml";

fn json(out: &std::process::Output) -> Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The fit's answer is the model's own: `pim solve` with the fitted coefficients from the fitted
/// contact velocities gives the fitted separation velocities. Its cost is never above PIM's zero
/// branch, which is the model's special case (et and friction reproduce any admissible PIM
/// answer without a moment impulse).
#[test]
fn fit_tangential_is_the_models_own_answer() {
    let out = pim_ok(&[
        "fit",
        CASE,
        "--cost",
        "q2",
        "--model",
        "tangential",
        "--format",
        "json",
    ]);
    let v = json(&out);
    assert_eq!(v["model"], "tangential");
    let branches = v["branches"].as_array().unwrap();
    assert_eq!(branches.len(), 1);
    let b = &branches[0];
    assert_eq!(b["moment"], "zero");
    assert_eq!(b["status"], "optimal");
    let t = &b["tangential"];
    let (e, et) = (num(&b["e"]), num(&t["et"]));
    let friction = num(&t["friction_max"]);
    assert!((0.0..=0.2).contains(&e) && (-1.0..=1.0).contains(&et));
    let names: Vec<&str> = b["identifiability"]
        .as_array()
        .unwrap()
        .iter()
        .map(|i| i["coefficient"].as_str().unwrap())
        .collect();
    assert_eq!(names, ["e", "et", "friction", "speed1", "speed2"]);

    // The model solved forwards from the fitted contact state.
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap();
    let head = &text[..text.find("[estimates.initial]").unwrap()];
    let state = |s: &Value, k: &str| {
        format!(
            "vehicle{k} = {{ vx = {}, vy = {}, omega = {} }}\n",
            num(&s[format!("vehicle{k}")]["vx"]),
            num(&s[format!("vehicle{k}")]["vy"]),
            num(&s[format!("vehicle{k}")]["omega"])
        )
    };
    let case = format!(
        "{head}[coefficients]\ne = {e}\net = {et}\nfriction = {friction}\n\n[initial]\n{}{}",
        state(&b["initial"], "1"),
        state(&b["initial"], "2")
    );
    let path = scratch_file("tangential_fit", "forward.toml", case);
    let s = json(&pim_ok(&["solve", &path, "--format", "json"]));
    for k in ["vehicle1", "vehicle2"] {
        for c in ["vx", "vy", "omega"] {
            let (a, f) = (num(&s["final"][k][c]), num(&b["final"][k][c]));
            assert!((a - f).abs() < 1e-6, "{k}.{c}: solve {a} fit {f}");
        }
    }

    let pim = json(&pim_ok(&[
        "fit", CASE, "--cost", "q2", "--branch", "zero", "--format", "json",
    ]));
    let pim_cost = num(&pim["branches"][0]["cost"]);
    let cost = num(&b["cost"]);
    assert!(
        cost <= pim_cost * (1.0 + 1e-6),
        "{cost} > PIM zero {pim_cost}"
    );

    let table =
        String::from_utf8(pim_ok(&["fit", CASE, "--cost", "q2", "--model", "tangential"]).stdout)
            .unwrap();
    assert!(table.contains("tangential model ("), "{table}");
    let dir = scratch_dir("tangential_fit", "out");
    let d = dir.display().to_string();
    pim_ok(&[
        "fit",
        CASE,
        "--cost",
        "q2",
        "--model",
        "tangential",
        "--out",
        &d,
    ]);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(
        md.contains("| status | mode | e | et | friction limit | cost | energy lost [%] |"),
        "{md}"
    );
    assert!(dir.join("diagram.svg").is_file());
    assert!(
        table.contains("friction = ") || table.contains("et = "),
        "{table}"
    );
}

/// Both models over two RICSAC tests: records of each model, the side-by-side table and figure,
/// and the tangential model never worse than PIM's zero branch.
#[test]
fn batch_compares_the_models() {
    let dir = scratch_dir("tangential_fit", "batch");
    let d = dir.display().to_string();
    let out = pim_ok(&[
        "batch",
        "--model",
        "pim,tangential",
        "--cost",
        "q2",
        "--tests",
        "7,9",
        "--format",
        "json",
        "--out",
        &d,
    ]);
    let v = json(&out);
    let records = v["records"].as_array().unwrap();
    // Two PIM branches and one tangential record per test.
    assert_eq!(records.len(), 6);
    for t in [7, 9] {
        let of = |model: &str, branch: &str| {
            records
                .iter()
                .find(|r| r["test"] == t && r["model"] == model && r["moment_branch"] == branch)
                .unwrap_or_else(|| panic!("test {t} {model} {branch}"))
        };
        let tangential = of("tangential", "zero");
        assert_eq!(tangential["best"], true);
        assert!(tangential["tangential"].is_object());
        let zero = num(&of("pim", "zero")["cost"]);
        let cost = num(&tangential["cost"]);
        assert!(cost <= zero * (1.0 + 1e-6), "test {t}: {cost} > {zero}");
    }
    let models = std::fs::read_to_string(dir.join("models.txt")).unwrap();
    assert!(models.contains("The two models side by side"), "{models}");
    let svg = std::fs::read_to_string(dir.join("models.svg")).unwrap();
    assert!(svg.contains("Q2 tangential") && svg.contains("Q2 pim"));
    let csv = std::fs::read_to_string(dir.join("records.csv")).unwrap();
    assert!(csv.starts_with("test,cost_function,model,branch"), "{csv}");
    assert!(csv.lines().nth(1).unwrap().contains(",pim,"));
}

#[test]
fn bad_models_and_bounds_say_why() {
    let out = pim(&["batch", CASE, "--model", "tangential"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("--model compares the models over a data file"));
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap().replace(
        "mu = [-1.2, 1.2]",
        "mu = [-1.2, 1.2]\nfriction = [0.8, 0.2]",
    );
    // A friction box the data want to leave: the answer ends on its bound, and the user is told.
    let narrow = text.replace("friction = [0.8, 0.2]", "friction = [0.0, 0.05]");
    let path = scratch_file("tangential_fit", "narrow.toml", narrow);
    let out = pim_ok(&["fit", &path, "--cost", "q2", "--model", "tangential"]);
    assert!(
        stderr(&out).contains(
            "the tangential model's fit ends on a bound: friction limit at its upper bound; \
             widen [bounds] friction"
        ),
        "{}",
        stderr(&out)
    );
    let path = scratch_file("tangential_fit", "bad_bounds.toml", text);
    let out = pim(&["fit", &path, "--cost", "q2", "--model", "tangential"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("friction = [0.8, 0.2] must satisfy 0 <= low <= high <= 100"),
        "{}",
        stderr(&out)
    );
}
