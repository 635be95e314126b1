//! Continuity: a case changed a little answers a little differently. The newcomer's case
//! (`cases/main_oak_turns_a.toml`, a sedan into an SUV's side, both rests, a mark, an EDR) is
//! swept in vehicle 2's position at contact in steps of 0.1 ft, as a drag moves it in the
//! editor; each answer is compared with the refinements from its neighbours' answers, and the
//! command's `--from` is run end to end.

use crate::common;
use common::*;
use pim_case::case::Case;
use pim_studies::reconstruct::{case_reconstruction, reconstruct_searching, How, Reconstructed};

const CASE: &str = include_str!("../cases/main_oak_turns_a.toml");
const LINE: &str = "position = { x = 22.30, y = 21.5 }";

fn how() -> How {
    How {
        model: pim_fit::FitModel::Pim,
        moment_form: pim_core::MomentForm::Corrected,
        branches: vec![pim_fit::MomentBranch::Free, pim_fit::MomentBranch::Zero],
    }
}

/// The case with vehicle 2's CG at contact at `y` ft (east of the reference point).
fn at(y: f64) -> Case {
    assert!(CASE.contains(LINE), "the swept line is in the case");
    let text = CASE.replace(LINE, &format!("position = {{ x = 22.30, y = {y:.2} }}"));
    Case::from_text("sweep.toml", &text).expect("a valid case")
}

fn chi(done: &Reconstructed) -> f64 {
    done.outcome
        .best
        .as_ref()
        .map_or(f64::INFINITY, |b| b.chi_square)
}

/// The lowest chi-square of the case at `y` refined from the answer `neighbour` gave (its
/// combinations near its best, from where they ended: no search).
fn from_neighbour(y: f64, neighbour: &Reconstructed) -> f64 {
    let h = how();
    let input = case_reconstruction(&at(y), h.model, h.moment_form, h.branches).unwrap();
    pim_reconstruct::redo(
        &input.reconstruction,
        &input.settings,
        &neighbour.outcome,
        4.0,
    )
    .unwrap()
    .map_or(f64::INFINITY, |f| f.chi_square)
}

/// Sweeps `count` positions from `first` ft: each answer at most what a neighbour's answer
/// refined gives (no jump a neighbouring start would remove), and the chi-square smooth along
/// the sweep (its second differences within 0.05: a jump of d between two steps is a second
/// difference of about d; here the chi-square falls about 0.44 a step along a gentle curve).
fn sweep(first: f64, count: usize) {
    let ys: Vec<f64> = (0..count).map(|i| first + 0.1 * i as f64).collect();
    let answers: Vec<Reconstructed> = ys
        .iter()
        .map(|&y| {
            reconstruct_searching(&at(y), how(), true, &Default::default()).expect("answered")
        })
        .collect();
    let cost: Vec<f64> = answers.iter().map(chi).collect();
    for (i, &y) in ys.iter().enumerate() {
        for j in [i.wrapping_sub(1), i + 1] {
            let Some(n) = answers.get(j) else { continue };
            let neighbour = from_neighbour(y, n);
            assert!(
                cost[i] <= neighbour + 1e-6 * (1.0 + neighbour),
                "y {y:.1} ft: answered {:.4}, but refined from the answer at {:.1} ft {neighbour:.4}",
                cost[i],
                ys[j]
            );
        }
    }
    for i in 1..count - 1 {
        let second = cost[i + 1] - 2.0 * cost[i] + cost[i - 1];
        assert!(
            second.abs() <= 0.05,
            "a jump at y {:.1} ft: chi-squares {:.4?}",
            ys[i],
            cost
        );
    }
    eprintln!("sweep from {first:.1} ft: chi-squares {cost:.4?}");
}

/// 21.2 to 21.8 ft about the case's 21.5 (about 15 s).
#[test]
fn a_tenth_of_a_foot_changes_the_answer_a_little() {
    sweep(21.2, 7);
}

/// 20.5 to 22.5 ft (21 positions, about 50 s).
#[test]
#[ignore = "slow: 21 reconstructions"]
fn a_tenth_of_a_foot_changes_the_answer_a_little_over_two_feet() {
    sweep(20.5, 21);
}

