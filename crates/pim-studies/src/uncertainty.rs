//! Propagating input uncertainty through the fit: a seeded parametric bootstrap.
//!
//! Each draw perturbs the estimates by their standard deviations (`[sigma]`, and `sigma` on
//! observations) and the inputs the fit takes as exact by `[uncertainty]` (normal with the given
//! standard deviation, or `{ uniform = [lo, hi] }`), refits every branch, keeps the best, and
//! records the quantities a report needs. Draw `i` uses its own random stream (seeded from
//! `seed` and `i`), so the result is bit-identical for any thread count.

use crate::fitcase::{self, CostChoice};
use crate::intervals::dominant_inputs;
pub use crate::intervals::{BoundHit, Summary};
use pim_case::case::Case;
pub use pim_case::spread::{
    standard_normal, ImpactSpread, Spread, UncertaintySection, VehicleSpread,
};
use pim_case::{InputError, Result};
pub use pim_documents::uncertainty::{
    quantities, Sensitivity, Study, QUANTITIES, SPEEDS, TANGENTIAL_QUANTITIES,
};
use pim_fit::{FitSettings, MomentBranch, Quantity, Status};
use rand::SeedableRng;
use rayon::prelude::*;
use std::collections::BTreeMap;

pub use pim_case::tolerances::Tolerances;

/// The random stream of draw `i`: SplitMix64 of the seed and the index.
pub(crate) fn stream(seed: u64, i: u64) -> rand::rngs::StdRng {
    let mut z = seed
        .wrapping_add(0x9E37_79B9_7F4A_7C15u64.wrapping_mul(i + 1))
        .wrapping_add(0x632B_E59B_D9B4_E019);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    rand::rngs::StdRng::seed_from_u64(z ^ (z >> 31))
}

/// One draw's answer (best branch), or `None` when no branch was admissible.
#[derive(Debug, Clone, PartialEq)]
pub struct DrawResult {
    /// The best branch.
    pub branch: MomentBranch,
    /// The values of the model's [`quantities`].
    pub values: [f64; 8],
    /// The search bounds the draw's answer rests on.
    pub bounds: Vec<pim_fit::SearchBound>,
}

pub(crate) use pim_case::drawn::{fit_inputs as inputs, Input};

/// The draws of a study, in parallel and watched: draw `i` perturbs a copy of `case` by every
/// input from its own random stream (`seed`, `i`), so the result is the same for any thread
/// count, and `answer` answers the copy. Each finished draw is a step of the phase `draws`;
/// once the observer cancels no new draw starts. The inputs drawn and the answer of every draw
/// made, in draw order, and whether the study was cancelled.
pub(crate) fn draw_each<T: Send>(
    case: &Case,
    inputs: &[Input],
    (draws, seed): (usize, u64),
    observer: &dyn crate::watch::Observer,
    answer: impl Fn(&Case) -> T + Sync,
) -> (Vec<(Vec<f64>, T)>, Option<crate::watch::Cancelled>) {
    let phase = crate::watch::Phase::start(observer, "draws", draws);
    let results = (0..draws)
        .into_par_iter()
        .filter_map(|i| {
            if phase.stopped() {
                return None;
            }
            let mut rng = stream(seed, i as u64);
            let mut c = case.clone();
            let xs: Vec<f64> = inputs
                .iter()
                .map(|inp| {
                    let x = inp.spread.draw(inp.nominal, &mut rng);
                    (inp.apply)(&mut c, x);
                    x
                })
                .collect();
            let out = answer(&c);
            phase.step();
            Some((xs, out))
        })
        .collect();
    (results, phase.cancelled())
}

/// Fits one version of the case; the best branch's quantities (those of the fit with the crush
/// energy as evidence, when the case's damage is evidence).
fn fit_once(
    case: &Case,
    choice: CostChoice,
    settings: &pim_fit::ValidSettings,
) -> Option<DrawResult> {
    let problem = fitcase::problem(case, choice).ok()?;
    // With [bounds] on the geometry, each draw is a full fit over the geometry box.
    let report = fitcase::fit(case, &problem, settings).ok()?;
    answer_of(case, &problem, &report, settings)
}

/// The quantities of a case's answer: the best branch of `report`, or the fit with the crush
/// energy as evidence when the case's damage is evidence.
fn answer_of(
    case: &Case,
    problem: &pim_fit::FitProblem,
    report: &pim_fit::FitReport,
    settings: &pim_fit::ValidSettings,
) -> Option<DrawResult> {
    if case.has_damage() {
        let unit = fitcase::sigma_unit(case).ok()?;
        let damage = crate::damage_fit::fit_damage(case, problem, report, settings, unit).ok()?;
        if let Some(f) = damage.and_then(|d| d.with_energy) {
            return Some(DrawResult {
                bounds: search_bounds(&f.solution, settings.get()),
                branch: f.moment,
                values: values_of(&f.solution),
            });
        }
    }
    best_of(report, settings.get())
}

