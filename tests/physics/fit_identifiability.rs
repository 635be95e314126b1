//! The identifiability ranges of Q1 and Q2 fits against an independent scan with pim-core:
//! along e at the optimum's mu and em, every admissible e whose cost is within the tolerance must
//! lie inside the reported range of e (the search computes that interval's ends exactly).
use crate::common;
use common::*;
use pim_core::{solve_backward_with_sign, solve_forward, Coefficients, SolveOptions};
use pim_fit::*;

fn check(test: u32, preset: CostPreset, branch: MomentBranch) -> usize {
    let tests = ricsac_tests();
    let t = tests.iter().find(|t| t.test == test).unwrap();
    let impact = t.impact().unwrap();
    let problem = FitProblem::from_preset(impact, preset, &t.initial(), &t.separation(), None);
    let settings = FitSettings {
        branches: vec![branch],
        ..FitSettings::default()
    };
    let report = fit(&problem, &settings.clone().check().unwrap()).unwrap();
    let b = &report.branches[0];
    let s = b.solution.as_ref().expect("a solution");
    assert!(!s.sticking, "the scan below is for a sliding optimum");
    let range = b
        .identifiability
        .iter()
        .find(|i| i.coefficient == Quantity::E)
        .unwrap();
    let limit = s.cost * (1.0 + settings.identifiability_tolerance);
    let (measured, fixed) = match preset {
        CostPreset::Q1 => (t.initial().to_vector(), t.separation()),
        _ => (t.separation().to_vector(), t.initial()),
    };
    let mut inside = 0;
    for i in 0..=20_000 {
        let e = 0.2 * i as f64 / 20_000.0;
        let coef = Coefficients {
            e,
            mu: s.mu,
            em: s.em,
        };
        let opts = SolveOptions::default();
        let solved = match preset {
            CostPreset::Q1 => {
                solve_backward_with_sign(&impact, &coef, &fixed, &opts, s.friction_sign)
                    .map(|r| (r.initial.to_vector(), r.admissibility.admissible))
            }
            _ => solve_forward(&impact, &coef, &fixed, &opts)
                .map(|r| (r.separation.to_vector(), r.admissibility.admissible)),
        };
        let Ok((u, admissible)) = solved else {
            continue;
        };
        let cost = (u - measured).norm_squared();
        if admissible && cost <= limit * (1.0 - 1e-9) {
            inside += 1;
            assert!(
                e >= range.low - 1e-9 && e <= range.high + 1e-9,
                "RICSAC {test} {preset:?}: e = {e} (cost {cost}, limit {limit}) outside the \
                 reported [{}, {}]",
                range.low,
                range.high
            );
        }
    }
    inside
}

#[test]
fn e_ranges_contain_every_near_optimal_e_on_the_optimum_line() {
    // RICSAC 4 Q1 free: a 1 % cost band spans e from about 0.0856 to 0.0892.
    let n = check(4, CostPreset::Q1, MomentBranch::Free);
    assert!(n > 50, "{n} scan points inside");
    let n = check(4, CostPreset::Q2, MomentBranch::Free);
    assert!(n > 50, "{n} scan points inside");
    let n = check(8, CostPreset::Q1, MomentBranch::Zero);
    assert!(n > 50, "{n} scan points inside");
}
