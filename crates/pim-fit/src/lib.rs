//! # pim-fit: certified least-squares estimation of the PIM coefficients
//!
//! Finds the impact coefficients `(e, mu, e_m)` and the twelve velocity components
//! `U = (v1x, v1y, w1, v2x, v2y, w2, V1x, V1y, W1, V2x, V2y, W2)` (m/s, rad/s) that satisfy the six
//! Planar Impact Mechanics equations of [`pim_core`] and come closest to what is measured or
//! estimated:
//!
//! ```text
//! minimise    Q(U) = sum_k w_k (U_k - U_k_est)^2 + sum_j w_j (a_j . U - t_j)^2
//! subject to  F(e, mu, em, s) X + G(e, mu, em, s) x = 0        (equations 1-6)
//!             U_k = value            for components known exactly
//!             e_min <= e <= e_max,   em in [-1, 0] (branch "free") or em = 1 (branch "zero")
//!             mu between 0 and mu_max(U) (signed), mu_min <= mu <= mu_max_bound
//!             |v| <= v_bound, |w| <= w_bound
//!             the vehicles approach at C at contact, s = sgn(vn) sgn(vt)
//!             T(X) <= T(x)                                       (no kinetic energy created)
//! ```
//!
//! The observation rows `a_j` cover EDR-style data: delta-V along and across a vehicle's axis,
//! the speed along its heading ([`ObservationKind`]). Presets Q1, Q2, Q3 ([`CostPreset`]) are the
//! cost functions of Vossou & Koulocheris (2018): Q1 holds the separation velocities fixed and
//! estimates the contact ones, Q2 the reverse (Brach's fits), Q3 estimates all twelve.
//!
//! ## How the global optimum is found
//! For fixed coefficients, friction sign and tangential mode the best U is a convex quadratic
//! program in the six contact components (`X = R x`); it is solved in closed form when no
//! inequality is active and by clarabel otherwise, and the non-convex energy condition is
//! enforced exactly through its Lagrangian (see the `inner` module). "mu between 0 and mu_max" is
//! linear in U for a fixed sign of mu, and its boundary mu = mu_max is the sticking mode
//! (equation 5a), searched on its own. The coefficients live in a small box, searched by a grid
//! whose points are solved exactly wherever their lower bound could beat the best value, then
//! refined by Nelder-Mead (argmin) from the best grid points of distinct cells and polished by a
//! compass search. When one whole state is known (Q1, Q2) the six equations reduce to a 3x3
//! system in the impulse, both states are affine in e (or in 1 + 1/e) at fixed `(mu, e_m)`, and
//! e is minimised exactly at every point of the search (a quadratic over at most two intervals),
//! which removes one dimension from the box. The [`Certificate`] of each branch records that
//! search. Infeasible data are an
//! [`Status::Infeasible`] outcome with the reason in words, never a solution that violates the
//! equations.
//!
//! ```
//! use pim_core::*;
//! use pim_fit::*;
//! let v = |mass, yaw_inertia, heading, d, phi| Vehicle { mass, yaw_inertia, heading, d, phi };
//! let impact = Impact::new(Collision {
//!     vehicle1: v(1036.0, 1348.0, 0.0, 1.4, 0.0),
//!     vehicle2: v(2189.0, 5287.0, 90.0, 1.6, -30.0),
//!     crush_angle: 0.0,
//! })?;
//! // Synthetic data from known coefficients: the fit must find them again.
//! let initial = Velocities::from_vector(&nalgebra::Vector6::new(-9.48, 0.0, 0.0, 0.0, 9.48, 0.0));
//! let truth = Coefficients { e: 0.1, mu: 0.3, em: 1.0 };
//! let sep = solve_forward(&impact, &truth, &initial, &SolveOptions::default())?.separation;
//! let problem = FitProblem::from_preset(impact, CostPreset::Q2, &initial, &sep, None);
//! let report = fit(&problem, &FitSettings::default().check()?)?;
//! let zero = report.branches.iter().find(|b| b.moment == MomentBranch::Zero).unwrap();
//! let s = zero.solution.as_ref().unwrap();
//! assert!(s.cost < 1e-8 && (s.e - 0.1).abs() < 1e-3 && (s.mu - 0.3).abs() < 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod determined;
mod error;
mod inner;
mod problem;
mod report;
mod search;

