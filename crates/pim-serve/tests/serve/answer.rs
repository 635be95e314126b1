//! The server's answers without a browser: the rest moved in each frame and unit, a live answer
//! against the whole search.

use crate::{changed_lines, example};
use std::path::Path;

fn rest_line(text: &str, vehicle: u8) -> String {
    let section = format!("[scene.vehicle{vehicle}]");
    let at = text.find(&section).unwrap();
    text[at..]
        .lines()
        .find(|l| l.starts_with("rest ="))
        .unwrap()
        .to_string()
}

/// A natural-frame SI case: the page point is (x, y) in metres; the comment after it is kept.
#[test]
fn moves_a_natural_si_rest() {
    let text = example("runout_scene.toml");
    let moved = pim_serve::move_rest("runout_scene.toml", &text, 2, [10.004, 1.5]).unwrap();
    assert_eq!(
        rest_line(&moved, 2),
        "rest = { x = 10.0, y = 1.5, heading = 2.7 }           # m, m, deg"
    );
    let (a, b): (Vec<&str>, Vec<&str>) = (text.lines().collect(), moved.lines().collect());
    assert_eq!(a.len(), b.len());
    assert_eq!(a.iter().zip(&b).filter(|(x, y)| x != y).count(), 1);
}

/// An SAE case in feet: the page's right is +y, up is +x.
#[test]
fn moves_an_sae_us_rest() {
    let text = example("reconstruction_us.toml");
    let moved = pim_serve::move_rest("reconstruction_us.toml", &text, 2, [81.7, 52.06]).unwrap();
    assert_eq!(
        rest_line(&moved, 2),
        "rest = { x = 52.06, y = 81.7, heading = 241.0 }"
    );
    // Bad requests are refused, not written.
    assert!(pim_serve::move_rest("r.toml", &text, 3, [0.0, 0.0]).is_err());
    assert!(pim_serve::move_rest("r.toml", &text, 1, [f64::NAN, 0.0]).is_err());
    assert!(pim_serve::move_rest("r.toml", "not = [toml", 1, [0.0, 0.0]).is_err());
}

/// A rest given by tyre points is dragged whole: both points move by the CG's offset, and the
/// plan's measured rest (its handle at the CG the tyres imply) lands on the page point, to the
/// hundredth the file writes.
#[test]
fn moves_a_rest_given_by_tyre_points() {
    let text = example("reconstruction_us.toml").replace(
        "rest = { x = 50.1, y = 79.7, heading = 241.0 }\nrest_sigma = { x = 1.0, y = 1.0, heading = 3.0 }",
        "rest_tyres = [ { wheel = \"front_left\", x = 48.6, y = 77.3, sigma = 0.3 },\n  \
         { wheel = \"rear_left\", x = 53.0, y = 85.3, sigma = 0.3 } ]",
    );
    assert!(text.contains("rest_tyres"));
    let before = pim_serve::answer("t.toml", &text).unwrap();
    let at = |a: &pim_serve::Answer| {
        a.plan
            .vehicles
            .iter()
            .find(|v| v.vehicle == 2)
            .and_then(|v| v.given_rest.as_ref())
            .unwrap()
            .at
    };
    let [h, v] = at(&before);
    let moved = pim_serve::move_rest("t.toml", &text, 2, [h + 2.0, v - 1.0]).unwrap();
    let line = moved.lines().find(|l| l.starts_with("rest_tyres")).unwrap();
    // SAE: the page's right is +y, up is +x.
    assert_eq!(
        line,
        "rest_tyres = [ { wheel = \"front_left\", x = 47.6, y = 79.3, sigma = 0.3 },"
    );
    assert!(moved.contains("{ wheel = \"rear_left\", x = 52.0, y = 87.3, sigma = 0.3 } ]"));
    let after = pim_serve::answer("t.toml", &moved).unwrap();
    let [h2, v2] = at(&after);
    assert!(
        (h2 - h - 2.0).abs() < 1e-9 && (v2 - v + 1.0).abs() < 1e-9,
        "{h2} {v2}"
    );
}

