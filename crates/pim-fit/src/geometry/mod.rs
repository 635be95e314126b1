//! The impact geometry as unknowns: the impact centre of each vehicle and the crush-surface
//! angle estimated with the coefficients, within bounds the user gives.
//!
//! Brach (1984, Table 2) refits RICSAC collision 6 with four impact centres: delta-V and the
//! energy loss barely change, e_m does. Users rarely know the impact centre to better than tens
//! of centimetres or the crush-surface angle to better than several degrees, so [`fit_geometry`]
//! searches them too. For a fixed geometry the fit is the certified coefficient search of
//! [`crate::fit`]; over the geometry box the branch's optimal cost `Q*(g)` is minimised by
//!
//! 1. a grid over the box (9, 7, 5, 4 or 3 points per input for 1, 2, 3, 4 or 5 inputs whose
//!    bounds differ; an input with equal bounds is held) plus the
//!    case's own geometry, every point a complete fit of the asked branches;
//! 2. Nelder-Mead (argmin) over the box, scaled to the unit cube, from the best grid point, from
//!    the case's geometry and from the other local minima of the grid (up to four starts per
//!    branch), each of its points a complete fit of that branch;
//! 3. the proof ([`certify`]): a branch-and-bound over boxes of the inputs that bounds each
//!    box's optimal cost from below by weak duality, until every box is within the tolerance of
//!    the best cost (a box's centre that fits better replaces the best point);
//! 4. scans along each input through the optimum (nine points across its whole range) for the
//!    identifiability ranges: the values whose cost is within the identifiability tolerance.
//!
//! The optimum is global in the coefficients at every geometry point. The cost `Q*(g)` is not
//! convex in the geometry; over it the optimum is proven where [`GeometryProof`] says
//! `proven` (a relative 1e-4 of the cost, or 1e-6 of the data's `1 + sum w t^2` when larger),
//! and otherwise the best found with the proven lower bound (`bounded`) or without one
//! (`not_attempted`, and why). The reported branch is the full fit (with its own certificate and
//! coefficient ranges) at the branch's best geometry.

use crate::error::{FitError, Result};
use crate::problem::{FitProblem, MomentBranch};
use crate::report::{BranchReport, FitReport, Status};
mod certify;
pub(crate) mod types;
use crate::settings::{FitSettings, ValidSettings};
use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;
use pim_core::Collision;
use rayon::prelude::*;
pub use types::{
    impact_at, CentreEstimate, GeometryBound, GeometryEstimate, GeometryInput, GeometryProof,
    GeometryRange, GeometrySearch, ProofStatus,
};

/// Grid points per input for `k` estimated inputs.
fn points_per_input(k: usize) -> usize {
    match k {
        0 | 1 => 9,
        2 => 7,
        3 => 5,
        4 => 4,
        _ => 3,
    }
}

/// Checks the geometry bounds against the problem's collision.
fn check(problem: &FitProblem, geometry: &[GeometryBound]) -> Result<()> {
    let c = problem.impact.collision();
    for (i, g) in geometry.iter().enumerate() {
        let name = g.input.name();
        let [lo, hi] = g.bounds;
        if g.input.vehicle().is_some_and(|v| v != 1 && v != 2) {
            return Err(FitError::BadBounds(format!("{name}: vehicles are 1 and 2")));
        }
        if !(lo.is_finite() && hi.is_finite() && lo <= hi) {
            return Err(FitError::BadBounds(format!(
                "{name} = [{lo}, {hi}] must be finite with low <= high"
            )));
        }
        if matches!(g.input, GeometryInput::D(_)) && lo < 0.0 {
            return Err(FitError::BadBounds(format!(
                "{name} = [{lo}, {hi}]: a distance cannot be negative"
            )));
        }
        let start = g.input.get(c);
        let slack = 1e-9 * (1.0 + lo.abs().max(hi.abs()));
        if start < lo - slack || start > hi + slack {
            return Err(FitError::BadBounds(format!(
                "{name} = [{lo}, {hi}] does not contain the case's value {start:.6}, where the \
                 search starts"
            )));
        }
        for h in &geometry[..i] {
            let polar = |x: GeometryInput| matches!(x, GeometryInput::D(_) | GeometryInput::Phi(_));
            let same_vehicle =
                h.input.vehicle().is_some() && h.input.vehicle() == g.input.vehicle();
            if h.input == g.input {
                return Err(FitError::BadBounds(format!("{name} is bounded twice")));
            }
            if same_vehicle && polar(h.input) != polar(g.input) {
                return Err(FitError::BadBounds(format!(
                    "{} and {name}: bound the impact centre either by d / phi or by impact_point \
                     x / y, not both",
                    h.input.name()
                )));
            }
        }
    }
    Ok(())
}

