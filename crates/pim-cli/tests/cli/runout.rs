//! `pim runout` end to end: the run-out of the solve's separation velocities, the separation
//! velocities estimated back from the scene, the SAE frame, the drawing, and the located
//! messages for inputs the run-out model cannot use.
use crate::common;
use common::*;

const SPIN: &str = "examples/cases/runout_spin.toml";
const SCENE: &str = "examples/cases/runout_scene.toml";

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// Both cars of the example run out from the solve: they come to rest, the tyres take all the
/// kinetic energy, the path's samples run in time and end at the rest.
#[test]
fn runout_of_the_solve() {
    let v = json(&pim_ok(&["runout", SPIN, "--format", "json"]));
    assert_eq!(v["source"], "solve");
    let vehicles = v["vehicles"].as_array().unwrap();
    assert_eq!(vehicles.len(), 2);
    for car in vehicles {
        assert_eq!(car["end"], "rest");
        let (k, w) = (num(&car["initial_energy"]), num(&car["tyre_work"]));
        assert!((k - w).abs() < 1e-6 * k, "energy {k} against work {w}");
        let path = car["path"].as_array().unwrap();
        assert!(path.len() > 10);
        for pair in path.windows(2) {
            assert!(num(&pair[1]["t"]) > num(&pair[0]["t"]));
        }
        let last = path.last().unwrap();
        assert!((num(&last["x"]) - num(&car["rest"]["x"])).abs() < 1e-12);
        assert!((num(&last["t"]) - num(&car["time"])).abs() < 1e-12);
        assert!(num(&last["speed"]).abs() < 1e-12);
        // The rotation is the rest heading less the heading at separation.
        let rot = num(&car["rest"]["heading"]) - num(&car["separation"]["heading"]);
        assert!((rot - num(&car["rotation"])).abs() < 1e-9);
    }
    // Car 2 is struck behind its CG and spins: about three quarters of a turn.
    let rot2 = num(&vehicles[1]["rotation"]);
    assert!(rot2 > 200.0 && rot2 < 340.0, "{rot2}");
}

/// The scene example gives car 2's rest and a mark from the solve's run-out (rounded to the
/// centimetre and the degree): the estimate finds the solve's separation velocities back within
/// what that rounding allows, for one count of turns.
#[test]
fn separation_from_the_scene() {
    let truth = json(&pim_ok(&["runout", SPIN, "--format", "json"]));
    let sep = &truth["vehicles"][1]["separation"];
    let v = json(&pim_ok(&["runout", SCENE, "--format", "json"]));
    assert_eq!(v["source"], "scene");
    let car = &v["vehicles"][0];
    assert_eq!(car["vehicle"], 2);
    let est = &car["estimate"];
    assert_eq!(est["unknowns"], serde_json::json!(["vx", "vy", "yaw_rate"]));
    let candidates = est["candidates"].as_array().unwrap();
    assert_eq!(candidates.len(), 7);
    let consistent: Vec<_> = candidates
        .iter()
        .filter(|c| c["consistent"] == true)
        .collect();
    assert_eq!(consistent.len(), 1, "one count fits");
    let best = &candidates[0];
    assert_eq!(best["turns"], 1);
    for (k, tol) in [("vx", 0.02), ("vy", 0.02), ("yaw_rate", 0.02)] {
        let (a, b) = (num(&best["separation"][k]), num(&sep[k]));
        assert!((a - b).abs() < tol, "{k}: {a} against {b}");
    }
    // Standard errors for every unknown; the residuals within a sigma.
    assert!(best["sigma"].as_array().unwrap().iter().all(|s| s.is_f64()));
    for r in best["residuals"].as_array().unwrap() {
        assert!(num(&r["z"]).abs() < 1.0, "{r}");
    }
    // The table says the same.
    let out = pim_ok(&["runout", SCENE]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("estimated from the scene"), "{text}");
    assert!(text.contains("consistent"), "{text}");
}

