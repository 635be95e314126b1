//! Friction zones in the whole reconstruction. A zone's friction with `friction_sigma` is fitted
//! and its prior drawn by the study: the SUV of the verge example, which ends its run-out on
//! the zone, leaves the impact with a wider spread of speeds. Realistic crashes whose vehicle
//! 2 slides onto a verge (`realistic_scenes`' generator) are answered on the verge's friction,
//! and a verge stated wrong with its spread is fitted back toward the truth.
use crate::common;
use crate::realistic_scenes::{check, reconstructed, run_simulated, simulated, Wheels};
use pim_case::case::Case;
use std::path::Path;

fn verge(sigma: Option<f64>) -> Case {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../examples/cases/reconstruction_verge_us.toml");
    let mut text = std::fs::read_to_string(&path).unwrap();
    if let Some(s) = sigma {
        text = text.replacen(
            "friction = 0.45 ",
            &format!("friction = 0.45\nfriction_sigma = {s} "),
            1,
        );
    }
    Case::from_text(&path.display().to_string(), &text).unwrap()
}

/// 40 draws of the study with and without a spread of 0.1 on the verge's friction (the same
/// seed): the verge's friction is among the inputs drawn (the centre of its prior), and the
/// 90 % interval of the SUV's speed at separation is wider with it.
#[test]
#[ignore = "long: tests/long runs it"]
fn a_zones_friction_is_drawn_by_the_study() {
    let width = |case: &Case| {
        let done = pim_studies::reconstruct::reconstruct(
            case,
            pim_fit::FitModel::Pim,
            pim_core::MomentForm::Corrected,
            pim_fit::MomentBranch::ALL.to_vec(),
        )
        .unwrap();
        let study = pim_studies::reconstruct_study::run_around(
            case,
            &done,
            40,
            7,
            &pim_studies::watch::Unwatched,
        )
        .unwrap();
        let q = &study.quantities["vehicle2.speed_at_separation"];
        (study.inputs.clone(), q.p95 - q.p05)
    };
    let (inputs, spread) = width(&verge(Some(0.1)));
    let (plain_inputs, plain) = width(&verge(None));
    println!(
        "SUV at separation: 90 % width {spread:.3} m/s with the verge's spread, {plain:.3} without"
    );
    assert!(
        inputs.iter().any(|i| i == "grass verge friction"),
        "{inputs:?}"
    );
    assert!(
        !plain_inputs.iter().any(|i| i.contains("verge")),
        "{plain_inputs:?}"
    );
    assert!(spread > plain, "{spread} against {plain}");
    // A spread that is no spread is refused at its line.
    let bad = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../examples/cases/reconstruction_verge_us.toml"),
    )
    .unwrap()
    .replacen(
        "friction = 0.45 ",
        "friction = 0.45\nfriction_sigma = -0.1 ",
        1,
    );
    let e = Case::from_text("verge.toml", &bad)
        .and_then(|c| c.scene_inputs().map(|_| ()))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("zones[0].friction_sigma") && e.contains("above 0"),
        "{e}"
    );
}

/// Crashes whose vehicle 2 slides from the road onto a verge of 55-75 % of the road's friction
/// half way along its run-out, the verge stated as a friction zone (`[[runout.zones]]`): each
/// is answered at or below the truth's chi-square, the 90 % intervals of both contact speeds
/// hold the truth, and the same case without its zone does not answer as well (its wheels on
/// the road's friction throughout cannot reach the rest the verge let them reach).
#[test]
#[ignore = "long: tests/long runs it"]
fn a_run_out_onto_a_verge_is_answered_on_the_verges_friction() {
    for wheels in VERGE_WHEELS {
        let (seed, s) = (95_000..)
            .find_map(|seed| simulated(seed, wheels, true).map(|s| (seed, s)))
            .unwrap();
        let text = s.text.clone();
        let truth = [s.contact.vehicle1.speed(), s.contact.vehicle2.speed()];
        let r = run_simulated(seed, wheels, s, 20).expect("answered");
        check(std::slice::from_ref(&r));
        assert_eq!(r.covered, [true, true], "seed {seed}: truth {truth:?}");
        let start = text.find("[[runout.zones]]").unwrap();
        let end = start + text[start..].find("\n\n").unwrap();
        let without = format!("{}{}", &text[..start], &text[end + 1..]);
        let done = reconstructed(&Case::from_text("without_zone.toml", &without).unwrap());
        let cost = done
            .outcome
            .best
            .as_ref()
            .map_or(f64::INFINITY, |b| b.chi_square);
        println!(
            "seed {seed}: with the verge {:?}, without it {cost:.2} ({:?})",
            r.found, done.outcome.status
        );
        assert!(
            cost > r.found.unwrap(),
            "seed {seed}: {cost} without the zone"
        );
    }
}

