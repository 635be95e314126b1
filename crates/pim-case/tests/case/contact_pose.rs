//! `[contact_sigma]`: the pose at contact as unknowns, read in SI and the natural frame, moved
//! as the module says (a heading about the CG, a CG in the scene with the impact centre held, an
//! impact point on the vehicle with the vehicle following), and refused at the line of the field
//! at fault.
use pim_case::case::Case;
use pim_case::contact_pose::PoseInput;
use std::path::Path;

fn example(sigma: &str) -> Case {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases/reconstruction_us.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    Case::from_text("pose.toml", &format!("{text}\n[contact_sigma]\n{sigma}\n")).unwrap()
}

fn starts(case: &Case) -> Vec<[f64; 3]> {
    case.scene_inputs()
        .unwrap()
        .vehicles
        .iter()
        .map(|v| [v.start.x, v.start.y, v.start.heading])
        .collect()
}

const FOOT: f64 = 0.3048;

/// The SAE example in feet: each standard deviation in metres and radians, in the order
/// written; all offsets zero give the case as it is.
#[test]
fn the_unknowns_are_read_in_si_and_zero_offsets_change_nothing() {
    let case = example(
        "vehicle1 = { heading = 3.0, position = { x = 1.0, y = 2.0 } }\n\
         vehicle2 = { impact_point = { x = 0.8 } }\ncentre = { y = 0.5 }\ncrush_angle = 5.0",
    );
    let u = case.contact_unknowns().unwrap();
    let got: Vec<(PoseInput, f64)> = u.iter().map(|u| (u.input, u.sigma)).collect();
    let expected = [
        (PoseInput::Heading(0), 3f64.to_radians()),
        (PoseInput::Position(0, 0), FOOT),
        (PoseInput::Position(0, 1), 2.0 * FOOT),
        (PoseInput::ImpactPoint(1, 0), 0.8 * FOOT),
        (PoseInput::Centre(1), 0.5 * FOOT),
        (PoseInput::CrushAngle, 5f64.to_radians()),
    ];
    assert_eq!(got.len(), expected.len());
    for ((a, x), (b, y)) in got.iter().zip(expected) {
        assert_eq!(*a, b);
        assert!((x - y).abs() < 1e-12, "{a:?}: {x} vs {y}");
    }
    let same = case.with_contact(&u, &vec![0.0; u.len()]).unwrap();
    for (a, b) in starts(&case).iter().zip(starts(&same)) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() < 1e-12, "{a:?} vs {b:?}");
        }
    }
    let (a, b) = (case.impact().unwrap(), same.impact().unwrap());
    let (a, b) = (*a.collision(), *b.collision());
    for (x, y) in [(a.vehicle1, b.vehicle1), (a.vehicle2, b.vehicle2)] {
        assert!((x.heading - y.heading).abs() < 1e-12 && (x.d - y.d).abs() < 1e-12);
        assert!((x.phi - y.phi).abs() < 1e-10, "{} vs {}", x.phi, y.phi);
    }
    assert!((a.crush_angle - b.crush_angle).abs() < 1e-12);
}

