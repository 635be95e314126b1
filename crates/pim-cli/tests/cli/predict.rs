//! End-to-end test of `pim predict-dv`: the JSON document and the table.
use crate::common;
use common::pim_ok;
use serde_json::Value;
use std::path::Path;
use std::process::Command;

#[test]
fn predict_dv_json_has_every_test_and_field() {
    let out = Command::new(env!("CARGO_BIN_EXE_pim"))
        .args(["predict-dv", "--format", "json"])
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    let tests = j["tests"].as_array().unwrap();
    assert_eq!(tests.len(), 11);
    for t in tests {
        for k in ["test", "L", "energy_loss_fraction", "mu_m_point_mass"] {
            assert!(t[k].is_number(), "{k}: {t}");
        }
        for v in ["delta_v1", "delta_v2"] {
            for k in ["measured", "eq14", "eq14_two_thirds", "eq17"] {
                assert!(t[v][k].as_f64().unwrap() > 0.0, "{v}.{k}: {t}");
            }
        }
    }
}

#[test]
fn out_writes_the_figure() {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("predict_out");
    let out = Command::new(env!("CARGO_BIN_EXE_pim"))
        .args(["predict-dv", "--out", dir.to_str().unwrap()])
        .current_dir(Path::new(env!("CARGO_MANIFEST_DIR")).join("../.."))
        .output()
        .unwrap();
    assert!(out.status.success());
    let svg = std::fs::read_to_string(dir.join("predict_dv.svg")).unwrap();
    assert!(svg.contains("m1 / m2 = 1") && svg.contains("eq. 17, point mass"));
}

#[test]
fn the_prediction_table_reads_in_the_units_asked_for() {
    let si = String::from_utf8_lossy(&pim_ok(&["predict-dv"]).stdout).to_string();
    let kmh =
        String::from_utf8_lossy(&pim_ok(&["predict-dv", "--units", "kmh"]).stdout).to_string();
    let measured = |t: &str| -> f64 {
        let line = t
            .lines()
            .find(|l| l.trim_start().starts_with("1 "))
            .unwrap();
        line.split('|')
            .nth(1)
            .unwrap()
            .split_whitespace()
            .next()
            .unwrap()
            .parse()
            .unwrap()
    };
    assert!((measured(&kmh) - 3.6 * measured(&si)).abs() < 0.006);
    assert!(kmh.contains("delta-V in km/h") && si.contains("delta-V in m/s"));
}
