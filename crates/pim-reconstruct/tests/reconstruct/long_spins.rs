//! The whole reconstruction on simulated crashes with long, spinning run-outs (up to 80 m and
//! two full turns): the reported chi-square is never above the truth's (the truth is one of the
//! states searched over, so a search that misses it reports more), and no consistent scene is
//! refused.
use crate::common;

use common::crash::{crash_with, settings, truth_cost, Crash};
use pim_reconstruct::{reconstruct, Status};
use std::f64::consts::TAU;

/// Contact speeds of the long run-outs, m/s.
const SPEEDS: std::ops::Range<f64> = 12.0..32.0;

/// A crash whose run-outs end within 80 m and two turns, with at least one vehicle that
/// spins half a turn or slides 30 m.
fn long_spin(seed: u64) -> Option<Crash> {
    let c = crash_with(seed, 1.0, SPEEDS)?;
    let mut long = false;
    for run in &c.runouts {
        let turns = run.rotation.abs() / TAU;
        if run.distance > 80.0 || turns > 2.0 {
            return None;
        }
        long |= turns >= 0.5 || run.distance >= 30.0;
    }
    long.then_some(c)
}

/// `crashes` long-spin crashes from `first_seed`: (worst excess of the reported chi-square
/// over the truth's, refusals, median and longest seconds).
fn sweep(crashes: usize, first_seed: u64) -> Vec<String> {
    use rayon::prelude::*;
    let seeds: Vec<u64> = (first_seed..)
        .filter(|&s| long_spin(s).is_some())
        .take(crashes)
        .collect();
    let failures: Vec<String> = seeds
        .par_iter()
        .filter_map(|&seed| {
            let c = long_spin(seed).expect("drawn");
            let truth = truth_cost(&c);
            let out = reconstruct(&c.recon, &settings()).expect("valid input");
            let turns: Vec<f64> = c.runouts.iter().map(|r| r.rotation / TAU).collect();
            let dist: Vec<f64> = c.runouts.iter().map(|r| r.distance).collect();
            let found = out.best.as_ref().map(|b| b.chi_square);
            let ok = out.status != Status::NoSolution
                && found.is_some_and(|f| f <= truth + 1e-6 * (1.0 + truth));
            eprintln!(
                "seed {seed}: truth {truth:.3}, found {found:?}, {:?}, turns {turns:.2?}, \
                 distance {dist:.1?}",
                out.status
            );
            (!ok).then(|| {
                format!(
                    "FAIL seed {seed}: chi-square {found:?} against the truth's {truth:.3} ({:?}: \
                     {:?}); turns {turns:.2?}, distances {dist:.1?} m",
                    out.status, out.reason
                )
            })
        })
        .collect();
    failures
}

#[test]
#[ignore = "long: tests/long runs it"]
fn long_spinning_runouts_never_cost_more_than_the_truth() {
    let failures = sweep(8, 70_000);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The crashes of the 200 on which a search from the scenes' own candidates alone stopped in
/// a wrong basin: four refused as inconsistent (chi-square 337 to 1,082 against the truth's 9
/// to 23) and one answered at 13.05 against 11.66.
#[test]
#[ignore = "long: tests/long runs it"]
fn crashes_whose_scenes_have_several_basins() {
    let failures: Vec<String> = [80_325, 80_549, 80_787, 80_914, 81_377]
        .into_iter()
        .filter_map(|seed| {
            let c = long_spin(seed).expect("a long-spin crash");
            let truth = truth_cost(&c);
            let out = reconstruct(&c.recon, &settings()).expect("valid input");
            let found = out.best.as_ref().map(|b| b.chi_square);
            let ok = out.status == Status::Found
                && found.is_some_and(|f| f <= truth + 1e-6 * (1.0 + truth));
            (!ok).then(|| format!("seed {seed}: {found:?} against the truth's {truth:.3}"))
        })
        .collect();
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

/// The full figure: 200 crashes (minutes on two cores).
#[test]
#[ignore]
fn long_spinning_runouts_200_crashes() {
    let failures = sweep(200, 80_000);
    assert!(
        failures.is_empty(),
        "{} of 200:\n{}",
        failures.len(),
        failures.join("\n")
    );
}