/// A live answer (refined from the last one) after a rest moved 0.3 m lands where the whole
/// search lands: the same chi-square to 1e-3 and speeds to 1 cm/s.
#[test]
fn a_live_answer_follows_the_whole_search() {
    let file = "reconstruction_us.toml";
    let text = example(file);
    let (_, outcome) = pim_serve::answer_following(file, &text, None).unwrap();
    let moved = pim_serve::move_rest(file, &text, 2, [79.7 + 1.0, 50.1]).unwrap();
    let (live, _) = pim_serve::answer_following(file, &moved, outcome.as_ref()).unwrap();
    let whole = pim_serve::answer(file, &moved).unwrap();
    assert!(live.live && !whole.live);
    let best = |a: &pim_serve::Answer| a.document["best"].clone();
    let (l, w) = (best(&live), best(&whole));
    let chi = |b: &serde_json::Value| b["chi_square"].as_f64().unwrap();
    assert!(
        (chi(&l) - chi(&w)).abs() < 1e-3,
        "{} against {}",
        chi(&l),
        chi(&w)
    );
    for v in 0..2 {
        let s = |b: &serde_json::Value| b["vehicles"][v]["speed_at_contact"].as_f64().unwrap();
        assert!((s(&l) - s(&w)).abs() < 0.01, "{} against {}", s(&l), s(&w));
    }
    // The plan draws both vehicles, their paths and the rests given.
    assert_eq!(whole.plan.vehicles.len(), 2);
    assert!(whole
        .plan
        .vehicles
        .iter()
        .all(|v| v.path.len() > 10 && v.given_rest.is_some()));
}

/// The page's uncertainty study is `pim uncertainty`'s: the draws asked for, the quantities of
/// every phase, and a cancel that leaves the draws finished as the answer.
#[test]
fn a_study_and_a_cancelled_one() {
    use pim_studies::watch::{CancelSwitch, Unwatched};
    let text = example("reconstruction_us.toml");
    let doc = pim_serve::study("reconstruction_us.toml", &text, (8, 1), &[], &Unwatched).unwrap();
    assert_eq!(doc["draws"], 8);
    assert!(doc["cancelled"].is_null());
    let q = &doc["quantities"]["vehicle2.speed_at_contact"];
    assert!(q["p05"].as_f64().unwrap() <= q["p95"].as_f64().unwrap());
    let stop = CancelSwitch::default();
    stop.cancel();
    let doc = pim_serve::study("reconstruction_us.toml", &text, (8, 1), &[], &stop);
    // Stopped before its first draw: cancelled with none done, or no intervals to give.
    match doc {
        Ok(d) => assert_eq!(d["cancelled"]["done"], 0, "{d}"),
        Err(e) => assert!(e.to_string().contains("draw"), "{e}"),
    }
    let e = pim_serve::study("reconstruction_us.toml", &text, (0, 1), &[], &Unwatched).unwrap_err();
    assert!(e.to_string().contains("between 1 and"), "{e}");
}

/// The background set to scale by two points and a distance in the page's unit: the points and
/// the distance written in the file's (ft), the first point's page position in its frame (SAE:
/// the page's right is +y), every other line kept.
#[test]
fn a_background_set_to_scale() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/scene");
    let text = std::fs::read_to_string(root.join("intersection_us.toml")).unwrap();
    let change = pim_serve::BackgroundChange {
        pixels: Some([[1000.04, 1460.0], [1599.96, 1460.0]]),
        distance: Some(9.144),
        at: Some([40.0, -66.0]),
        ..Default::default()
    };
    let out = pim_serve::set_background(
        "scene/intersection_us.toml",
        &text,
        &change,
        Some(pim_case::units::UnitSystem::Si),
    )
    .unwrap();
    let changed = changed_lines(&out, &text);
    // The points round to the tenth of a pixel they were: only the distance and `at` change.
    assert_eq!(changed.len(), 2, "{changed:?}");
    assert!(out.contains("distance = 30.0"), "{out}");
    assert!(out.contains("at = { x = -216.535, y = 131.234 }"), "{out}");
    let a = pim_serve::answer("scene/intersection_us.toml", &out).unwrap();
    let b = a.plan.background.unwrap();
    assert_eq!(b.image, "scene/intersection.png");
    assert!((b.per_pixel - 0.05).abs() < 1e-3, "{}", b.per_pixel);
}

