//! End-to-end tests of `pim uncertainty`: the schema, and bit-identical results for any thread
//! count.
use crate::common;
use common::*;

/// A fresh scratch directory for one test.
fn scratch(name: &str) -> std::path::PathBuf {
    scratch_dir("cli_uncertainty", name)
}
use serde_json::Value;

const CASE: &str = "examples/cases/ricsac7_uncertainty.toml";

#[test]
fn same_answer_for_any_thread_count_and_the_documented_schema() {
    let run = |threads: &str| {
        let out = pim_ok(&[
            "uncertainty",
            CASE,
            "--cost",
            "q2",
            "--draws",
            "120",
            "--seed",
            "5",
            "--threads",
            threads,
            "--format",
            "json",
        ]);
        out.stdout
    };
    let one = run("1");
    assert_eq!(one, run("2"), "threads 1 and 2 differ");
    let j: Value = serde_json::from_slice(&one).unwrap();
    assert_eq!(j["draws"], 120);
    assert_eq!(j["seed"], 5);
    assert!(j["feasible_draws"].as_u64().unwrap() >= 110);
    for q in [
        "e",
        "mu",
        "em",
        "speed1",
        "speed2",
        "delta_v1",
        "delta_v2",
        "energy_loss_percent",
    ] {
        let s = &j["quantities"][q];
        let (p05, p50, p95) = (
            s["p05"].as_f64().unwrap(),
            s["p50"].as_f64().unwrap(),
            s["p95"].as_f64().unwrap(),
        );
        assert!(p05 <= p50 && p50 <= p95, "{q}: {s}");
        assert!(s["sd"].as_f64().unwrap() >= 0.0);
        assert!(j["nominal"][q].is_number(), "{q}");
    }
    let shares: f64 = j["branch_share"]
        .as_object()
        .unwrap()
        .values()
        .map(|v| v.as_f64().unwrap())
        .sum();
    assert!((shares - 1.0).abs() < 1e-12);
    // Under Q2 the contact speeds follow their own estimates: speed1 is dominated by the
    // estimate of vehicle 1's vx.
    let s1 = j["sensitivity"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["quantity"] == "speed1")
        .unwrap();
    assert_eq!(s1["inputs"][0][0], "estimate initial.vehicle1.vx");
    // A different seed gives different draws.
    let other = pim(&[
        "uncertainty",
        CASE,
        "--cost",
        "q2",
        "--draws",
        "120",
        "--seed",
        "6",
        "--format",
        "json",
    ]);
    assert_ne!(one, other.stdout);
}