/// The search over the geometry box, in unit-cube coordinates.
struct Search<'a> {
    problem: &'a FitProblem,
    geometry: &'a [GeometryBound],
    /// The inner fits of every asked branch (no identifiability ranges).
    all: ValidSettings,
    /// The inner fit of each branch alone, likewise.
    single: Vec<(MomentBranch, ValidSettings)>,
}

impl<'a> Search<'a> {
    /// The search, with its inner fits' settings checked once.
    fn new(
        problem: &'a FitProblem,
        geometry: &'a [GeometryBound],
        settings: &ValidSettings,
    ) -> Result<Self> {
        let inner = |branches: Vec<MomentBranch>| {
            FitSettings {
                ranges: false,
                branches,
                ..settings.get().clone()
            }
            .check()
        };
        let asked = &settings.get().branches;
        Ok(Search {
            problem,
            geometry,
            all: inner(asked.clone())?,
            single: asked
                .iter()
                .map(|&b| Ok((b, inner(vec![b])?)))
                .collect::<Result<_>>()?,
        })
    }

    fn collision(&self, u: &[f64]) -> Collision {
        let mut c = *self.problem.impact.collision();
        for (g, &t) in self.geometry.iter().zip(u) {
            let [lo, hi] = g.bounds;
            g.input.set(&mut c, lo + t.clamp(0.0, 1.0) * (hi - lo));
        }
        c
    }

    fn problem_at(&self, u: &[f64]) -> Option<FitProblem> {
        let impact = impact_at(&self.problem.impact, self.collision(u)).ok()?;
        Some(FitProblem {
            impact,
            ..self.problem.clone()
        })
    }

    /// The optimal cost of each asked branch at `u`, in the order asked (infinite where the
    /// branch has no answer).
    fn costs(&self, u: &[f64]) -> Vec<f64> {
        self.costs_with(u, &self.all)
    }

    /// The optimal cost of one branch at `u`.
    fn cost(&self, u: &[f64], branch: MomentBranch) -> f64 {
        let (_, settings) = self
            .single
            .iter()
            .find(|(b, _)| *b == branch)
            .expect("an asked branch");
        self.costs_with(u, settings)[0]
    }

    fn costs_with(&self, u: &[f64], settings: &ValidSettings) -> Vec<f64> {
        let infinite = vec![f64::INFINITY; settings.get().branches.len()];
        let Some(problem) = self.problem_at(u) else {
            return infinite;
        };
        let Ok(report) = crate::fit(&problem, settings) else {
            return infinite;
        };
        report
            .branches
            .iter()
            .map(|b| match (b.status, &b.solution) {
                (Status::Optimal | Status::LimitReached, Some(s)) => s.cost,
                _ => f64::INFINITY,
            })
            .collect()
    }
}

struct Objective<'a> {
    search: &'a Search<'a>,
    branch: MomentBranch,
    fits: &'a std::cell::Cell<usize>,
}

impl CostFunction for Objective<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, u: &Self::Param) -> std::result::Result<f64, ArgminError> {
        if u.iter().any(|t| !(0.0..=1.0).contains(t)) {
            return Ok(f64::INFINITY);
        }
        self.fits.set(self.fits.get() + 1);
        Ok(self.search.cost(u, self.branch))
    }
}

