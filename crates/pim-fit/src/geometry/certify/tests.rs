//! The bound of a box against complete fits at points inside it (RICSAC 6, the example case's
//! five geometry inputs): never above, and equal to the fit at a point.

use super::*;
use crate::geometry::types::GeometryInput;
use crate::problem::CostPreset;
use crate::report::Status;
use nalgebra::Vector6;
use pim_core::{Collision, Vehicle, Velocities};

// -3.14 rad/s is the case's yaw rate, not pi.
#[allow(clippy::approx_constant)]
fn problem(preset: CostPreset) -> FitProblem {
    let v = |mass: f64, yaw_inertia: f64, heading: f64, d: f64, phi: f64| Vehicle {
        mass,
        yaw_inertia,
        heading,
        d,
        phi,
    };
    let c = Collision {
        vehicle1: v(1950.0, 4703.0, 0.0, 2.56, -17.9),
        vehicle2: v(1190.0, 2263.0, 60.0, 0.61, -90.0),
        crush_angle: -30.0,
    };
    let x = Velocities::from_vector(&Vector6::new(-9.61, 0.0, 0.0, 4.66, 8.32, 0.0));
    let xf = Velocities::from_vector(&Vector6::new(-5.69, 1.26, -0.52, -1.28, 5.49, -3.14));
    FitProblem::from_preset(Impact::new(c).unwrap(), preset, &x, &xf, None)
}

fn bounds() -> Vec<GeometryBound> {
    [
        (GeometryInput::D(1), [2.44, 2.56]),
        (GeometryInput::Phi(1), [-25.0, -15.0]),
        (GeometryInput::D(2), [0.61, 0.76]),
        (GeometryInput::Phi(2), [-90.0, -60.0]),
        (GeometryInput::CrushAngle, [-40.0, -20.0]),
    ]
    .map(|(input, bounds)| GeometryBound { input, bounds })
    .to_vec()
}

fn settings(branch: MomentBranch) -> FitSettings {
    FitSettings {
        e: [0.0, 0.45],
        velocity_bound: 20.0,
        yaw_rate_bound: 5.0,
        branches: vec![branch],
        ranges: false,
        ..Default::default()
    }
}

/// The fit at unit-cube point t: its cost and e_m.
fn fit_at(p: &FitProblem, g: &[GeometryBound], s: &FitSettings, t: &[f64]) -> Option<(f64, f64)> {
    let mut c = *p.impact.collision();
    for (b, &v) in g.iter().zip(t) {
        b.input
            .set(&mut c, b.bounds[0] + v * (b.bounds[1] - b.bounds[0]));
    }
    let problem = FitProblem {
        impact: Impact::new(c).ok()?,
        ..p.clone()
    };
    let r = crate::fit(&problem, &s.clone().check().unwrap()).ok()?;
    let b = &r.branches[0];
    match (b.status, &b.solution) {
        (Status::Optimal, Some(x)) => Some((x.cost, x.em)),
        _ => None,
    }
}

#[test]
fn a_box_is_never_bounded_above_the_fits_inside_it_and_a_point_is_bounded_at_its_fit() {
    let g = bounds();
    let mut seed = 12345u64;
    let mut next = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut checked, mut tight) = (0, 0);
    for preset in [CostPreset::Q2, CostPreset::Q3] {
        let p = problem(preset);
        for branch in MomentBranch::ALL {
            let s = settings(branch);
            let ctx = Context::new(&p, &g, &s, branch).unwrap();
            for _ in 0..6 {
                let width = [0.02, 0.1, 0.3, 1.0][(next() * 4.0) as usize];
                let lo: Vec<f64> = (0..5).map(|_| (next() * (1.0 - width)).max(0.0)).collect();
                let hi: Vec<f64> = lo.iter().map(|l| (l + width).min(1.0)).collect();
                let points: Vec<Vec<f64>> = (0..6)
                    .map(|_| {
                        lo.iter()
                            .zip(&hi)
                            .map(|(a, b)| a + next() * (b - a))
                            .collect()
                    })
                    .collect();
                let fits: Vec<(f64, f64)> = points
                    .iter()
                    .filter_map(|t| fit_at(&p, &g, &s, t))
                    .collect();
                for &(c, em) in &fits {
                    // An e_m interval of the free branch that holds the fit's e_m.
                    let em_box = match branch {
                        MomentBranch::Zero => [1.0, 1.0],
                        MomentBranch::Free => {
                            let w = [0.05, 0.3, 1.0][(next() * 3.0) as usize];
                            let a = (em - next() * w).max(-1.0);
                            [a, (a + w).min(0.0).max(em)]
                        }
                    };
                    let b = ctx
                        .bound_box(&lo, &hi, em_box, c, &Proved::default())
                        .unwrap();
                    assert!(
                        b.low <= c * (1.0 + 1e-9) + 1e-9,
                        "{preset:?} {branch:?}: box {lo:?}..{hi:?} e_m {em_box:?} bounded at {} \
                         above the fit's {c}",
                        b.low
                    );
                    checked += 1;
                }
                // At a point (and a narrow e_m interval around the fit's e_m) the bound is the
                // fit.
                if let Some(&(c, em)) = fits.first() {
                    let t = &points[0];
                    let em_box = match branch {
                        MomentBranch::Zero => [1.0, 1.0],
                        MomentBranch::Free => [(em - 1e-7).max(-1.0), (em + 1e-7).min(0.0)],
                    };
                    let b = ctx.bound_box(t, t, em_box, c, &Proved::default()).unwrap();
                    assert!(b.low <= c * (1.0 + 1e-9) + 1e-9, "{} above {c}", b.low);
                    assert!(
                        b.low >= c * (1.0 - 1e-6),
                        "{preset:?} {branch:?}: at {t:?} (e_m {em}) bounded at {}, the fit {c}",
                        b.low
                    );
                    tight += 1;
                }
            }
        }
    }
    assert!(
        checked >= 60 && tight >= 16,
        "{checked} boxes, {tight} points"
    );
}