/// A piece of evidence switched off: the answer is the reconstruction of the case with its
/// lines deleted (the same document), every piece is listed with its largest residual, the
/// piece off has none, and a name that is no piece is refused with the names there are.
#[test]
fn evidence_switched_off_is_the_case_without_it() {
    let file = "reconstruction_us.toml";
    let text = example(file);
    let edr = "vehicle2 EDR speed 0.5 s before contact".to_string();
    let (all, _) = pim_serve::answer_without(file, &text, None, None, &[]).unwrap();
    let names: Vec<&str> = all.pieces.iter().map(|p| p.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "the estimates ([estimates])",
            "sedan tracking",
            "SUV tracking",
            edr.as_str(),
            "vehicle1 rest",
            "vehicle1 mark 1",
            "vehicle2 rest",
            "vehicle2 mark 1"
        ]
    );
    // The EDR's residual is -0.20 sigma in the answer with everything (`pim fit` prints it).
    let z = all.pieces[3].z.unwrap();
    assert!((z + 0.20).abs() < 0.005, "EDR z {z}");
    assert!(all.pieces.iter().all(|p| !p.off && p.z.is_some()));
    // Each piece says what it is (the plan finds the piece it draws by that), and its residual
    // is the largest of the evidence table's rows whose source it holds.
    let ids: Vec<(&str, Option<u8>, Option<usize>)> = all
        .pieces
        .iter()
        .map(|p| (p.id.kind, p.id.vehicle, p.id.index))
        .collect();
    assert_eq!(
        ids,
        [
            ("estimates", None, None),
            ("observation", None, Some(0)),
            ("observation", None, Some(1)),
            ("edr", Some(2), Some(0)),
            ("rest", Some(1), None),
            ("mark", Some(1), Some(0)),
            ("rest", Some(2), None),
            ("mark", Some(2), Some(0)),
        ]
    );
    let rows = all.document["best"]["evidence"].as_array().unwrap();
    let largest = |pick: &dyn Fn(&serde_json::Value) -> bool| {
        rows.iter()
            .filter(|r| pick(&r["source"]))
            .map(|r| r["z"].as_f64().unwrap())
            .max_by(|a, b| a.abs().total_cmp(&b.abs()))
    };
    let rest2 = largest(&|s| {
        s["kind"] == "scene"
            && s["vehicle"] == 2
            && ["rest_x", "rest_y", "rest_heading"].contains(&s["what"]["kind"].as_str().unwrap())
    });
    assert_eq!(all.pieces[6].z, rest2);
    let estimates = largest(&|s| s["kind"] == "estimate");
    assert_eq!(all.pieces[0].z, estimates);

    let (off, _) =
        pim_serve::answer_without(file, &text, None, None, std::slice::from_ref(&edr)).unwrap();
    let deleted: String = text
        .lines()
        .filter(|l| !l.starts_with("edr = "))
        .map(|l| format!("{l}\n"))
        .collect();
    let without = pim_serve::answer(file, &deleted).unwrap();
    assert_eq!(off.document, without.document);
    assert_ne!(off.document, all.document);
    let p = off.pieces.iter().find(|p| p.name == edr).unwrap();
    assert!(p.off && p.z.is_none());
    // The plan still shows every mark and rest.
    assert_eq!(off.plan.vehicles.len(), 2);
    assert!(off
        .plan
        .vehicles
        .iter()
        .all(|v| v.given_rest.is_some() && v.marks.len() == 1));

    let e = pim_serve::answer_without(file, &text, None, None, &["vehicle3 rest".to_string()])
        .err()
        .unwrap()
        .to_string();
    assert!(
        e.contains("\"vehicle3 rest\" is no piece") && e.contains("vehicle2 mark 1"),
        "{e}"
    );
    // The study of the case without it is the study of the case with its lines deleted.
    let a = pim_serve::study(
        file,
        &text,
        (6, 1),
        std::slice::from_ref(&edr),
        &pim_studies::watch::Unwatched,
    )
    .unwrap();
    let b = pim_serve::study(file, &deleted, (6, 1), &[], &pim_studies::watch::Unwatched).unwrap();
    assert_eq!(a, b);
}

