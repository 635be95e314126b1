//! The geometry at contact moved by hand: a vehicle's CG and heading, the impact centre and
//! the crush surface's normal written back in the file's own form, unit and frame; the plan of
//! the edited text puts each where the page asked, and nothing else of the file changes.

use crate::example;
use pim_serve::{answer_following, edit_contact, ContactChange, Plan};

/// The lines that differ (same count of lines required).
fn changed(a: &str, b: &str) -> Vec<String> {
    let (a, b): (Vec<&str>, Vec<&str>) = (a.lines().collect(), b.lines().collect());
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(&b)
        .filter(|(x, y)| x != y)
        .map(|(_, y)| y.to_string())
        .collect()
}

/// The plan of `text` and the outcome to follow: the first whole, the next ones following it
/// (the plan's geometry does not depend on the search, and a whole answer of a moved vehicle
/// would search and tabulate its conflicts).
fn plan(
    file: &str,
    text: &str,
    previous: Option<&pim_reconstruct::Outcome>,
) -> (Plan, Option<pim_reconstruct::Outcome>) {
    let (a, o) = answer_following(file, text, previous).unwrap();
    (a.plan, o.or_else(|| previous.cloned()))
}

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} against {b}");
}

/// SAE, feet, `[impact] centre` with each CG `position`, the crush surface from vehicle 1's
/// nose: the page's right is +y, up is +x, headings clockwise from x.
#[test]
fn an_sae_case_with_positions_is_edited_in_its_own_form() {
    let file = "reconstruction_us.toml";
    let text = example(file);
    let (before, first) = plan(file, &text, None);
    let first = first.as_ref();
    // Vehicle 2 moved to the page point (3.0, 2.5) ft: position.y = 3.0, position.x = 2.5.
    let moved = edit_contact(
        file,
        &text,
        &ContactChange {
            vehicle: Some(2),
            at: Some([3.0, 2.5]),
            ..Default::default()
        },
        None,
    )
    .unwrap();
    assert_eq!(changed(&text, &moved), ["position = { x = 2.5, y = 3.0 }"]);
    let drawn = plan(file, &moved, first).0;
    close(drawn.vehicles[1].cg[0], 3.0, 1e-6, "cg h");
    close(drawn.vehicles[1].cg[1], 2.5, 1e-6, "cg v");
    close(
        drawn.vehicles[1].heading,
        before.vehicles[1].heading,
        1e-9,
        "heading kept",
    );
    // Turned to 60 deg on the page: 30 deg clockwise from north.
    let turned = edit_contact(
        file,
        &moved,
        &ContactChange {
            vehicle: Some(2),
            heading: Some(60.0),
            ..Default::default()
        },
        None,
    )
    .unwrap();
    assert_eq!(changed(&moved, &turned), ["heading = 30.0"]);
    let drawn = plan(file, &turned, first).0;
    close(drawn.vehicles[1].heading, 60.0, 1e-9, "heading");
    close(drawn.vehicles[1].cg[0], 3.0, 1e-6, "the CG stays");
    // The crush surface's normal to 80 deg on the page: 10 deg clockwise from vehicle 1's
    // nose, which points north.
    let normal = edit_contact(
        file,
        &text,
        &ContactChange {
            normal: Some(80.0),
            ..Default::default()
        },
        None,
    )
    .unwrap();
    assert_eq!(
        changed(&text, &normal),
        ["crush_angle_from_vehicle1 = 10.0     # the crush plane square to the sedan's axis"]
    );
    close(
        plan(file, &normal, first).0.impact.unwrap().normal,
        80.0,
        1e-9,
        "normal",
    );
    close(
        before.impact.as_ref().unwrap().normal,
        90.0,
        1e-9,
        "normal before",
    );
    // The impact centre moved; the CGs stay.
    let centre = edit_contact(
        file,
        &text,
        &ContactChange {
            centre: Some([1.0, -2.0]),
            ..Default::default()
        },
        None,
    )
    .unwrap();
    assert_eq!(
        changed(&text, &centre),
        ["centre = { x = -2.0, y = 1.0 }       # the impact area is the diagram's origin"]
    );
    let drawn = plan(file, &centre, first).0;
    let c = drawn.impact.unwrap().centre;
    close(c[0], 1.0, 1e-9, "centre h");
    close(c[1], -2.0, 1e-9, "centre v");
    for k in 0..2 {
        close(
            drawn.vehicles[k].cg[0],
            before.vehicles[k].cg[0],
            1e-9,
            "cg",
        );
        close(
            drawn.vehicles[k].cg[1],
            before.vehicles[k].cg[1],
            1e-9,
            "cg",
        );
    }
}

