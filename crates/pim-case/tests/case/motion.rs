//! A motion case (`[start]`, no impact): read in SI and the natural frame whatever its units
//! and convention, with each misplaced or missing piece refused at its line; per-axle and
//! per-wheel braking in a sequence read to each wheel's share.

use pim_case::case::Case;
use pim_case::motion::is_motion;

fn example() -> String {
    let p = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/motion/malibu_us.toml"
    );
    std::fs::read_to_string(p).unwrap()
}

fn load(text: &str) -> Result<Case, String> {
    Case::motion_from_text("motion.toml", text).map_err(|e| e.to_string())
}

#[test]
fn the_example_reads_in_si_with_its_stated_start() {
    let text = example();
    assert!(is_motion(&text));
    let case = load(&text).unwrap();
    assert!(case.is_motion());
    let inputs = case.scene_inputs().unwrap();
    assert_eq!(inputs.vehicles.len(), 1);
    let v = &inputs.vehicles[0];
    // 3298 lb, 2040 slug ft^2, 30 mph along +x, wheelbase 106 in.
    assert!((v.chassis.mass - 3298.0 * 0.453_592_37).abs() < 1e-9);
    assert!((v.chassis.yaw_inertia - 2040.0 * 1.355_817_948_3).abs() < 1e-6);
    assert!((v.start.vx - 30.0 * 0.447_04).abs() < 1e-12 && v.start.vy.abs() < 1e-12);
    assert!((v.chassis.wheelbase - 8.833 * 0.3048).abs() < 1e-12);
    // PC-Crash's maximum slip angle of 10 deg on 0.76: saturation at 7.6 deg.
    assert!((v.chassis.saturation_angle.to_degrees() - 7.6).abs() < 1e-12);
    assert_eq!(v.chassis.inputs.len(), 2);
    assert_eq!(v.chassis.inputs[1].braking, [Some(0.5); 4]);
    // A case with an impact refuses [start] and says which command follows it.
    let e = Case::from_text("motion.toml", &text)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("[start] makes it a motion case") && e.contains("pim runout motion.toml"),
        "{e}"
    );
}

#[test]
fn a_start_by_components_and_in_the_sae_frame() {
    let text = example().replace(
        "speed = 30.0                 # mph, along the heading\nomega = 0.0",
        "vx = 20.0\nvy = 10.0\nomega = 5.0",
    );
    let natural = load(&text).unwrap().scene_inputs().unwrap().vehicles[0].start;
    let sae = load(&format!(
        "convention = \"sae\"\n{}",
        text.replace("y = 0.0", "y = 2.0")
    ))
    .unwrap()
    .scene_inputs()
    .unwrap()
    .vehicles[0]
        .start;
    assert!((natural.vx - 20.0 * 0.447_04).abs() < 1e-12);
    assert!((natural.vy - 10.0 * 0.447_04).abs() < 1e-12);
    // The case's yaw-rate unit: rad/s (its [units] gives no other).
    assert!((natural.yaw_rate - 5.0).abs() < 1e-12);
    // SAE: y to the right, yaw rates clockwise: mirrored into the natural frame.
    assert!((sae.vy + natural.vy).abs() < 1e-12 && (sae.yaw_rate + natural.yaw_rate).abs() < 1e-12);
    assert!((sae.y + 2.0 * 0.3048).abs() < 1e-12);
}

#[test]
fn misplaced_and_missing_pieces_are_refused_at_their_line() {
    let refused = |text: &str, words: &[&str]| {
        let e = load(text).unwrap_err();
        assert!(e.starts_with("motion.toml:"), "{e}");
        for w in words {
            assert!(e.contains(w), "{w:?} not in {e}");
        }
    };
    let base = example();
    refused(
        &format!("{base}\n[impact]\ncrush_angle = 0.0\n"),
        &["impact", "no impact sections"],
    );
    refused(
        &base.replace("speed = 30.0 ", "speed = 30.0\nvx = 3.0 "),
        &["start.vehicle1.speed", "not both"],
    );
    refused(
        &base.replace("speed = 30.0 ", "vy = 3.0 "),
        &["start.vehicle1", "both vx and vy"],
    );
    refused(
        &base.replace("[start.vehicle1]", "[start.vehicle2]"),
        &["vehicle1", "needs [start.vehicle1]"],
    );
    refused(
        &format!("{base}\n[start.vehicle2]\nx = 1.0\ny = 1.0\nheading = 0.0\nspeed = 1.0\n"),
        &["start.vehicle2", "no [vehicle2]"],
    );
    refused(
        &base.replace("mass = 3298.0", "mass = 3.0"),
        &["vehicle1.mass", "between"],
    );
    refused(
        &base.replace("heading = 0.0                # deg", "heading = 1000.0"),
        &["start.vehicle1.heading"],
    );
    refused(
        &base.replace("braking = 0.5,", "braking = { front = 0.5, middle = 0.2 },"),
        &["runout.vehicle1.inputs", "middle", "not an axle or a wheel"],
    );
    refused(
        &base.replace("braking = 0.5,", "braking = { rear = 1.5 },"),
        &["rear", "between 0 and 1"],
    );
}

#[test]
fn braking_by_axle_and_by_wheel_the_wheel_before_its_axle() {
    let text = example().replace(
        "braking = 0.5,",
        "braking = { front = 0.8, rear = 0.3, rear_right = 0.1 },",
    );
    let v = &load(&text).unwrap().scene_inputs().unwrap().vehicles[0];
    assert_eq!(
        v.chassis.inputs[1].braking,
        [Some(0.8), Some(0.8), Some(0.3), Some(0.1)]
    );
    let text = example().replace("braking = 0.5,", "braking = { front_left = 0.4 },");
    let v = &load(&text).unwrap().scene_inputs().unwrap().vehicles[0];
    assert_eq!(v.chassis.inputs[1].braking, [Some(0.4), None, None, None]);
}
