//! The uncertainty study's spread against the spread of the answers themselves: one realistic
//! crash measured many times over (the same crash, other noise), each measurement
//! reconstructed. Where the study is right, the deviation of the answers over the measurements
//! and the study's deviation of one measurement agree (to the sampling error of both), and the
//! study's 90 % intervals hold the truth in about 90 % of the measurements.
use crate::common;
use crate::realistic_scenes::{reconstructed, simulated, studied, wheels_named};
use pim_case::case::Case;

fn number(name: &str, default: usize) -> usize {
    std::env::var(name).map_or(default, |v| v.parse().expect("a whole number"))
}

/// `SEED` and `WHEELS` as `write_a_realistic_case` takes them, `MEASUREMENTS` measurements
/// (default 24), a study of `DRAWS` draws (default 40) on each of the first `STUDIES` (default
/// 6): prints each measurement's answer, the truth and the study's deviation, then the
/// deviation of the answers and the mean deviation of the studies, per vehicle.
#[test]
#[ignore]
fn one_crash_measured_many_times() {
    use rayon::prelude::*;
    let seed = common::seed_from_env();
    let wheels = wheels_named(&std::env::var("WHEELS").unwrap_or_else(|_| "Locked,Locked".into()));
    let (n, draws, studies) = (
        number("MEASUREMENTS", 24),
        number("DRAWS", 40),
        number("STUDIES", 6),
    );
    // Each measurement's answers, and its study's 5 % and 95 % points and deviation.
    type Interval = (f64, f64, f64);
    let rows: Vec<([f64; 2], Option<[Interval; 2]>)> = (0..n)
        .into_par_iter()
        .filter_map(|k| {
            let s = common::with_noise(k as u64, || simulated(seed, wheels, false))?;
            let case = Case::from_text(&format!("realistic_{seed}_{k}.toml"), &s.text).ok()?;
            let done = reconstructed(&case);
            let best = done.document.best.as_ref()?;
            let speeds = [
                best.vehicles[0].speed_at_contact,
                best.vehicles[1].speed_at_contact,
            ];
            let chi = done
                .outcome
                .best
                .as_ref()
                .map_or(f64::NAN, |b| b.chi_square);
            let study = (k < studies).then(|| {
                studied(&case, &done, draws, seed).ok().map(|st| {
                    std::array::from_fn(|v| {
                        let q = &st.quantities[&format!("vehicle{}.speed_at_contact", v + 1)];
                        (q.p05, q.p95, q.sd)
                    })
                })
            });
            let truth = [s.contact.vehicle1.speed(), s.contact.vehicle2.speed()];
            eprintln!(
                "measurement {k}: chi-square {chi:.3}, answers {:.4?}, truth {:.4?}, study {:.4?}",
                speeds,
                truth,
                study.flatten()
            );
            Some((speeds, study.flatten()))
        })
        .collect();
    let s = common::with_noise(0, || simulated(seed, wheels, false)).expect("a crash");
    let truth = [s.contact.vehicle1.speed(), s.contact.vehicle2.speed()];
    for v in 0..2 {
        let answers: Vec<f64> = rows.iter().map(|r| r.0[v]).collect();
        let mean = answers.iter().sum::<f64>() / answers.len() as f64;
        let sd = (answers.iter().map(|a| (a - mean).powi(2)).sum::<f64>()
            / (answers.len() - 1) as f64)
            .sqrt();
        let study_sds: Vec<f64> = rows.iter().filter_map(|r| r.1.map(|q| q[v].2)).collect();
        let covered = rows
            .iter()
            .filter_map(|r| r.1.map(|q| q[v].0 <= truth[v] && truth[v] <= q[v].1))
            .filter(|c| *c)
            .count();
        eprintln!(
            "vehicle {}: truth {:.4}, answers' mean {mean:.4} and deviation {sd:.4} over {}, \
             studies' mean deviation {:.4} over {}, their intervals hold the truth {covered} times",
            v + 1,
            truth[v],
            answers.len(),
            study_sds.iter().sum::<f64>() / study_sds.len().max(1) as f64,
            study_sds.len()
        );
    }
}
