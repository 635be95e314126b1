//! `[runout] duration`: each run-out followed for a stated time, its end the state then (exit
//! 0), as PC-Crash simulates a fixed window of motion.
use crate::common;
use common::*;

const SPIN: &str = "examples/cases/runout_spin.toml";

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn with(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(repo().join(SPIN)).unwrap();
    assert!(text.contains(from), "{from}");
    scratch_file("runout_duration", name, text.replacen(from, to, 1))
}

/// The state after 0.5 s is the full run-out's at 0.5 s (its path sampled there, to the
/// integration's precision), both cars still moving, exit 0.
#[test]
fn the_state_after_a_stated_time_is_the_run_outs_then() {
    let full = json(&pim_ok(&["runout", SPIN, "--format", "json"]));
    let case = with("half.toml", "[runout]\n", "[runout]\nduration = 0.5\n");
    let out = pim_ok(&["runout", &case, "--format", "json"]);
    let short = json(&out);
    assert_eq!(short["duration"], 0.5);
    for (k, v) in short["vehicles"].as_array().unwrap().iter().enumerate() {
        assert_eq!(v["end"], "time_limit");
        assert!((num(&v["time"]) - 0.5).abs() < 1e-12);
        let at = full["vehicles"][k]["path"]
            .as_array()
            .unwrap()
            .iter()
            .find(|p| (num(&p["t"]) - 0.5).abs() < 1e-12)
            .expect("the full path sampled at 0.5 s")
            .clone();
        for c in ["x", "y"] {
            let d = num(&v["rest"][c]) - num(&at[c]);
            assert!(d.abs() < 1e-6, "vehicle {k} {c}: {d}");
        }
        assert!((num(&v["rest"]["heading"]) - num(&at["heading"])).abs() < 1e-6);
        assert!(num(&at["speed"]) > 1.0, "still moving");
    }
    let text = pim_ok(&["runout", &case]);
    let said = String::from_utf8_lossy(&text.stdout);
    assert!(
        said.contains("followed for the stated duration (0.5 s)"),
        "{said}"
    );
}

#[test]
fn a_duration_and_a_time_limit_or_a_scene_are_refused() {
    let both = with(
        "both.toml",
        "[runout]\n",
        "[runout]\nduration = 0.5\ntime_limit = 10\n",
    );
    let out = pim(&["runout", &both]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("runout.duration"), "{}", stderr(&out));
    let bad = with("zero.toml", "[runout]\n", "[runout]\nduration = 0\n");
    let out = pim(&["runout", &bad]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("must be above 0"), "{}", stderr(&out));
    let text =
        std::fs::read_to_string(repo().join("examples/cases/reconstruction_us.toml")).unwrap();
    let scene = scratch_file(
        "runout_duration",
        "scene.toml",
        text.replacen("[runout]\n", "[runout]\nduration = 2.0\n", 1),
    );
    let out = pim(&["fit", &scene]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("duration"), "{}", stderr(&out));
}