/// A heading turns the vehicle about its CG (its start holds, the impact centre stays where it
/// is in the scene); a CG offset moves the start and nothing else; an impact point moved on the
/// vehicle moves the vehicle the other way; the centre moves the impact centre alone.
#[test]
fn each_offset_moves_what_it_names() {
    let case = example(
        "vehicle1 = { heading = 3.0, position = { x = 1.0, y = 1.0 } }\n\
         vehicle2 = { heading = 3.0, impact_point = { x = 1.0 } }\ncentre = { x = 1.0 }",
    );
    let u = case.contact_unknowns().unwrap();
    let base = starts(&case);
    let c0 = case.impact_centre();
    let at = |k: usize, x: f64| {
        let mut p = vec![0.0; u.len()];
        p[k] = x;
        case.with_contact(&u, &p).unwrap()
    };
    let close = |a: f64, b: f64| (a - b).abs() < 1e-9;
    // vehicle1.heading: its CG holds, its heading turns, the centre holds.
    let turned = at(0, 0.05);
    let s = starts(&turned);
    assert!(close(s[0][0], base[0][0]) && close(s[0][1], base[0][1]));
    assert!(close(s[0][2], base[0][2] + 0.05));
    let c = turned.impact_centre();
    assert!(close(c[0], c0[0]) && close(c[1], c0[1]));
    // vehicle1.position.y: its CG moves, vehicle 2 and the centre hold.
    let moved = at(2, 0.2);
    let s = starts(&moved);
    assert!(close(s[0][1], base[0][1] + 0.2) && close(s[0][0], base[0][0]));
    assert!(close(s[1][0], base[1][0]) && close(s[1][1], base[1][1]));
    // vehicle2.impact_point.x: the impact centre 0.1 m further forward on vehicle 2, held in
    // the scene, so that vehicle 2 moves 0.1 m back along its heading.
    let along = at(4, 0.1);
    let s = starts(&along);
    let h = base[1][2];
    assert!(close(s[1][0], base[1][0] - 0.1 * h.cos()));
    assert!(close(s[1][1], base[1][1] - 0.1 * h.sin()));
    assert!(close(s[0][0], base[0][0]) && close(s[0][1], base[0][1]));
    // vehicle2.heading with its impact point fitted: turned about the impact centre (its CG
    // on a circle about it, 0.05 rad further round).
    let about = at(3, 0.05);
    let s = starts(&about);
    assert!(close(s[1][2], base[1][2] + 0.05));
    let bearing = |p: &[f64; 3]| (p[1] - c0[1]).atan2(p[0] - c0[0]);
    let radius = |p: &[f64; 3]| (p[1] - c0[1]).hypot(p[0] - c0[0]);
    assert!(close(radius(&s[1]), radius(&base[1])));
    assert!(close(bearing(&s[1]), bearing(&base[1]) + 0.05));
    // centre.x: the impact centre moves, vehicle 1 (its CG held) stays, vehicle 2 (its
    // impact point held) moves with it.
    let shifted = at(5, 0.3);
    let s = starts(&shifted);
    assert!(close(s[0][0], base[0][0]) && close(s[0][1], base[0][1]));
    assert!(close(s[1][0], base[1][0] + 0.3) && close(s[1][1], base[1][1]));
    assert!(close(shifted.impact_centre()[0], c0[0] + 0.3));
}

/// The offsets between a case and the same case moved are the offsets it was moved by.
#[test]
fn the_offsets_between_two_cases_invert_the_move() {
    let case = example(
        "vehicle1 = { heading = 3.0, position = { x = 1.0, y = 1.0 } }\n\
         vehicle2 = { heading = 3.0, impact_point = { x = 1.0, y = 0.5 } }\n\
         centre = { x = 1.0, y = 1.0 }\ncrush_angle = 4.0",
    );
    let u = case.contact_unknowns().unwrap();
    let p: Vec<f64> = (0..u.len())
        .map(|k| 0.03 * (k as f64 + 1.0) * if k % 2 == 0 { 1.0 } else { -1.0 })
        .collect();
    let moved = case.with_contact(&u, &p).unwrap();
    let back = moved.contact_offsets_from(&case, &u).unwrap();
    for ((a, b), x) in back.iter().zip(&p).zip(&u) {
        assert!((a - b).abs() < 1e-9, "{}: {a} vs {b}", x.name);
    }
}

fn refused(sigma: &str) -> String {
    example(sigma).contact_unknowns().unwrap_err().to_string()
}

/// Each bad section is refused at its line, naming the field.
#[test]
fn a_bad_contact_sigma_is_refused_at_its_line() {
    let both = refused("vehicle1 = { position = { x = 1.0 }, impact_point = { y = 1.0 } }");
    assert!(
        both.contains("contact_sigma.vehicle1.impact_point") && both.contains("not both"),
        "{both}"
    );
    let zero = refused("vehicle2 = { heading = 0.0 }");
    assert!(
        zero.contains("contact_sigma.vehicle2.heading") && zero.contains("above 0"),
        "{zero}"
    );
    let wide = refused("crush_angle = 120.0");
    assert!(wide.contains("at most 90"), "{wide}");
    let empty = refused("vehicle1 = {}");
    assert!(empty.contains("no standard deviation"), "{empty}");
    // Located: the line of the field.
    assert!(zero.contains(":"), "{zero}");
}
