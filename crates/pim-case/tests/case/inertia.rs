//! A vehicle without a yaw inertia: estimated from its length and width, named as an estimate;
//! refused, naming the field and both ways to give it, when the outline is not given either.
use pim_case::case::Case;
use pim_case::inertia::{from_outline, InertiaSource};

const FOOT: f64 = 0.3048;
const POUND: f64 = 0.453_592_37;

fn example() -> String {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    std::fs::read_to_string(root.join("examples/cases/reconstruction_us.toml")).unwrap()
}

/// The example with vehicle 1's `yaw_inertia = ...` line left out.
fn without_vehicle1_inertia() -> String {
    let text = example();
    let at = text.find("[vehicle1]").unwrap();
    let line = at + text[at..].find("\nyaw_inertia = ").unwrap() + 1;
    let end = line + text[line..].find('\n').unwrap() + 1;
    format!("{}{}", &text[..line], &text[end..])
}

#[test]
fn a_vehicle_without_a_yaw_inertia_takes_the_outlines_estimate() {
    let case = Case::from_text("no_inertia.toml", &without_vehicle1_inertia()).unwrap();
    let v1 = &case.content.vehicle1;
    // 3400 lb, 16 by 6 ft: 0.9 m (L^2 + W^2) / 12.
    let expected = 0.9 * 3400.0 * POUND * ((16.0 * FOOT).powi(2) + (6.0 * FOOT).powi(2)) / 12.0;
    assert!((v1.yaw_inertia - expected).abs() < 1e-9 * expected);
    assert!((v1.yaw_inertia - from_outline(v1.mass, 16.0 * FOOT, 6.0 * FOOT)).abs() < 1e-9);
    assert_eq!(v1.yaw_inertia_source, InertiaSource::Outline);
    // Vehicle 2 writes its own: kept, and not named as an estimate.
    assert_eq!(
        case.content.vehicle2.yaw_inertia_source,
        InertiaSource::Stated
    );
    assert!((case.content.vehicle2.yaw_inertia - 2400.0 * 1.355_817_948).abs() < 1e-3);
    // Named once, in the case's own units (2314 slug ft^2), with its rule.
    let said = case.estimated();
    assert_eq!(said.len(), 1, "{said:?}");
    assert!(
        said[0].starts_with(
            "vehicle1.yaw_inertia: not given, estimated as 2314 slug ft^2 from mass 3400 lb, \
             length 16.00 and width 6.00 ft as 0.9 m (L^2 + W^2) / 12"
        ),
        "{}",
        said[0]
    );
    // An estimate is not a plausibility warning (`--strict` does not fail on it).
    assert!(case.warnings().is_empty(), "{:?}", case.warnings());
}

#[test]
fn without_an_inertia_or_an_outline_the_case_is_refused_at_the_field() {
    let text = without_vehicle1_inertia();
    let at = text.find("[vehicle1]").unwrap();
    let line = at + text[at..].find("\nlength = ").unwrap() + 1;
    let end = line + text[line..].find('\n').unwrap() + 1;
    let text = format!("{}{}", &text[..line], &text[end..]);
    let e = Case::from_text("no_inertia.toml", &text)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains(
            "vehicle1.yaw_inertia: missing or not a number; give its yaw moment of inertia \
             (or length and width, from which it is estimated)"
        ),
        "{e}"
    );
}

#[test]
fn an_inertia_written_as_nan_is_refused_not_estimated() {
    let text = example().replacen("yaw_inertia = 1900.0", "yaw_inertia = nan", 1);
    assert!(text.contains("yaw_inertia = nan"));
    let e = Case::from_text("nan.toml", &text).unwrap_err().to_string();
    assert!(e.contains("vehicle1.yaw_inertia"), "{e}");
}

/// An outline out of its range is refused as the outline (not as the inertia estimated from
/// it); an estimate out of the inertia's range is refused naming it as an estimate.
#[test]
fn an_estimate_from_a_bad_outline_is_refused_at_the_outline() {
    let text = without_vehicle1_inertia();
    let huge = text.replacen("length = 16.0", "length = 1e200", 1);
    let e = Case::from_text("huge.toml", &huge).unwrap_err().to_string();
    assert!(e.contains("vehicle1.length"), "{e}");
    // 230 lb on 2 by 1 ft: 0.9 x 104 kg x 0.46 m^2 / 12 = 3.6 kg m^2, below the 10 of any
    // road vehicle.
    let light = text
        .replacen("mass = 3400.0", "mass = 230.0", 1)
        .replacen("length = 16.0", "length = 2.0", 1)
        .replacen("width = 6.0", "width = 1.0", 1)
        .replacen("cg_to_front = 7.2", "cg_to_front = 1.0", 1);
    assert_eq!(
        light.matches(" = 2.0\n").count(),
        text.matches(" = 2.0\n").count() + 1
    );
    let e = Case::from_text("light.toml", &light)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("vehicle1.yaw_inertia: estimated from the mass, length and width:"),
        "{e}"
    );
}