#[test]
fn nothing_uncertain_is_an_input_error() {
    let out = pim(&[
        "uncertainty",
        "examples/cases/ricsac7_fit.toml",
        "--cost",
        "q2",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("nothing is uncertain"));
}

#[test]
fn out_writes_the_record_the_table_and_three_figures() {
    let dir = scratch("out");
    pim_ok(&[
        "uncertainty",
        CASE,
        "--cost",
        "q2",
        "--draws",
        "60",
        "--out",
        dir.to_str().unwrap(),
    ]);
    for f in [
        "uncertainty.json",
        "uncertainty.txt",
        "histograms.svg",
        "speeds.svg",
        "tornado.svg",
    ] {
        let text = std::fs::read_to_string(dir.join(f)).unwrap();
        assert!(text.len() > 200, "{f}");
    }
    let svg = std::fs::read_to_string(dir.join("histograms.svg")).unwrap();
    assert!(svg.contains("90 %"));
}

/// RICSAC 9 of data/ricsac.csv written by hand as a natural-form case file (vehicle 1's nose
/// at heading1_deg + 180 = 180 degrees; phi is measured from the nose in both forms), with the
/// tolerances of examples/ricsac_tolerances.toml.
const RICSAC9_WITH_TOLERANCES: &str = r#"
[vehicle1]
mass = 1036.0
yaw_inertia = 1348.0
heading = 180.0
d = 1.4
phi = 6.0
[vehicle2]
mass = 2189.0
yaw_inertia = 5287.0
heading = 90.0
d = 1.6
phi = -29.7
[impact]
crush_angle = 0.0
[estimates.initial]
vehicle1 = { vx = -9.48, vy = 0.0, omega = 0.0 }
vehicle2 = { vx = 0.0, vy = 9.48, omega = 0.0 }
[estimates.final]
vehicle1 = { vx = -0.86, vy = 4.52, omega = -3.14 }
vehicle2 = { vx = -3.02, vy = 7.38, omega = 0.79 }
# The bounds a RICSAC batch states for its tests (Vossou & Koulocheris' setting).
[bounds]
e = [0.0, 0.2]
mu = [-1.2, 1.2]
velocity = 20.0
yaw_rate = 5.0
"#;

#[test]
fn data_file_intervals_equal_those_of_the_same_test_as_a_case_file() {
    let dir = scratch("data_intervals");
    let tolerances = std::fs::read_to_string(repo().join("examples/ricsac_tolerances.toml"))
        .expect("example tolerances");
    let case = dir.join("ricsac9.toml");
    std::fs::write(&case, format!("{RICSAC9_WITH_TOLERANCES}{tolerances}")).unwrap();
    let batch = pim_ok(&[
        "batch",
        "data/ricsac.csv",
        "--tests",
        "9",
        "--cost",
        "q2",
        "--draws",
        "40",
        "--seed",
        "3",
        "--tolerances",
        "examples/ricsac_tolerances.toml",
        "--format",
        "json",
    ]);
    let j: Value = serde_json::from_slice(&batch.stdout).unwrap();
    let records = j["records"].as_array().unwrap();
    assert_eq!(records.len(), 2);
    let best: Vec<&Value> = records.iter().filter(|r| r["best"] == true).collect();
    assert_eq!(best.len(), 1);
    let other = records.iter().find(|r| r["best"] == false).unwrap();
    assert!(other.get("intervals").is_none(), "only the best record");
    let single = pim_ok(&[
        "uncertainty",
        case.to_str().unwrap(),
        "--cost",
        "q2",
        "--draws",
        "40",
        "--seed",
        "3",
        "--format",
        "json",
    ]);
    let u: Value = serde_json::from_slice(&single.stdout).unwrap();
    for q in ["speed1", "speed2", "delta_v1", "delta_v2", "e", "mu"] {
        for p in ["p05", "p50", "p95"] {
            let (a, b) = (
                best[0]["intervals"][q][p].as_f64().unwrap(),
                u["quantities"][q][p].as_f64().unwrap(),
            );
            assert!(
                (a - b).abs() <= 1e-9 * (1.0 + b.abs()),
                "{q} {p}: {a} vs {b}"
            );
        }
    }
    // The interval contains the fitted value and has width.
    let s = &best[0]["intervals"]["delta_v1"];
    let fitted = best[0]["delta_v"]["vehicle1"].as_f64().unwrap();
    assert!(s["p05"].as_f64().unwrap() < fitted && fitted < s["p95"].as_f64().unwrap());
}

#[test]
fn data_file_draws_need_tolerances_and_only_standard_deviations() {
    let tol = scratch("uniform_tolerances").join("tol.toml");
    std::fs::write(
        &tol,
        "[uncertainty]\nvehicle1 = { d = { uniform = [1.0, 1.2] } }\n",
    )
    .unwrap();
    let example = "examples/ricsac_tolerances.toml";
    let data = "data/ricsac.csv";
    let cases: [(&[&str], &[&str]); 4] = [
        (&[data, "--draws", "5"], &["--tolerances FILE"]),
        (&[data, "--tolerances", example], &["with --draws"]),
        (
            &[data, "--draws", "5", "--tolerances", tol.to_str().unwrap()],
            &["tol.toml", "vehicle1.d", "standard deviation"],
        ),
        (
            &[CASE, "--draws", "5", "--tolerances", example],
            &["case files carry their own"],
        ),
    ];
    for (args, says) in cases {
        let out = pim(&[&["batch"], args].concat());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = stderr(&out);
        assert!(says.iter().all(|s| err.contains(s)), "{args:?}: {err}");
    }
}

/// `--model tangential`: every draw fits the second model; its coefficients e, et and the
/// friction limit stand in the places of PIM's e, mu and em, the speeds and delta-V are the
/// same quantities, and the study says which model it is.
#[test]
fn the_tangential_model_is_drawn_like_pim() {
    let run = |model: &str| {
        let out = pim_ok(&[
            "uncertainty",
            CASE,
            "--cost",
            "q2",
            "--model",
            model,
            "--draws",
            "100",
            "--format",
            "json",
        ]);
        serde_json::from_slice::<Value>(&out.stdout).unwrap()
    };
    let (t, p) = (run("tangential"), run("pim"));
    assert_eq!(t["model"], "tangential");
    assert_eq!(p["model"], "pim");
    let names = |j: &Value| {
        let mut n: Vec<String> = j["quantities"]
            .as_object()
            .unwrap()
            .keys()
            .cloned()
            .collect();
        n.sort();
        n
    };
    assert!(names(&t).contains(&"et".to_string()) && names(&t).contains(&"friction".to_string()));
    assert!(!names(&t).contains(&"mu".to_string()));
    assert_eq!(t["feasible_draws"], 100);
    // RICSAC 7 slides under Q2 with either model: the friction limit is PIM's mu (the sliding
    // forms agree, em = 1), so both nominal fits give the same speed, and the limit's
    // interval is ended by its default bound 1.2, as PIM's mu is.
    let nominal = |j: &Value, q: &str| j["nominal"][q].as_f64().unwrap();
    assert!((nominal(&t, "friction") - nominal(&p, "mu")).abs() < 1e-6);
    assert!((nominal(&t, "speed1") - nominal(&p, "speed1")).abs() < 1e-6);
    assert_eq!(
        t["quantities"]["friction"]["reaches_bound"]["bound"],
        "friction"
    );
    for q in ["speed1", "delta_v1"] {
        let (lo, hi) = (
            t["quantities"][q]["p05"].as_f64().unwrap(),
            t["quantities"][q]["p95"].as_f64().unwrap(),
        );
        assert!(lo < nominal(&t, q) && nominal(&t, q) < hi, "{q}: {lo} {hi}");
    }
    // The table names moment branches only for the model that has them.
    let table = |model: &str| {
        let out = pim_ok(&["uncertainty", CASE, "--model", model, "--draws", "20"]);
        String::from_utf8_lossy(&out.stdout).to_string()
    };
    assert!(!table("tangential").contains("branch"));
    assert!(table("pim").contains("best branch over the draws"));
}

/// A case whose [bounds] estimate the geometry: each draw is a full fit over the geometry box.
/// A geometry input both estimated and drawn is refused, naming it.
#[test]
fn geometry_bounds_are_searched_by_every_draw() {
    let dir = scratch("geometry");
    let base =
        std::fs::read_to_string(repo().join("examples/cases/ricsac6_geometry.toml")).unwrap();
    let case = dir.join("geometry.toml");
    std::fs::write(
        &case,
        format!(
            "{base}\n[sigma.final]\nvehicle1 = {{ vx = 0.3, vy = 0.3, omega = 0.1 }}\n\
             vehicle2 = {{ vx = 0.3, vy = 0.3, omega = 0.1 }}\n"
        ),
    )
    .unwrap();
    let out = pim_ok(&[
        "uncertainty",
        case.to_str().unwrap(),
        "--cost",
        "q2",
        "--draws",
        "20",
        "--format",
        "json",
    ]);
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["feasible_draws"], 20);
    // The nominal fit is the geometry fit of `pim fit` on the same case.
    let fit = pim(&[
        "fit",
        case.to_str().unwrap(),
        "--cost",
        "q2",
        "--format",
        "json",
    ]);
    let f: Value = serde_json::from_slice(&fit.stdout).unwrap();
    let best = f["branches"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["moment"] == f["best"])
        .unwrap();
    assert!((j["nominal"]["e"].as_f64().unwrap() - best["e"].as_f64().unwrap()).abs() < 1e-9);
    let both = dir.join("both.toml");
    std::fs::write(
        &both,
        format!(
            "{}\n[uncertainty]\nvehicle1 = {{ d = 0.05 }}\n",
            std::fs::read_to_string(&case).unwrap()
        ),
    )
    .unwrap();
    let out = pim(&[
        "uncertainty",
        both.to_str().unwrap(),
        "--cost",
        "q2",
        "--draws",
        "5",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        String::from_utf8_lossy(&out.stderr).contains(
            "vehicle1.d is estimated by [bounds] (an unknown of every draw's fit) and drawn by \
             [uncertainty]"
        ),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// A tolerances file is checked before the batch runs: a standard deviation it cannot use
/// stops the run with exit 2 and a message naming the tolerances file, line, column and field
/// (it used to reach every row as "no intervals", naming the data file, with exit 0).
#[test]
fn a_tolerances_file_is_checked_before_the_batch() {
    let dir = scratch("bad_tolerances");
    for (name, text, says) in [
        (
            "negative.toml",
            "[sigma.initial]\nvehicle1 = { vx = -0.5, vy = 0.5, omega = 0.1 }\n",
            "negative.toml:2:19: sigma.initial.vehicle1.vx: -0.5: a standard deviation must be",
        ),
        (
            "zero.toml",
            "[sigma.final]\nvehicle2 = { vx = 0.5, vy = 0.5, omega = 0.0 }\n",
            "zero.toml:2:42: sigma.final.vehicle2.omega: 0: a standard deviation must be",
        ),
        (
            "mass.toml",
            "[uncertainty]\nvehicle1 = { mass = -10.0 }\n",
            "mass.toml:2:21: uncertainty.vehicle1.mass: a standard deviation >= 0",
        ),
    ] {
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        let out = pim(&[
            "batch",
            "data/ricsac.csv",
            "--draws",
            "5",
            "--tolerances",
            path.to_str().unwrap(),
        ]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(says), "{name}: {err}");
        assert!(out.stdout.is_empty(), "{name}: the batch ran");
    }
}