/// A tyre mark dragged: its x and y rewritten in the file's unit and frame (SAE: the page's
/// right is +y), the rest of its entry and the line's comment kept; a mark the case does not
/// have is refused.
#[test]
fn moves_a_tyre_mark() {
    let text = example("reconstruction_us.toml");
    let moved =
        pim_serve::move_mark("reconstruction_us.toml", &text, (1, 0), [2.5, 11.0], None).unwrap();
    assert_eq!(
        changed_lines(&moved, &text),
        ["marks = [ { x = 11.0, y = 2.5, sigma = 0.5 } ]     # a yaw mark the CG passed"]
    );
    let e = pim_serve::move_mark("reconstruction_us.toml", &text, (1, 3), [0.0, 0.0], None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("the array has 1 entries"), "{e}");
    assert!(pim_serve::move_mark("r.toml", &text, (3, 0), [0.0, 0.0], None).is_err());
}

/// A skid set from the page: `[pre_impact.vehicleN] skid` rewritten in the file's unit (the
/// comment kept), drawn at that length behind the CG; a bad length is refused.
#[test]
fn sets_a_skid() {
    let file = "reconstruction_us.toml";
    let text = example(file);
    let (a, outcome) = pim_serve::answer_following(file, &text, None).unwrap();
    assert_eq!(a.plan.vehicles[0].skid, Some(42.0));
    assert_eq!(a.plan.vehicles[1].skid, None);
    let set = pim_serve::set_skid(file, &text, (1, 30.004), None).unwrap();
    assert_eq!(
        changed_lines(&set, &text),
        ["skid = 30.0                         # ft of locked-wheel skid up to the impact"]
    );
    let (b, _) = pim_serve::answer_following(file, &set, outcome.as_ref()).unwrap();
    assert_eq!(b.plan.vehicles[0].skid, Some(30.0));
    // In metres on the page: written in the file's feet.
    let si = pim_serve::set_skid(
        file,
        &text,
        (1, 9.144),
        Some(pim_case::units::UnitSystem::Si),
    )
    .unwrap();
    assert!(si.contains("skid = 30.0 "), "{si}");
    assert!(pim_serve::set_skid(file, &text, (1, -1.0), None).is_err());
    assert!(pim_serve::set_skid(file, &text, (3, 10.0), None).is_err());
}

/// A study's bands: each vehicle's run-out from the velocities at separation of each feasible
/// draw, on the page; each ends near the rest the scene gives (the draws move the rests by
/// their sigma of 1 ft); the document is the study's, bands or not.
#[test]
fn a_studys_bands_are_the_draws_run_outs() {
    let file = "reconstruction_us.toml";
    let text = example(file);
    let s = pim_serve::studied(
        file,
        &text,
        (8, 1),
        (&[], None),
        &pim_studies::watch::Unwatched,
    )
    .unwrap();
    let feasible = s.document["feasible_draws"].as_u64().unwrap() as usize;
    assert_eq!(s.bands.len(), 2 * feasible.min(pim_serve::BAND_DRAWS));
    let plan = pim_serve::answer(file, &text).unwrap().plan;
    for (vehicle, path) in &s.bands {
        let rest = plan.vehicles[usize::from(*vehicle) - 1]
            .given_rest
            .as_ref()
            .unwrap()
            .at;
        let end = path.last().unwrap();
        let d = (end[0] - rest[0]).hypot(end[1] - rest[1]);
        assert!(
            d < 6.0,
            "vehicle {vehicle}'s band ends {d} ft from the rest"
        );
    }
    let doc = pim_serve::study(file, &text, (8, 1), &[], &pim_studies::watch::Unwatched).unwrap();
    assert_eq!(doc, s.document);
}

/// The page's batch: `pim batch`'s records of the files (a file that cannot be read gives
/// failed records and the batch goes on); cancelled before it starts, it says so.
#[test]
fn a_batch_gives_the_records_of_each_file() {
    use pim_studies::case_batch::CaseText;
    let files = vec![
        CaseText {
            name: "reconstruction_us.toml".into(),
            text: Ok(example("reconstruction_us.toml")),
        },
        CaseText {
            name: "missing.toml".into(),
            text: Err("missing.toml: cannot be read".into()),
        },
    ];
    let doc = pim_serve::batch(&files, &pim_studies::watch::Unwatched);
    assert_eq!(doc["files"], 2);
    let records = doc["records"].as_array().unwrap();
    assert!(records.iter().any(|r| r["file"] == "reconstruction_us.toml"
        && r["best"] == true
        && r["reconstruction"]["status"] == "found"));
    assert!(records
        .iter()
        .any(|r| r["file"] == "missing.toml" && r["outcome"] == "failed"));
    assert!(doc["cancelled"].is_null());
    let stop = pim_studies::watch::CancelSwitch::default();
    stop.cancel();
    let doc = pim_serve::batch(&files, &stop);
    assert_eq!(doc["cancelled"]["done"], 0);
    assert_eq!(doc["records"].as_array().unwrap().len(), 0);
}

