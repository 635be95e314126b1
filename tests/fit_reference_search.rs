//! The certified search is never beaten by a slow, independent reference search: a dense grid
//! over the coefficient box plus pattern-search polishing, on the real (noisy) RICSAC data.
//!
//! The reference uses pim-core only: for Q2 the separation state is a forward solve from the
//! fixed contact state; for Q1 the contact state is a backward solve from the fixed separation
//! state (each friction sign); for Q3 the unconstrained least-squares contact state for
//! `X = R x` is computed from the assembled equations and kept only when it is admissible. Every
//! reference point must pass pim-core's admissibility check, the velocity bounds and approach.
mod common;
use common::*;
use nalgebra::{Matrix6, Vector6};
use pim_core::*;
use pim_fit::*;

const VB: f64 = 20.0;
const WB: f64 = 5.0;

fn within_bounds(v: &Velocities) -> bool {
    v.to_vector()
        .iter()
        .enumerate()
        .all(|(k, x)| x.abs() <= if k % 3 == 2 { WB } else { VB })
}

fn sq(a: &Velocities, b: &Velocities) -> f64 {
    (a.to_vector() - b.to_vector()).norm_squared()
}

/// Reference cost at (e, mu, em); `stick` uses the no-slip condition (mu = mu_max).
fn reference_cost(
    impact: &Impact,
    preset: CostPreset,
    x_meas: &Velocities,
    xf_meas: &Velocities,
    c: Coefficients,
    stick: bool,
) -> f64 {
    let opts = SolveOptions {
        tangential: if stick {
            TangentialCondition::NoSlip
        } else {
            TangentialCondition::Sliding
        },
        ..Default::default()
    };
    let admissible = |r: &ImpactReport| {
        r.admissibility.admissible
            && within_bounds(&r.initial)
            && within_bounds(&r.separation)
            && impact.check_approach(&r.initial).is_ok()
            && (!stick || r.mu_max.is_some_and(|m| m.abs() <= 1.2))
    };
    match preset {
        CostPreset::Q2 => match solve_forward(impact, &c, x_meas, &opts) {
            Ok(r) if admissible(&r) => sq(&r.separation, xf_meas),
            _ => f64::INFINITY,
        },
        CostPreset::Q1 => [1.0, -1.0]
            .iter()
            .filter_map(|&s| solve_backward_with_sign(impact, &c, xf_meas, &opts, s).ok())
            .filter(|r| admissible(r))
            .map(|r| sq(&r.initial, x_meas))
            .fold(f64::INFINITY, f64::min),
        CostPreset::Q3 => [1.0, -1.0]
            .iter()
            .filter_map(|&s| {
                let sys = equations::assemble(impact, &c, s, &opts);
                let r: Matrix6<f64> = -sys.f.lu().solve(&sys.g)?;
                // min |x - a|^2 + |R x - b|^2
                let h = Matrix6::identity() + r.transpose() * r;
                let g: Vector6<f64> = x_meas.to_vector() + r.transpose() * xf_meas.to_vector();
                let x = h.cholesky()?.solve(&g);
                let init = Velocities::from_vector(&x);
                let sep = Velocities::from_vector(&(r * x));
                if impact.friction_sign(&init) * s < 0.0 {
                    return None;
                }
                let rep = analyse(impact, &c, &opts, &init, &sep, s).ok()?;
                let c_eff = if stick {
                    Coefficients {
                        mu: rep.mu_max?,
                        ..c
                    }
                } else {
                    c
                };
                let rep = analyse(impact, &c_eff, &opts, &init, &sep, s).ok()?;
                admissible(&rep).then(|| sq(&init, x_meas) + sq(&sep, xf_meas))
            })
            .fold(f64::INFINITY, f64::min),
    }
}

fn axis(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// Dense grid then pattern search; returns the best reference cost.
fn reference_search(
    impact: &Impact,
    preset: CostPreset,
    x: &Velocities,
    xf: &Velocities,
    branch: MomentBranch,
) -> f64 {
    let ems: Vec<f64> = match branch {
        MomentBranch::Zero => vec![1.0],
        MomentBranch::Free => axis(-1.0, 0.0, 11),
    };
    let mut best = (f64::INFINITY, [0.0; 3], false);
    for stick in [false, true] {
        let mus = if stick {
            vec![0.0]
        } else {
            axis(-1.2, 1.2, 49)
        };
        for &e in &axis(0.0, 0.2, 21) {
            for &mu in &mus {
                for &em in &ems {
                    let c =
                        reference_cost(impact, preset, x, xf, Coefficients { e, mu, em }, stick);
                    if c < best.0 {
                        best = (c, [e, mu, em], stick);
                    }
                }
            }
        }
    }
    if !best.0.is_finite() {
        return best.0;
    }
    // Pattern search from the best grid point.
    let (mut cost, mut p, stick) = best;
    let mut step = [0.005, 0.025, 0.05];
    let lo = [0.0, -1.2, -1.0];
    let hi = [0.2, 1.2, 0.0];
    for _ in 0..400 {
        let mut improved = false;
        for k in 0..3 {
            if (k == 1 && stick) || (k == 2 && branch == MomentBranch::Zero) {
                continue;
            }
            for d in [-1.0, 1.0] {
                let mut q = p;
                q[k] = (q[k] + d * step[k]).clamp(lo[k], hi[k]);
                let c = reference_cost(
                    impact,
                    preset,
                    x,
                    xf,
                    Coefficients {
                        e: q[0],
                        mu: q[1],
                        em: q[2],
                    },
                    stick,
                );
                if c < cost {
                    cost = c;
                    p = q;
                    improved = true;
                }
            }
        }
        if !improved {
            step.iter_mut().for_each(|s| *s *= 0.5);
            if step[0] < 1e-7 {
                break;
            }
        }
    }
    cost
}

#[test]
fn fit_is_never_worse_than_the_reference_search_on_ricsac() {
    let tests = pim_cli::ricsac::load(&repo_path("data/ricsac.csv")).unwrap();
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