/// `pim fit --from`: the answer of the case moved 0.1 ft is refined on the case as it is, the
/// search runs too, and the answer is the lower (here the same minimum as without it); a document of
/// another kind, text that is not JSON or frictions that are not numbers are refused with the
/// file named.
#[test]
fn fit_from_an_earlier_answer() {
    let dir = scratch_dir("continuity", "from");
    let earlier = dir.join("earlier.json");
    let a = pim_ok(&[
        "fit",
        "crates/pim-cli/tests/cases/main_oak_turns_a.toml",
        "--format",
        "json",
    ]);
    std::fs::write(&earlier, &a.stdout).unwrap();
    let b = |extra: &[&str]| {
        let mut args = vec![
            "fit",
            "crates/pim-cli/tests/cases/main_oak_turns_b.toml",
            "--format",
            "json",
        ];
        args.extend_from_slice(extra);
        let out = pim(&args);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let d: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        d["best"]["chi_square"].as_f64().unwrap()
    };
    let fresh = b(&[]);
    let from = b(&["--from", earlier.to_str().unwrap()]);
    assert!((fresh - 31.667).abs() < 1e-3, "{fresh}");
    // The same minimum, to the refinement's convergence (it stops where a step gains less than
    // 1e-6 (1 + chi-square)): the two reach it along different paths.
    assert!(
        (from - fresh).abs() <= 1e-6 * (1.0 + fresh),
        "{from} against {fresh}"
    );

    let other = scratch_file(
        "continuity",
        "solve.json",
        r#"{"kind": "fit", "branches": []}"#,
    );
    let not_json = scratch_file("continuity", "broken.json", "{ not json");
    let mut doc: serde_json::Value = serde_json::from_slice(&a.stdout).unwrap();
    doc["best"]["frictions"] = serde_json::json!([0.7, "high"]);
    let bad_friction = scratch_file("continuity", "bad_friction.json", doc.to_string());
    for (file, says) in [
        (&other, "not a reconstruction's"),
        (&not_json, "not a JSON document"),
        (
            &bad_friction,
            "best.frictions: expected a list of positive numbers",
        ),
    ] {
        let out = pim(&[
            "fit",
            "crates/pim-cli/tests/cases/main_oak_turns_b.toml",
            "--from",
            file,
        ]);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        let e = stderr(&out);
        assert!(e.contains(file.as_str()) && e.contains(says), "{e}");
    }
    // A case without scene evidence has nothing to start from.
    let out = pim(&["fit", "examples/cases/ricsac7_fit.toml", "--from", &other]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("no scene evidence"),
        "{}",
        stderr(&out)
    );
}

/// The document carries the fitted frictions its run-outs ran on (`best.frictions`, the
/// friction rows' stated values plus their residuals), and `pim fit --from` of the guide's
/// example's own answer returns that answer.
#[test]
fn fit_from_its_own_answer_keeps_the_fitted_friction() {
    let case = "examples/cases/reconstruction_us.toml";
    let a = pim_ok(&["fit", case, "--format", "json"]);
    let earlier = scratch_file(
        "continuity",
        "own.json",
        std::str::from_utf8(&a.stdout).unwrap(),
    );
    let d: serde_json::Value = serde_json::from_slice(&a.stdout).unwrap();
    let frictions = d["best"]["frictions"].as_array().expect("fitted frictions");
    let row = d["best"]["evidence"]
        .as_array()
        .unwrap()
        .iter()
        .find(|e| e["source"]["kind"] == "friction")
        .expect("the friction's row");
    // The example states the road's friction as 0.72.
    let fitted = frictions[0].as_f64().unwrap();
    assert!((fitted - (0.72 + row["residual"].as_f64().unwrap())).abs() < 1e-12);
    let b = pim_ok(&["fit", case, "--format", "json", "--from", &earlier]);
    let e: serde_json::Value = serde_json::from_slice(&b.stdout).unwrap();
    let chi = |v: &serde_json::Value| v["best"]["chi_square"].as_f64().unwrap();
    assert!(
        (chi(&e) - chi(&d)).abs() <= 1e-6 * (1.0 + chi(&d)),
        "{} {}",
        chi(&e),
        chi(&d)
    );
    assert!((e["best"]["frictions"][0].as_f64().unwrap() - fitted).abs() < 1e-4);
}