pub use error::{FitError, Result};
pub use problem::{
    forward_axis, state_vector, CostPreset, FitProblem, FitSettings, Knowledge, MomentBranch,
    Observation, ObservationKind, ValidSettings, Vector12, COMPONENT_NAMES,
};
pub use report::{BranchReport, Certificate, FitReport, Identifiability, Solution, Status};

use inner::{Mode, Prepared, Violation};
use pim_core::{Coefficients, SolveOptions, TangentialCondition, Velocities};
use search::{search_branch, Outcome, Point};

/// Fits both (or the selected) moment branches. Errors only for an invalid problem; infeasible
/// data give a report whose branches say so.
pub fn fit(problem: &FitProblem, settings: &ValidSettings) -> Result<FitReport> {
    problem.check()?;
    let s = settings.get();
    let prep = Prepared::new(problem, s);
    // The branches are independent searches: run them side by side.
    let outcomes: Vec<Outcome> = match s.branches.as_slice() {
        [a, b] => {
            let (x, y) = rayon::join(
                || search_branch(&prep, s, *a),
                || search_branch(&prep, s, *b),
            );
            vec![x, y]
        }
        list => list.iter().map(|&b| search_branch(&prep, s, b)).collect(),
    };
    let mut branches = Vec::with_capacity(s.branches.len());
    for (&branch, out) in s.branches.iter().zip(&outcomes) {
        branches.push(branch_report(&prep, problem, s, branch, out)?);
    }
    let solved: Vec<(MomentBranch, f64)> = branches
        .iter()
        .filter(|b| b.status != Status::Infeasible)
        .filter_map(|b| b.solution.as_ref().map(|sol| (b.moment, sol.cost)))
        .collect();
    let mut notes = Vec::new();
    let min = solved.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
    let tied: Vec<MomentBranch> = solved
        .iter()
        .filter(|s| s.1 <= min + 1e-6 * (1.0 + min))
        .map(|s| s.0)
        .collect();
    let best = if tied.contains(&MomentBranch::Zero) {
        Some(MomentBranch::Zero)
    } else {
        tied.first().copied()
    };
    if tied.len() > 1 {
        notes.push(format!(
            "both moment branches fit the data equally well (cost {min:.3e}): the data do not \
             decide whether a moment impulse acts, and the coefficients differ between the \
             branches; the zero branch (no moment impulse, one coefficient fewer) is reported as \
             best"
        ));
    }
    Ok(FitReport {
        branches,
        best,
        notes,
    })
}

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

fn branch_report(
    prep: &Prepared,
    problem: &FitProblem,
    settings: &FitSettings,
    branch: MomentBranch,
    out: &Outcome,
) -> Result<BranchReport> {
    let certificate = certificate(out);
    let Some(best) = out.best else {
        return Ok(BranchReport {
            moment: branch,
            status: Status::Infeasible,
            reason: Some(explain_infeasible(prep, problem, settings, out)),
            solution: None,
            identifiability: Vec::new(),
            certificate,
        });
    };
    let solution = solution(prep, &best)?;
    let identifiability = identifiability(settings, branch, out, solution.cost);
    let mut reason_note = None;
    if !solution.undetermined.is_empty() {
        reason_note = Some(format!(
            "the data do not determine {}: equally good solutions differ along them, and the \
             values shown are the smallest-norm choice",
            solution.undetermined.join(", ")
        ));
    }
    let (status, reason) = if out.limit_reached {
        (
            Status::LimitReached,
            Some(format!(
                "the refinement that found this point reached its iteration limit and none of \
                 the other {} refinements reached the same cost; it is the best point found",
                out.refinements.saturating_sub(1)
            )),
        )
    } else {
        (Status::Optimal, reason_note)
    };
    Ok(BranchReport {
        moment: branch,
        status,
        reason,
        solution: Some(solution),
        identifiability,
        certificate,
    })
}

