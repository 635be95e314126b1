//! A vehicle against a fixed barrier through the command line: solve with both models, fit, the
//! diagram, and the messages for barrier sections that cannot be right.
use crate::common;
use common::*;

const EXAMPLE: &str = "examples/cases/barrier_small_overlap.toml";

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The example: the car keeps 10 % of its closing speed at the barrier face (e = 0.1), the
/// barrier does not move, and the energy is the car's.
#[test]
fn solve_against_the_barrier() {
    let v = json(&pim_ok(&["solve", EXAMPLE, "--format", "json"]));
    let r = &v;
    assert_eq!(v["barrier"], true);
    let sep2 = &r["final"]["vehicle2"];
    for k in ["vx", "vy", "omega"] {
        assert_eq!(sep2[k], 0.0);
    }
    let vn = r["relative_velocity"]["normal_initial"].as_f64().unwrap();
    let vn_f = r["relative_velocity"]["normal_final"].as_f64().unwrap();
    assert!((vn_f + 0.1 * vn).abs() < 1e-9, "{vn} -> {vn_f}");
    let m = 1650.0;
    let speed = 64.4 / 3.6;
    let t0 = r["energy"]["initial"].as_f64().unwrap();
    assert!((t0 - 0.5 * m * speed * speed).abs() < 1e-6 * t0);
    assert_eq!(r["vehicles"][1]["delta_v"], 0.0);
    let table = String::from_utf8(pim_ok(&["solve", EXAMPLE]).stdout).unwrap();
    assert!(
        table.contains("vehicle 2 is a fixed rigid barrier"),
        "{table}"
    );
    // The car does not slide along the face at contact, but the off-centre impulse makes its
    // front slide: friction acts on the no-slip impulse's side (mu_max 0.245), the car is
    // pushed sideways and yaws (README: 17.87 m/s, 2.991 rad/s).
    assert_eq!(r["friction_basis"], "no_slip_impulse");
    let mu_max = r["mu_max"].as_f64().unwrap();
    assert!((mu_max - 0.2452).abs() < 1e-4, "{mu_max}");
    assert_eq!(r["admissible"], true);
    let dv = r["vehicles"][0]["delta_v"].as_f64().unwrap();
    let yaw = r["vehicles"][0]["yaw_rate_change"].as_f64().unwrap();
    assert!(
        (dv - 17.87).abs() < 0.005 && (yaw - 2.991).abs() < 0.0005,
        "{dv} {yaw}"
    );
    // The Carpenter-Welcher preset with its cap at the same ratio gives the same answer (at
    // vt = 0 both are that ratio on the no-slip impulse's side with Vn = -e vn).
    let impc = json(&pim_ok(&[
        "solve",
        "examples/cases/barrier_small_overlap_impc.toml",
        "--format",
        "json",
    ]));
    for k in ["vx", "vy", "omega"] {
        let a = r["final"]["vehicle1"][k].as_f64().unwrap();
        let b = impc["final"]["vehicle1"][k].as_f64().unwrap();
        assert!((a - b).abs() < 1e-9, "{k}: PIM {a}, IMPC {b}");
    }
    // With PIM's no-slip form: IMPC with a cap that does not bind (18.69 m/s, 2.119 rad/s).
    let stick = json(&pim_ok(&[
        "solve",
        EXAMPLE,
        "--no-slip",
        "--format",
        "json",
    ]));
    let dv = stick["vehicles"][0]["delta_v"].as_f64().unwrap();
    let yaw = stick["vehicles"][0]["yaw_rate_change"].as_f64().unwrap();
    assert!(
        (dv - 18.69).abs() < 0.005 && (yaw - 2.119).abs() < 0.0005,
        "{dv} {yaw}"
    );
}

fn barrier_case(extra_vehicle2: &str, coefficients: &str, initial2: &str) -> String {
    let text = std::fs::read_to_string(repo().join(EXAMPLE)).unwrap();
    let text = text
        .replace(
            "[vehicle2]\nbarrier = true",
            &format!("[vehicle2]\nbarrier = true\n{extra_vehicle2}"),
        )
        .replace("em = 1.0               # no moment impulse", "")
        .replace(
            "mu = 0.2               # impulse ratio along the barrier face (between 0 and mu_max = 0.245 here)",
            coefficients,
        )
        .replace(
            "vehicle1 = { vx = 64.4, vy = 0.0, omega = 0.0 }",
            &format!("vehicle1 = {{ vx = 64.4, vy = 8.0, omega = 0.0 }}\n{initial2}"),
        );
    text
}

/// The second model against the same barrier: sliding at its friction limit it is PIM with
/// mu = friction and em = 1.
#[test]
fn tangential_model_against_the_barrier_equals_sliding_pim() {
    let tangential = scratch_file(
        "barrier",
        "tangential.toml",
        barrier_case("", "et = 0.0\nfriction = 0.1", ""),
    );
    let pim_case = scratch_file(
        "barrier",
        "pim.toml",
        barrier_case("", "mu = 0.1\nem = 1.0", ""),
    );
    let a = json(&pim_ok(&["solve", &tangential, "--format", "json"]));
    let b = json(&pim_ok(&["solve", &pim_case, "--format", "json"]));
    assert_eq!(a["model"]["mode"], "slide", "{a}");
    for k in ["vx", "vy", "omega"] {
        let x = a["final"]["vehicle1"][k].as_f64().unwrap();
        let y = b["final"]["vehicle1"][k].as_f64().unwrap();
        assert!((x - y).abs() < 1e-9, "{k}: {x} against {y}");
    }
}

