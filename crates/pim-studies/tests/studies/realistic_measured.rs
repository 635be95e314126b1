//! Realistic crashes (`realistic_scenes`' generator, the same crashes and run-outs) with the
//! scene as a survey gives it instead of worked-out CG positions: each rest by the left front
//! and left rear tyres' contact points (0.1 m), vehicle 1's right front tyre mark at two points,
//! vehicle 2's left front tyre's yaw mark traced by five points (0.2 m). The residuals are
//! those tyre points against the simulated vehicle's; none is carried to the CG by hand.
//!
//! Asserted as for the CG scenes: none refused, none answered above the truth's chi-square;
//! the `--ignored` sweep draws the intervals and reports their coverage.
use crate::realistic_scenes::{check, run_simulated, simulated_as, Wheels};

/// Each wheel state once on each vehicle (rotated so that no pair repeats), the first
/// admissible crash from its seed.
fn crashes(count: usize, first_seed: u64, draws: usize) -> Vec<crate::realistic_scenes::Outcome> {
    const ALL: [Wheels; 5] = [
        Wheels::Locked,
        Wheels::Abs,
        Wheels::Rolling,
        Wheels::Steered,
        Wheels::Jammed,
    ];
    (0..count)
        .map(|i| {
            let wheels = [ALL[i % 5], ALL[(i + 2 + i / 5) % 5]];
            (first_seed + 1000 * i as u64..)
                .find_map(|seed| {
                    let s = simulated_as(seed, wheels, false, true)?;
                    run_simulated(seed, wheels, s, draws)
                })
                .unwrap()
        })
        .collect()
}

/// Five crashes, every wheel state on each vehicle: answered at or below the truth.
#[test]
#[ignore = "long: tests/long runs it"]
fn measured_scenes_are_answered() {
    check(&crashes(5, 120_000, 0));
}

/// 40 crashes with 100 draws each (`CASES`, `DRAWS` change them): none refused, none above the
/// truth, and the coverage of the 90 % intervals of the contact speeds printed.
#[test]
#[ignore]
fn measured_scenes_40() {
    let number = |name: &str, default: usize| {
        std::env::var(name).map_or(default, |v| v.parse().expect("a whole number"))
    };
    let rate = check(&crashes(number("CASES", 40), 120_000, number("DRAWS", 100)));
    assert!((0.85..=0.95).contains(&rate), "coverage {rate}");
}

/// Seed 128,000: vehicle 1 steered and rolling 98 m through -1.44 turns on a road of 0.55
/// stated as 0.60 +- 0.05, vehicle 2 ABS-braked 9.5 m, vehicle 1's EDR at 18.5 m/s. It was
/// refused at a chi-square of 66.7 where the truth's is 16.0: the first point of each
/// combination was the impact fitted without the EDR (evidence not linear in the velocities
/// was linearised only from the second step on), far from any state the EDR allows, and the
/// continuation before the refusal restarted each stage on the stated friction, where a run-out
/// fitted on 0.53 ends tens of metres from its rest. With the EDR linearised in the first point
/// it answers at 10.2 with the true counts of turns (-1, -1) and 18.60 / 10.88 m/s at contact
/// against 18.66 / 10.74.
#[test]
#[ignore = "long: tests/long runs it"]
fn a_long_steered_runout_is_answered() {
    let wheels = [Wheels::Steered, Wheels::Abs];
    let s = simulated_as(128_000, wheels, false, true).expect("an admissible crash");
    let r = run_simulated(128_000, wheels, s, 0).expect("reconstructed");
    check(&[r]);
}
