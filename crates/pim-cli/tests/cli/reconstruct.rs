//! `pim fit` and `pim uncertainty` of a case with scene evidence: the three phases in one fit,
//! the speeds of every phase, the evidence against the fit, the counts of turns compared, the
//! intervals through all phases, and the answers to contradictory or bad input.
use crate::common;
use common::*;

const CASE: &str = "examples/cases/reconstruction_us.toml";
const MPH: f64 = 0.44704;

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

fn num(v: &serde_json::Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn case_with(name: &str, from: &str, to: &str) -> String {
    let text = std::fs::read_to_string(repo().join(CASE)).unwrap();
    assert!(text.contains(from), "{from}");
    scratch_file("reconstruct", name, text.replace(from, to))
}

/// `pim fit --out` writes the plan for CAD (`scene.dxf`) beside the figure: read back by a DXF
/// reader, it has its layers and feet as its unit; both vehicles' outlines at contact and at
/// rest are closed four-cornered polylines in their colours (blue 5, red 1); each CG path ends at
/// the answer's rest (on the SAE plan: right is y, up is x, in feet).
#[test]
fn the_scene_for_cad_is_written_beside_the_figure() {
    let dir = scratch_dir("reconstruct", "cad").join("out");
    let out = pim_ok(&["fit", CASE, "--out", dir.to_str().unwrap()]);
    assert!(out.status.success());
    let d = dxf::Drawing::load_file(dir.join("scene.dxf")).unwrap();
    let layers: Vec<&str> = d.layers().map(|l| l.name.as_str()).collect();
    for l in ["CONTACT", "REST", "PATHS", "EVIDENCE", "IMPACT"] {
        assert!(layers.contains(&l), "{layers:?}");
    }
    assert_eq!(d.header.default_drawing_units, dxf::enums::Units::Feet);
    type Polyline = (u8, Vec<(f64, f64)>, bool);
    let on = |layer: &str| -> Vec<Polyline> {
        d.entities()
            .filter(|e| e.common.layer == layer)
            .filter_map(|e| match &e.specific {
                dxf::entities::EntityType::LwPolyline(p) => Some((
                    e.common.color.index().unwrap_or(0),
                    p.vertices.iter().map(|v| (v.x, v.y)).collect(),
                    p.is_closed(),
                )),
                _ => None,
            })
            .collect()
    };
    for layer in ["CONTACT", "REST"] {
        let outlines = on(layer);
        assert_eq!(outlines.len(), 2);
        assert!(outlines
            .iter()
            .all(|(_, v, closed)| v.len() == 4 && *closed));
        let mut colors: Vec<u8> = outlines.iter().map(|o| o.0).collect();
        colors.sort();
        assert_eq!(colors, [1, 5]);
    }
    let result: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap();
    let paths = on("PATHS");
    for v in result["best"]["vehicles"].as_array().unwrap() {
        let color = if v["vehicle"] == 1 { 5 } else { 1 };
        let path = &paths.iter().find(|p| p.0 == color).unwrap().1;
        let rest = &v["rest"];
        let last = path[path.len() - 1];
        let foot = 0.3048;
        assert!(
            (last.0 + num(&rest["y"]) / foot).abs() < 1e-6,
            "{last:?} {rest}"
        );
        assert!(
            (last.1 - num(&rest["x"]) / foot).abs() < 1e-6,
            "{last:?} {rest}"
        );
    }
}

/// The example's scene was made by solving the crash forwards (38 and 27 mph, e = 0.12,
/// mu = 0.15, no moment impulse) and running both cars out to rest with the run-out model; the
/// rests were rounded to 0.1 ft and 1 deg, the marks read off the paths. The reconstruction
/// finds the speeds back within what that rounding allows (0.2 mph), and the speed before the
/// sedan's 42 ft skid from v0^2 = vc^2 + 2 mu g d.
#[test]
fn the_example_is_reconstructed() {
    let v = json(&pim_ok(&["fit", CASE, "--format", "json"]));
    assert_eq!(v["kind"], "reconstruction");
    assert_eq!(v["status"], "found");
    let b = &v["best"];
    let cars = b["vehicles"].as_array().unwrap();
    let contact1 = num(&cars[0]["speed_at_contact"]);
    let contact2 = num(&cars[1]["speed_at_contact"]);
    assert!((contact1 / MPH - 38.0).abs() < 0.2, "{}", contact1 / MPH);
    assert!((contact2 / MPH - 27.0).abs() < 0.2, "{}", contact2 / MPH);
    assert!((num(&b["e"]) - 0.12).abs() < 0.01);
    assert!((num(&b["mu"]) - 0.15).abs() < 0.01);
    // The skid brakes on the road of the run-outs: at its fitted friction (0.72 stated, its
    // residual in the evidence table).
    let fitted = 0.72
        + b["evidence"]
            .as_array()
            .unwrap()
            .iter()
            .find(|e| e["name"] == "road friction")
            .map(|e| num(&e["residual"]))
            .expect("the road friction is fitted");
    let d = 42.0 * 0.3048;
    let v0 = (contact1 * contact1 + 2.0 * fitted * 9.80665 * d).sqrt();
    assert!((num(&cars[0]["speed_before_braking"]) - v0).abs() < 1e-9);
    assert!(cars[1]["speed_before_braking"].is_null());
    assert_eq!(cars[0]["speed_at_rest"], serde_json::json!(0.0));
    // Every piece of evidence is there, its shares summing to 100 %.
    let ev = b["evidence"].as_array().unwrap();
    assert_eq!(ev.len(), 14);
    let share: f64 = ev.iter().map(|e| num(&e["share_percent"])).sum();
    assert!((share - 100.0).abs() < 1e-6, "{share}");
    assert!(ev.iter().any(|e| e["phase"] == "pre_impact"));
    // The counts of turns: all 49 combinations listed, the best among them.
    let counts = v["counts"].as_array().unwrap();
    assert_eq!(counts.len(), 49);
    assert_eq!(counts.iter().filter(|c| c["state"] == "best").count(), 1);
    assert!(num(&v["runouts"]) > 0.0);
    assert!(v["proven"].as_str().unwrap().contains("not proven global"));
    // The table says the same in the case's units.
    let t = String::from_utf8(pim_ok(&["fit", CASE]).stdout).unwrap();
    assert!(
        t.contains("before braking") && t.contains("(speeds in mph)"),
        "{t}"
    );
}

/// A rest position 43 ft from where the impact sends the car: exit 3 with the reason and the
/// largest residuals, not a silent fit.
#[test]
fn contradictory_evidence_is_refused() {
    let f = case_with(
        "far_rest.toml",
        "rest = { x = 11.9, y = 2.9, heading = 144.0 }",
        "rest = { x = 11.9, y = -40.0, heading = 144.0 }",
    );
    let out = pim(&["fit", &f]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let e = stderr(&out);
    assert!(
        e.contains("no reconstruction") && e.contains("the largest residuals"),
        "{e}"
    );
}

/// Bad pre-impact input: located, exit 2.
#[test]
fn bad_pre_impact_input_is_located() {
    for (name, from, to, field) in [
        (
            "braking.toml",
            "braking = 1.0 ",
            "braking = 1.5 ",
            "braking",
        ),
        ("skid.toml", "skid = 42.0", "skid = -42.0", "skid"),
        ("edr.toml", "sigma = 1.5 }", "sigma = 0.0 }", "edr[0]"),
        (
            "grade.toml",
            "skid = 42.0",
            "grade_percent = 3.0",
            "grade_percent",
        ),
    ] {
        let f = case_with(name, from, to);
        let out = pim(&["fit", &f]);
        assert_eq!(out.status.code(), Some(2), "{name}: {}", stderr(&out));
        assert!(stderr(&out).contains(field), "{name}: {}", stderr(&out));
    }
}

/// Intervals through all three phases: every speed's nominal lies inside its 90 % interval,
/// the road friction is among the inputs drawn and dominates a speed.
#[test]
fn intervals_through_all_phases() {
    let v = json(&pim_ok(&[
        "uncertainty",
        CASE,
        "--draws",
        "24",
        "--format",
        "json",
    ]));
    assert_eq!(v["kind"], "reconstruction");
    assert_eq!(v["feasible_draws"], 24);
    for q in [
        "vehicle1.speed_before_braking",
        "vehicle1.speed_at_contact",
        "vehicle2.speed_at_contact",
        "vehicle2.speed_at_separation",
    ] {
        let s = &v["quantities"][q];
        let n = num(&v["nominal"][q]);
        assert!(num(&s["p05"]) < n && n < num(&s["p95"]), "{q}: {s}");
    }
    let inputs: Vec<&str> = v["inputs"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_str().unwrap())
        .collect();
    assert!(
        inputs.contains(&"road friction")
            && inputs.contains(&"vehicle2 EDR speed 0.5 s before contact")
    );
}

/// The report of a reconstruction with its intervals: `pim uncertainty --out` writes the nominal
/// reconstruction, the study and the scene to scale into one page.
#[test]
fn the_report_holds_the_intervals_and_the_scene() {
    let dir = scratch_dir("reconstruct", "report");
    let out_dir = dir.join("r");
    let out = pim_ok(&[
        "uncertainty",
        CASE,
        "--draws",
        "12",
        "--out",
        out_dir.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    for f in [
        "result.json",
        "uncertainty.json",
        "scene.svg",
        "report.html",
        "report.md",
    ] {
        assert!(out_dir.join(f).exists(), "{f}");
    }
    let html = std::fs::read_to_string(out_dir.join("report.html")).unwrap();
    assert!(html.contains("vehicle1.speed_at_contact") && html.contains("<svg"));
    assert!(html.contains("braking 42.0 ft"), "the skid is drawn");
}
