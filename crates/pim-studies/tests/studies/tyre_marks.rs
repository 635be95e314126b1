//! A mark names the tyre that left it: its residual is measured from that tyre's path, not the
//! CG's. On the SAE example (`reconstruction_us.toml`) a point of the SUV's front right tyre
//! trace, taken from the answer's own run-out, is met as a front-right mark (its residual a
//! tenth of its sigma, the speeds unchanged) while the same point read as a point of the
//! CG's path is not; a wheel the vehicle does not have is refused at its line. A yaw mark
//! traced along that tyre's path (`traces`) is met point by point; a rest given by tyre points
//! is met as measured.

use pim_case::case::Case;
use pim_core::VehicleId;
use std::path::Path;

const FOOT: f64 = 0.3048;

fn example() -> (String, String) {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases/reconstruction_us.toml");
    (
        path.display().to_string(),
        std::fs::read_to_string(&path).unwrap(),
    )
}

fn reconstructed(file: &str, text: &str) -> pim_studies::reconstruct::Reconstructed {
    let case = Case::from_text(file, text).unwrap();
    pim_studies::reconstruct::reconstruct(
        &case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    )
    .unwrap()
}

/// Vehicle 2's (the SUV's) scene in the answer.
fn suv_scene(done: &pim_studies::reconstruct::Reconstructed) -> &pim_reconstruct::SceneFit {
    let best = done.outcome.best.as_ref().expect("an answer");
    best.scene
        .iter()
        .find(|s| s.vehicle == VehicleId::Two)
        .unwrap()
}

/// Vehicle 2's mark 1 residual in sigmas, the chi-square and both speeds at contact (m/s).
fn summary(done: &pim_studies::reconstruct::Reconstructed) -> (f64, f64, [f64; 2]) {
    let best = done.outcome.best.as_ref().expect("an answer");
    let scene = suv_scene(done);
    let mark = scene.residuals.iter().find(|r| r.name == "mark 1").unwrap();
    (
        mark.value / mark.sigma,
        best.chi_square,
        [best.phases[0].contact, best.phases[1].contact],
    )
}

/// The example, its answer's summary, its fitted run-outs and the SUV's index among them.
fn the_suv() -> (
    String,
    String,
    (f64, f64, [f64; 2]),
    pim_studies::runout::RunoutResult,
    usize,
) {
    let (file, text) = example();
    let case = Case::from_text(&file, &text).unwrap();
    let done = reconstructed(&file, &text);
    let best = done.outcome.best.as_ref().unwrap();
    let fitted = pim_studies::runout::fitted(&case, best, 0.02, false).unwrap();
    let k = fitted
        .inputs
        .iter()
        .position(|v| v.id == VehicleId::Two)
        .unwrap();
    (file, text, summary(&done), fitted, k)
}

