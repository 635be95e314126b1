//! The three phases in one fit (pim-reconstruct) on simulated crashes with known truth: random
//! admissible impacts (the stress corpus's draw), both vehicles run out to rest with the
//! run-out model, the scene given as a reconstructionist has it (rest positions and headings
//! modulo a full turn, marks the CGs passed), the contact state's direction and yaw rate as
//! evidence, the speeds unknown.
use crate::common;

use common::crash::{common_normal, crash, settings, truth_cost};
use pim_fit::Knowledge;
use pim_reconstruct::{reconstruct, Reconstruction, Status};
use rand::rngs::StdRng;
use rand::SeedableRng;

#[test]
fn noise_free_scenes_give_back_the_impact_speeds() {
    noise_free(12);
}

/// The full figure: 100 noise-free crashes.
#[test]
#[ignore]
fn noise_free_100_crashes() {
    noise_free(100);
}

fn noise_free(crashes: usize) {
    let mut done = 0;
    let mut seed = 0;
    let mut worst: f64 = 0.0;
    let mut times = Vec::new();
    while done < crashes {
        seed += 1;
        let Some(c) = crash(seed, 0.0) else { continue };
        let t = std::time::Instant::now();
        let out = reconstruct(&c.recon, &settings()).unwrap();
        let el = t.elapsed();
        assert_eq!(out.status, Status::Found, "seed {seed}: {:?}", out.reason);
        let b = out.best.as_ref().unwrap();
        let err = c.speed_error(b);
        eprintln!(
            "seed {seed}: chi2 {:.3e}, speed error {err:.2e}, {} fits, {} runouts, {:?}, tried {}",
            b.chi_square,
            out.fits,
            out.runouts,
            el,
            out.tried.len()
        );
        worst = worst.max(err);
        times.push(el.as_secs_f64());
        done += 1;
    }
    times.sort_by(f64::total_cmp);
    eprintln!(
        "{crashes} noise-free crashes: worst impact-speed error {worst:.2e} m/s; time median \
         {:.3} s, max {:.3} s",
        times[times.len() / 2],
        times[times.len() - 1]
    );
    assert!(worst < 1e-3, "worst speed error {worst}");
}

#[test]
fn noisy_scenes_never_cost_more_than_the_truth() {
    let mut done = 0;
    let mut seed = 1000;
    while done < 10 {
        seed += 1;
        let Some(c) = crash(seed, 1.0) else { continue };
        let out = reconstruct(&c.recon, &settings()).unwrap();
        assert_eq!(out.status, Status::Found, "seed {seed}: {:?}", out.reason);
        let b = out.best.as_ref().unwrap();
        let truth = truth_cost(&c);
        // The run-outs are integrated to 1e-10: costs agree to far better than 1e-6.
        assert!(
            b.chi_square <= truth + 1e-6,
            "seed {seed}: the reconstruction costs {} against the truth's {truth}",
            b.chi_square
        );
        assert!(b.converged, "seed {seed}");
        done += 1;
    }
}

/// One bootstrap draw of a reconstruction, as `pim uncertainty` draws a case: every estimate
/// and observation of the contact state by its standard deviation, every rest position,
/// heading and mark by its sigma.
fn perturbed(r: &Reconstruction, rng: &mut StdRng) -> Reconstruction {
    let mut p = r.clone();
    let unit = r.unit.unwrap_or(1.0);
    for c in p.contact.components.iter_mut() {
        if let Knowledge::Estimated { value, weight } = c {
            *value += (unit / *weight).sqrt() * common_normal(rng);
        }
    }
    for o in p.contact.observations.iter_mut() {
        o.value += (unit / o.weight).sqrt() * common_normal(rng);
    }
    for v in p.scene.iter_mut() {
        if let Some(rest) = v.evidence.rest.as_mut() {
            rest.x += rest.sigma_xy[0] * common_normal(rng);
            rest.y += rest.sigma_xy[1] * common_normal(rng);
            if let Some(h) = rest.heading.as_mut() {
                *h += rest.sigma_heading * common_normal(rng);
            }
        }
        for m in v.evidence.marks.iter_mut() {
            m.x += m.sigma * common_normal(rng);
            m.y += m.sigma * common_normal(rng);
        }
    }
    p
}