/// The crush profile drawn on the outline at contact: the damaged face's width between its two
/// ends, each depth measured in from the face (the sedan's front: 60 in wide, 26 in deepest).
#[test]
fn the_crush_profile_is_drawn_on_the_outline() {
    let file = "reconstruction_damage_us.toml";
    let (a, _) = pim_serve::answer_following(file, &example(file), None).unwrap();
    let d = &a.plan.vehicles[0].damage;
    assert_eq!(d.len(), 9, "{d:?}");
    let (p, q) = (d[0], d[7]);
    let width = (q[0] - p[0]).hypot(q[1] - p[1]);
    assert!((width - 60.0 / 12.0).abs() < 1e-9, "width {width} ft");
    let depth =
        |x: [f64; 2]| ((q[0] - p[0]) * (x[1] - p[1]) - (q[1] - p[1]) * (x[0] - p[0])).abs() / width;
    let deepest = d[1..7].iter().map(|&x| depth(x)).fold(0.0, f64::max);
    assert!((deepest - 26.0 / 12.0).abs() < 1e-9, "deepest {deepest} ft");
    assert_eq!(a.plan.vehicles[1].damage.len(), 9);
    // The deepest point lies behind the face, inside the outline at contact.
    let o = &a.plan.vehicles[0].contact;
    let inside = |x: [f64; 2]| {
        let mut c = false;
        for i in 0..o.len() - 1 {
            let (a, b) = (o[i], o[i + 1]);
            if (a[1] > x[1]) != (b[1] > x[1])
                && x[0] < (b[0] - a[0]) * (x[1] - a[1]) / (b[1] - a[1]) + a[0]
            {
                c = !c;
            }
        }
        c
    };
    assert!(d[1..7].iter().all(|&x| inside(x)), "{d:?} against {o:?}");
}

/// A case that gives its coefficients is solved as `pim solve` solves it (the same text), and
/// both run-outs are drawn from its separation.
#[test]
fn a_case_with_coefficients_is_solved() {
    let file = "runout_spin.toml";
    let text = example(file);
    let a = pim_serve::answer(file, &text).unwrap();
    assert_eq!(a.question, "solve");
    let case = pim_case::case::Case::from_text(file, &text).unwrap();
    let solved = pim_studies::documents::solve(&case, &pim_core::SolveOptions::default()).unwrap();
    assert_eq!(a.document, serde_json::to_value(&solved.document).unwrap());
    assert!(a.table.contains("solved forwards"), "{}", a.table);
    assert_eq!(a.plan.vehicles.len(), 2);
    assert!(a
        .plan
        .vehicles
        .iter()
        .all(|v| v.path.len() > 10 && !v.every.is_empty()));
}

