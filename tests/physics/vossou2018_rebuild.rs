//! Vossou & Koulocheris (2018) print, per RICSAC test and cost function, the error of every
//! fitted velocity component (their Tables 4-6, `data/reference/vossou2018_table{4,5,6}.csv`),
//! not the fitted velocities. This test rebuilds those velocities from the printed errors and the
//! measured ones (their Table 1 = `data/ricsac.csv`) and checks what the columns are: read as
//! `|fitted| - |measured|`, the rebuilt velocities conserve linear momentum (as any solution of
//! the impact equations must); read as `fitted - measured`, they do not.
//!
//! Rebuilding: a component with error `d` and measurement `m` has `|fitted| = |m| + d`; its sign
//! is not printed, so each rebuilt state takes the signs (the measured sign unless a flip lets
//! the state conserve momentum better) that minimise the momentum residual. The residual is
//! stated as the velocity vehicle 2 would need to change to close it:
//! `|m1 dV1 + m2 dV2| / m2`, m/s, in x and y.
use crate::common;
use common::*;
use pim_fit::CostPreset;
use std::collections::HashMap;

/// The printed errors of one cost function: test -> (component index 0..12 -> error).
fn printed(preset: CostPreset) -> HashMap<u32, Vec<(usize, f64)>> {
    let file = format!(
        "data/reference/{}",
        pim_case::reference::vossou_table(preset)
    );
    let names = [
        "vi1x", "vi1y", "wi1", "vi2x", "vi2y", "wi2", "vf1x", "vf1y", "wf1", "vf2x", "vf2y", "wf2",
    ];
    read_reference(&file)
        .iter()
        .map(|r| {
            let errors = names
                .iter()
                .enumerate()
                .filter(|(_, n)| r.0.contains_key(**n))
                .map(|(k, n)| (k, r.num(n)))
                .collect();
            (r.num("test") as u32, errors)
        })
        .collect()
}

/// The twelve measured components of a test.
fn measured(t: &pim_case::ricsac::RicsacTest) -> [f64; 12] {
    let (a, b) = (t.initial().to_vector(), t.separation().to_vector());
    std::array::from_fn(|k| if k < 6 { a[k] } else { b[k - 6] })
}

/// The linear-momentum residual of a 12-vector (contact, separation) in x and y, as the change
/// of vehicle 2's velocity that would close it, m/s.
fn momentum_miss(t: &pim_case::ricsac::RicsacTest, u: &[f64; 12]) -> [f64; 2] {
    let (m1, m2) = (t.mass1_kg, t.mass2_kg);
    let p = |k1: usize, k2: usize| (m1 * (u[6 + k1] - u[k1]) + m2 * (u[6 + k2] - u[k2])) / m2;
    [p(0, 3).abs(), p(1, 4).abs()]
}

/// The rebuilt state under one reading: `abs` reads the errors as `|fitted| - |measured|`
/// (signs chosen to conserve momentum best), otherwise as `fitted - measured`.
fn rebuild(
    t: &pim_case::ricsac::RicsacTest,
    errors: &[(usize, f64)],
    abs: bool,
) -> ([f64; 12], usize) {
    let m = measured(t);
    let mut base = m;
    for &(k, d) in errors {
        base[k] = if abs {
            m[k].signum() * (m[k].abs() + d)
        } else {
            m[k] + d
        };
    }
    if !abs {
        return (base, 0);
    }
    // Flips of the linear components only (the yaw rates do not enter linear momentum).
    let linear: Vec<usize> = errors
        .iter()
        .map(|&(k, _)| k)
        .filter(|k| k % 3 != 2)
        .collect();
    let mut best = (base, 0usize, f64::INFINITY);
    for mask in 0..(1u32 << linear.len()) {
        let mut u = base;
        for (i, &k) in linear.iter().enumerate() {
            if mask & (1 << i) != 0 {
                u[k] = -u[k];
            }
        }
        let [x, y] = momentum_miss(t, &u);
        let flips = mask.count_ones() as usize;
        // A flip must buy a clearly better balance (1 cm/s) to be taken.
        let score = x.max(y) + 0.01 * flips as f64;
        if score < best.2 {
            best = (u, flips, score);
        }
    }
    (best.0, best.1)
}