fn solution(prep: &Prepared, best: &Point) -> Result<Solution> {
    let c = &best.candidate;
    let coefficients = Coefficients {
        e: best.theta.e,
        mu: c.mu_eff,
        em: best.theta.em,
    };
    let options = SolveOptions {
        moment_form: prep.form,
        tangential: match best.mode {
            Mode::Sliding => TangentialCondition::Sliding,
            Mode::Sticking => TangentialCondition::NoSlip,
        },
    };
    let initial = Velocities::from_vector(&c.x);
    let separation = Velocities::from_vector(&c.xf);
    let r = pim_core::analyse(
        &prep.impact,
        &coefficients,
        &options,
        &initial,
        &separation,
        best.sign,
    )?;
    let residuals = r.residuals(&prep.impact);
    Ok(Solution {
        e: coefficients.e,
        mu: coefficients.mu,
        em: coefficients.em,
        cost: c.cost,
        initial,
        separation,
        sticking: best.mode == Mode::Sticking,
        friction_sign: best.sign,
        max_residual: residuals.max_relative(),
        residuals,
        active_constraints: prep.active_constraints(&best.theta, best.mode, best.sign, c),
        energy_loss_percent: r.energy.loss_percent,
        mu_max: r.mu_max,
        mu_ratio: r.mu_ratio,
        delta_v: r.delta_v,
        impulse: r.impulse,
        admissible: r.admissibility.admissible,
        undetermined: prep
            .undetermined_components(&best.theta, best.mode, best.sign)
            .into_iter()
            .map(str::to_string)
            .collect(),
    })
}

fn identifiability(
    settings: &FitSettings,
    branch: MomentBranch,
    out: &Outcome,
    best: f64,
) -> Vec<Identifiability> {
    let tol = settings.identifiability_tolerance;
    let limit = search::near_limit(best, tol, out.data_scale);
    let near: Vec<&[f64; 7]> = out.samples.iter().filter(|s| s[3] <= limit).collect();
    let range = |k: usize| {
        near.iter()
            .fold([f64::INFINITY, f64::NEG_INFINITY], |r, s| {
                [r[0].min(s[k]), r[1].max(s[k])]
            })
    };
    let flat = near.iter().any(|s| s[6] > 0.5);
    let mut list = Vec::new();
    let boxes = [
        settings.e[1] - settings.e[0],
        settings.mu[1] - settings.mu[0],
        1.0,
    ];
    let n = if branch == MomentBranch::Free { 3 } else { 2 };
    for (k, name) in ["e", "mu", "em"].iter().enumerate().take(n) {
        let [low, high] = range(k);
        list.push(Identifiability {
            coefficient: name.to_string(),
            low,
            high,
            tolerance: tol,
            identifiable: boxes[k] <= 0.0 || high - low < 0.5 * boxes[k],
            open_ended: false,
        });
    }
    for (k, name) in [(4, "speed1"), (5, "speed2")] {
        let [low, high] = range(k);
        list.push(Identifiability {
            coefficient: name.to_string(),
            low,
            high,
            tolerance: tol,
            identifiable: !flat && high - low <= 0.1 * high.max(1.0),
            open_ended: flat,
        });
    }
    list
}