/// The two cases' estimates of vehicle 1's separation state agree to the precision the run-outs
/// give the answer (SI JSON): 5e-5 m/s and rad/s. The cost of run-outs integrated to 1e-10
/// still moves by about 3e-8 between neighbouring states (measured on this scene: the step
/// sequences differ), and its curvature along the least determined unknown is about 113
/// (1 / 0.094^2, the speed's standard error), so its minimum is located to
/// `sqrt(2 * 3e-8 / 113) = 2.3e-5`: the two unit systems, whose inputs differ by rounding,
/// land anywhere within it (0.0005 of the standard error).
fn same_separation(a: &str, b: &str) {
    let run = |case: &str| json(&pim_ok(&["runout", case, "--format", "json"]));
    let (a, b) = (run(a), run(b));
    let (a, b) = (
        &a["vehicles"][0]["separation"],
        &b["vehicles"][0]["separation"],
    );
    for (k, tol) in [
        ("vx", 5e-5),
        ("vy", 5e-5),
        ("yaw_rate", 5e-5),
        ("x", 1e-9),
        ("y", 1e-9),
    ] {
        assert!(
            (num(&a[k]) - num(&b[k])).abs() < tol,
            "{k}: {} {}",
            a[k],
            b[k]
        );
    }
}

/// The same scene written in SAE's frame (y to the right, angles clockwise) gives the mirrored
/// separation velocities.
#[test]
fn the_sae_frame() {
    let text = std::fs::read_to_string(repo().join(SCENE)).unwrap();
    let sae = text
        .replace("title = ", "convention = \"sae\"\ntitle = ")
        .replace("heading = 90.0", "heading = -90.0")
        .replace(
            "impact_point = { x = -1.6, y = 0.88 }",
            "impact_point = { x = -1.6, y = -0.88 }",
        )
        .replace(
            "rest = { x = 9.58, y = 2.55, heading = 2.7 }",
            "rest = { x = 9.58, y = -2.55, heading = -2.7 }",
        )
        .replace(
            "{ x = 3.58, y = 2.14, sigma = 0.05 }",
            "{ x = 3.58, y = -2.14, sigma = 0.05 }",
        );
    let path = scratch_file("runout", "scene_sae.toml", sae);
    // The JSON is in the natural frame: the same physical motion.
    same_separation(SCENE, &path);
    // The table speaks SAE: y and the yaw rate change sign.
    let out = pim_ok(&["runout", &path]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains("frame: SAE"), "{table}");
    assert!(table.contains("yaw rate -7.3"), "{table}");
}

/// `--draw` writes the plan view.
#[test]
fn draws_the_runout() {
    let dir = scratch_dir("runout", "draw");
    let svg = dir.join("spin.svg");
    pim_ok(&["runout", SPIN, "--draw", svg.to_str().unwrap()]);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.starts_with("<svg"), "{}", &text[..80.min(text.len())]);
    assert!(text.contains("vehicle 2"));
    assert!(text.contains("every 0.5 s"));
}