/// e implied by a 12-vector: `-Vn / vn` at the impact centre.
fn implied_e(t: &pim_case::ricsac::RicsacTest, u: &[f64; 12]) -> f64 {
    let impact = t.impact().unwrap();
    let row = pim_core::equations::normal_velocity_row(&impact);
    let x = nalgebra::Vector6::from_column_slice(&u[..6]);
    let y = nalgebra::Vector6::from_column_slice(&u[6..]);
    -(row * y)[0] / (row * x)[0]
}

#[test]
fn vossou_columns_are_differences_of_magnitudes() {
    let tests = ricsac_tests();
    let mut rows = Vec::new();
    println!(
        "test cost  printed rebuilt flips | momentum miss |u|-|m| (x, y) | fitted-measured | e"
    );
    for preset in CostPreset::ALL {
        let table = printed(preset);
        for t in &tests {
            let Some(errors) = table.get(&t.test) else {
                continue;
            };
            let printed_cost: f64 = errors.iter().map(|(_, d)| d * d).sum();
            let (abs, flips) = rebuild(t, errors, true);
            let (plain, _) = rebuild(t, errors, false);
            let m = measured(t);
            let rebuilt_cost: f64 = (0..12).map(|k| (abs[k] - m[k]).powi(2)).sum();
            let miss_abs = momentum_miss(t, &abs);
            let miss_plain = momentum_miss(t, &plain);
            let e = implied_e(t, &abs);
            println!(
                "{:>4} {}  {:>7.2} {:>7.2} {:>5} | {:>6.3} {:>6.3} | {:>6.3} {:>6.3} | {:+.3}",
                t.test,
                preset.name(),
                printed_cost,
                rebuilt_cost,
                flips,
                miss_abs[0],
                miss_abs[1],
                miss_plain[0],
                miss_plain[1],
                e
            );
            rows.push((
                t.test,
                preset,
                printed_cost,
                rebuilt_cost,
                miss_abs,
                miss_plain,
                e,
            ));
        }
    }
    let q2 = |test: u32| {
        rows.iter()
            .find(|r| r.0 == test && r.1 == CostPreset::Q2)
            .unwrap()
    };
    // Read as |fitted| - |measured|, V18's Q2 velocities conserve momentum to 4 cm/s in tests
    // 1, 3, 4, 6, 8 and 11 (measured: at most 0.034 m/s, test 1 in x); read as fitted -
    // measured, they miss by metres per second. Test 10 misses y-momentum by 0.30 m/s under both
    // readings with the data file's masses (1046 / 2141 kg): its fitted y-velocities need a mass
    // ratio of 0.455 against 0.489; test 12 misses x by 0.50 m/s and test 7 x by 1.43 m/s (a mass
    // ratio of about 1.41 against the data's 1.63): inputs V18 does not print.
    for test in [1, 3, 4, 6, 8, 11] {
        let r = q2(test);
        assert!(r.4[0].max(r.4[1]) < 0.04, "test {test}: {:?}", r.4);
    }
    assert!((q2(10).4[1] - 0.298).abs() < 0.005, "{:?}", q2(10).4);
    assert!((q2(12).4[0] - 0.497).abs() < 0.005, "{:?}", q2(12).4);
    // Where a fitted component changes sign, the printed squares understate V18's cost: test
    // 12 under Q1 prints 13.28, its rebuilt velocities cost 23.04.
    let q1_12 = rows
        .iter()
        .find(|r| r.0 == 12 && r.1 == CostPreset::Q1)
        .unwrap();
    assert!(
        (q1_12.2 - 13.28).abs() < 0.01 && (q1_12.3 - 23.04).abs() < 0.01,
        "{q1_12:?}"
    );
    let worst_plain = rows
        .iter()
        .filter(|r| r.1 == CostPreset::Q2)
        .map(|r| r.5[0].max(r.5[1]))
        .fold(0.0, f64::max);
    assert!(worst_plain > 5.0, "{worst_plain}");
    // Test 11 under Q2 needs e slightly below 0: the vehicles still approach at separation.
    assert!(q2(11).6 < 0.0 && q2(11).6 > -0.05, "{}", q2(11).6);
}

