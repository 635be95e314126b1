//! From the outcome of a branch's search to its report: the solution checked by pim-core, the
//! status and reason, the identifiability ranges and the certificate.

use crate::error::Result;
use crate::inner::Inner;
use crate::problem::{FitProblem, MomentBranch};
use crate::report::{
    BranchReport, Certificate, Identifiability, Limits, Quantity, Reason, Solution, Status,
};
use crate::search::{near_limit, Outcome, Point, Sample};
use crate::settings::FitSettings;
use pim_core::{SolveOptions, Velocities};

fn certificate(out: &Outcome) -> Certificate {
    let profile = if out.profiled_e {
        " (e minimised exactly at every point: with one state known, both states are affine in \
         e or in 1 + 1/e)"
    } else {
        ""
    };
    Certificate {
        method: format!(
            "grid over the coefficient box per tangential mode (sliding; sticking at \
             mu = mu_max){profile}, every grid point whose lower bound could beat the incumbent \
             solved exactly, then Nelder-Mead from the best grid points of distinct cells, the \
             results near the best polished by a compass search"
        ),
        grid_points: out.grid_points,
        evaluations: out.evaluations,
        exact_solves: out.exact_solves,
        qp_solves: out.qp_solves,
        refinements: out.refinements,
        refinements_agreeing: out.refinements_agreeing,
        energy_uncertified_points: out.uncertified,
    }
}

/// The report of one branch.
pub(crate) fn report(
    inner: &Inner,
    problem: &FitProblem,
    settings: &FitSettings,
    branch: MomentBranch,
    out: &Outcome,
) -> Result<BranchReport> {
    let certificate = certificate(out);
    let Some(best) = out.best else {
        let limits = Limits {
            velocity: settings.velocity_bound,
            yaw_rate: settings.yaw_rate_bound,
            mu: settings.mu,
            e: settings.e,
        };
        return Ok(BranchReport {
            moment: branch,
            status: Status::Infeasible,
            reason: Some(crate::inner::explain_infeasible(
                inner,
                problem,
                limits,
                &out.violations,
            )),
            solution: None,
            identifiability: Vec::new(),
            certificate,
            geometry: None,
        });
    };
    let (solution, problems) = solution(inner, settings, branch, &best)?;
    let identifiability = if settings.ranges {
        identifiability(settings, branch, out, solution.cost)
    } else {
        Vec::new()
    };
    let (status, reason) = if !problems.is_empty() {
        (Status::CheckFailed, Some(Reason::CheckFailed(problems)))
    } else if out.limit_reached {
        (
            Status::LimitReached,
            Some(Reason::LimitReached {
                other_refinements: out.refinements.saturating_sub(1),
            }),
        )
    } else if !solution.undetermined.is_empty() {
        (
            Status::Optimal,
            Some(Reason::Undetermined(solution.undetermined.clone())),
        )
    } else {
        (Status::Optimal, None)
    };
    Ok(BranchReport {
        moment: branch,
        status,
        reason,
        solution: Some(solution),
        identifiability,
        certificate,
        geometry: None,
    })
}

/// The solution of the best point, analysed by pim-core, and what pim-core's check of it found
/// wrong (empty when the equations hold and the answer is admissible).
fn solution(
    inner: &Inner,
    settings: &FitSettings,
    branch: MomentBranch,
    best: &Point,
) -> Result<(Solution, Vec<String>)> {
    let c = &best.candidate;
    let coefficients = pim_core::Coefficients {
        mu: c.mu_eff,
        ..best.at.c
    };
    let options = SolveOptions {
        moment_form: settings.moment_form,
        tangential: best.at.mode,
    };
    let initial = Velocities::from_vector(&c.x);
    let separation = Velocities::from_vector(&c.xf);
    let r = pim_core::analyse(
        &inner.impact,
        &coefficients,
        &options,
        &initial,
        &separation,
        best.at.sign,
    )?;
    let residuals = r.residuals(&inner.impact);
    let mut problems = r.inadmissibility_reasons();
    if residuals.max_relative() > 1e-8 {
        problems.push(format!(
            "the six equations hold only to {:.1e} (relative)",
            residuals.max_relative()
        ));
    }
    let solution = Solution {
        e: coefficients.e,
        mu: coefficients.mu,
        em: coefficients.em,
        cost: c.cost,
        initial,
        separation,
        sticking: best.at.mode == pim_core::TangentialCondition::NoSlip,
        friction_sign: best.at.sign,
        max_residual: residuals.max_relative(),
        residuals,
        active_constraints: inner.active_constraints(&best.at, c, branch == MomentBranch::Free),
        energy_loss_percent: r.energy.loss_percent,
        mu_max: r.mu_max,
        mu_ratio: r.mu_ratio,
        delta_v: r.delta_v,
        vehicles: r.vehicles,
        energy_loss: r.energy.loss,
        impulse: r.impulse,
        admissible: r.admissibility.admissible,
        undetermined: inner.undetermined_components(&best.at),
    };
    Ok((solution, problems))
}

fn identifiability(
    settings: &FitSettings,
    branch: MomentBranch,
    out: &Outcome,
    best: f64,
) -> Vec<Identifiability> {
    let tol = settings.identifiability_tolerance;
    let limit = near_limit(best, tol, out.data_scale);
    let near: Vec<&Sample> = out.samples.iter().filter(|s| s.cost <= limit).collect();
    let range = |q: Quantity| {
        near.iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |r, s| {
                [r[0].min(s.get(q)), r[1].max(s.get(q))]
            })
    };
    let flat = near.iter().any(|s| s.flat);
    let mut quantities = vec![Quantity::E, Quantity::Mu];
    if branch == MomentBranch::Free {
        quantities.push(Quantity::Em);
    }
    quantities.extend([Quantity::Speed1, Quantity::Speed2]);
    quantities
        .into_iter()
        .map(|q| {
            let [low, high] = range(q);
            // A coefficient is pinned down when its range covers less than half its box; a
            // speed when it spans at most 10 % of itself and the cost is not flat.
            let (identifiable, open_ended) = match q {
                Quantity::Speed1 | Quantity::Speed2 => {
                    (!flat && high - low <= 0.1 * high.max(1.0), flat)
                }
                _ => {
                    let size = match q {
                        Quantity::E => settings.e[1] - settings.e[0],
                        Quantity::Mu => settings.mu[1] - settings.mu[0],
                        _ => 1.0,
                    };
                    (size <= 0.0 || high - low < 0.5 * size, false)
                }
            };
            Identifiability {
                coefficient: q,
                low,
                high,
                tolerance: tol,
                identifiable,
                open_ended,
            }
        })
        .collect()
}