/// A case and the status and message each bad input gets.
fn refused(case: &str, name: &str, expect: &[&str]) {
    let path = scratch_file("runout", name, case);
    let out = pim(&["runout", &path]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{name}: {err}");
    for e in expect {
        assert!(err.contains(e), "{name}: {err:?} lacks {e:?}");
    }
}

const BASE: &str = r#"
[vehicle1]
mass = 1500.0
yaw_inertia = 2500.0
heading = 0.0
impact_point = { x = 2.0, y = 0.0 }
length = 4.5
width = 1.8
[vehicle2]
mass = 1500.0
yaw_inertia = 2500.0
heading = 90.0
impact_point = { x = 0.0, y = 0.9 }
[impact]
crush_angle = 0.0
[final]
vehicle1 = { vx = 5.0, vy = 1.0, omega = 0.5 }
vehicle2 = { vx = 8.0, vy = 0.0, omega = -1.0 }
"#;

const WHEELS: &str = "
[runout.vehicle1]
wheelbase = 2.7
track = 1.5
cg_to_front_axle = 1.2
";

#[test]
fn bad_inputs_are_located() {
    // The base runs.
    let ok = format!("{BASE}[runout]\nfriction = 0.7\n{WHEELS}");
    let path = scratch_file("runout", "ok.toml", &ok);
    pim_ok(&["runout", &path]);
    // A wheel outside the outline.
    refused(
        &format!(
            "{BASE}[runout]\n{}",
            WHEELS.replace("track = 1.5", "track = 1.9")
        ),
        "track.toml",
        &["runout.vehicle1.track", "wider than the vehicle"],
    );
    // A wheelbase longer than the vehicle.
    refused(
        &format!(
            "{BASE}[runout]\n{}",
            WHEELS.replace("wheelbase = 2.7", "wheelbase = 4.8")
        ),
        "wheelbase.toml",
        &["wheelbase"],
    );
    // Friction 0 and beyond 1.5.
    for (name, f) in [("f0.toml", "0.0"), ("f2.toml", "1.6")] {
        refused(
            &format!("{BASE}[runout]\nfriction = {f}\n{WHEELS}"),
            name,
            &["runout.friction", "between 0.01 and 1.5"],
        );
    }
    // A sigma <= 0.
    refused(
        &format!(
            "{BASE}[runout]\n{WHEELS}[scene.vehicle1]\nrest = {{ x = 5.0, y = 1.0 }}\n\
             rest_sigma = {{ x = 0.0, y = 0.1 }}\n"
        ),
        "sigma.toml",
        &[
            "scene.vehicle1.rest_sigma.x",
            "standard deviation must be above 0",
        ],
    );
    // Rest evidence without [runout].
    refused(
        &format!("{BASE}[scene.vehicle1]\nrest = {{ x = 5.0, y = 1.0 }}\nrest_sigma = {{ x = 0.1, y = 0.1 }}\n"),
        "norunout.toml",
        &["needs [runout]"],
    );
    // Scene evidence of a vehicle without its wheels.
    refused(
        &format!(
            "{BASE}[runout]\n{WHEELS}[scene.vehicle2]\nrest = {{ x = 5.0, y = 1.0 }}\n\
             rest_sigma = {{ x = 0.1, y = 0.1 }}\n"
        ),
        "nowheels.toml",
        &["scene.vehicle2", "[runout.vehicle2]"],
    );
    // A wheel state that is not one, and a wheel that is not one.
    refused(
        &format!("{BASE}[runout]\n{WHEELS}wheels = \"lockd\"\n"),
        "state.toml",
        &["runout.vehicle1.wheels", "\"lockd\" is not a wheel state"],
    );
    refused(
        &format!(
            "{BASE}[runout]\n{WHEELS}wheels = {{ front_left = \"locked\", front_right = \"locked\", \
             rear_left = \"locked\", rear_rihgt = \"locked\" }}\n"
        ),
        "wheelname.toml",
        &["rear_rihgt", "not a wheel"],
    );
    // No [runout] at all.
    refused(BASE, "none.toml", &["no [runout] section"]);
    // Scene values out of their ranges (they reached the search before: a count of a billion
    // turns spun without end), refused in the file's words.
    let scene = std::fs::read_to_string(repo().join(SCENE)).unwrap();
    let rest = "rest = { x = 9.58, y = 2.55, heading = 2.7 }";
    for (name, from, to, says) in [
        (
            "far.toml",
            rest,
            "rest = { x = 1.0e6, y = 2.55, heading = 2.7 }",
            "scene.vehicle2.rest.x: 1000000: must be a number from -10000 to 10000 m",
        ),
        (
            "heading.toml",
            rest,
            "rest = { x = 9.58, y = 2.55, heading = 1.0e10 }",
            "scene.vehicle2.rest.heading: 10000000000: must be a number from -360 to 360 deg",
        ),
        (
            "turns.toml",
            "marks = [",
            "turns = 1000000000\nmarks = [",
            "scene.vehicle2.turns: 1000000000: at most 20 full turns either way",
        ),
        (
            "mark.toml",
            "{ x = 3.58, y = 2.14, sigma = 0.05 }",
            "{ x = 3.58e9, y = 2.14, sigma = 0.05 }",
            "scene.vehicle2.marks[0].x: 3580000000",
        ),
    ] {
        let text = scene.replace(from, to);
        assert_ne!(text, scene, "{name}");
        let path = scratch_file("runout", name, text);
        let out = pim_within(&["runout", &path], 30);
        assert_eq!(out.status.code(), Some(2), "{name}: {}", stderr(&out));
        assert!(stderr(&out).contains(says), "{name}: {}", stderr(&out));
    }
}

/// A run-out still moving at its time limit: the output is printed, the status is 3 and the
/// message says why.
#[test]
fn time_limit_is_exit_3() {
    let case = format!("{BASE}[runout]\ntime_limit = 2.0\n{WHEELS}wheels = \"rolling\"\n");
    let path = scratch_file("runout", "limit.toml", case);
    let out = pim(&["runout", &path, "--format", "json"]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(stderr(&out).contains("time limit"), "{}", stderr(&out));
    let v = json(&out);
    assert_eq!(v["vehicles"][0]["end"], "time_limit");
}

/// `--from fit`: the fit's separation velocities are run out (RICSAC 7's refit with wheels).
#[test]
fn from_the_fit() {
    let text = std::fs::read_to_string(repo().join("examples/cases/ricsac7_fit.toml")).unwrap();
    let case = format!(
        "{text}\n{}",
        WHEELS.replace("runout.vehicle1", "runout.vehicle2")
    );
    let path = scratch_file("runout", "fit.toml", case);
    let fit = json(&pim_ok(&["fit", &path, "--cost", "q2", "--format", "json"]));
    let best = fit["best"].as_str().unwrap().to_string();
    let branch = fit["branches"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["moment"] == best.as_str())
        .unwrap();
    let sep = &branch["final"]["vehicle2"];
    let v = json(&pim_ok(&[
        "runout", &path, "--from", "fit", "--cost", "q2", "--format", "json",
    ]));
    assert_eq!(v["source"], "fit");
    let car = &v["vehicles"][0];
    assert_eq!(car["vehicle"], 2);
    for (a, b) in [("vx", "vx"), ("vy", "vy"), ("yaw_rate", "omega")] {
        let (x, y) = (num(&car["separation"][a]), num(&sep[b]));
        assert!((x - y).abs() < 1e-9, "{a}: {x} against the fit's {y}");
    }
    assert_eq!(car["end"], "rest");
}

/// The scene example written in US units (ft): the same estimate in SI.
#[test]
fn us_units() {
    let text = std::fs::read_to_string(repo().join(SCENE)).unwrap();
    let ft = 0.3048;
    let f = |m: f64| format!("{}", m / ft);
    let us = text
        .replace("title = ", "[units]\nlength = \"ft\"\n\ntitle = ")
        .replace(
            "impact_point = { x = 2.1, y = 0.0 }",
            &format!("impact_point = {{ x = {}, y = 0.0 }}", f(2.1)),
        )
        .replace(
            "impact_point = { x = -1.6, y = 0.88 }",
            &format!("impact_point = {{ x = {}, y = {} }}", f(-1.6), f(0.88)),
        )
        .replace("length = 4.3", &format!("length = {}", f(4.3)))
        .replace("width = 1.76", &format!("width = {}", f(1.76)))
        .replace("cg_to_front = 2.0", &format!("cg_to_front = {}", f(2.0)))
        .replace("wheelbase = 2.55", &format!("wheelbase = {}", f(2.55)))
        .replace("track = 1.5", &format!("track = {}", f(1.5)))
        .replace(
            "cg_to_front_axle = 1.1",
            &format!("cg_to_front_axle = {}", f(1.1)),
        )
        .replace(
            "rest = { x = 9.58, y = 2.55, heading = 2.7 }",
            &format!(
                "rest = {{ x = {}, y = {}, heading = 2.7 }}",
                f(9.58),
                f(2.55)
            ),
        )
        .replace(
            "rest_sigma = { x = 0.05, y = 0.05, heading = 1.0 }",
            &format!(
                "rest_sigma = {{ x = {}, y = {}, heading = 1.0 }}",
                f(0.05),
                f(0.05)
            ),
        )
        .replace(
            "{ x = 3.58, y = 2.14, sigma = 0.05 }",
            &format!(
                "{{ x = {}, y = {}, sigma = {} }}",
                f(3.58),
                f(2.14),
                f(0.05)
            ),
        );
    // The file has [units] before the title's line: move the title up.
    let us = us.replacen("[units]\nlength = \"ft\"\n\ntitle = ", "title = ", 1);
    let us = us.replacen(
        "\n[vehicle1]",
        "\n[units]\nspeed = \"mph\"\nlength = \"ft\"\n\n[vehicle1]",
        1,
    );
    let path = scratch_file("runout", "scene_us.toml", us);
    same_separation(SCENE, &path);
    // The table is in the case's units.
    let out = pim_ok(&["runout", &path]);
    let table = String::from_utf8_lossy(&out.stdout);
    assert!(table.contains(" ft") && table.contains(" mph"), "{table}");
}

/// Evidence no run-out reaches (a mark behind the start, the rest ahead of it): the output
/// says why, with exit status 3, and does not call the counts equally good.
#[test]
fn unreachable_evidence_is_exit_3() {
    let case = format!(
        "{}[runout]\n{WHEELS}[scene.vehicle1]\nrest = {{ x = 10.0, y = 0.0, heading = 0.0 }}\n\
         rest_sigma = {{ x = 0.05, y = 0.05, heading = 1.0 }}\n\
         marks = [ {{ x = -12.0, y = 4.0, sigma = 0.05 }} ]\n",
        BASE.split("[final]").next().unwrap()
    );
    let path = scratch_file("runout", "unreachable.toml", case);
    let out = pim(&["runout", &path, "--format", "json"]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("misses mark 1") && stderr(&out).contains("does not reach"),
        "{}",
        stderr(&out)
    );
    let v = json(&out);
    let est = &v["vehicles"][0]["estimate"];
    assert!(est["candidates"][0]["reason"].is_string());
    assert!(!est["undetermined"]
        .as_array()
        .unwrap()
        .iter()
        .any(|u| u.as_str().unwrap().contains("equally well")));
}

/// PC-Crash's free rolling: `rolling_resistance = 0` is accepted, and a car whose wheels roll
/// on without resistance is followed to the time limit, whose state is its answer (exit 0, said
/// in the notes), while a time limit reached by a car that should have stopped stays a failure.
#[test]
fn free_rolling_is_followed_to_the_time_limit() {
    let text = std::fs::read_to_string(repo().join("examples/cases/runout_spin.toml")).unwrap();
    let free = text
        .replace(
            "friction = 0.75                        # dry asphalt",
            "friction = 0.75\ntime_limit = 4.0",
        )
        .replace(
            "braking = 0.8                          # the driver brakes hard after the impact",
            "rolling_resistance = 0.0",
        );
    assert_ne!(free, text);
    let f = scratch_file("runout", "free_rolling.toml", &free);
    let out = pim_ok(&["runout", &f, "--format", "json"]);
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let v1 = &doc["vehicles"][0];
    assert_eq!(v1["end"], "time_limit", "{v1}");
    assert!(
        (v1["time"].as_f64().unwrap() - 4.0).abs() < 1e-9,
        "{}",
        v1["time"]
    );
    let notes = doc["notes"].to_string();
    assert!(
        notes.contains("vehicle 1: free-rolling wheels without rolling resistance do not stop"),
        "{notes}"
    );
    // With the default resistance the same car stops well within the limit? It rolls far: at
    // 4 s it is still moving, and that is a failure (exit 3), not an answer.
    let slow = free.replace("rolling_resistance = 0.0", "rolling_resistance = 0.015");
    let f = scratch_file("runout", "resisting.toml", &slow);
    let out = pim(&["runout", &f, "--format", "json"]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("does not come to rest"),
        "{}",
        stderr(&out)
    );
}