/// The closest forward solve to a rebuilt 12-vector over em in V18's range [-1, 0], with e and
/// mu implied by the vector (e = -Vn/vn, mu = |Pt/Pn|), under one form of the moment equation:
/// (em, largest linear miss m/s, largest yaw miss rad/s, mu, mu_max of that solve).
fn closest_solve(
    t: &pim_case::ricsac::RicsacTest,
    u: &[f64; 12],
    form: pim_core::MomentForm,
) -> Option<(f64, f64, f64, f64, Option<f64>)> {
    let impact = t.impact().unwrap();
    let x = nalgebra::Vector6::from_column_slice(&u[..6]);
    let y = nalgebra::Vector6::from_column_slice(&u[6..]);
    let p = pim_core::equations::impulse_of(&impact, &(y - x));
    let (e, mu) = (implied_e(t, u), (p.tangential / p.normal).abs());
    let opts = pim_core::SolveOptions {
        moment_form: form,
        ..Default::default()
    };
    let state = pim_core::Velocities::from_vector(&x);
    let mut best: Option<(f64, f64, f64, f64, Option<f64>)> = None;
    for i in 0..=200 {
        let em = -1.0 + i as f64 / 200.0;
        let c = pim_core::Coefficients {
            e: e.max(0.0),
            mu,
            em,
        };
        let Ok(r) = pim_core::solve_forward(&impact, &c, &state, &opts) else {
            continue;
        };
        let s = r.separation.to_vector();
        let lin = [0, 1, 3, 4]
            .iter()
            .map(|&k| (s[k] - y[k]).abs())
            .fold(0.0, f64::max);
        let yaw = [2, 5]
            .iter()
            .map(|&k| (s[k] - y[k]).abs())
            .fold(0.0, f64::max);
        if best.is_none_or(|b| lin + yaw < b.1 + b.2) {
            best = Some((em, lin, yaw, mu, r.mu_max));
        }
    }
    best
}

#[test]
fn which_moment_equation_vossou_solved() {
    let tests = ricsac_tests();
    let table = printed(CostPreset::Q2);
    println!("test | corrected: em  miss m/s  rad/s | brach1983: em  miss m/s  rad/s  mu  mu_max");
    let mut found = HashMap::new();
    for t in &tests {
        let Some(errors) = table.get(&t.test) else {
            continue;
        };
        let (u, _) = rebuild(t, errors, true);
        let c = closest_solve(t, &u, pim_core::MomentForm::Corrected).unwrap();
        let b = closest_solve(t, &u, pim_core::MomentForm::Brach1983).unwrap();
        println!(
            "{:>4} | {:+.3} {:.3} {:.3} | {:+.3} {:.3} {:.3} {:.3} {:?}",
            t.test, c.0, c.1, c.2, b.0, b.1, b.2, b.3, b.4
        );
        found.insert(t.test, (c, b));
    }
    // Tests 8, 9 and 10: V18's Q2 velocities are a forward solve of the 1983 moment equation
    // (the one with the sign error) with em inside [-1, 0] to 0.14 rad/s, and miss every
    // solve of the corrected one by 0.53 to 3.31 rad/s (measured; the linear miss of test 10 is
    // its momentum miss, 0.30 m/s).
    for test in [8, 9, 10] {
        let (c, b) = found[&test];
        assert!(b.2 < 0.15 && b.0 < -0.5, "test {test}: 1983 {b:?}");
        assert!(c.2 > 0.5 && c.2 > 3.0 * b.2, "test {test}: corrected {c:?}");
    }
    // And they need a friction ratio above what sticking needs (mu > mu_max: the sliding
    // reverses, which the default fit does not admit): test 10 mu 0.753 against mu_max 0.621,
    // test 8 0.597 against 0.462 (test 9 sits at mu_max, 0.694).
    for (test, mu, mu_max) in [(10, 0.753, 0.621), (8, 0.597, 0.462)] {
        let b = found[&test].1;
        let m = b.4.unwrap();
        assert!(
            (b.3 - mu).abs() < 0.002 && (m - mu_max).abs() < 0.002,
            "test {test}: {b:?}"
        );
        assert!(b.3 > m);
    }
}

