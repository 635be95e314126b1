//! `[runout.vehicleN] inputs`: the driver's inputs over time (PC-Crash's sequences) in the
//! case file: read, checked at their line, and acting on the run-out.
use crate::common;
use common::*;

const SPIN: &str = "examples/cases/runout_spin.toml";

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

fn with(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(repo().join(SPIN)).unwrap();
    assert!(text.contains(from), "{from}");
    scratch_file("runout_inputs", name, text.replacen(from, to, 1))
}

fn rest(v: &serde_json::Value, k: usize) -> [f64; 3] {
    let r = &v["vehicles"][k]["rest"];
    ["x", "y", "heading"].map(|f| r[f].as_f64().unwrap())
}

/// The car's braking at 0.8 written as an input from the start is the same run-out to the
/// last digit; braking after a reaction time of 1 s built up over 0.3 s takes it further, and
/// a steering-wheel input (with the vehicle's steer ratio) moves its rest.
#[test]
fn inputs_act_on_the_run_out() {
    let base = json(&pim_ok(&["runout", SPIN, "--format", "json"]));
    let same = with(
        "same.toml",
        "braking = 0.8                          # the driver brakes hard after the impact",
        "inputs = [ { at = 0.0, braking = 0.8 } ]",
    );
    let a = json(&pim_ok(&["runout", &same, "--format", "json"]));
    // Bit for bit: the same JSON numbers.
    assert_eq!(a["vehicles"][0]["rest"], base["vehicles"][0]["rest"]);
    let late = with(
        "late.toml",
        "braking = 0.8                          # the driver brakes hard after the impact",
        "inputs = [ { at = 1.0, braking = 0.8, build_up = 0.3 } ]",
    );
    let b = json(&pim_ok(&["runout", &late, "--format", "json"]));
    let d = |v: &serde_json::Value| v["vehicles"][0]["distance"].as_f64().unwrap();
    assert!(d(&b) > d(&base) + 1.0, "{} against {}", d(&b), d(&base));
    let steered = with(
        "steered.toml",
        "braking = 0.8                          # the driver brakes hard after the impact",
        "steer_ratio = 16.0\ninputs = [ { at = 0.0, braking = 0.8 }, { at = 0.5, steering_wheel = 180.0, build_up = 0.5 } ]",
    );
    let c = json(&pim_ok(&["runout", &steered, "--format", "json"]));
    // The car slides sideways at 0.8 braking (little grip is left across the wheels): 11 deg of
    // steer moves its rest by centimetres, not metres.
    let (p, q) = (rest(&c, 0), rest(&a, 0));
    let moved = (p[0] - q[0]).hypot(p[1] - q[1]);
    assert!(
        moved > 0.05 && moved < 1.0,
        "the steer moves the rest {moved} m"
    );
}

/// Inputs out of order, a share above 1, a steering wheel without a ratio and an input that
/// changes nothing are refused at their line, exit 2.
#[test]
fn bad_inputs_are_refused_at_their_line() {
    for (name, inputs, says) in [
        (
            "order.toml",
            "inputs = [ { at = 2.0, braking = 0.5 }, { at = 1.0, braking = 0.2 } ]",
            "order",
        ),
        (
            "share.toml",
            "inputs = [ { at = 1.0, braking = 1.5 } ]",
            "between 0 and 1",
        ),
        (
            "ratio.toml",
            "inputs = [ { at = 1.0, steering_wheel = 90.0 } ]",
            "steer_ratio",
        ),
        (
            "nothing.toml",
            "inputs = [ { at = 1.0, build_up = 0.2 } ]",
            "neither",
        ),
        (
            "negative.toml",
            "inputs = [ { at = -1.0, braking = 0.5 } ]",
            "at least 0",
        ),
        (
            "unknown.toml",
            "inputs = [ { at = 1.0, brake = 0.5 } ]",
            "brake",
        ),
    ] {
        let case = with(
            name,
            "braking = 0.8                          # the driver brakes hard after the impact",
            inputs,
        );
        let out = pim(&["runout", &case]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        let err = stderr(&out);
        assert!(err.contains(says), "{name}: {err}");
        assert!(
            err.contains(&format!("{name}:49")),
            "{name}: the line: {err}"
        );
    }
}

/// The whole reconstruction takes the inputs too: the example's rolling wheels braked at 0.3
/// written as an input from the start give its document unchanged; the braking begun 0.5 s
/// after the impact and built up over 0.3 s gives another answer.
#[test]
fn the_reconstruction_takes_the_inputs() {
    const CASE: &str = "examples/cases/reconstruction_us.toml";
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap();
    let from = "braking = 0.3                       # the rolling wheels still braked at 30 % of the friction";
    assert!(text.contains(from));
    let fit = |name: &str, to: &str| {
        let case = scratch_file("runout_inputs", name, text.replacen(from, to, 1));
        json(&pim_ok(&["fit", &case, "--format", "json"]))
    };
    let base = json(&pim_ok(&["fit", CASE, "--format", "json"]));
    assert_eq!(
        fit("r_same.toml", "inputs = [ { at = 0.0, braking = 0.3 } ]"),
        base
    );
    let late = fit(
        "r_late.toml",
        "inputs = [ { at = 0.5, braking = 0.3, build_up = 0.3 } ]",
    );
    let speed = |v: &serde_json::Value| {
        v["best"]["vehicles"][0]["speed_at_contact"]
            .as_f64()
            .unwrap()
    };
    assert!(
        (speed(&late) - speed(&base)).abs() > 0.1,
        "{} {}",
        speed(&late),
        speed(&base)
    );
}