/// The verge's friction fitted (`friction_sigma` on the zone): the first verge crash (vehicle 2
/// locked onto a verge of 55-75 % of the road's friction) with the verge stated 0.15 too high,
/// at a standard deviation of 0.15. Held as stated, the run-out cannot reach its rest on so
/// much grip without speeds the other evidence does not want; fitted, the verge's friction
/// comes at least half way back to the truth (the rest on the verge measures it), the
/// chi-square is below the held one's and at most the truth's (whose run-outs are on the true
/// verge, its prior one deviation off), and both contact speeds lie within 0.5 m/s of the
/// truth.
#[test]
fn a_verges_friction_is_fitted_from_the_rest_on_it() {
    let wheels = [Wheels::Locked, Wheels::Locked];
    let (seed, s) = (95_000..)
        .find_map(|seed| simulated(seed, wheels, true).map(|s| (seed, s)))
        .unwrap();
    let start = s.text.find("name = \"verge\"\nfriction = ").unwrap() + 26;
    let end = start + s.text[start..].find('\n').unwrap();
    let truth_mu: f64 = s.text[start..end].parse().unwrap();
    let stated = truth_mu + 0.15;
    let at = |text: &str| Case::from_text(&format!("verge_{seed}.toml"), text).unwrap();
    let held = format!("{}{stated:.4}{}", &s.text[..start], &s.text[end..]);
    let fitted = format!(
        "{}{stated:.4}\nfriction_sigma = 0.15{}",
        &s.text[..start],
        &s.text[end..]
    );
    // The truth's chi-square: its run-outs on the true verge, and the verge's prior.
    let truth = common::truth_cost(&at(&s.text), &s.contact, &s.separation, s.friction) + 1.0;
    let answer = |text: &str| {
        let done = reconstructed(&at(text));
        let b = done.outcome.best.clone().expect("an answer");
        let zone = done
            .input
            .reconstruction
            .frictions
            .iter()
            .position(|f| f.zone == Some(0))
            .map(|g| b.frictions[g]);
        let speeds = b.phases.iter().map(|p| p.contact).collect::<Vec<_>>();
        (done.outcome.status, b.chi_square, zone, speeds)
    };
    let (_, held_cost, held_zone, held_speeds) = answer(&held);
    let (status, cost, zone, speeds) = answer(&fitted);
    let mu = zone.expect("the verge's friction fitted");
    println!(
        "seed {seed}: verge {truth_mu} stated {stated:.4}: held chi-square {held_cost:.2}, \
         speeds {held_speeds:.3?}; fitted {mu:.4} at {cost:.3} (truth's {truth:.3}), speeds \
         {speeds:.3?} against {:.3} {:.3}",
        s.contact.vehicle1.speed(),
        s.contact.vehicle2.speed()
    );
    assert_eq!(held_zone, None);
    assert_eq!(status, pim_reconstruct::Status::Found);
    assert!((mu - truth_mu).abs() < 0.5 * (stated - truth_mu), "{mu}");
    assert!(cost <= truth, "{cost} above the truth's {truth}");
    assert!(held_cost > cost, "held {held_cost}, fitted {cost}");
    let true_speeds = [s.contact.vehicle1.speed(), s.contact.vehicle2.speed()];
    for (v, t) in speeds.iter().zip(true_speeds) {
        assert!((v - t).abs() < 0.5, "{speeds:?} against {true_speeds:?}");
    }
}

/// The wheels of the crashes of [`a_run_out_onto_a_verge_is_answered_on_the_verges_friction`]
/// (each the first admissible crash from seed 95,000).
const VERGE_WHEELS: [[Wheels; 2]; 2] = [
    [Wheels::Locked, Wheels::Locked],
    [Wheels::Abs, Wheels::Locked],
];
