//! From the outcome of a branch's search to its report: the solution checked by pim-core, the
//! status and reason, the identifiability ranges and the certificate.

use crate::certificate::{Certificate, Method, Route};
use crate::error::Result;
use crate::inner::Inner;
use crate::problem::MomentBranch;
use crate::report::{
    BranchReport, Identifiability, Quantity, Reason, Solution, Status, TangentialFit,
};
use crate::search::{near_limit, Outcome, Point, Sample};
use crate::settings::FitSettings;
use pim_core::{SolveOptions, Velocities};

fn certificate(out: &Outcome, inner: &Inner) -> Certificate {
    let (route, description) = if let Some(c) = out.convex {
        let what = if out.friction_max.is_some() {
            "the tangential model's modes: over the contact state and the impulse every \
             condition but the energy is linear once the mode (sticking, or sliding on a side \
             with the sticking impulse's normal part on either side of its pole) and the sign \
             of the initial tangential velocity are fixed, the friction rule on the sticking \
             impulse at some et of the range eliminated exactly"
        } else {
            "PIM's sign patterns: over the contact state and the impulse every condition but \
             the energy is linear once the signs of the friction, of the normal and tangential impulse, of the \
             frictionless and no-slip normal impulses, of the final tangential velocity and \
             (free branch) of the linear-impulse yaw rate are fixed"
        };
        (
            Route::Convex,
            format!(
                "convex decomposition of {what}; each pattern is a strictly convex QP solved to \
                 its KKT-verified optimum by a dual active-set method ({} patterns{}, {} solved, \
                 {} stopped by their lower bound or found empty); {}",
                c.patterns,
                if c.intervals > 1 {
                    format!(" over {} e_m intervals of a branch-and-bound", c.intervals)
                } else {
                    String::new()
                },
                c.solved,
                c.pruned,
                if out.best.is_some() {
                    "the best checked by the exact constraint set"
                } else if c.patterns == 0 {
                    "the conditions all patterns share (bounds, approach, restitution range, the \
                     known components) have no common point: the branch has no feasible point"
                } else {
                    "every pattern is empty, and together they contain the feasible set: the \
                     branch has no feasible point"
                }
            ),
        )
    } else if out.friction_max.is_some() {
        (
            Route::Grid,
            "grid over the coefficient box per contact mode of the tangential model (sticking \
             over e and et; sliding over e, friction and et), every grid point whose lower bound \
             could beat the incumbent solved exactly, then Nelder-Mead from the best grid points \
             of distinct cells, the results near the best polished by a compass search"
                .to_string(),
        )
    } else {
        let profile = if out.profiled_e {
            " (e minimised exactly at every point: with one state known, both states are affine \
             in e or in 1 + 1/e)"
        } else {
            ""
        };
        (
            Route::Grid,
            format!(
                "grid over the coefficient box per tangential mode (sliding; sticking at \
                 mu = mu_max){profile}, every grid point whose lower bound could beat the \
                 incumbent solved exactly, then Nelder-Mead from the best grid points of distinct \
                 cells, the results near the best polished by a compass search"
            ),
        )
    };
    // The reason for a fallback, as the search recorded it, only on the grid route.
    let fallback = out.fallback.filter(|_| route == Route::Grid);
    let description = match fallback {
        Some(why) => format!("{description} (not the convex route: {})", why.words()),
        None => description,
    };
    Certificate {
        method: Method {
            route,
            fallback,
            description,
        },
        grid_points: out.grid_points,
        evaluations: out.evaluations,
        exact_solves: out.exact_solves,
        qp_solves: out.qp_solves,
        refinements: out.refinements,
        refinements_agreeing: out.refinements_agreeing,
        energy_uncertified_points: out.uncertified,
        operations: inner.operations.load(std::sync::atomic::Ordering::Relaxed),
    }
}

