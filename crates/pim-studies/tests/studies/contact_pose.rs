//! The pose at contact fitted (`[contact_sigma]`) on realistic simulated crashes whose pose at
//! contact is stated wrong: each vehicle's CG moved by 1 ft along both axes and its heading turned
//! by 3 degrees (signs drawn per crash), with priors of that size. The answer's whole cost (its
//! chi-square with the priors' share) is never above the true pose's. The fitted pose moves toward
//! the truth (over the crashes: one crash alone may move along a direction its evidence does not
//! see), and the contact speeds of the uncertainty study (each draw's pose fitted again) hold the
//! truth within three standard deviations (the hold of the 90 % intervals is printed).
use crate::realistic_scenes::{simulated, Wheels};
use pim_case::case::Case;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

const FOOT: f64 = 0.3048;
const TURN_DEG: f64 = 3.0;

/// `text` with vehicle `k`'s (1 or 2) `key = value` line of its `[vehicleK]` section changed
/// by `f`.
fn changed(text: &str, k: usize, key: &str, f: impl Fn(f64) -> f64) -> String {
    let head = format!("[vehicle{k}]\n");
    let start = text.find(&head).expect("the vehicle's section") + head.len();
    let at = start + text[start..].find(&format!("\n{key} = ")).unwrap() + key.len() + 4;
    let end = at + text[at..].find('\n').unwrap();
    let value: f64 = text[at..end].trim().parse().unwrap();
    format!("{}{:.9}{}", &text[..at], f(value), &text[end..])
}

/// `text` with each vehicle's position `{ x = .., y = .. }` moved by `d` (m) and its heading
/// turned by `turn` (deg).
fn moved(text: &str, d: [[f64; 2]; 2], turn: [f64; 2]) -> String {
    let mut t = text.to_string();
    for k in 0..2 {
        t = changed(&t, k + 1, "heading", |h| h + turn[k]);
        let head = format!("[vehicle{}]\n", k + 1);
        let start = t.find(&head).unwrap();
        let at = start + t[start..].find("position = {").unwrap();
        let end = at + t[at..].find('}').unwrap() + 1;
        let inner = &t[at + "position = {".len()..end - 1];
        let xy: Vec<f64> = inner
            .split(',')
            .map(|p| p.split('=').nth(1).unwrap().trim().parse().unwrap())
            .collect();
        let new = format!(
            "position = {{ x = {:.9}, y = {:.9} }}",
            xy[0] + d[k][0],
            xy[1] + d[k][1]
        );
        t = format!("{}{new}{}", &t[..at], &t[end..]);
    }
    t
}

fn reconstructed(name: &str, text: &str) -> pim_studies::reconstruct::Reconstructed {
    let case = Case::from_text(name, text).expect("a valid case");
    pim_studies::reconstruct::reconstruct(
        &case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    )
    .expect("reconstructed")
}

fn contact_speeds(r: &pim_studies::reconstruct::Reconstructed) -> [f64; 2] {
    let b = r.document.best.as_ref().expect("an answer");
    [
        b.vehicles[0].speed_at_contact,
        b.vehicles[1].speed_at_contact,
    ]
}