/// Fits the coefficients and the bounded geometry inputs. With no geometry bounds it is
/// [`crate::fit`]. Each branch's report is the complete fit at that branch's best geometry, with
/// [`BranchReport::geometry`] saying what was estimated and how well.
pub fn fit_geometry(
    problem: &FitProblem,
    geometry: &[GeometryBound],
    settings: &ValidSettings,
) -> Result<FitReport> {
    if geometry.is_empty() {
        return crate::fit(problem, settings);
    }
    let normalised = problem.normalised()?;
    let problem = &normalised;
    problem.check()?;
    check(problem, geometry)?;
    let s = settings.get();
    let search = Search::new(problem, geometry, settings)?;
    // Inputs with equal bounds are held: the grid's density follows the others.
    let n = points_per_input(
        geometry
            .iter()
            .filter(|g| g.bounds[1] > g.bounds[0])
            .count(),
    );
    // The grid in unit-cube coordinates (an input with equal bounds has one point), then the
    // case's own geometry.
    let axes: Vec<Vec<f64>> = geometry
        .iter()
        .map(|g| {
            if g.bounds[0] >= g.bounds[1] {
                vec![0.0]
            } else {
                (0..n).map(|i| i as f64 / (n - 1) as f64).collect()
            }
        })
        .collect();
    let mut points = crate::search::product(axes.iter().cloned());
    let n_grid = points.len();
    let c0 = problem.impact.collision();
    let start: Vec<f64> = geometry
        .iter()
        .map(|g| {
            let [lo, hi] = g.bounds;
            if hi > lo {
                ((g.input.get(c0) - lo) / (hi - lo)).clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
        .collect();
    points.push(start.clone());
    let values: Vec<Vec<f64>> = points.par_iter().map(|u| search.costs(u)).collect();
    let per_branch: Vec<Result<crate::report::BranchReport>> = s
        .branches
        .par_iter()
        .enumerate()
        .map(|(j, &branch)| {
            let value = |i: usize| values[i][j];
            branch_search(&search, settings, branch, &points, &value, n_grid, &axes, n)
        })
        .collect();
    let branches = per_branch.into_iter().collect::<Result<Vec<_>>>()?;
    let (best, notes) = crate::run::choose_best(&branches, s);
    Ok(FitReport {
        model: s.model,
        branches,
        best,
        notes,
    })
}

/// The search of one branch over the geometry: starts from the grid, Nelder-Mead, the scans,
/// and the complete fit at the best geometry.
#[allow(clippy::too_many_arguments)]
fn branch_search(
    search: &Search<'_>,
    settings: &ValidSettings,
    branch: MomentBranch,
    points: &[Vec<f64>],
    value: &dyn Fn(usize) -> f64,
    n_grid: usize,
    axes: &[Vec<f64>],
    n: usize,
) -> Result<BranchReport> {
    // Inputs with room to move (those with equal bounds are held).
    let k = axes.iter().filter(|a| a.len() > 1).count().max(1);
    let mut fits = points.len();
    let mut order: Vec<usize> = (0..points.len())
        .filter(|&i| value(i).is_finite())
        .collect();
    order.sort_by(|&a, &b| value(a).total_cmp(&value(b)));
    let step = 1.0 / (n - 1) as f64;
    // Starts: the best grid point, the case's geometry, the other local minima of the grid.
    let mut starts: Vec<usize> = order.first().copied().into_iter().collect();
    let case_point = points.len() - 1;
    if value(case_point).is_finite() && !starts.contains(&case_point) {
        starts.push(case_point);
    }
    add_local_minima(&mut starts, (points, &order, value), n_grid, step);
    let mut best: Option<(Vec<f64>, f64)> = order.first().map(|&i| (points[i].clone(), value(i)));
    let mut refinements = 0;
    for &i in &starts {
        refinements += 1;
        let (found, counted) = nelder_mead(
            search,
            settings,
            branch,
            (&points[i], value(i)),
            (axes, step, k),
        );
        fits += counted;
        if let Some((p, c)) = found {
            if best.as_ref().is_none_or(|b| c < b.1) {
                best = Some((p, c));
            }
        }
    }
    let Some((u, cost)) = best else {
        // No geometry the search tried admits an answer: the proof says whether any does, and
        // the complete fit at the case's geometry gives the reason.
        let (proof, found) = prove(
            search,
            settings,
            branch,
            (points[case_point].clone(), f64::INFINITY),
        );
        fits += found.as_ref().map_or(0, |f| f.2);
        let mut report = complete(search, settings, branch, &points[case_point])?;
        report.geometry = Some(estimate(
            search,
            &points[case_point],
            Vec::new(),
            GeometrySearch {
                method: method(k, n, points.len(), refinements),
                points_per_input: n,
                grid_points: points.len(),
                refinements,
                fits,
                proof,
            },
        ));
        return Ok(report);
    };
    let (mut u, mut cost) = (u, cost);
    fits += snap_to_bounds(search, branch, (&mut u, &mut cost), k);
    // The proof over the box (and a better point, should a box's centre give one).
    let (proof, found) = prove(search, settings, branch, (u.clone(), cost));
    fits += found.as_ref().map_or(0, |f| f.2);
    if let Some((q, c, _)) = found {
        if c < cost {
            (u, cost) = (q, c);
        }
    }
    let (ranges, scanned) = scan_ranges(search, settings, branch, (&u, cost));
    fits += scanned;
    let mut report = complete(search, settings, branch, &u)?;
    report.geometry = Some(estimate(
        search,
        &u,
        ranges,
        GeometrySearch {
            method: method(k, n, points.len(), refinements),
            points_per_input: n,
            grid_points: points.len(),
            refinements,
            fits: fits + 1,
            proof,
        },
    ));
    Ok(report)
}

/// The grid's other local minima (points no neighbour of the grid undercuts), in order of
/// value, added to `starts` up to four in all.
fn add_local_minima(
    starts: &mut Vec<usize>,
    (points, order, value): (&[Vec<f64>], &[usize], &Value),
    n_grid: usize,
    step: f64,
) {
    let neighbours = |i: usize, j: usize| {
        i != j
            && points[i]
                .iter()
                .zip(&points[j])
                .all(|(a, b)| (a - b).abs() <= 1.01 * step)
    };
    for &i in order {
        if starts.len() >= 4 {
            break;
        }
        if i < n_grid
            && !starts.contains(&i)
            && (0..n_grid).all(|j| !neighbours(i, j) || value(j) >= value(i))
        {
            starts.push(i);
        }
    }
}

/// The cost of grid point `i` (infinite where no answer).
type Value<'a> = dyn Fn(usize) -> f64 + 'a;

/// Nelder-Mead from the grid point `start` (cost `value`), its simplex half a grid step along
/// each free input: the best point and cost it found, and the complete fits it ran.
fn nelder_mead(
    search: &Search<'_>,
    settings: &ValidSettings,
    branch: MomentBranch,
    (start, value): (&[f64], f64),
    (axes, step, k): (&[Vec<f64>], f64, usize),
) -> (Option<(Vec<f64>, f64)>, usize) {
    let counted = std::cell::Cell::new(0);
    let obj = Objective {
        search,
        branch,
        fits: &counted,
    };
    let mut simplex = vec![start.to_vec()];
    for (d, axis) in axes.iter().enumerate() {
        let mut v = start.to_vec();
        if axis.len() > 1 {
            v[d] = if v[d] + 0.5 * step <= 1.0 {
                v[d] + 0.5 * step
            } else {
                v[d] - 0.5 * step
            };
        } else {
            v[d] += 1e-9; // outside the box: never better
        }
        simplex.push(v);
    }
    let tol = settings.get().search.nelder_mead_tolerance * (1.0 + value);
    let result = NelderMead::new(simplex)
        .with_sd_tolerance(tol)
        .and_then(|nm| {
            Executor::new(obj, nm)
                .configure(|st| st.max_iters(100 * k as u64 + 100))
                .timer(false)
                .run()
        });
    let found = result.ok().and_then(|r| {
        let st = r.state();
        st.get_best_param().map(|p| (p.clone(), st.get_best_cost()))
    });
    (found, counted.get())
}

/// Nelder-Mead approaches a bound without reaching it: each of the `k` inputs within 0.1 % of
/// its range from a bound is put on it when that costs no more. The complete fits run.
fn snap_to_bounds(
    search: &Search<'_>,
    branch: MomentBranch,
    (u, cost): (&mut Vec<f64>, &mut f64),
    k: usize,
) -> usize {
    let mut fits = 0;
    for d in 0..k {
        let snapped = if u[d] <= 1e-3 {
            0.0
        } else if u[d] >= 1.0 - 1e-3 {
            1.0
        } else {
            continue;
        };
        let mut q = u.clone();
        q[d] = snapped;
        fits += 1;
        let c = search.cost(&q, branch);
        if c <= *cost {
            (*u, *cost) = (q, c);
        }
    }
    fits
}

/// Scans through the optimum `u` (cost `cost`) along each input: the range of each over which
/// the cost stays within the identifiability tolerance, and the complete fits run.
fn scan_ranges(
    search: &Search<'_>,
    settings: &ValidSettings,
    branch: MomentBranch,
    (u, cost): (&[f64], f64),
) -> (Vec<GeometryRange>, usize) {
    let mut fits = 0;
    let tol = settings.get().identifiability_tolerance;
    let limit = cost * (1.0 + tol) + 1e-6 * (1.0 + crate::inner::data_scale_of(search.problem));
    let mut ranges = Vec::new();
    for (d, g) in search.geometry.iter().enumerate() {
        let [lo, hi] = g.bounds;
        let at = |t: f64| lo + t * (hi - lo);
        let mut low = at(u[d]);
        let mut high = low;
        if hi > lo {
            for i in 0..9 {
                let mut q = u.to_vec();
                q[d] = i as f64 / 8.0;
                fits += 1;
                if search.cost(&q, branch) <= limit {
                    low = low.min(at(q[d]));
                    high = high.max(at(q[d]));
                }
            }
        }
        let value = at(u[d]);
        ranges.push(GeometryRange {
            input: g.input.name(),
            value,
            bounds: g.bounds,
            low,
            high,
            tolerance: tol,
            identifiable: hi <= lo || high - low < 0.5 * (hi - lo),
            at_bound: hi > lo && (u[d] <= 1e-3 || u[d] >= 1.0 - 1e-3),
        });
    }
    (ranges, fits)
}

/// The proof over the box for one branch, and the best point it met (unit-cube coordinates,
/// cost, complete fits run).
fn prove(
    search: &Search<'_>,
    settings: &ValidSettings,
    branch: MomentBranch,
    best: (Vec<f64>, f64),
) -> (GeometryProof, Option<(Vec<f64>, f64, usize)>) {
    let cost_at = |t: &[f64]| search.cost(t, branch);
    let limit = if best.1.is_finite() {
        certify::MAX_BOXES
    } else {
        certify::MAX_BOXES_NO_ANSWER
    };
    let absolute = certify::absolute_tolerance(search.problem);
    let not = |reason: String| GeometryProof {
        status: ProofStatus::NotAttempted,
        lower: None,
        tolerance: certify::TOLERANCE,
        absolute,
        boxes: 0,
        reason: Some(reason),
    };
    if !settings.get().geometry_proof {
        return (
            not("not asked (geometry_proof off, as in an uncertainty draw)".into()),
            None,
        );
    }
    let proof = certify::Context::new(search.problem, search.geometry, settings.get(), branch)
        .and_then(|context| certify::prove(&context, best, &cost_at, limit));
    match proof {
        Err(reason) => (not(reason.to_string()), None),
        Ok(p) => {
            let status = match (p.closed, p.upper.is_finite()) {
                (true, true) => ProofStatus::Proven,
                (true, false) => ProofStatus::ProvenInfeasible,
                (false, _) => ProofStatus::Bounded,
            };
            let proof = GeometryProof {
                status,
                lower: Some(p.lower),
                tolerance: certify::TOLERANCE,
                absolute,
                boxes: p.boxes,
                reason: p.reason,
            };
            (proof, Some((p.at, p.upper, p.fits)))
        }
    }
}

fn method(k: usize, n: usize, grid: usize, refinements: usize) -> String {
    format!(
        "geometry: {grid} points ({n} per input over {k} input{}, and the case's own geometry), \
         each a certified fit of the coefficients; Nelder-Mead over the geometry from \
         {refinements} start{}; then a branch-and-bound over the geometry box that bounds each \
         box's optimal cost below by weak duality (see the proof)",
        if k == 1 { "" } else { "s" },
        if refinements == 1 { "" } else { "s" }
    )
}

/// The complete fit (certificate, coefficient ranges) of one branch at `u`.
fn complete(
    search: &Search<'_>,
    settings: &ValidSettings,
    branch: MomentBranch,
    u: &[f64],
) -> Result<BranchReport> {
    let problem = search.problem_at(u).ok_or_else(|| {
        FitError::BadBounds("the geometry bounds admit no valid collision".into())
    })?;
    let valid = FitSettings {
        branches: vec![branch],
        ..settings.get().clone()
    }
    .check()?;
    let report = crate::fit(&problem, &valid)?;
    Ok(report
        .branches
        .into_iter()
        .next()
        .expect("one branch asked"))
}

fn estimate(
    search: &Search<'_>,
    u: &[f64],
    ranges: Vec<GeometryRange>,
    record: GeometrySearch,
) -> GeometryEstimate {
    let c = search.collision(u);
    GeometryEstimate {
        vehicle1: CentreEstimate {
            d: c.vehicle1.d,
            phi: c.vehicle1.phi,
        },
        vehicle2: CentreEstimate {
            d: c.vehicle2.d,
            phi: c.vehicle2.phi,
        },
        crush_angle: c.crush_angle,
        ranges,
        search: record,
    }
}