/// The report of one branch.
pub(crate) fn report(
    inner: &Inner,
    settings: &FitSettings,
    branch: MomentBranch,
    out: &Outcome,
) -> Result<BranchReport> {
    let certificate = certificate(out, inner);
    let Some(best) = out.best else {
        return Ok(BranchReport {
            moment: branch,
            status: Status::Infeasible,
            reason: Some(crate::inner::explain_infeasible(
                inner,
                crate::report::Limits::of(settings),
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
    let initial = Velocities::from_vector(&c.x);
    let separation = Velocities::from_vector(&c.xf);
    let mut problems = Vec::new();
    let (r, tangential) = if inner.family.friction() == crate::family::Friction::Limit {
        let (r, t, mut more) = tangential_check(inner, settings, best, &initial)?;
        problems.append(&mut more);
        (r, Some(t))
    } else {
        let options = SolveOptions {
            moment_form: settings.moment_form,
            tangential: best.at.mode,
        };
        // The sign of equation 5 as the forward model reads it from the fitted contact state
        // (the friction rule: the searched sign where it slides, the no-slip impulse's side
        // where it does not), with mu re-expressed so that mu' = mu sign is the searched one.
        let (sign, _) = pim_core::contact_friction(&inner.impact, &best.at.c, &initial, &options);
        let coefficients = pim_core::Coefficients {
            mu: c.mu_eff * best.at.sign.value() * sign.value(),
            ..best.at.c
        };
        let r = pim_core::analyse(
            &inner.impact,
            &coefficients,
            &options,
            &initial,
            &separation,
            sign,
        )?;
        (r, None)
    };
    let coefficients = r.coefficients;
    let residuals = r.residuals(&inner.impact);
    // With mu bounded by its box alone (asked for), mu beyond mu_max is no failed check; the
    // solution still says it is not admissible (`admissible`, `mu_ratio`).
    if settings.mu_max_condition {
        problems.extend(r.friction_reason());
    }
    problems.extend(r.energy_reason());
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
        sticking: tangential.is_none() && best.at.mode == pim_core::TangentialCondition::NoSlip,
        friction_sign: r.friction_sign,
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
        tangential,
    };
    Ok((solution, problems))
}

/// The tangential model's check of a fitted point: its own forward solve from the fitted
/// contact state must give the fitted separation state, in the mode the search assumed.
fn tangential_check(
    inner: &Inner,
    settings: &FitSettings,
    best: &Point,
    initial: &Velocities,
) -> Result<(pim_core::ImpactReport, TangentialFit, Vec<String>)> {
    let c = &best.candidate;
    let sliding = best.at.mode == pim_core::TangentialCondition::Sliding;
    let friction = if sliding {
        best.at.c.mu
    } else {
        settings.friction[1]
    };
    let coefficients = pim_core::TangentialCoefficients {
        e: best.at.c.e,
        et: best.at.et,
        friction,
    };
    let t = pim_core::solve_tangential(&inner.impact, &coefficients, initial)?;
    let mut problems = Vec::new();
    let gap = (t.report.separation.to_vector() - c.xf).amax();
    let scale = c.xf.amax().max(c.x.amax()).max(1.0);
    if gap > 1e-8 * scale {
        problems.push(format!(
            "the tangential model's forward solve differs from the fitted separation by \
             {gap:.1e}"
        ));
    }
    let mode = if sliding {
        pim_core::ContactMode::Slide
    } else {
        pim_core::ContactMode::Stick
    };
    // On the boundary both modes give the same answer: the forward solve may read it either way.
    if t.mode != mode && gap > 1e-8 * scale {
        problems.push(format!(
            "the tangential model's forward solve {} where the fit assumed it {}",
            words(t.mode),
            words(mode)
        ));
    }
    let fit = TangentialFit {
        mode,
        et: best.at.et,
        // Sticking: any friction limit from the impulse ratio to the bound (the ratio onto it
        // against round-off).
        friction: if sliding {
            friction
        } else {
            t.impulse_ratio.abs().min(friction)
        },
        friction_max: friction,
        impulse_ratio: t.impulse_ratio,
        stick_ratio: t.stick_ratio,
    };
    Ok((t.report, fit, problems))
}

fn words(m: pim_core::ContactMode) -> &'static str {
    match m {
        pim_core::ContactMode::Stick => "sticks",
        pim_core::ContactMode::Slide => "slides",
    }
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
                let [lo, hi] = s.span(q);
                [r[0].min(lo), r[1].max(hi)]
            })
    };
    let flat = near.iter().any(|s| s.flat);
    let mut quantities = if out.friction_max.is_some() {
        vec![Quantity::E, Quantity::Et, Quantity::Friction]
    } else {
        vec![Quantity::E, Quantity::Mu]
    };
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
                        Quantity::Et => settings.et[1] - settings.et[0],
                        Quantity::Friction => settings.friction[1] - settings.friction[0],
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
