//! One fit: the moment branches searched side by side, each turned into its report, and the
//! best branch chosen.

use crate::branch;
use crate::error::Result;
use crate::inner::Inner;
use crate::problem::{FitProblem, MomentBranch};
use crate::report::{BranchReport, FitReport, Status};
use crate::search::{search_branch, Outcome};
use crate::settings::{FitSettings, ValidSettings};

/// Fits both (or the selected) moment branches. Errors only for an invalid problem; infeasible
/// data give a report whose branches say so.
pub fn fit(problem: &FitProblem, settings: &ValidSettings) -> Result<FitReport> {
    let normalised = problem.normalised()?;
    let problem = &normalised;
    problem.check()?;
    let s = settings.get();
    let inner = Inner::new(problem, s);
    let mut notes = Vec::new();
    // The branches are independent searches: run them side by side.
    let outcomes: Vec<Outcome> = match s.branches.as_slice() {
        [a, b] => {
            let (x, y) = rayon::join(
                || search_branch(&inner, s, *a),
                || search_branch(&inner, s, *b),
            );
            vec![x, y]
        }
        list => list.iter().map(|&b| search_branch(&inner, s, b)).collect(),
    };
    let mut branches = Vec::with_capacity(s.branches.len());
    for (&branch, out) in s.branches.iter().zip(&outcomes) {
        branches.push(branch::report(&inner, s, branch, out)?);
    }
    let (best, more) = choose_best(&branches, s);
    notes.extend(more);
    Ok(FitReport {
        model: s.model,
        branches,
        best,
        notes,
    })
}

/// The best branch among solved ones (ties within the agreement tolerance go to the zero
/// branch, which has one coefficient fewer), and a note when both fit equally well.
pub(crate) fn choose_best(
    branches: &[BranchReport],
    s: &FitSettings,
) -> (Option<MomentBranch>, Vec<String>) {
    let mut notes = Vec::new();
    let solved: Vec<(MomentBranch, f64)> = branches
        .iter()
        .filter(|b| matches!(b.status, Status::Optimal | Status::LimitReached))
        .filter_map(|b| b.solution.as_ref().map(|sol| (b.moment, sol.cost)))
        .collect();
    let min = solved.iter().map(|s| s.1).fold(f64::INFINITY, f64::min);
    let tie = s.search.agreement_tolerance;
    let tied: Vec<MomentBranch> = solved
        .iter()
        .filter(|s| s.1 <= min + tie * (1.0 + min))
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
    (best, notes)
}