#[test]
fn fit_against_the_barrier_recovers_the_coefficients() {
    // Separation velocities of the example solved with e = 0.1, mu = 0.2, em = 1 (vy = 8 km/h
    // at contact, so that friction acts; mu_max is 0.278), written to the case as Q2 estimates.
    let solved = scratch_file(
        "barrier",
        "solve.toml",
        barrier_case("", "mu = 0.2\nem = 1.0", ""),
    );
    let v = json(&pim_ok(&["solve", &solved, "--format", "json"]));
    let sep = &v["final"]["vehicle1"];
    let kmh = |k: &str| sep[k].as_f64().unwrap() * 3.6;
    let text = std::fs::read_to_string(&solved).unwrap();
    let head = text.split("[coefficients]").next().unwrap();
    let case = format!(
        "{head}[bounds]\nyaw_rate = 10.0\n\n[estimates.initial]\nvehicle1 = {{ vx = 64.4, vy = 8.0, omega = 0.0 }}\n\n\
         [estimates.final]\nvehicle1 = {{ vx = {}, vy = {}, omega = {} }}\n",
        kmh("vx"),
        kmh("vy"),
        sep["omega"].as_f64().unwrap()
    );
    let file = scratch_file("barrier", "fit.toml", case);
    let v = json(&pim_ok(&["fit", &file, "--cost", "q2", "--format", "json"]));
    let zero = v["branches"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["moment"] == "zero")
        .unwrap();
    let s = zero;
    assert_eq!(s["status"], "optimal");
    assert!(s["cost"].as_f64().unwrap() < 1e-10, "{s}");
    assert!((s["e"].as_f64().unwrap() - 0.1).abs() < 1e-5, "{s}");
    assert!((s["mu"].as_f64().unwrap() - 0.2).abs() < 1e-5, "{s}");
    assert_eq!(s["final"]["vehicle2"]["vx"], 0.0);
    // The second model fits the same data: sliding PIM is its sliding mode, so the impulse
    // ratio (its PIM-equivalent mu) and e come back.
    let v = json(&pim_ok(&[
        "fit",
        &file,
        "--cost",
        "q2",
        "--model",
        "tangential",
        "--format",
        "json",
    ]));
    let t = &v["branches"][0];
    assert_eq!(t["status"], "optimal");
    assert!(t["cost"].as_f64().unwrap() < 1e-9, "{t}");
    assert!((t["e"].as_f64().unwrap() - 0.1).abs() < 1e-4, "{t}");
    assert!((t["mu"].as_f64().unwrap() - 0.2).abs() < 1e-4, "{t}");
}

#[test]
fn the_diagram_draws_a_wall() {
    let dir = scratch_dir("barrier", "draw");
    let svg = dir.join("d.svg");
    pim_ok(&["draw", EXAMPLE, "--output", svg.to_str().unwrap()]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("barrier (fixed, rigid)"));
    assert!(!text.contains("CG2"));
}

/// Each wrong barrier section is refused with exit 2 and a message naming the section.
#[test]
fn barrier_mistakes_are_named() {
    let cases = [
        (
            barrier_case("mass = 1000.0", "mu = 0.3\nem = 1.0", ""),
            "[vehicle2] is a barrier (barrier = true) and cannot have mass",
        ),
        (
            barrier_case(
                "",
                "mu = 0.3\nem = 1.0",
                "vehicle2 = { vx = 1.0, vy = 0.0, omega = 0.0 }",
            ),
            "[initial] vehicle2 = { vx = 1, vy = 0, omega = 0 }: vehicle 2 is a fixed barrier",
        ),
        (
            std::fs::read_to_string(repo().join(EXAMPLE))
                .unwrap()
                .replace("[vehicle1]", "[vehicle1]\nbarrier = true"),
            "only vehicle 2 can be a barrier",
        ),
        (
            std::fs::read_to_string(repo().join(EXAMPLE))
                .unwrap()
                .replace(
                    "[vehicle2]\nbarrier = true",
                    "[vehicle2]\nheading = 0.0\nd = 0.0\nphi = 0.0\nyaw_inertia = 5.0",
                ),
            "vehicle2.mass: missing or not a number; give the vehicle's mass (or barrier = true",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let f = scratch_file("barrier", &format!("bad{i}.toml"), text);
        let out = pim(&["solve", &f]);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains(want), "{i}: {}", stderr(&out));
    }
    // A fit case with an estimate of the barrier.
    let text = std::fs::read_to_string(repo().join(EXAMPLE)).unwrap();
    let head = text.split("[coefficients]").next().unwrap();
    let f = scratch_file(
        "barrier",
        "bad_fit.toml",
        format!(
            "{head}[estimates.initial]\nvehicle1 = {{ vx = 64.4, vy = 0.0, omega = 0.0 }}\n\
             [estimates.final]\nvehicle1 = {{ vx = 10.0, vy = 0.0, omega = 1.0 }}\n\
             vehicle2 = {{ vx = 0.0 }}\n"
        ),
    );
    let out = pim(&["fit", &f, "--cost", "q3"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("[estimates] final.vehicle2.vx: vehicle 2 is a fixed barrier"),
        "{}",
        stderr(&out)
    );
}