/// What keeps a rebuilt V18 solution from being a point of V18's own conditions (Brach's 1983
/// moment equation with em in [-1, 0], e in [0, 0.2], mu in [0, 1.2], the velocity bounds,
/// linear momentum with the data's masses, no energy created), by name; empty if nothing does.
fn outside_v18_conditions(t: &pim_case::ricsac::RicsacTest, u: &[f64; 12]) -> Vec<String> {
    let mut why = Vec::new();
    let miss = momentum_miss(t, u);
    if miss[0].max(miss[1]) > 0.05 {
        why.push(format!(
            "does not conserve momentum with the data's masses (miss {:.2} / {:.2} m/s): inputs \
             V18 does not print",
            miss[0], miss[1]
        ));
    }
    let e = implied_e(t, u);
    if !(-0.005..=0.205).contains(&e) {
        why.push(format!("needs e = {e:.3}, outside [0, 0.2]"));
    }
    if (0..12).any(|k| u[k].abs() > if k % 3 == 2 { 5.0 } else { 20.0 }) {
        why.push("exceeds the velocity bounds".into());
    }
    // Printed to 0.01, each rebuilt component is within 0.005 of V18's: a solve of their
    // equations comes within about 0.02 of it (the em scan adds 0.005 of em).
    match closest_solve(t, u, pim_core::MomentForm::Brach1983) {
        Some((_, lin, yaw, mu, _)) if lin <= 0.02 && yaw <= 0.02 && mu <= 1.2 => {}
        Some((em, lin, yaw, mu, _)) => why.push(format!(
            "no solve of the 1983 moment equation with em in [-1, 0] comes near it (closest: em \
             {em:+.2}, mu {mu:.3}, miss {lin:.2} m/s, {yaw:.2} rad/s)"
        )),
        None => why.push("no forward solve".into()),
    }
    let energy = |v: &[f64]| {
        let (m1, m2, i1, i2) = (
            t.mass1_kg,
            t.mass2_kg,
            t.yaw_inertia1_kgm2,
            t.yaw_inertia2_kgm2,
        );
        m1 * (v[0] * v[0] + v[1] * v[1])
            + i1 * v[2] * v[2]
            + m2 * (v[3] * v[3] + v[4] * v[4])
            + i2 * v[5] * v[5]
    };
    if energy(&u[6..]) > energy(&u[..6]) * (1.0 + 1e-3) {
        why.push("creates kinetic energy".into());
    }
    why
}

/// `pim batch --conditions v18` reproduces or betters V18 under V18's own conditions: on
/// every fit whose rebuilt solution satisfies those conditions our free-branch cost is at or
/// below the rebuilt cost (beyond it by at most what printing the errors to 0.01 can move
/// it); the others are named with what keeps V18's solution outside the conditions.
#[test]
fn ours_under_v18_conditions_at_or_below_v18() {
    let tests = ricsac_tests();
    let plan = pim_studies::batch::BatchPlan::new(
        &CostPreset::ALL,
        &pim_fit::MomentBranch::ALL,
        0.2,
        pim_core::MomentForm::Corrected,
    )
    .unwrap()
    .with_v18_conditions();
    let records = pim_studies::batch::run(&tests, &plan, &pim_studies::watch::Unwatched);
    let (mut compared, mut explained) = (0, 0);
    println!("test cost  rebuilt   ours | why V18's solution is outside V18's conditions");
    for preset in CostPreset::ALL {
        let table = printed(preset);
        for t in &tests {
            let Some(errors) = table.get(&t.test) else {
                continue;
            };
            let (u, _) = rebuild(t, errors, true);
            let m = measured(t);
            let rebuilt: f64 = (0..12).map(|k| (u[k] - m[k]).powi(2)).sum();
            let r = records
                .iter()
                .find(|r| r.test == t.test && r.cost_function == preset)
                .unwrap();
            assert_eq!(r.moment_branch, pim_fit::MomentBranch::Free);
            let ours = r
                .branch
                .as_ref()
                .filter(|_| r.solved())
                .and_then(|b| b.cost)
                .unwrap_or(f64::INFINITY);
            let why = outside_v18_conditions(t, &u);
            println!(
                "{:>4} {}  {rebuilt:>7.2} {ours:>7.2} | {}",
                t.test,
                preset.name(),
                why.join("; ")
            );
            if why.is_empty() {
                // The printed errors are rounded to 0.01: the rebuilt point is within 0.005
                // of V18's in each printed component.
                let rounding: f64 = errors.iter().map(|(_, d)| 0.01 * d.abs() + 2.5e-5).sum();
                assert!(
                    ours <= rebuilt + rounding,
                    "test {} {}: ours {ours} above V18's rebuilt {rebuilt} (+{rounding:.3})",
                    t.test,
                    preset.name()
                );
                compared += 1;
            } else {
                explained += 1;
            }
        }
    }
    assert_eq!(compared + explained, 33);
    println!("{compared} compared, {explained} explained");
}