/// The first crash from `seed` with `wheels`, its pose stated wrong, fitted: checked as the
/// module says, with a study of `draws`.
fn pose_fitted_toward_the_truth(mut seed: u64, w: [Wheels; 2], draws: usize) -> (f64, f64) {
    let s = loop {
        seed += 1;
        if let Some(s) = simulated(seed, w, false) {
            break s;
        }
    };
    let mut rng = StdRng::seed_from_u64(seed);
    let mut sign = || if rng.random_bool(0.5) { 1.0 } else { -1.0 };
    let d = [
        [sign() * FOOT, sign() * FOOT],
        [sign() * FOOT, sign() * FOOT],
    ];
    let turn = [sign() * TURN_DEG, sign() * TURN_DEG];
    let wrong = moved(&s.text, d, turn);
    let started = std::time::Instant::now();
    let fitted_text = format!(
        "{wrong}\n[contact_sigma]\nvehicle1 = {{ heading = {TURN_DEG}, position = {{ x = {FOOT}, \
         y = {FOOT} }} }}\nvehicle2 = {{ heading = {TURN_DEG}, position = {{ x = {FOOT}, y = \
         {FOOT} }} }}\n"
    );
    if std::env::var("POSE_DUMP").is_ok() {
        let dir = std::env::temp_dir();
        std::fs::write(dir.join(format!("pose_{seed}_truth.toml")), &s.text).unwrap();
        std::fs::write(dir.join(format!("pose_{seed}_fitted.toml")), &fitted_text).unwrap();
    }
    let fitted = reconstructed("fitted.toml", &fitted_text);
    let b = fitted.document.best.as_ref().expect("an answer");
    assert_eq!(b.contact_pose.len(), 6);
    // The distance to the truth in the priors' deviations, stated and fitted: the truth
    // lies at minus the offsets the stated pose was moved by.
    let truth_offset = [-turn[0], -d[0][0], -d[0][1], -turn[1], -d[1][0], -d[1][1]];
    let (mut before, mut after) = (0.0, 0.0);
    for (row, t) in b.contact_pose.iter().zip(truth_offset) {
        before += (t / row.prior_sigma).powi(2);
        after += ((row.fitted - row.stated - t) / row.prior_sigma).powi(2);
    }
    let truth = [s.contact.vehicle1.speed(), s.contact.vehicle2.speed()];
    let err = |v: [f64; 2]| (v[0] - truth[0]).hypot(v[1] - truth[1]);
    // The whole cost at the true pose: the reconstruction there (the truth's own case) and
    // the priors' share of its offsets from the stated pose.
    let at_truth = reconstructed("truth.toml", &s.text);
    let truth_cost = at_truth
        .document
        .best
        .as_ref()
        .expect("an answer")
        .chi_square
        + before;
    eprintln!(
        "seed {seed} {w:?}: distance to the true pose {:.2} -> {:.2} prior sigmas; contact \
         speed error {:.3} m/s; chi-square {:.2} (the true pose's {truth_cost:.2}); {:.1} s, \
         {} refits in {} iterations",
        before.sqrt(),
        after.sqrt(),
        err(contact_speeds(&fitted)),
        b.chi_square,
        started.elapsed().as_secs_f64(),
        fitted.pose.as_ref().unwrap().refits,
        fitted.pose.as_ref().unwrap().iterations
    );
    for row in &b.contact_pose {
        eprintln!(
            "  {} stated {:.3} fitted {:.3} +- {:.3}",
            row.name, row.stated, row.fitted, row.sigma
        );
    }
    // The true pose is one the fit could have ended at: its answer is no worse.
    assert!(
        b.chi_square <= truth_cost * (1.0 + 1e-6),
        "seed {seed}: {} above the true pose's {truth_cost}",
        b.chi_square
    );
    // The study's intervals, each draw's pose fitted again: the truth within three of its
    // standard deviations of the median (the 90 % interval's hold is printed).
    let case = Case::from_text("fitted.toml", &fitted_text).unwrap();
    let study = pim_studies::reconstruct_study::run_around(
        &case,
        &fitted,
        draws,
        seed,
        &pim_studies::watch::Unwatched,
    )
    .expect("a study");
    assert!(
        study.feasible_draws * 10 >= draws * 9,
        "{}",
        study.feasible_draws
    );
    for (k, t) in truth.iter().enumerate() {
        let q = &study.quantities[&format!("vehicle{}.speed_at_contact", k + 1)];
        eprintln!(
            "  vehicle{} contact speed {t:.3} m/s: 90 % interval {:.3} to {:.3}{}",
            k + 1,
            q.p05,
            q.p95,
            if q.p05 <= *t && *t <= q.p95 {
                ""
            } else {
                " MISSED"
            }
        );
        assert!(
            (t - q.p50).abs() < 3.0 * q.sd,
            "seed {seed} vehicle{}",
            k + 1
        );
    }
    for (name, q) in study
        .quantities
        .iter()
        .filter(|(n, _)| n.starts_with("contact "))
    {
        eprintln!("  {name}: {:.3} to {:.3}", q.p05, q.p95);
    }
    assert_eq!(fitted.outcome.status, pim_reconstruct::Status::Found);
    (before, after)
}

#[test]
#[ignore = "long: tests/long runs it"]
fn a_pose_stated_wrong_is_fitted_toward_the_truth() {
    let (before, after) = pose_fitted_toward_the_truth(71_005, [Wheels::Abs, Wheels::Locked], 30);
    // Toward the truth, in the priors' metric.
    assert!(after < before, "{after} vs {before}");
}