/// Natural frame, metres, each vehicle's `impact_point` (the centre at the origin): a vehicle
/// moved or turned keeps the centre where it is (its impact point is rewritten); the centre
/// itself is refused with the way to move it.
#[test]
fn a_case_with_impact_points_keeps_its_centre() {
    let file = "runout_scene.toml";
    let text = example(file);
    let (before, first) = plan(file, &text, None);
    let first = first.as_ref();
    close(
        before.impact.as_ref().unwrap().centre[0],
        0.0,
        1e-12,
        "centre",
    );
    // Vehicle 2 turned 10 deg about its CG.
    let h0 = before.vehicles.iter().find(|v| v.vehicle == 2).unwrap();
    let turned = edit_contact(
        file,
        &text,
        &ContactChange {
            vehicle: Some(2),
            heading: Some(h0.heading + 10.0),
            ..Default::default()
        },
        None,
    )
    .unwrap();
    let lines = changed(&text, &turned);
    assert_eq!(lines.len(), 2, "{lines:?}");
    assert!(lines[0].starts_with("heading = 100.0"), "{lines:?}");
    assert!(lines[1].starts_with("impact_point = { x = "), "{lines:?}");
    let drawn = plan(file, &turned, first).0;
    let h1 = drawn.vehicles.iter().find(|v| v.vehicle == 2).unwrap();
    close(h1.heading, h0.heading + 10.0, 1e-9, "heading");
    // The impact point is written to a centimetre: the CG stays within one.
    close(h1.cg[0], h0.cg[0], 0.01, "cg x");
    close(h1.cg[1], h0.cg[1], 0.01, "cg y");
    close(
        drawn.impact.unwrap().centre[0],
        0.0,
        1e-12,
        "the centre stays",
    );
    // Vehicle 1's CG moved to (-2.5, 0.3) m.
    let moved = edit_contact(
        file,
        &text,
        &ContactChange {
            vehicle: Some(1),
            at: Some([-2.5, 0.3]),
            ..Default::default()
        },
        None,
    )
    .unwrap();
    assert_eq!(
        changed(&text, &moved),
        ["impact_point = { x = 2.5, y = -0.3 }"]
    );
    let e = edit_contact(
        file,
        &text,
        &ContactChange {
            centre: Some([1.0, 1.0]),
            ..Default::default()
        },
        None,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("write [impact] centre with each vehicle's CG position"),
        "{e}"
    );
}

/// Bad changes are refused, not written.
#[test]
fn bad_changes_are_refused() {
    let file = "reconstruction_us.toml";
    let text = example(file);
    let bad = |c: ContactChange| edit_contact(file, &text, &c, None).unwrap_err().to_string();
    assert!(bad(ContactChange {
        vehicle: Some(3),
        at: Some([0.0, 0.0]),
        ..Default::default()
    })
    .contains("vehicle 3"));
    assert!(bad(ContactChange {
        vehicle: Some(1),
        at: Some([f64::NAN, 0.0]),
        ..Default::default()
    })
    .contains("not a number"));
    let polar = text.replace("position = { x = 1.0, y = 1.5 }", "d = 1.8\nphi = 10.0");
    assert!(edit_contact(
        file,
        &polar,
        &ContactChange {
            vehicle: Some(2),
            heading: Some(0.0),
            ..Default::default()
        },
        None
    )
    .is_err());
}