#[test]
fn a_tyre_mark_is_measured_from_its_tyres_path() {
    let (file, text, (_, chi0, speeds0), fitted, k) = the_suv();
    // The SUV's front right tyre 40 % of the way through its fitted run-out, in the file's
    // frame (SAE: y to the right) and feet.
    let run = &fitted.runouts[k];
    let m = run.at(0.4 * run.time);
    let [ax, ay] = fitted.inputs[k].chassis.wheel_position(1);
    let (s, c) = m.heading.sin_cos();
    let (x, y) = (m.x + c * ax - s * ay, m.y + s * ax + c * ay);
    let (x_ft, y_ft) = (x / FOOT, -y / FOOT);
    let given = "marks = [ { x = 32.6, y = 48.2, sigma = 0.5 } ]";
    assert!(text.contains(given));
    let with = |wheel: &str| {
        text.replace(
            given,
            &format!("marks = [ {{ x = {x_ft:.3}, y = {y_ft:.3}, sigma = 0.5{wheel} }} ]"),
        )
    };
    let on_tyre = reconstructed(&file, &with(", wheel = \"front_right\""));
    let (z, chi, speeds) = summary(&on_tyre);
    println!("front right: z {z:.4}, chi-square {chi:.3} (was {chi0:.3}), speeds {speeds:?} (were {speeds0:?})");
    // The point is the earlier answer's; refitted with it, every piece of evidence moves the
    // answer a little (the other residuals were a few hundredths of their sigmas): the mark is
    // met within a tenth of its sigma.
    assert!(z.abs() < 0.1, "{z}");
    assert!(chi <= chi0 + 0.05, "{chi} against {chi0}");
    for (a, b) in speeds.iter().zip(&speeds0) {
        assert!((a - b).abs() < 0.05, "{speeds:?} against {speeds0:?}");
    }
    // The same point taken for a point of the CG's path: the tyre is about 3 ft right of the
    // CG and 4 ft ahead of it, and the CG passes there only if the rest of the evidence gives
    // way (measured: chi-square 4.40 against 0.07).
    let on_cg = reconstructed(&file, &with(""));
    let (z_cg, chi_cg, _) = summary(&on_cg);
    println!("as the CG's: z {z_cg:.3}, chi-square {chi_cg:.3}");
    assert!(chi_cg > chi + 4.0, "{chi_cg} against {chi}");
    // No such wheel: refused at its line, naming the wheels there are.
    let bad = with(", wheel = \"front_middle\"");
    let err = Case::from_text(&file, &bad).unwrap_err().to_string();
    println!("{err}");
    assert!(
        err.contains(":102:") && err.contains("front_right"),
        "{err}"
    );
}

/// A rest given as it is measured, the left tyres' contact points: on the SAE example the
/// SUV's rest replaced by its front and rear left tyres where the answer's run-out leaves
/// them (sigma 0.3 ft each) gives the same answer; the rest's residuals are of the tyres'
/// centroid and the heading they give; a rear tyre measured a foot off the wheelbase is said
/// (a warning naming both spacings), and a rest given twice or by one tyre is refused at its
/// line.
#[test]
fn a_rest_given_by_tyre_points_is_met_as_measured() {
    let (file, text, (_, chi0, speeds0), fitted, k) = the_suv();
    let rest = fitted.runouts[k].rest;
    let chassis = &fitted.inputs[k].chassis;
    let (s, c) = rest.heading.sin_cos();
    // A tyre's point in the file's frame (SAE: y to the right) and feet.
    // `back` feet farther back along the vehicle than its geometry puts it.
    let tyre = |w: usize, back: f64| {
        let [a, b] = chassis.wheel_position(w);
        let a = a - back * FOOT;
        let (x, y) = (rest.x + c * a - s * b, rest.y + s * a + c * b);
        (x / FOOT, -y / FOOT)
    };
    let given = "rest = { x = 50.1, y = 79.7, heading = 241.0 }\nrest_sigma = { x = 1.0, y = 1.0, heading = 3.0 }";
    assert!(text.contains(given));
    let tyres = |rear_back: f64| {
        let (fl, rl) = (tyre(0, 0.0), tyre(2, rear_back));
        text.replace(
            given,
            &format!(
                "rest_tyres = [ {{ wheel = \"front_left\", x = {:.3}, y = {:.3}, sigma = 0.3 }},\n  \
                 {{ wheel = \"rear_left\", x = {:.3}, y = {:.3}, sigma = 0.3 }} ]",
                fl.0,
                fl.1,
                rl.0,
                rl.1
            ),
        )
    };
    let measured = reconstructed(&file, &tyres(0.0));
    let (_, chi, speeds) = summary(&measured);
    let scene = suv_scene(&measured);
    let names: Vec<&str> = scene.residuals.iter().map(|r| r.name.as_str()).collect();
    println!(
        "tyres: chi-square {chi:.3} (was {chi0:.3}), speeds {speeds:?} (were {speeds0:?}); {:?}",
        scene.residuals
    );
    assert_eq!(names, ["rest.x", "rest.y", "rest.heading", "mark 1"]);
    for r in &scene.residuals[..3] {
        assert!((r.value / r.sigma).abs() < 0.1, "{r:?}");
    }
    // The same rest, measured more tightly than the CG's 1 ft: the answer moves by little.
    for (a, b) in speeds.iter().zip(&speeds0) {
        assert!((a - b).abs() < 0.1, "{speeds:?} against {speeds0:?}");
    }
    assert!(chi <= chi0 + 0.1, "{chi} against {chi0}");
    // The rear tyre measured 1.5 ft farther back than the wheelbase puts it: a misfit of
    // (1.5 / (0.3 sqrt 2))^2 = 12.5 with one degree of freedom, p 4e-4, said.
    let off = Case::from_text(&file, &tyres(1.5)).unwrap();
    let warnings = off.warnings().join("\n");
    println!("{warnings}");
    assert!(
        warnings.contains("scene.vehicle2.rest_tyres")
            && warnings.contains("front_left to rear_left measured"),
        "{warnings}"
    );
    assert!(Case::from_text(&file, &tyres(0.0))
        .unwrap()
        .warnings()
        .iter()
        .all(|w| !w.contains("rest_tyres")));
    // Given twice, or by one tyre: refused at the line.
    let twice = tyres(0.0).replace(
        "rest_tyres = [",
        "rest = { x = 50.1, y = 79.7 }\nrest_tyres = [",
    );
    let err = Case::from_text(&file, &twice)
        .and_then(|c| c.scene_inputs().map(|_| c))
        .err()
        .unwrap()
        .to_string();
    assert!(
        err.contains("rest_tyres") && err.contains("given twice"),
        "{err}"
    );
}

