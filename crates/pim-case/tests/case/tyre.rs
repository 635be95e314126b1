//! The three ways a case gives the run-out's linear tyre read to one saturation angle, and
//! PC-Crash's "maximum slip angle" means what PC-Crash means by it: the lateral force per unit
//! load `min(alpha / max_slip_angle, friction)`, saturating at `friction x max_slip_angle`.

use pim_case::case::Case;

fn example() -> String {
    let p = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/cases/runout_scene.toml"
    );
    std::fs::read_to_string(p).unwrap()
}

/// The saturation angle (deg) of vehicle 2's run-out with `line` added to its section, on a
/// road of friction 0.76.
fn saturation(line: &str) -> Result<f64, String> {
    let text = example().replace(
        "[runout.vehicle2]\n",
        &format!("[runout.vehicle2]\nfriction = 0.76\n{line}\n"),
    );
    let case = Case::from_text("tyre.toml", &text).map_err(|e| e.to_string())?;
    let inputs = case.scene_inputs().map_err(|e| e.to_string())?;
    Ok(inputs.vehicles[0].chassis.saturation_angle.to_degrees())
}

#[test]
fn pc_crash_max_slip_angle_saturates_at_friction_times_it() {
    let pc = saturation("max_slip_angle = 10.0").unwrap();
    assert!((pc - 7.6).abs() < 1e-12, "{pc}");
    // The same tyre as a cornering stiffness of 1/10 per degree.
    let cs = saturation("cornering_stiffness = 0.1").unwrap();
    assert!((cs - pc).abs() < 1e-12, "{cs} {pc}");
    // The toolkit's own parameter is the angle of saturation itself.
    let own = saturation("saturation_angle = 10.0").unwrap();
    assert!((own - 10.0).abs() < 1e-12, "{own}");
    assert!((saturation("").unwrap() - 10.0).abs() < 1e-12);
}

#[test]
fn two_ways_at_once_or_a_bad_angle_are_refused_with_the_line() {
    let e = saturation("saturation_angle = 10.0\nmax_slip_angle = 10.0").unwrap_err();
    assert!(
        e.starts_with("tyre.toml:")
            && e.contains("runout.vehicle2.max_slip_angle")
            && e.contains("not saturation_angle and max_slip_angle"),
        "{e}"
    );
    let e = saturation("max_slip_angle = -3.0").unwrap_err();
    assert!(
        e.contains("max_slip_angle") && e.contains("must be above 0"),
        "{e}"
    );
}

/// Vehicle 2's front wheels' steer angles (deg) with `lines` added to its section.
fn steer(lines: &str) -> Result<[f64; 2], String> {
    let text = example().replace(
        "[runout.vehicle2]\n",
        &format!("[runout.vehicle2]\n{lines}\n"),
    );
    let case = Case::from_text("steer.toml", &text).map_err(|e| e.to_string())?;
    let inputs = case.scene_inputs().map_err(|e| e.to_string())?;
    Ok(inputs.vehicles[0].chassis.steer.map(f64::to_degrees))
}

#[test]
fn steering_per_wheel_and_by_the_steering_wheel() {
    assert!(steer("").unwrap().iter().all(|a| a.abs() < 1e-15));
    let both = steer("steer = 5.0").unwrap();
    assert!((both[0] - 5.0).abs() < 1e-12 && (both[1] - 5.0).abs() < 1e-12);
    let each = steer("steer = { front_left = 6.1, front_right = 4.4 }").unwrap();
    assert!((each[0] - 6.1).abs() < 1e-12 && (each[1] - 4.4).abs() < 1e-12);
    // 90 deg at the steering wheel over 16: 5.625 deg for the middle of the axle; the example's
    // wheelbase 2.55 m and track 1.5 m give the inner (left) wheel more, by Ackermann.
    let sw = steer("steering_wheel = 90.0\nsteer_ratio = 16.0").unwrap();
    let expected = pim_runout::ackermann(5.625f64.to_radians(), 2.55, 1.5)
        .unwrap()
        .map(f64::to_degrees);
    assert!((sw[0] - expected[0]).abs() < 1e-9 && (sw[1] - expected[1]).abs() < 1e-9);
    assert!(sw[0] > 5.625 && sw[1] < 5.625, "{sw:?}");
    let e = steer("steering_wheel = 90.0").unwrap_err();
    assert!(
        e.contains("runout.vehicle2.steering_wheel") && e.contains("needs steer_ratio"),
        "{e}"
    );
    let e = steer("steer = 3.0\nsteering_wheel = 90.0\nsteer_ratio = 16.0").unwrap_err();
    assert!(e.contains("not both"), "{e}");
    let e = steer("steer = { front_left = 6.1 }").unwrap_err();
    assert!(e.contains("runout.vehicle2.steer"), "{e}");
}
