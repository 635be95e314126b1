//! End-to-end tests of `pim uncertainty`: the schema, and bit-identical results for any thread
//! count.
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn pim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pim"))
        .args(args)
        .current_dir(repo())
        .output()
        .expect("run pim")
}

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

const CASE: &str = "examples/cases/ricsac7_uncertainty.toml";

#[test]
fn same_answer_for_any_thread_count_and_the_documented_schema() {
    let run = |threads: &str| {
        let out = pim(&[
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
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
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
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("uncertainty_out");
    let _ = std::fs::remove_dir_all(&dir);
    let out = pim(&[
        "uncertainty",
        CASE,
        "--cost",
        "q2",
        "--draws",
        "60",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
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
