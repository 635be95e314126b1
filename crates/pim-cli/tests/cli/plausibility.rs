//! Plausibility warnings: each fires on a made-up mistake, naming the field and its line, and
//! none fires on any example case.
use crate::common;
use common::*;

fn warnings(text: &str, name: &str) -> String {
    let path = scratch_file("plausibility", name, text);
    let out = pim(&["solve", &path, "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    stderr(&out)
}

#[test]
fn each_warning_fires_on_its_mistake_and_names_the_line() {
    let side = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml")).unwrap();
    let cases: [(&str, String, &str); 4] = [
        (
            "point_ahead.toml",
            side.replace(
                "impact_point = { x = 2.0, y = 0.0 }",
                "impact_point = { x = 4.6, y = 0.0 }",
            ),
            ":13:16: vehicle1.impact_point: the impact centre (4.60, 0.00) m from the CG lies 2.60 m outside",
        ),
        (
            "deg_per_s.toml",
            side.replace(
                "vehicle2 = { vx = 0.0, vy = 0.0, omega = 0.0 }",
                "vehicle2 = { vx = 0.0, vy = 0.0, omega = 9.0 }",
            ),
            "initial.vehicle2.omega: a yaw rate of 9.00 rad/s (516 deg/s)",
        ),
        (
            "sideways.toml",
            side.replace(
                "vehicle1 = { vx = 15.0, vy = 0.0, omega = 0.0 }",
                "vehicle1 = { vx = 15.0, vy = -12.0, omega = 0.0 }",
            ),
            "initial.vehicle1.vx: the vehicle moves 39 deg off its heading with no yaw rate",
        ),
        (
            "radians.toml",
            side.replace("heading = 90.0", "heading = 1.5708"),
            "vehicle2.heading: 1.5708 is read as degrees; it looks like radians (90.0 deg)",
        ),
    ];
    for (name, text, want) in cases {
        assert_ne!(text, side, "{name}: the mistake was not written");
        let msg = warnings(&text, name);
        assert!(msg.contains(want), "{name}: {msg}");
    }
    // Beyond what any vehicle does (15 rad/s) it is refused, with the same hint.
    let path = scratch_file(
        "plausibility",
        "deg_per_s_refused.toml",
        side.replace(
            "vehicle2 = { vx = 0.0, vy = 0.0, omega = 0.0 }",
            "vehicle2 = { vx = 0.0, vy = 0.0, omega = 90.0 }",
        ),
    );
    let out = pim(&["solve", &path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains(
            "initial.vehicle2.omega: must be a number between -15 and 15 rad/s, got 90 (in SI, \
             after [units]); degrees per second meant? set [units] yaw_rate = \"deg/s\""
        ),
        "{}",
        stderr(&out)
    );
    // A small crush angle in degrees is not taken for radians.
    let small = side.replace("crush_angle = 0.0", "crush_angle = 3.4");
    assert_ne!(small, side);
    let msg = warnings(&small, "crush_small.toml");
    assert!(!msg.contains("radians"), "{msg}");
}

#[test]
fn no_example_case_draws_a_warning() {
    let mut n = 0;
    for entry in std::fs::read_dir(repo().join("examples/cases")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let f = p.display().to_string();
            let dir = scratch_dir("plausibility", "draws");
            let svg = dir.join("x.svg").display().to_string();
            let out = pim(&["draw", &f, "-o", &svg]);
            assert!(out.status.success(), "{f}: {}", stderr(&out));
            assert!(!stderr(&out).contains("warning"), "{f}: {}", stderr(&out));
            n += 1;
        }
    }
    assert!(n >= 10, "{n} examples");
}

/// Heavy vehicles: a rail vehicle or heavy-haul combination up to 1,000 t is solved, with a
/// warning above a loaded truck's 60 t; from 200 t the warning points to `barrier = true` (the
/// IMPC convention gives a barrier 1e6 lb); beyond 1,000 t the mass is refused. --strict makes
/// the warning exit 1.
#[test]
fn heavy_vehicles_are_accepted_with_a_warning() {
    let side = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml")).unwrap();
    let heavy = |mass: &str, inertia: &str| {
        side.replacen(
            "[vehicle2]\ndescription = \"struck car\"\nmass = 1500.0\nyaw_inertia = 2500.0",
            &format!(
                "[vehicle2]\ndescription = \"struck car\"\nmass = {mass}\nyaw_inertia = {inertia}"
            ),
            1,
        )
    };
    // A 90 t rail car: solved, warned, no word of a barrier.
    let rail = heavy("90000.0", "9.0e6");
    assert!(rail.contains("mass = 90000.0"));
    let w = warnings(&rail, "rail.toml");
    assert!(
        w.contains("vehicle2.mass: 90000 kg is heavier than any road vehicle"),
        "{w}"
    );
    assert!(!w.contains("barrier = true"), "{w}");
    // The IMPC barrier of 1e6 lb.
    let impc = heavy("453592.0", "5.0e7");
    let w = warnings(&impc, "impc.toml");
    assert!(
        w.contains("453592 kg is heavier than any road vehicle"),
        "{w}"
    );
    assert!(w.contains("barrier = true"), "{w}");
    let path = scratch_file("plausibility", "impc_strict.toml", &impc);
    assert_eq!(pim(&["solve", &path, "--strict"]).status.code(), Some(1));
    // Beyond 1,000 t: refused, with the range.
    let path = scratch_file("plausibility", "too_heavy.toml", heavy("2.0e6", "5.0e7"));
    let out = pim(&["solve", &path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("vehicle2.mass: must be a number between 100 and 1000000 kg"),
        "{}",
        stderr(&out)
    );
}

/// A heading a few hundredths of a degree off an axis is a measured heading, not radians: its
/// radian reading (2.3 deg) is within 5 deg of it, so no warning; at 0.1 the readings are 5.6
/// deg apart and it warns.
#[test]
fn a_heading_nearly_along_an_axis_is_not_taken_for_radians() {
    let side = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml")).unwrap();
    let near = side.replace("heading = 90.0", "heading = 0.04");
    assert_ne!(near, side);
    let msg = warnings(&near, "near_axis.toml");
    assert!(!msg.contains("radians"), "{msg}");
    let msg = warnings(
        &side.replace("heading = 90.0", "heading = 0.1"),
        "tenth.toml",
    );
    assert!(
        msg.contains("vehicle2.heading: 0.1 is read as degrees; it looks like radians (5.7 deg)"),
        "{msg}"
    );
}

/// A heading a few degrees off an axis in a case whose other heading is plainly in degrees is a
/// heading, not radians (the newcomer's sedan at -4.1, 4.1 deg west of north, beside an SUV at
/// 90): no warning, and so nothing for `--strict` to fail on. The warning, when a case is in
/// radians throughout, gives the value as written, its sign kept.
#[test]
fn a_small_heading_beside_one_in_degrees_is_not_taken_for_radians() {
    let text = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml"))
        .unwrap()
        .replace("heading = 0.0 ", "heading = -4.1");
    assert!(text.contains("heading = -4.1"));
    let msg = warnings(&text, "small_heading.toml");
    assert!(!msg.contains("radians"), "{msg}");
    let radians = text.replace("heading = 90.0", "heading = 1.5708");
    let msg = warnings(&radians, "all_radians.toml");
    assert!(
        msg.contains("vehicle1.heading: -4.1 is read as degrees; it looks like radians"),
        "{msg}"
    );
}

/// A yaw inertia left out beside the outline is estimated: a note on stderr naming the value,
/// its rule and its inputs, not a warning (`--strict` exits 0); the answer is that of the same
/// case with the estimate written in.
#[test]
fn an_estimated_yaw_inertia_is_a_note_not_a_warning() {
    let side = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml")).unwrap();
    let without = side.replacen("yaw_inertia = 2500.0                   # kg m^2\n", "", 1);
    assert_ne!(without, side);
    let path = scratch_file("plausibility", "estimated_inertia.toml", &without);
    let out = pim(&["solve", &path, "--strict"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    // 1500 kg, 4.5 by 1.8 m: 0.9 x 1500 (20.25 + 3.24) / 12 = 2642.6 kg m^2.
    assert_eq!(
        stderr(&out).lines().next().unwrap(),
        "pim: note: vehicle1.yaw_inertia: not given, estimated as 2643 kg m^2 from mass 1500 \
         kg, length 4.50 and width 1.80 m as 0.9 m (L^2 + W^2) / 12 (0.9 times the mass spread \
         evenly over the outline), within 11 % of the RICSAC cars' listed inertias; give the \
         measured value if known"
    );
    let written = side.replacen("yaw_inertia = 2500.0  ", "yaw_inertia = 2642.625", 1);
    let written = scratch_file("plausibility", "written_inertia.toml", &written);
    let json = |p: &str| {
        String::from_utf8_lossy(&pim(&["solve", p, "--format", "json"]).stdout).to_string()
    };
    assert_eq!(
        json(&path),
        json(&written).replace("written_inertia", "estimated_inertia")
    );
}