/// A yaw mark surveyed along its length: on the SAE example the SUV's front right tyre's path
/// between 20 % and 60 % of its fitted run-out, five points as a trace of that tyre, is met
/// point by point (each residual within a tenth of its sigma, the speeds as before); the same
/// points traced by the CG are not; a trace of one point, or a bad sigma, is refused at its
/// line.
#[test]
fn a_traced_mark_is_met_along_its_tyres_path() {
    let (file, text, (_, chi0, speeds0), fitted, k) = the_suv();
    let run = &fitted.runouts[k];
    let [ax, ay] = fitted.inputs[k].chassis.wheel_position(1);
    let points: Vec<String> = [0.2, 0.3, 0.4, 0.5, 0.6]
        .iter()
        .map(|f| {
            let m = run.at(f * run.time);
            let (s, c) = m.heading.sin_cos();
            let (x, y) = (m.x + c * ax - s * ay, m.y + s * ax + c * ay);
            format!("[{:.3}, {:.3}]", x / FOOT, -y / FOOT)
        })
        .collect();
    let given = "marks = [ { x = 32.6, y = 48.2, sigma = 0.5 } ]";
    let with = |wheel: &str, pts: &str, sigma: f64| {
        text.replace(
            given,
            &format!("{given}\ntraces = [ {{ {wheel}points = [ {pts} ], sigma = {sigma} }} ]"),
        )
    };
    let all = points.join(", ");
    let traced = reconstructed(&file, &with("wheel = \"front_right\", ", &all, 0.5));
    let best = traced.outcome.best.as_ref().unwrap();
    let scene = best
        .scene
        .iter()
        .find(|s| s.vehicle == VehicleId::Two)
        .unwrap();
    // The mark of the case, then the trace's five points.
    let names: Vec<&str> = scene.residuals.iter().map(|r| r.name.as_str()).collect();
    assert_eq!(
        &names[3..],
        ["mark 1", "mark 2", "mark 3", "mark 4", "mark 5", "mark 6"]
    );
    for r in &scene.residuals[4..] {
        assert!((r.value / r.sigma).abs() < 0.1, "{r:?}");
    }
    let speeds = [best.phases[0].contact, best.phases[1].contact];
    println!(
        "traced: chi-square {:.3} (was {chi0:.3}), speeds {speeds:?} (were {speeds0:?})",
        best.chi_square
    );
    for (a, b) in speeds.iter().zip(&speeds0) {
        assert!((a - b).abs() < 0.05, "{speeds:?} against {speeds0:?}");
    }
    // Traced by the CG: the tyre's path lies about 3 ft off the CG's.
    let by_cg = reconstructed(&file, &with("", &all, 0.5));
    let chi_cg = by_cg.outcome.best.as_ref().unwrap().chi_square;
    println!("as the CG's trace: chi-square {chi_cg:.3}");
    assert!(chi_cg > best.chi_square + 10.0, "{chi_cg}");
    // One point, a sigma of 0: refused at the trace's line.
    for (bad, why) in [
        (with("", &points[0], 0.5), "two or more points"),
        (with("", &all, 0.0), "above 0"),
    ] {
        let err = Case::from_text(&file, &bad)
            .and_then(|c| c.scene_inputs().map(|_| c))
            .err()
            .unwrap()
            .to_string();
        assert!(
            err.contains("scene.vehicle2.traces[0]") && err.contains(why),
            "{err}"
        );
    }
}