fn search_bounds(s: &pim_fit::Solution, settings: &FitSettings) -> Vec<pim_fit::SearchBound> {
    let mut bounds: Vec<pim_fit::SearchBound> = s
        .active_constraints
        .iter()
        .filter_map(|a| a.search_bound(settings).map(|(b, _)| b))
        .collect();
    bounds.sort();
    bounds.dedup();
    bounds
}

fn values_of(s: &pim_fit::Solution) -> [f64; 8] {
    [
        s.e,
        s.tangential.as_ref().map_or(s.mu, |t| t.et),
        s.tangential.as_ref().map_or(s.em, |t| t.friction),
        s.vehicles[0].speed_initial,
        s.vehicles[1].speed_initial,
        s.vehicles[0].delta_v,
        s.vehicles[1].delta_v,
        s.energy_loss_percent,
    ]
}

/// The quantities of a fit's best branch, when it has an answer.
fn best_of(report: &pim_fit::FitReport, settings: &FitSettings) -> Option<DrawResult> {
    let b = report.best_branch()?;
    if !matches!(b.status, Status::Optimal | Status::LimitReached) {
        return None;
    }
    let s = b.solution.as_ref()?;
    Some(DrawResult {
        bounds: search_bounds(s, settings),
        branch: b.moment,
        values: values_of(s),
    })
}

/// The smallest compass step of a draw's fit, as a fraction of the coefficient box.
pub const DRAW_POLISH_LAST_STEP: f64 = 1e-5;

/// Runs the study: `draws` perturbed refits of `case` under `choice`, seeded by `seed`.
/// The observer sees each finished draw (phase `draws`) and can cancel the study: then the
/// draws finished make the answer and [`Study::cancelled`] says so.
pub fn run(
    case: &Case,
    unc: &UncertaintySection,
    choice: CostChoice,
    settings: FitSettings,
    draws: usize,
    seed: u64,
    observer: &dyn crate::watch::Observer,
) -> Result<Study> {
    check_drawn(case, unc)?;
    let inputs = inputs(case, unc)?;
    if inputs.is_empty() {
        return Err(InputError::new(
            &case.file,
            "nothing is uncertain: give [sigma] for the estimates and/or [uncertainty] for the \
             inputs the fit takes as exact",
        ));
    }
    let settings = fitcase::settings_from(case, settings)?;
    // The nominal fit: also says which quantities the data do not determine.
    let problem = fitcase::problem(case, choice)?;
    let report = fitcase::fit(case, &problem, &settings)?;
    let nominal = answer_of(case, &problem, &report, &settings);
    let set_by_case = |b| fitcase::sets_bound(case, b);
    let nominal_bounds = report
        .best_branch()
        .map(|b| pim_documents::records::bounds_reached(b, settings.get(), &set_by_case))
        .unwrap_or_default();
    let undetermined = undetermined_of(&report);
    // A draw needs only its optimum (no identifiability ranges, no proof over a geometry box),
    // to a precision well below the spread of the draws: the compass polish stops at 1e-5 of
    // the coefficient box instead of 1e-7 (e to 2e-6, mu to 2.4e-5 with the default box).
    let mut draw_settings = FitSettings {
        ranges: false,
        geometry_proof: false,
        ..settings.get().clone()
    };
    draw_settings.search.polish_last_step = DRAW_POLISH_LAST_STEP;
    let draw_settings = draw_settings
        .check()
        .map_err(|e| InputError::new(&case.file, e))?;
    let (results, cancelled) = draw_each(case, &inputs, (draws, seed), observer, |c| {
        fit_once(c, choice, &draw_settings)
    });
    let feasible: Vec<(&Vec<f64>, &DrawResult)> = results
        .iter()
        .filter_map(|(x, r)| r.as_ref().map(|r| (x, r)))
        .collect();
    let shares = bound_shares(&feasible);
    let source = |b| pim_documents::records::BoundSource::of(set_by_case(b));
    let names = self::quantities(settings.get().model);
    let mut quantities = BTreeMap::new();
    let mut sensitivity = Vec::new();
    let xs: Vec<&Vec<f64>> = feasible.iter().map(|(xs, _)| *xs).collect();
    for (q, name) in names.iter().enumerate() {
        let y: Vec<f64> = feasible.iter().map(|(_, r)| r.values[q]).collect();
        quantities.insert(
            name.to_string(),
            Summary::of(
                &y,
                undetermined[q],
                crate::intervals::bound_hit(name, &shares, &source),
            ),
        );
        sensitivity.push(Sensitivity {
            quantity: name.to_string(),
            inputs: dominant_inputs(inputs.iter().map(|i| i.name.as_str()), &xs, &y),
        });
    }
    let linearised_sd = if cancelled.is_some() {
        BTreeMap::new()
    } else {
        linearised(case, &inputs, choice, &draw_settings)
    };
    let branch_share = branch_shares(&feasible);
    Ok(Study {
        units: pim_documents::records::SiUnits,
        model: settings.get().model,
        draws: results.len(),
        seed,
        feasible_draws: feasible.len(),
        nominal: nominal
            .as_ref()
            .map(|r| {
                names
                    .iter()
                    .zip(r.values)
                    .map(|(n, v)| (n.to_string(), v))
                    .collect()
            })
            .unwrap_or_default(),
        nominal_branch: nominal.map(|r| r.branch),
        nominal_bounds,
        bound_share: shares
            .iter()
            .map(|(b, share)| (b.name().to_string(), *share))
            .collect(),
        quantities,
        branch_share,
        sensitivity,
        linearised_sd,
        cancelled,
        samples: feasible.iter().map(|(_, r)| r.values).collect(),
    })
}