/// A yaw mark traced on the page (the Trace tool): three points of the SUV's fitted CG path,
/// in feet on the SAE page, are appended to `[scene.vehicle2] traces` in the file's frame
/// (x up the page, y to its right) with their wheel and sigma, every other line kept. Traced by
/// the CG the answer meets them (the chi-square within 0.05 of the case's); the same points
/// named the SUV's front right tyre lie a tyre's offset from its path and are not met. One
/// point, a sigma of 0 and a wheel the SUV does not have are refused.
#[test]
fn adds_a_traced_mark() {
    let file = "reconstruction_us.toml";
    let text = example(file);
    let plain = pim_serve::answer(file, &text).unwrap();
    let chi = |a: &pim_serve::Answer| a.document["best"]["chi_square"].as_f64().unwrap();
    let suv = plain.plan.vehicles.iter().find(|v| v.vehicle == 2).unwrap();
    let n = suv.path.len();
    let points: Vec<[f64; 2]> = [n / 5, 2 * n / 5, 3 * n / 5]
        .iter()
        .map(|&i| [suv.path[i][0], suv.path[i][1]])
        .collect();
    let trace = |wheel: &str, sigma: f64, points: Vec<[f64; 2]>| pim_serve::NewTrace {
        vehicle: 2,
        points,
        sigma,
        wheel: wheel.into(),
    };
    let traced =
        pim_serve::add_trace(file, &text, &trace("cg", 0.5, points.clone()), None).unwrap();
    let added: Vec<&str> = traced
        .lines()
        .filter(|l| !text.lines().any(|m| m == *l))
        .collect();
    assert_eq!(traced.lines().count(), text.lines().count() + 1);
    let written: Vec<String> = points
        .iter()
        .map(|p| {
            format!(
                "[{}, {}]",
                (p[1] * 100.0).round() / 100.0,
                (p[0] * 100.0).round() / 100.0
            )
        })
        .collect();
    assert_eq!(
        added,
        [format!(
            "traces = [ {{ wheel = \"cg\", points = [{}], sigma = 0.5 }} ]",
            written.join(", ")
        )],
        "{traced}"
    );
    let (met, on_tyre) = (
        chi(&pim_serve::answer(file, &traced).unwrap()),
        pim_serve::add_trace(
            file,
            &text,
            &trace("front_right", 0.5, points.clone()),
            None,
        )
        .map(|t| chi(&pim_serve::answer(file, &t).unwrap()))
        .unwrap(),
    );
    println!(
        "chi-square {:.3}; traced by the CG {met:.3}, by the front right tyre {on_tyre:.3}",
        chi(&plain)
    );
    assert!((met - chi(&plain)).abs() < 0.05, "{met}");
    assert!(on_tyre > met + 10.0, "{on_tyre}");
    for bad in [
        trace("cg", 0.5, points[..1].to_vec()),
        trace("cg", 0.0, points.clone()),
        trace("middle_left", 0.5, points.clone()),
    ] {
        assert!(pim_serve::add_trace(file, &text, &bad, None).is_err());
    }
}

/// A rest placed by its tyre points (the Tyres tool): written as `rest_tyres` in the file's
/// frame and unit, the CG's `rest` and `rest_sigma` replaced, and the case answered as before
/// (the points are the example's rest's left tyres: SAE, feet). Fewer than two points, or a
/// name that is no tyre, are refused.
#[test]
fn a_rest_is_placed_by_its_tyre_points() {
    use pim_serve::{place_rest_tyres, NewRestTyres, NewTyre};
    let text = example("reconstruction_us.toml");
    let tyre = |at: [f64; 2], name: &str| NewTyre {
        at,
        name: name.into(),
        corner: false,
        point: None,
    };
    // The page's right is +y, up is +x: front left (45.94, 77.66), rear left (50.21, 85.36).
    let rest = NewRestTyres {
        vehicle: 2,
        points: vec![
            tyre([77.66, 45.94], "front_left"),
            tyre([85.36, 50.21], "rear_left"),
        ],
        sigma: 0.3,
    };
    let placed = place_rest_tyres("r.toml", &text, &rest, None).unwrap();
    let section = &placed[placed.find("[scene.vehicle2]").unwrap()..];
    assert!(section.contains(
        "rest_tyres = [\n  { wheel = \"front_left\", x = 45.94, y = 77.66, sigma = 0.3 },\n  { wheel = \"rear_left\", x = 50.21, y = 85.36, sigma = 0.3 },\n]"
    ), "{section}");
    assert!(!section.contains("rest = {") && !section.contains("rest_sigma"));
    let a = pim_serve::answer("r.toml", &placed).unwrap();
    assert_eq!(a.document["status"], "found");
    // Placed again as a CG, the tyre points go.
    let back = pim_serve::place_rest(
        "r.toml",
        &placed,
        &pim_serve::NewRest {
            vehicle: 2,
            at: [79.7, 50.1],
            heading: Some(241.0),
            sigma: 1.0,
            point: None,
        },
        None,
    )
    .unwrap();
    assert!(!back.contains("rest_tyres"));
    // Refused: one point; a name that is no tyre (the case names the field).
    let one = NewRestTyres {
        points: vec![tyre([77.66, 45.94], "front_left")],
        ..rest.clone()
    };
    assert!(place_rest_tyres("r.toml", &text, &one, None).is_err());
    let mut bad = rest.clone();
    bad.points[1].name = "boot".into();
    let e = place_rest_tyres("r.toml", &text, &bad, None)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rest_tyres"), "{e}");
}