/// Every wheel state (`--ignored`: about 30 s a crash).
#[test]
#[ignore]
fn a_pose_stated_wrong_is_fitted_toward_the_truth_for_every_wheel_state() {
    let wheels = [
        [Wheels::Locked, Wheels::Rolling],
        [Wheels::Abs, Wheels::Locked],
        [Wheels::Jammed, Wheels::Abs],
        [Wheels::Rolling, Wheels::Steered],
        [Wheels::Steered, Wheels::Jammed],
    ];
    let (mut before, mut after) = (0.0, 0.0);
    for (i, w) in wheels.into_iter().enumerate() {
        let (b, a) = pose_fitted_toward_the_truth(71_000 + 100 * i as u64, w, 40);
        before += b;
        after += a;
    }
    // Toward the truth over the crashes, in the priors' metric (one crash alone may move
    // along a direction its evidence does not see).
    eprintln!("sum of squared distances to the truth: {before:.2} -> {after:.2}");
    assert!(after < before, "{after} vs {before}");
}

/// A prior of the pose that the scene contradicts is a row of the consistency table: the pose
/// example with the SUV placed 4.5 ft east of where it was struck (its CG, the impact centre
/// held) and the impact point on its side held to 0.3 ft, the only value of the pose fitted.
/// The whole answer fits poorly; left out, that prior's row is refitted from the whole answer
/// (the value still fitted, its prior gone, one degree of freedom fewer), fits, is named by
/// the summary, lies below the whole fit like every row, and its speeds come back toward the
/// example's.
#[test]
#[ignore = "long: tests/long runs it"]
fn a_prior_the_scene_contradicts_is_a_row_of_the_consistency_table() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let text =
        std::fs::read_to_string(root.join("examples/cases/reconstruction_pose_us.toml")).unwrap();
    let answer = |text: &str| {
        let case = Case::from_text("pose.toml", text).expect("a valid case");
        pim_studies::consistency::answer(
            &case,
            pim_fit::FitModel::Pim,
            pim_core::MomentForm::Corrected,
            pim_fit::MomentBranch::ALL.to_vec(),
            &pim_studies::watch::Unwatched,
        )
        .expect("reconstructed")
        .document
    };
    let example = answer(&text);
    let v1_example = example.best.as_ref().unwrap().vehicles[0].speed_at_contact;
    let mut moved = text.clone();
    for (from, to) in [
        (
            "position = { x = 1.0, y = 1.5 }",
            "position = { x = 1.0, y = 6.0 }",
        ),
        (
            "vehicle1 = { heading = 3.0, position = { x = 1.0, y = 1.0 } }\n",
            "",
        ),
        (
            "vehicle2 = { heading = 3.0, impact_point = { x = 0.8 } }",
            "vehicle2 = { impact_point = { x = 0.3 } }",
        ),
    ] {
        assert!(moved.contains(from), "{from}");
        moved = moved.replacen(from, to, 1);
    }
    let d = answer(&moved);
    let whole = d.best.as_ref().expect("an answer");
    assert!(whole.p_value.unwrap() < 0.01, "{}", whole.chi_square);
    let table = d.consistency.as_ref().expect("a poor fit has its table");
    let name = "vehicle2.impact_point.x at contact (prior)";
    let row = table
        .rows
        .iter()
        .find(|r| r.left_out == [name])
        .expect("the prior's row");
    eprintln!(
        "whole {:.2} ({} dof); without the prior {:.2} ({:?} dof), v1 {:.3} -> {:.3} m/s \
         (the example's {v1_example:.3})",
        whole.chi_square,
        whole.degrees_of_freedom,
        row.chi_square.unwrap(),
        row.degrees_of_freedom,
        whole.vehicles[0].speed_at_contact,
        row.speed_at_contact[0].unwrap()
    );
    assert!(row.consistent, "{row:?}");
    assert!(row.chi_square.unwrap() < 2.0, "{row:?}");
    assert_eq!(row.degrees_of_freedom, Some(whole.degrees_of_freedom - 1));
    assert!(table.summary.contains(name), "{}", table.summary);
    let off = |v: f64| (v - v1_example).abs();
    assert!(
        off(row.speed_at_contact[0].unwrap()) < off(whole.vehicles[0].speed_at_contact),
        "{row:?}"
    );
    for r in &table.rows {
        assert_ne!(r.status, "failed", "{r:?}");
        assert!(
            r.chi_square.unwrap() <= whole.chi_square * (1.0 + 1e-9),
            "{r:?}"
        );
    }
}