/// Inputs a study of the impact alone cannot draw: a geometry [bounds] estimates (an unknown
/// of every draw's fit) and the whole reconstruction's inputs.
fn check_drawn(case: &Case, unc: &UncertaintySection) -> Result<()> {
    // The geometry [bounds] estimates is an unknown of every draw's fit (a full fit over the
    // geometry box); drawing it as well would make it both, so one of the two must go.
    for g in fitcase::geometry(case)? {
        if unc.draws_geometry(g.input) {
            return Err(InputError::new(
                &case.file,
                format!(
                    "{} is estimated by [bounds] (an unknown of every draw's fit) and drawn by \
                     [uncertainty]: give it one or the other",
                    g.input.name()
                ),
            ));
        }
    }
    // The reconstruction's inputs are never dropped in silence by a study of the impact alone.
    for (n, v) in [(1, &unc.vehicle1), (2, &unc.vehicle2)] {
        if let Some(key) = v.scene_only().first() {
            return Err(InputError::new(
                &case.file,
                format!(
                    "[uncertainty.vehicle{n}] {key} is an input of the whole reconstruction \
                     (a case with [scene] evidence, without --cost); this study fits the \
                     impact alone and would not draw it"
                ),
            ));
        }
    }
    Ok(())
}

/// Which of the study's quantities the nominal fit leaves undetermined (the coefficients by
/// their identifiability, the speeds by the solution's undetermined directions).
fn undetermined_of(report: &pim_fit::FitReport) -> [bool; 8] {
    let mut undetermined = [false; 8];
    if let Some(b) = report.best_branch() {
        for i in &b.identifiability {
            if !i.identifiable {
                let k = match i.coefficient {
                    Quantity::E => 0,
                    Quantity::Mu | Quantity::Et => 1,
                    Quantity::Em | Quantity::Friction => 2,
                    Quantity::Speed1 => 3,
                    Quantity::Speed2 => 4,
                };
                undetermined[k] = true;
            }
        }
        if b.solution
            .as_ref()
            .is_some_and(|s| !s.undetermined.is_empty())
        {
            undetermined[3..].iter_mut().for_each(|u| *u = true);
        }
    }
    undetermined
}

/// Each search bound reached by some feasible draw, with the share of the draws reaching it.
fn bound_shares(feasible: &[(&Vec<f64>, &DrawResult)]) -> Vec<(pim_fit::SearchBound, f64)> {
    pim_fit::SearchBound::ALL
        .iter()
        .map(|&b| {
            let k = feasible
                .iter()
                .filter(|(_, r)| r.bounds.contains(&b))
                .count();
            (b, k as f64 / feasible.len().max(1) as f64)
        })
        .filter(|(_, share)| *share > 0.0)
        .collect()
}

/// The share of the feasible draws on each branch of the moment.
fn branch_shares(feasible: &[(&Vec<f64>, &DrawResult)]) -> BTreeMap<String, f64> {
    let mut branch_share = BTreeMap::new();
    for b in [MomentBranch::Free, MomentBranch::Zero] {
        let k = feasible.iter().filter(|(_, r)| r.branch == b).count();
        branch_share.insert(
            b.name().to_string(),
            k as f64 / feasible.len().max(1) as f64,
        );
    }
    branch_share
}

/// The delta-method standard deviations (see [`Study::linearised_sd`]).
fn linearised(
    case: &Case,
    inputs: &[Input],
    choice: CostChoice,
    settings: &pim_fit::ValidSettings,
) -> BTreeMap<String, f64> {
    let grads: Vec<Option<[f64; 8]>> = inputs
        .par_iter()
        .map(|inp| {
            let sd = inp.spread.sd();
            if sd <= 0.0 {
                return Some([0.0; 8]);
            }
            let h = 0.5 * sd;
            let at = |x: f64| {
                let mut c = case.clone();
                (inp.apply)(&mut c, x);
                fit_once(&c, choice, settings)
            };
            let (p, m) = (at(inp.nominal + h)?, at(inp.nominal - h)?);
            Some(std::array::from_fn(|q| {
                (p.values[q] - m.values[q]) / (2.0 * h) * sd
            }))
        })
        .collect();
    let mut out = BTreeMap::new();
    if grads.iter().all(Option::is_some) {
        for (q, name) in quantities(settings.get().model).iter().enumerate() {
            let var: f64 = grads.iter().flatten().map(|g| g[q] * g[q]).sum();
            out.insert(name.to_string(), var.sqrt());
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    #[test]
    fn streams_differ_and_repeat() {
        let a: f64 = stream(7, 3).random();
        let b: f64 = stream(7, 3).random();
        let c: f64 = stream(7, 4).random();
        assert!(a.to_bits() == b.to_bits() && a.to_bits() != c.to_bits());
    }
}
