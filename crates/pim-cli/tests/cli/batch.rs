//! End-to-end tests of `pim batch` and `pim compare-costs` on data/ricsac.csv.
use crate::common;
use common::*;

fn scratch(name: &str) -> std::path::PathBuf {
    scratch_dir("cli_batch", name)
}
use serde_json::Value;

#[test]
fn full_batch_json_has_66_sound_records_and_writes_the_figures() {
    let out_dir = scratch("full");
    let out = pim(&[
        "batch",
        "data/ricsac.csv",
        "--format",
        "json",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    // Some Q1 fits are infeasible by the data: they are answers, the batch ran, status 0; and
    // nothing is on stderr with --format json.
    assert_eq!(out.status.code(), Some(0));
    assert!(
        out.stderr.is_empty(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    let recs = j["records"].as_array().unwrap();
    assert_eq!(recs.len(), 66);
    let mut infeasible = Vec::new();
    for r in recs {
        let outcome = r["outcome"].as_str().unwrap();
        match outcome {
            "optimal" | "limit_reached" => {
                assert!(r["max_residual"].as_f64().unwrap() < 1e-10, "{r}");
                assert_eq!(r["admissible"], Value::Bool(true), "{r}");
                assert!(r["energy_loss_percent"].as_f64().unwrap() >= 0.0);
                assert!(r["velocity_error"].as_array().unwrap().len() == 12);
            }
            "infeasible" => {
                assert!(!r["reason"].as_str().unwrap().is_empty());
                infeasible.push((
                    r["test"].as_u64().unwrap(),
                    r["cost_function"].as_str().unwrap().to_string(),
                ));
            }
            other => panic!("unexpected outcome {other}: {r}"),
        }
    }
    // The infeasible records: Q1 of tests 1, 6, 7, 10, 11, both branches.
    assert_eq!(infeasible.len(), 10);
    assert!(infeasible
        .iter()
        .all(|(t, c)| c == "q1" && [1, 6, 7, 10, 11].contains(t)));
    for f in [
        "cost.svg",
        "coefficients.svg",
        "delta_v.svg",
        "separation.svg",
        "records.csv",
        "records.json",
        "velocity_errors.csv",
        "summary.txt",
        "compare_costs.txt",
        "brach1984.txt",
    ] {
        let p = out_dir.join(f);
        let len = std::fs::metadata(&p).map(|m| m.len()).unwrap_or(0);
        assert!(len > 1000, "{f} missing or nearly empty ({len} bytes)");
    }
    let svg = std::fs::read_to_string(out_dir.join("cost.svg")).unwrap();
    assert!(svg.contains("<svg") && svg.contains("RICSAC test") && svg.contains("Q3"));
    let csv = std::fs::read_to_string(out_dir.join("records.csv")).unwrap();
    assert_eq!(csv.lines().count(), 67);
}

#[test]
fn output_is_identical_for_any_thread_count() {
    let a = pim(&["batch", "--format", "json", "--threads", "1"]);
    let b = pim(&["batch", "--format", "json", "--threads", "2"]);
    let c = pim(&["batch", "--format", "csv", "--threads", "1"]);
    let d = pim(&["batch", "--format", "csv", "--threads", "2"]);
    assert!(!a.stdout.is_empty());
    assert!(a.stdout == b.stdout, "JSON differs between 1 and 2 threads");
    assert!(c.stdout == d.stdout, "CSV differs between 1 and 2 threads");
}

#[test]
fn the_readme_main_command_works_as_written() {
    let readme = std::fs::read_to_string(repo().join("README.md")).unwrap();
    let line = readme
        .lines()
        .find(|l| l.starts_with("cargo run --release -p pim-cli -- batch"))
        .expect("README opens with the batch command");
    let cmd = line.split('#').next().unwrap().trim();
    // Run the same arguments on the built binary (cargo run would rebuild in release mode).
    let args: Vec<&str> = cmd
        .trim_start_matches("cargo run --release -p pim-cli --")
        .split_whitespace()
        .collect();
    let out = pim(&args);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("Q2: contact velocities known exactly"));
    assert!(text.contains("Q2 against Brach 1984 Table 1"));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("56 of 66 records solved; 10 have no solution"),
        "{stderr}"
    );
}

#[test]
fn selections_and_views() {
    let out = pim(&[
        "batch", "--tests", "6,7", "--cost", "q2", "--branch", "zero", "--format", "json",
    ]);
    assert!(out.status.success());
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["records"].as_array().unwrap().len(), 2);
    let out = pim(&["compare-costs", "--tests", "3"]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success());
    assert!(
        text.contains("test  3") && text.contains("vf2y") && text.contains('*'),
        "{text}"
    );
    // Unknown test and bad flags: exit 2 naming them.
    let out = pim(&["batch", "--tests", "2"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("test 2 is not in data/ricsac.csv"));
    let out = pim(&["batch", "--threads", "0"]);
    assert_eq!(out.status.code(), Some(2));
    let out = pim(&["batch", "no/such.csv"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such.csv: cannot read: no such file"));
}

#[test]
fn strict_makes_infeasible_records_a_non_zero_status() {
    let out = pim(&["batch", "--tests", "1", "--cost", "q1", "--strict"]);
    assert_eq!(out.status.code(), Some(1));
    let out = pim(&["batch", "--tests", "1", "--cost", "q1"]);
    assert_eq!(out.status.code(), Some(0));
}

#[test]
fn a_batch_of_case_files_streams_records_and_names_bad_files() {
    let dir = scratch("cases_in");
    std::fs::create_dir_all(&dir).unwrap();
    let good = std::fs::read_to_string(repo().join("examples/cases/ricsac7_fit.toml")).unwrap();
    std::fs::write(dir.join("a.toml"), &good).unwrap();
    std::fs::write(
        dir.join("b.toml"),
        good.replace("mass = 1955.0", "mass = \"heavy\""),
    )
    .unwrap();
    std::fs::write(dir.join("notes.txt"), "not a case").unwrap();
    let out_dir = scratch("cases_out");
    let out = pim(&[
        "batch",
        dir.to_str().unwrap(),
        "--cost",
        "q2",
        "--format",
        "json",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    // Two .toml files x one cost x two branches; the text file is not a case.
    assert_eq!(lines.len(), 4);
    let a: Vec<&Value> = lines
        .iter()
        .filter(|r| r["file"].as_str().unwrap().ends_with("a.toml"))
        .collect();
    let b: Vec<&Value> = lines
        .iter()
        .filter(|r| r["file"].as_str().unwrap().ends_with("b.toml"))
        .collect();
    assert!(a.iter().all(|r| r["outcome"] == "optimal"));
    // The same answer as `pim fit --cost q2` (the zero branch of RICSAC 7: cost 1.06939).
    let zero = a.iter().find(|r| r["moment_branch"] == "zero").unwrap();
    assert!((zero["cost"].as_f64().unwrap() - 1.069_394_75).abs() < 1e-6);
    for r in &b {
        assert_eq!(r["outcome"], "failed");
        let e = r["error"].as_str().unwrap();
        assert!(e.contains("b.toml") && e.contains("vehicle1.mass"), "{e}");
    }
    let csv = std::fs::read_to_string(out_dir.join("records.csv")).unwrap();
    assert_eq!(csv.lines().count(), 5);
    assert!(csv.starts_with("file,cost_function,branch"));
    assert_eq!(
        std::fs::read_to_string(out_dir.join("records.jsonl"))
            .unwrap()
            .lines()
            .count(),
        4
    );
    let summary = std::fs::read_to_string(out_dir.join("summary.txt")).unwrap();
    assert!(
        summary.contains("2 case files, 4 records (2 solved, 2 without a solution); 1 files"),
        "{summary}"
    );
    // --strict: the failed file makes the status 1.
    let out = pim(&[
        "batch",
        dir.to_str().unwrap(),
        "--cost",
        "q2",
        "--strict",
        "--format",
        "csv",
    ]);
    assert_eq!(out.status.code(), Some(1));
}

#[test]
fn draws_add_intervals_to_the_best_record_of_each_case() {
    let out = pim(&[
        "batch",
        "examples/cases/ricsac7_uncertainty.toml",
        "examples/cases/ricsac7_fit.toml",
        "--cost",
        "q2",
        "--draws",
        "50",
        "--format",
        "json",
    ]);
    assert_eq!(
        out.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let recs: Vec<Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let best_unc = recs
        .iter()
        .find(|r| r["best"] == true && r["file"].as_str().unwrap().ends_with("uncertainty.toml"))
        .unwrap();
    let s = &best_unc["intervals"]["delta_v1"];
    assert!(
        s["p05"].as_f64().unwrap() < s["p95"].as_f64().unwrap(),
        "{s}"
    );
    // The same numbers as `pim uncertainty` with the same draws and seed.
    let u = pim(&[
        "uncertainty",
        "examples/cases/ricsac7_uncertainty.toml",
        "--cost",
        "q2",
        "--draws",
        "50",
        "--format",
        "json",
    ]);
    let u: Value = serde_json::from_slice(&u.stdout).unwrap();
    assert_eq!(
        u["quantities"]["delta_v1"],
        best_unc["intervals"]["delta_v1"]
    );
    // A case without sigmas says why it has no intervals.
    let best_fit = recs
        .iter()
        .find(|r| r["best"] == true && r["file"].as_str().unwrap().ends_with("ricsac7_fit.toml"))
        .unwrap();
    assert!(best_fit["intervals_error"]
        .as_str()
        .unwrap()
        .contains("nothing is uncertain"));
    // A data file has no sigmas: --draws is refused.
    assert_eq!(pim(&["batch", "--draws", "10"]).status.code(), Some(2));
}

#[test]
fn a_batch_of_case_files_fits_each_with_its_own_cost() {
    // Two crashes in one folder: an EDR-style case (vehicle 1's contact velocity known, the
    // rest estimated, a delta-V observation) and a plain one. Without --cost each is fitted as
    // `pim fit` fits it without --cost; a solve-only file is named on stderr with its reason.
    let base = std::fs::read_to_string(repo().join("examples/cases/ricsac7_fit.toml")).unwrap();
    let edr = base.replace(
        "[estimates.initial]\nvehicle1 = { vx = -13.01, vy = 0.0, omega = 0.0 }\n",
        "[known.initial]\nvehicle1 = { vx = -13.01, vy = 0.0, omega = 0.0 }\n\
         [estimates.initial]\n",
    )
        + "\n[[observations]]\nkind = \"delta_v_longitudinal\"\nvehicle = 2\nvalue = -4.0\n";
    assert_ne!(edr, base);
    let dir = scratch_dir("batch", "own_costs");
    std::fs::write(dir.join("a_edr.toml"), &edr).unwrap();
    std::fs::write(dir.join("b_plain.toml"), &base).unwrap();
    std::fs::copy(
        repo().join("examples/cases/side_impact.toml"),
        dir.join("c_solve_only.toml"),
    )
    .unwrap();
    let d = dir.display().to_string();
    let out = pim(&["batch", &d, "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(
        err.contains("c_solve_only.toml: [coefficients] is for `pim solve`"),
        "{err}"
    );
    let records: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    for name in ["a_edr.toml", "b_plain.toml"] {
        let path = dir.join(name).display().to_string();
        let fit: serde_json::Value =
            serde_json::from_slice(&pim_ok(&["fit", &path, "--format", "json"]).stdout).unwrap();
        for b in fit["branches"].as_array().unwrap() {
            let r = records
                .iter()
                .find(|r| r["file"] == path.as_str() && r["moment_branch"] == b["moment"])
                .unwrap_or_else(|| panic!("{path}: no record"));
            assert_eq!(r["cost_function"], "custom");
            for k in ["e", "mu", "em", "cost"] {
                assert_eq!(r[k], b[k], "{name} {k}");
            }
        }
    }
    // The EDR case's known component stays at its value.
    let edr_best = records
        .iter()
        .find(|r| r["file"].as_str().unwrap().ends_with("a_edr.toml") && r["best"] == true)
        .unwrap();
    assert_eq!(edr_best["initial"]["vehicle1"]["vx"], -13.01);
    // With --cost the presets override the files' own costs.
    let out = pim(&["batch", &d, "--cost", "q2", "--format", "csv"]);
    let csv = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        csv.lines()
            .skip(1)
            .all(|l| l.split(',').nth(1) == Some("q2")),
        "{csv}"
    );
}

#[test]
fn a_data_file_batch_reads_in_the_units_asked_for() {
    // --units us: the delta-V columns in mph (SI / 0.44704), the legend says so; the default
    // stays SI.
    let row = |units: Option<&str>| -> (f64, f64, String) {
        let mut args = vec!["batch", "data/ricsac.csv", "--tests", "9", "--cost", "q2"];
        if let Some(u) = units {
            args.extend(["--units", u]);
        }
        let text = String::from_utf8_lossy(&pim_ok(&args).stdout).to_string();
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with("9 zero"))
            .unwrap()
            .to_string();
        let cells: Vec<&str> = line.split_whitespace().collect();
        let slash = cells.iter().position(|c| *c == "/").unwrap();
        (
            cells[slash - 1].parse().unwrap(),
            cells[slash + 1].parse().unwrap(),
            text,
        )
    };
    let (fit_si, meas_si, si) = row(None);
    let (fit_us, meas_us, us) = row(Some("us"));
    assert!(
        (fit_us - fit_si / 0.44704).abs() < 0.006,
        "{fit_si} {fit_us}"
    );
    assert!(
        (meas_us - meas_si / 0.44704).abs() < 0.006,
        "{meas_si} {meas_us}"
    );
    assert!(us.contains("delta-V in mph") && !si.contains("delta-V in"));
}

/// `--conditions v18`: Vossou & Koulocheris (2018)'s setting (Brach's 1983 moment equation, mu
/// in [0, 1.2] without mu <= mu_max, the free branch), with their printed costs beside ours.
#[test]
fn v18_conditions_reproduce_their_setting_beside_their_costs() {
    let out_dir = scratch("v18");
    let out = pim_ok(&[
        "batch",
        "data/ricsac.csv",
        "--conditions",
        "v18",
        "--format",
        "json",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    let recs = j["records"].as_array().unwrap();
    // 11 tests x Q1, Q2, Q3, the free branch only.
    assert_eq!(recs.len(), 33);
    assert!(recs.iter().all(|r| r["moment"] == "free"));
    let rec = |test: u64, cost: &str| {
        recs.iter()
            .find(|r| r["test"] == test && r["cost_function"] == cost)
            .unwrap()
    };
    // Test 10 refitted under V18's conditions: below V18's printed 7.02 (Q2) and 5.36 (Q3);
    // its friction exceeds mu_max (the sliding reverses), which the record says.
    let q2 = rec(10, "q2");
    assert!((q2["cost"].as_f64().unwrap() - 6.91).abs() < 0.005, "{q2}");
    assert!((rec(10, "q3")["cost"].as_f64().unwrap() - 4.13).abs() < 0.005);
    assert_eq!(q2["status"], "optimal");
    assert_eq!(q2["admissible"], false);
    assert!(q2["mu"].as_f64().unwrap() > q2["mu_max"].as_f64().unwrap());
    // Every mu inside [0, 1.2], every e inside [0, 0.2].
    for r in recs.iter().filter(|r| r["status"] == "optimal") {
        let (mu, e) = (r["mu"].as_f64().unwrap(), r["e"].as_f64().unwrap());
        assert!((0.0..=1.2).contains(&mu) && (0.0..=0.2).contains(&e), "{r}");
    }
    // The table of their printed costs beside ours.
    let v18 = std::fs::read_to_string(out_dir.join("v18.txt")).unwrap();
    let row = v18.lines().find(|l| l.starts_with("  10 q2")).unwrap();
    assert!(row.contains("7.02") && row.contains("6.91"), "{row}");
    assert_eq!(v18.lines().filter(|l| l.contains(" q")).count(), 33);
    // The default keeps the corrected equations and mu <= mu_max: test 10 Q2 costs 29.22.
    let out = pim_ok(&["batch", "--tests", "10", "--cost", "q2", "--format", "json"]);
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    let free = &j["records"][0];
    assert_eq!(free["moment"], "free");
    assert!(
        (free["cost"].as_f64().unwrap() - 29.22).abs() < 0.005,
        "{free}"
    );
}

/// `--draws` on a case file with nothing uncertain: the table and the CSV say why the interval
/// columns are empty (the JSON's `intervals_error`), not only the JSON.
#[test]
fn draws_without_anything_uncertain_are_said_in_the_table_and_csv() {
    let case = "examples/cases/ricsac7_fit.toml";
    let out = pim_ok(&["batch", case, "--draws", "5"]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("no intervals for 1 records"), "{table}");
    assert!(table.contains("nothing is uncertain"), "{table}");
    let out = pim_ok(&["batch", case, "--draws", "5", "--format", "csv"]);
    let mut rows = csv::Reader::from_reader(out.stdout.as_slice());
    let header = rows.headers().unwrap().clone();
    let k = header.iter().position(|h| h == "intervals_note").unwrap();
    let notes: Vec<String> = rows.records().map(|r| r.unwrap()[k].to_string()).collect();
    assert!(
        notes.iter().any(|n| n.contains("nothing is uncertain")),
        "{notes:?}"
    );
}

/// compare-costs shares batch's flags but draws no intervals: --draws and --tolerances are
/// refused with the command that uses them, not ignored.
#[test]
fn compare_costs_refuses_the_interval_flags() {
    for args in [
        vec![
            "compare-costs",
            "--draws",
            "5",
            "--tolerances",
            "examples/ricsac_tolerances.toml",
        ],
        vec![
            "compare-costs",
            "--tolerances",
            "examples/ricsac_tolerances.toml",
        ],
        vec!["compare-costs", "--draws", "5"],
    ] {
        let out = pim(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            stderr(&out).contains("draws no intervals") && stderr(&out).contains("pim batch"),
            "{args:?}: {}",
            stderr(&out)
        );
    }
}

/// A batch of case files under a cost function that holds components fixed says that their
/// weights or sigmas have no effect (as `pim fit` does), in the summary and in the records.
#[test]
fn unused_sigmas_are_said_in_a_batch() {
    let text = std::fs::read_to_string(repo().join("examples/cases/ricsac7_fit.toml")).unwrap();
    let with = text.replacen(
        "[bounds]",
        "[sigma.initial]\nvehicle1 = { vx = 0.5, vy = 0.5, omega = 0.1 }\n\
         vehicle2 = { vx = 0.5, vy = 0.5, omega = 0.1 }\n[sigma.final]\n\
         vehicle1 = { vx = 0.5, vy = 0.5, omega = 0.1 }\n\
         vehicle2 = { vx = 0.5, vy = 0.5, omega = 0.1 }\n\n[bounds]",
        1,
    );
    let path = scratch_file("batch", "unused_sigma.toml", with);
    let out = pim_ok(&["batch", &path, "--cost", "q2"]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(
        table.contains("notes:") && table.contains("has no effect"),
        "{table}"
    );
    let out = pim_ok(&["batch", &path, "--cost", "q2", "--format", "json"]);
    let first: serde_json::Value =
        serde_json::from_str(String::from_utf8_lossy(&out.stdout).lines().next().unwrap()).unwrap();
    assert!(
        first["notes"][0]
            .as_str()
            .unwrap()
            .contains("[sigma] of initial.vehicle1.vx"),
        "{first}"
    );
    // Q3 estimates every component: nothing to say.
    let out = pim_ok(&["batch", &path, "--cost", "q3"]);
    assert!(!String::from_utf8_lossy(&out.stdout).contains("has no effect"));
}