fn describe(v: Violation, settings: &FitSettings) -> String {
    match v {
        Violation::Bound(k) => format!(
            "the velocities would exceed the bound on {} (|v| <= {} m/s, |omega| <= {} rad/s)",
            COMPONENT_NAMES[k], settings.velocity_bound, settings.yaw_rate_bound
        ),
        Violation::NotApproaching => {
            "the contact velocities would not approach at the impact centre".to_string()
        }
        Violation::SlidingDirection | Violation::Friction => {
            "the tangential impulse would reverse \
             the sliding direction, so no mu between 0 and mu_max fits"
                .to_string()
        }
        Violation::MuBound => format!(
            "stopping the sliding would need a friction ratio outside [{}, {}]",
            settings.mu[0], settings.mu[1]
        ),
        Violation::Energy => "the solution would create kinetic energy".to_string(),
        Violation::Singular => "the impact equations are singular".to_string(),
        Violation::Infeasible => {
            "the bounds, approach and sliding conditions admit no velocities together".to_string()
        }
        Violation::EnergyUncertified => {
            "the energy condition could not be enforced exactly".to_string()
        }
        Violation::Inconsistent => "the components held fixed contradict an equation on their \
             own (sticking needs no tangential relative velocity at separation, e = 0 no normal \
             one, em = 0 equal yaw rates)"
            .to_string(),
    }
}

fn explain_infeasible(
    prep: &Prepared,
    problem: &FitProblem,
    settings: &FitSettings,
    out: &Outcome,
) -> String {
    let impact = &prep.impact;
    let side = if impact.side() == 0.0 {
        1.0
    } else {
        impact.side()
    };
    // Separation velocities fixed: say what is wrong with them directly.
    let fixed_final: Vec<Option<f64>> = (6..12)
        .map(|k| match problem.components[k] {
            Knowledge::Known { value } => Some(value),
            _ => None,
        })
        .collect();
    if fixed_final.iter().all(Option::is_some) {
        let xf = nalgebra::Vector6::from_iterator(fixed_final.iter().map(|v| v.unwrap_or(0.0)));
        let (vn, vt) = impact.relative_velocity(&Velocities::from_vector(&xf));
        if side * vn < -1e-9 {
            return format!(
                "the fixed separation velocities still approach at the impact centre (normal \
                 relative velocity {vn:.3} m/s towards each other), which would need a negative \
                 restitution; no e in [{}, {}] fits them",
                settings.e[0], settings.e[1]
            );
        }
        let top = out
            .violations
            .iter()
            .max_by_key(|(_, n)| **n)
            .map(|(v, _)| *v);
        if matches!(top, Some(Violation::SlidingDirection | Violation::Friction)) {
            return format!(
                "the fixed separation velocities reverse the sliding direction (tangential \
                 relative velocity at separation {vt:.3} m/s), so no mu <= mu_max fits them"
            );
        }
    }
    let fixed_initial = (0..6).all(|k| matches!(problem.components[k], Knowledge::Known { .. }));
    if fixed_initial {
        let x = nalgebra::Vector6::from_iterator((0..6).map(|k| match problem.components[k] {
            Knowledge::Known { value } => value,
            _ => 0.0,
        }));
        if let Err(e) = impact.check_approach(&Velocities::from_vector(&x)) {
            return format!("the fixed contact velocities admit no impact: {e}");
        }
    }
    if out.violations.is_empty() {
        return "no candidate in the coefficient box satisfies the constraints".to_string();
    }
    // Sticking candidates against separation velocities that still slide are expected to fail;
    // they say nothing about why the data cannot be fitted when other failures exist.
    let mut counts: Vec<(Violation, usize)> = out
        .violations
        .iter()
        .filter(|(v, _)| out.violations.len() == 1 || **v != Violation::Inconsistent)
        .map(|(v, n)| (*v, *n))
        .collect();
    let total: usize = counts.iter().map(|c| c.1).sum();
    counts.sort_by_key(|c| std::cmp::Reverse(c.1));
    let pct = |n: usize| 100.0 * n as f64 / total as f64;
    let mut text = format!(
        "no coefficients in the box satisfy every constraint: {} ({:.0} % of the candidates)",
        describe(counts[0].0, settings),
        pct(counts[0].1)
    );
    if let Some(&(v, n)) = counts.get(1) {
        text.push_str(&format!("; {} ({:.0} %)", describe(v, settings), pct(n)));
    }
    text
}