/// Coverage of the 90 % intervals of both impact speeds over `crashes` simulated crashes with
/// noisy evidence, `draws` bootstrap draws each: (covered, intervals).
fn coverage(crashes: usize, draws: usize, first_seed: u64) -> (usize, usize) {
    use rayon::prelude::*;
    let seeds: Vec<u64> = (first_seed..)
        .filter(|&s| crash(s, 1.0).is_some())
        .take(crashes)
        .collect();
    let results: Vec<[bool; 2]> = seeds
        .par_iter()
        .filter_map(|&seed| {
            let c = crash(seed, 1.0).unwrap();
            let s = settings();
            let nominal = reconstruct(&c.recon, &s).ok()?;
            nominal.best.as_ref()?;
            let mut speeds: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
            for i in 0..draws {
                let mut rng = StdRng::seed_from_u64(seed * 100_003 + i as u64);
                let p = perturbed(&c.recon, &mut rng);
                if let Ok(Some(f)) = pim_reconstruct::redo(&p, &s, &nominal, 4.0) {
                    speeds[0].push(f.phases[0].contact);
                    speeds[1].push(f.phases[1].contact);
                }
            }
            let truth = [c.contact.vehicle1.speed(), c.contact.vehicle2.speed()];
            Some(std::array::from_fn(|k| {
                let mut v = speeds[k].clone();
                v.sort_by(f64::total_cmp);
                let q = |p: f64| v[((v.len() - 1) as f64 * p).round() as usize];
                !v.is_empty() && q(0.05) <= truth[k] && truth[k] <= q(0.95)
            }))
        })
        .collect();
    let covered = results.iter().flatten().filter(|b| **b).count();
    (covered, 2 * results.len())
}

/// 24 crashes, 60 draws: the 90 % intervals hold the true impact speeds in 75 % of the 48
/// intervals or more (a binomial 90 % gives fewer than 75 % with probability 0.3 %); the full
/// run of 200 crashes is `coverage_of_200_simulated_crashes`. A slow sweep (90 s on two
/// cores), run with `--ignored`: the suite asserts the coverage of the case files' study
/// (pim-studies' `scene_coverage.rs` and `realistic_scenes.rs`), which draws through this
/// crate's refit.
#[test]
#[ignore]
fn intervals_cover_the_true_impact_speeds() {
    let (covered, n) = coverage(24, 60, 5000);
    let rate = covered as f64 / n as f64;
    eprintln!("coverage {covered}/{n} = {rate:.3}");
    assert!(n >= 44, "only {n} intervals");
    assert!(rate >= 0.75, "coverage {rate}");
}

/// The full figure: 200 crashes, 100 draws each (about 25 minutes on two cores).
#[test]
#[ignore]
fn coverage_of_200_simulated_crashes() {
    let (covered, n) = coverage(200, 100, 20_000);
    let rate = covered as f64 / n as f64;
    eprintln!("coverage {covered}/{n} = {rate:.3}");
    assert!((0.85..=0.95).contains(&rate), "coverage {rate}");
}

/// Each vehicle's 90 % profile interval of its speed at contact around `nominal`, m/s (both
/// ends reached).
fn profile(
    c: &crate::common::crash::Crash,
    nominal: &pim_reconstruct::Outcome,
    k: usize,
) -> Option<(f64, f64)> {
    let p = pim_reconstruct::profile_interval(
        &c.recon,
        &settings(),
        nominal,
        pim_core::VehicleId::from_index(k),
        pim_reconstruct::PROFILE_LEVEL,
    )
    .ok()??;
    (p.lower.reached && p.upper.reached).then_some((p.lower.speed, p.upper.speed))
}

