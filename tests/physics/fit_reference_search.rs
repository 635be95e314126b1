//! The certified search is never beaten by a slow, independent reference search (a dense grid
//! over the coefficient box plus pattern-search polishing, with pim-core only; see
//! `common/reference.rs`) on the real (noisy) RICSAC data.
use crate::common;
use common::reference::{Box3, RefProblem};
use common::*;
use pim_fit::*;

fn reference_search(
    impact: &pim_core::Impact,
    preset: CostPreset,
    x: &pim_core::Velocities,
    xf: &pim_core::Velocities,
    branch: MomentBranch,
) -> f64 {
    RefProblem {
        impact,
        preset,
        x: *x,
        xf: *xf,
        bounds: Box3::default(),
    }
    .search(branch)
}

#[test]
fn fit_is_never_worse_than_the_reference_search_on_ricsac() {
    let tests = ricsac_tests();
    let settings = FitSettings::default().check().unwrap();
    let mut compared = 0;
    let mut lines = Vec::new();
    for t in &tests {
        let impact = t.impact().unwrap();
        let (x, xf) = (t.initial(), t.separation());
        for preset in CostPreset::ALL {
            let report = fit(
                &FitProblem::from_preset(impact, preset, &x, &xf, None),
                &settings,
            )
            .unwrap();
            for b in &report.branches {
                let reference = reference_search(&impact, preset, &x, &xf, b.moment);
                let ours = b.solution.as_ref().map_or(f64::INFINITY, |s| s.cost);
                lines.push(format!(
                    "test {:>2} {} {:>4}: fit {ours:>10.5}  reference {reference:>10.5}",
                    t.test,
                    preset.name(),
                    b.moment.name()
                ));
                if reference.is_finite() {
                    compared += 1;
                    assert!(
                        ours <= reference + 1e-6 * (1.0 + reference),
                        "test {} {:?} {:?}: fit {ours} > reference {reference}",
                        t.test,
                        preset,
                        b.moment
                    );
                }
            }
        }
    }
    println!("{}", lines.join("\n"));
    assert!(
        compared >= 40,
        "only {compared} problems had a feasible reference point"
    );
}
