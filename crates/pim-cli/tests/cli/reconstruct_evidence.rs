//! Evidence beyond the scene in the whole reconstruction: a scene case with `[damage]` fits the
//! crush energy with the scene in one chi-square, its residual a row of the evidence table, and
//! its study draws the damage; with `[runout] friction_sigma` the road friction is fitted (one
//! under both vehicles, or one each on their own surfaces), its residual a row too and its
//! interval in the study.
use crate::common;
use common::*;

const CASE: &str = "examples/cases/reconstruction_damage_us.toml";
const PLAIN: &str = "examples/cases/reconstruction_us.toml";

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

#[test]
fn the_crush_energy_is_a_residual_of_the_reconstruction() {
    let out = pim_ok(&["fit", CASE, "--format", "json"]);
    assert!(
        !stderr(&out).contains("does not take the crush"),
        "{}",
        stderr(&out)
    );
    let v = json(&out);
    assert_eq!(v["kind"], "reconstruction");
    let b = &v["best"];
    let evidence = b["evidence"].as_array().unwrap();
    let crush: Vec<&serde_json::Value> = evidence
        .iter()
        .filter(|e| e["name"] == "crush energy")
        .collect();
    assert_eq!(crush.len(), 1, "{evidence:?}");
    assert_eq!(crush[0]["quantity"], "energy");
    assert!(num(&crush[0]["sigma"]) > 0.0);
    // One chi-square: the sum of every row's z squared, the energy's included.
    let sum: f64 = evidence.iter().map(|e| num(&e["z"]).powi(2)).sum();
    let chi = num(&b["chi_square"]);
    assert!(
        (sum - chi).abs() <= 1e-6 * (1.0 + chi),
        "{sum} against {chi}"
    );
    // One datum more than the same scene without its crush.
    let plain = json(&pim_ok(&["fit", PLAIN, "--format", "json"]));
    assert_eq!(
        b["degrees_of_freedom"].as_i64().unwrap(),
        plain["best"]["degrees_of_freedom"].as_i64().unwrap() + 1
    );
    // The evidence agrees: within two standard deviations, and the fit is consistent.
    assert!(num(&crush[0]["z"]).abs() < 2.0);
    assert!(num(&b["p_value"]) > 0.05);
}

#[test]
fn the_crush_without_its_evidence_is_said_and_left_out() {
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap();
    let off = scratch_file(
        "reconstruct_evidence",
        "off.toml",
        text.replace(
            "relation = \"energy_loss\"",
            "relation = \"energy_loss\"\nevidence = false",
        ),
    );
    let out = pim_ok(&["fit", &off, "--format", "json"]);
    assert!(
        stderr(&out).contains("[damage] evidence = false"),
        "{}",
        stderr(&out)
    );
    let v = json(&out);
    let names: Vec<&str> = v["best"]["evidence"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["name"].as_str().unwrap())
        .collect();
    assert!(!names.contains(&"crush energy"), "{names:?}");
}

/// The study draws the damage's stiffness and crush depths as `pim uncertainty` of an impact
/// case does: they appear among the inputs that move the speeds.
#[test]
fn the_study_draws_the_damage() {
    let v = json(&pim_ok(&[
        "uncertainty",
        CASE,
        "--draws",
        "30",
        "--format",
        "json",
    ]));
    let text = v.to_string();
    assert!(text.contains("damage.vehicle1.a"), "{text}");
}

fn rows(v: &serde_json::Value) -> Vec<(String, f64, f64)> {
    v["best"]["evidence"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| {
            (
                e["name"].as_str().unwrap().to_string(),
                num(&e["residual"]),
                num(&e["sigma"]),
            )
        })
        .collect()
}

#[test]
fn the_road_friction_is_fitted_with_the_speeds() {
    let v = json(&pim_ok(&["fit", PLAIN, "--format", "json"]));
    let friction: Vec<(String, f64, f64)> = rows(&v)
        .into_iter()
        .filter(|r| r.0.starts_with("road friction"))
        .collect();
    assert_eq!(friction.len(), 1, "{friction:?}");
    // Stated 0.72 +- 0.05: fitted within its sigma.
    assert!((friction[0].2 - 0.05).abs() < 1e-12);
    assert!(friction[0].1.abs() < 0.05, "{friction:?}");
    // Without its sigma it is held, and said to be.
    let text = std::fs::read_to_string(repo().join(PLAIN)).unwrap();
    let held = scratch_file(
        "reconstruct_evidence",
        "held.toml",
        text.replace("friction_sigma = 0.05", ""),
    );
    let h = json(&pim_ok(&["fit", &held, "--format", "json"]));
    assert!(rows(&h).iter().all(|r| !r.0.starts_with("road friction")));
    assert!(h["undetermined"].to_string().contains("taken as given"));
}

#[test]
fn each_vehicle_on_its_own_surface_has_its_own_friction() {
    let text = std::fs::read_to_string(repo().join(PLAIN)).unwrap();
    let own = scratch_file(
        "reconstruct_evidence",
        "own.toml",
        text.replace("[runout.vehicle2]\n", "[runout.vehicle2]\nfriction = 0.6\n"),
    );
    let v = json(&pim_ok(&["fit", &own, "--format", "json"]));
    let names: Vec<String> = rows(&v)
        .into_iter()
        .map(|r| r.0)
        .filter(|n| n.starts_with("road friction"))
        .collect();
    assert_eq!(
        names,
        ["road friction", "road friction under vehicle2"],
        "{names:?}"
    );
}

#[test]
fn the_study_gives_the_friction_its_interval() {
    let v = json(&pim_ok(&[
        "uncertainty",
        PLAIN,
        "--draws",
        "30",
        "--format",
        "json",
    ]));
    let q = &v["quantities"]["road_friction"];
    assert!(num(&q["p05"]) < num(&q["p95"]), "{q}");
    assert!(num(&q["p05"]) > 0.5 && num(&q["p95"]) < 0.95, "{q}");
}