/// A rest given by two corners of the outline (the SUV's front left and rear right, where the
/// answer's run-out leaves them, sigma 0.3 ft): the same answer as the tyres give; a corner of
/// a vehicle without its outline, or a point naming both a tyre and a corner, is refused at
/// its line.
#[test]
fn a_rest_given_by_outline_corners_is_met_as_measured() {
    let (file, text, (_, chi0, speeds0), fitted, k) = the_suv();
    let rest = fitted.runouts[k].rest;
    let (s, c) = rest.heading.sin_cos();
    // The SUV's outline: 15.0 ft long, 6.2 ft wide, its CG 6.8 ft behind the front.
    let corner = |a: f64, b: f64| {
        let (a, b) = (a * FOOT, b * FOOT);
        let (x, y) = (rest.x + c * a - s * b, rest.y + s * a + c * b);
        (x / FOOT, -y / FOOT)
    };
    let (fl, rr) = (corner(6.8, 3.1), corner(6.8 - 15.0, -3.1));
    let given = "rest = { x = 50.1, y = 79.7, heading = 241.0 }\nrest_sigma = { x = 1.0, y = 1.0, heading = 3.0 }";
    let corners = text.replace(
        given,
        &format!(
            "rest_tyres = [ {{ corner = \"front_left\", x = {:.3}, y = {:.3}, sigma = 0.3 }},\n  \
             {{ corner = \"rear_right\", x = {:.3}, y = {:.3}, sigma = 0.3 }} ]",
            fl.0, fl.1, rr.0, rr.1
        ),
    );
    let measured = reconstructed(&file, &corners);
    let (_, chi, speeds) = summary(&measured);
    let scene = suv_scene(&measured);
    println!("corners: chi-square {chi:.3} (was {chi0:.3}), speeds {speeds:?} (were {speeds0:?})");
    for r in &scene.residuals[..3] {
        assert!((r.value / r.sigma).abs() < 0.1, "{r:?}");
    }
    for (a, b) in speeds.iter().zip(&speeds0) {
        assert!((a - b).abs() < 0.1, "{speeds:?} against {speeds0:?}");
    }
    assert!(chi <= chi0 + 0.1, "{chi} against {chi0}");
    assert!(Case::from_text(&file, &corners)
        .unwrap()
        .warnings()
        .iter()
        .all(|w| !w.contains("rest_tyres")));
    // Without the SUV's outline: no corner to measure.
    let at_suv = corners.find("[vehicle2]").unwrap();
    let no_outline = format!(
        "{}{}",
        &corners[..at_suv],
        corners[at_suv..].replacen("length = 15.0\n", "", 1)
    );
    let refused = |t: &str| {
        Case::from_text(&file, t)
            .and_then(|c| c.scene_inputs().map(|_| c))
            .err()
            .unwrap()
            .to_string()
    };
    let err = refused(&no_outline);
    assert!(
        err.contains("rest_tyres") && err.contains("outline"),
        "{err}"
    );
    let both = corners.replacen(
        "corner = \"front_left\"",
        "wheel = \"front_left\", corner = \"front_left\"",
        1,
    );
    let err = refused(&both);
    assert!(
        err.contains("rest_tyres[0]") && err.contains("one of the two"),
        "{err}"
    );
}
