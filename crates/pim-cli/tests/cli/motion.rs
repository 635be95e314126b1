//! `pim runout` of a motion case (`[start]`: a vehicle from a stated state, no impact), as a
//! PC-Crash user runs one vehicle: straight braking against its closed form (the figures that
//! PC-Crash's own braking runs agree with), a stated duration, the example.
use crate::common;
use common::*;

const MALIBU: &str = "examples/motion/malibu_us.toml";

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The example going straight (no steer) on free-rolling wheels without rolling resistance,
/// with `inputs` (a line, or nothing) and `extra` lines in `[runout]`.
fn malibu(name: &str, inputs: &str, extra: &str) -> String {
    let text = std::fs::read_to_string(repo().join(MALIBU)).unwrap();
    let start = text.find("steer_ratio = 15.9").unwrap();
    let text = format!("{}rolling_resistance = 0.0\n{inputs}\n", &text[..start])
        .replace("friction = 0.76\n", &format!("friction = 0.76\n{extra}"));
    scratch_file("motion", name, text)
}

/// From 30 mph (13.4112 m/s) on a 0.76 road: all four wheels braked fully stop in
/// `v^2 / (2 mu g)` = 12.0662 m = 39.59 ft whatever the load transfer; half the friction
/// circle (0.38 g) in 24.1324 m = 79.17 ft; a reaction time of 1.0 s before it adds 44.00 ft,
/// and so does braking from 44 ft travelled (an input by distance).
/// Rolling resistance 0, so that nothing but the braking decelerates.
#[test]
fn straight_braking_from_30_mph_stops_at_its_closed_form() {
    let v = 30.0 * 0.447_04;
    let ft = 0.3048;
    for (name, input, decel, react) in [
        ("full.toml", "{ at = 0.0, braking = 1.0 }", 0.76, 0.0),
        ("partial.toml", "{ at = 0.0, braking = 0.5 }", 0.38, 0.0),
        ("reaction.toml", "{ at = 1.0, braking = 1.0 }", 0.76, 1.0),
        // By distance: from 44.0 ft travelled, that is after 1.0 s at 30 mph.
        (
            "distance.toml",
            "{ distance = 44.0, braking = 1.0 }",
            0.76,
            1.0,
        ),
    ] {
        let file = malibu(name, &format!("inputs = [ {input} ]"), "");
        let out = json(&pim_ok(&["runout", &file, "--format", "json"]));
        let car = &out["vehicles"][0];
        let expected = v * react + v * v / (2.0 * decel * 9.80665);
        let x = car["rest"]["x"].as_f64().unwrap();
        assert!(
            (x - expected).abs() < 1e-6,
            "{name}: {x} against {expected}"
        );
        assert_eq!(out["source"], "start");
        let table = String::from_utf8(pim_ok(&["runout", &file]).stdout).unwrap();
        let printed = format!("rest        x {:.2} ft", expected / ft);
        assert!(table.contains(&printed), "{name}: {printed} not in {table}");
        if name == "distance.toml" {
            assert!(
                table.contains("inputs      from 44.00 ft: braking 1.00"),
                "{table}"
            );
        }
    }
}

/// `[runout] duration`: the state after it, exit 0; rolling freely without rolling resistance
/// a car at 30 mph covers 44.00 ft a second.
#[test]
fn a_stated_duration_gives_the_state_then() {
    let file = malibu("duration.toml", "", "duration = 1.0\n");
    let out = pim_ok(&["runout", &file]);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.contains("after (still moving)  x 44.00 ft, y 0.00 ft, heading 0.0 deg"),
        "{table}"
    );
}

/// The example (steering, then braking) runs, draws, and says where it started; a source of
/// separation velocities is refused, and another command points to `pim runout`.
#[test]
fn the_example_and_what_a_motion_case_refuses() {
    let svg = scratch_dir("motion", "draw").join("malibu.svg");
    let out = pim_ok(&["runout", MALIBU, "--draw", svg.to_str().unwrap()]);
    let table = String::from_utf8(out.stdout).unwrap();
    assert!(
        table.contains("start: the state stated in [start] (no impact)"),
        "{table}"
    );
    assert!(
        table.contains(
            "inputs      from 0.00 s: steer 5.8 / 5.5 deg over 0.50 s; from 2.00 s: braking \
             0.50 over 0.30 s"
        ),
        "{table}"
    );
    let drawn = std::fs::read_to_string(&svg).unwrap();
    assert!(drawn.contains("bold outline: at the start"));
    let out = pim(&["runout", MALIBU, "--from", "solve"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("a motion case starts from [start]"),
        "{}",
        stderr(&out)
    );
    let out = pim(&["solve", MALIBU]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("[start] makes it a motion case"),
        "{}",
        stderr(&out)
    );
}