/// Each end of a profile interval is where the profile has risen by 2.71: the ends that the
/// search in `profile_end` finds (steps out, then regula falsi) are those of a dense scan of
/// the profile (the forward speed pulled to 16 speeds from the answer to 1.5 times the end's
/// distance), to 0.02 m/s; and the interval holds the answer.
#[test]
fn a_profile_interval_ends_where_the_profile_has_risen_by_its_chi_square() {
    let s = settings();
    let rise = pim_reconstruct::profile_rise(pim_reconstruct::PROFILE_LEVEL);
    assert!((rise - 2.7055).abs() < 1e-4, "{rise}");
    let mut checked = 0;
    for seed in 5000.. {
        if checked == 2 {
            break;
        }
        let Some(c) = crash(seed, 1.0) else { continue };
        let nominal = reconstruct(&c.recon, &s).unwrap();
        let Some(best) = nominal.best.as_ref() else {
            continue;
        };
        let id = pim_core::VehicleId::One;
        let a = c.recon.contact.impact.forward_axis(id);
        let u = best.solution.initial.vehicle1;
        let g0 = u.vx * a[0] + u.vy * a[1];
        let answer = best.phases[0].contact;
        let (lo, hi) = profile(&c, &nominal, 0).expect("both ends reached");
        assert!(
            lo < answer && answer < hi,
            "seed {seed}: {lo} {answer} {hi}"
        );
        // Pulled at unit weight the refit reaches part of the way: scan the pulls far enough
        // out that the reached speeds pass the end.
        let mut points = Vec::new();
        for i in 0..=16 {
            let pull = g0 + 3.0 * (hi - answer) * i as f64 / 16.0;
            let p = pim_reconstruct::profile_point(&c.recon, &s, &nominal, id, pull)
                .unwrap()
                .expect("a refit");
            points.push((p.chi_square - best.chi_square, p.speed));
        }
        let crossing = points
            .windows(2)
            .find(|w| w[0].0 < rise && w[1].0 >= rise)
            .map(|w| {
                let t = (rise.sqrt() - w[0].0.max(0.0).sqrt())
                    / (w[1].0.sqrt() - w[0].0.max(0.0).sqrt());
                w[0].1 + t * (w[1].1 - w[0].1)
            })
            .expect("the scan passes the end");
        eprintln!("seed {seed}: upper end {hi:.4}, the scan's {crossing:.4}");
        assert!(
            (crossing - hi).abs() < 0.02,
            "seed {seed}: {hi} against {crossing}"
        );
        checked += 1;
    }
}

/// 24 crashes: the profile intervals hold the true impact speeds in 85-95 % of the 48
/// (`--ignored`, a slow sweep).
#[test]
#[ignore]
fn profile_intervals_cover_the_true_impact_speeds() {
    use rayon::prelude::*;
    let seeds: Vec<u64> = (5000..)
        .filter(|&s| crash(s, 1.0).is_some())
        .take(std::env::var("CRASHES").map_or(24, |v| v.parse().expect("a number")))
        .collect();
    let held: Vec<[bool; 2]> = seeds
        .par_iter()
        .filter_map(|&seed| {
            let c = crash(seed, 1.0).unwrap();
            let nominal = reconstruct(&c.recon, &settings()).ok()?;
            nominal.best.as_ref()?;
            let truth = [c.contact.vehicle1.speed(), c.contact.vehicle2.speed()];
            Some(std::array::from_fn(|k| {
                profile(&c, &nominal, k).is_some_and(|(lo, hi)| lo <= truth[k] && truth[k] <= hi)
            }))
        })
        .collect();
    let n = 2 * held.len();
    let covered = held.iter().flatten().filter(|b| **b).count();
    let rate = covered as f64 / n as f64;
    eprintln!("profile coverage {covered}/{n} = {rate:.3}");
    assert!((0.85..=0.95).contains(&rate), "coverage {rate}");
}
