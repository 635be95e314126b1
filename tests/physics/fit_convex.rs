//! The convex solve of Q3 (a union of strictly convex QPs over the contact state and the
//! impulse, with a branch-and-bound over e_m in the free branch) against the grid search it
//! replaces, which stays available as `search.convex = false`:
//! - on all 22 RICSAC Q3 problems (11 tests x both moment branches) the convex solve decides,
//!   and its cost is never above the grid search's, and below it by at most 1e-6 relative;
//! - on random noisy Q3 problems (both branches, sliding and sticking truths, mu_max of both
//!   signs) it is never above the grid search by more than 1e-6 relative, and decides at least
//!   90 % of the branches itself (the others: its optimum creates energy, whose condition is
//!   not convex over these variables, or lies where the six equations are singular).
//!
//! - with one state known (Q1, Q2) both branches take the same route over the subspace the
//!   known components leave: on the 44 RICSAC Q1/Q2 branch problems and on random noisy ones
//!   it is never above the grid search by more than 1e-6 relative, nor below it by more than
//!   the grid search's precision, and says infeasible exactly where the grid search does.
//!
//! The independent reference search of `fit_stress.rs` checks the same path on its cases.
use crate::common;
use pim_fit::*;
use rand::rngs::StdRng;
use rand::SeedableRng;

fn settings(convex: bool) -> ValidSettings {
    settings_of(convex, &MomentBranch::ALL)
}

fn settings_of(convex: bool, branches: &[MomentBranch]) -> ValidSettings {
    let mut s = FitSettings::default();
    s.search.convex = convex;
    s.ranges = false;
    s.branches = branches.to_vec();
    s.check().unwrap()
}

/// `(cost, decided by the convex solve)` per branch.
fn costs(problem: &FitProblem, convex: bool) -> Vec<(f64, bool)> {
    fit(problem, &settings(convex))
        .unwrap()
        .branches
        .iter()
        .map(|b| {
            (
                b.solution.as_ref().map_or(f64::INFINITY, |s| s.cost),
                b.certificate.method.route == Route::Convex,
            )
        })
        .collect()
}

#[test]
fn ricsac_q3_equals_the_grid_search() {
    let mut decided = 0;
    for t in common::ricsac_tests() {
        let impact = t.impact().unwrap();
        let problem =
            FitProblem::from_preset(impact, CostPreset::Q3, &t.initial(), &t.separation(), None);
        let fast = costs(&problem, true);
        let grid = costs(&problem, false);
        for ((c, by_convex), (g, _)) in fast.iter().zip(&grid) {
            assert!(c.is_finite() && g.is_finite(), "test {}", t.test);
            // Never above; below by at most the grid search's own precision (its compass
            // polish stops at 1e-7 of the box; test 4 free ends 1.7e-7 higher without the
            // scans of the ranges).
            assert!(
                *c <= g * (1.0 + 1e-9) && g - c <= 1e-6 * g,
                "test {}: convex {c} grid {g}",
                t.test
            );
            decided += usize::from(*by_convex);
        }
    }
    assert_eq!(
        decided, 22,
        "every RICSAC Q3 branch decided by the convex solve"
    );
}

/// A random collision with noisy estimates of both states (`None`: draw again).
fn draw(seed: u64) -> Option<FitProblem> {
    draw_as(seed, CostPreset::Q3)
}

fn draw_as(seed: u64, preset: CostPreset) -> Option<FitProblem> {
    let d = common::noisy_draw(&mut StdRng::seed_from_u64(seed))?;
    Some(FitProblem::from_preset(d.impact, preset, &d.x, &d.xf, None))
}

#[test]
fn random_q3_never_above_the_grid_search() {
    let problems: Vec<FitProblem> = (7_000..).filter_map(draw).take(60).collect();
    let (mut branches, mut decided) = (0, 0);
    for (i, p) in problems.iter().enumerate() {
        let fast = costs(p, true);
        let grid = costs(p, false);
        for ((c, by_convex), (g, _)) in fast.iter().zip(&grid) {
            branches += 1;
            decided += usize::from(*by_convex);
            assert!(
                *c <= g * (1.0 + 1e-6) + 1e-9,
                "problem {i}: convex {c} above grid {g}"
            );
        }
    }
    assert!(
        decided * 10 >= branches * 9,
        "the convex solve decided {decided} of {branches} branches"
    );
}

/// `(cost, route)` of one moment branch alone.
fn one_branch(problem: &FitProblem, branch: MomentBranch, convex: bool) -> (f64, Route) {
    let report = fit(problem, &settings_of(convex, &[branch])).unwrap();
    let b = &report.branches[0];
    (
        b.solution.as_ref().map_or(f64::INFINITY, |s| s.cost),
        b.certificate.method.route,
    )
}

fn agree(what: &str, fast: (f64, Route), grid: (f64, Route)) -> bool {
    let ((c, route), (g, _)) = (fast, grid);
    if g.is_infinite() || c.is_infinite() {
        assert!(
            c.is_infinite() && g.is_infinite(),
            "{what}: convex {c}, grid {g}"
        );
        return route == Route::Convex;
    }
    assert!(
        c <= g * (1.0 + 1e-6) + 1e-9,
        "{what}: convex {c} above grid {g}"
    );
    assert!(
        g - c <= 1e-6 * g + 1e-9,
        "{what}: convex {c} below grid {g}"
    );
    route == Route::Convex
}

#[test]
fn q1_q2_equal_the_grid_search() {
    for branch in MomentBranch::ALL {
        let (mut decided, mut solved) = (0, 0);
        for t in common::ricsac_tests() {
            let impact = t.impact().unwrap();
            for preset in [CostPreset::Q1, CostPreset::Q2] {
                let p =
                    FitProblem::from_preset(impact, preset, &t.initial(), &t.separation(), None);
                let (fast, grid) = (one_branch(&p, branch, true), one_branch(&p, branch, false));
                solved += usize::from(grid.0.is_finite());
                let what = format!("test {} {preset:?} {}", t.test, branch.name());
                decided += usize::from(agree(&what, fast, grid) && fast.0.is_finite());
            }
        }
        // Q1 of tests 1, 6, 7, 10 and 11 has no admissible solution in either branch.
        assert_eq!(
            (decided, solved),
            (17, 17),
            "{} branch: solved problems decided by the convex solve",
            branch.name()
        );
        let mut random = 0;
        for preset in [CostPreset::Q1, CostPreset::Q2] {
            for (i, p) in (9_000..)
                .filter_map(|s| draw_as(s, preset))
                .take(40)
                .enumerate()
            {
                let (fast, grid) = (one_branch(&p, branch, true), one_branch(&p, branch, false));
                let what = format!("{preset:?} problem {i} {}", branch.name());
                random += usize::from(agree(&what, fast, grid));
            }
        }
        assert!(
            random >= 60,
            "{} branch: the convex solve decided {random} of 80 random problems",
            branch.name()
        );
    }
}
