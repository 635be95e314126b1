//! The outer search over the coefficient box and its certificate.
//!
//! For each moment branch and each tangential mode the coefficients live in a small box:
//! sliding `(e, mu, em)` (em fixed at 1 in the zero branch) and sticking `(e, em)` (mu = mu_max).
//! When one whole state is known, e is not a dimension: every point minimises over e exactly
//! ([`Prepared::evaluate_profile`]), so the boxes are `(mu, em)` and `(em)` (one point for the
//! sticking mode of the zero branch).
//! 1. Grid: every grid point is evaluated for each friction sign at its equality-only optimum,
//!    a lower bound of the exact inner value. Points whose bound could still beat the best
//!    feasible value are then solved exactly (QP, energy) in order of their bounds, so the grid
//!    minimum is exact.
//! 2. Refinement: Nelder-Mead (argmin) from the best grid points of distinct cells, on the exact
//!    inner value, stopped when the simplex values agree to a relative 1e-6; then a compass
//!    search from every result within a relative 1e-3 of the best, down to steps of 1e-7 of
//!    the box.
//! 3. Certificate: how many grid points, exact solves and refinements, and whether the
//!    refinements from different starts agree.

use crate::inner::{Candidate, Eval, LineAt, Mode, Prepared, Theta, Violation};
use crate::problem::{FitSettings, MomentBranch};
use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;
use std::collections::BTreeMap;

/// A coefficient dimension of a search space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dim {
    pub lo: f64,
    pub hi: f64,
    pub n: usize,
}

/// One search space: a branch and a mode.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Space {
    pub branch: MomentBranch,
    pub mode: Mode,
    /// e (unless profiled), then mu (sliding only), then em (free branch only).
    pub dims: Vec<Dim>,
    /// The e range when e is not a dimension but minimised exactly at every point
    /// ([`Prepared::evaluate_profile`]).
    pub profile_e: Option<[f64; 2]>,
}

impl Space {
    /// Coefficients of a point (clamped onto the box, against round-off of the refinement).
    pub fn theta(&self, p: &[f64]) -> Theta {
        let c = |k: usize| p[k].clamp(self.dims[k].lo, self.dims[k].hi);
        let p: Vec<f64> = (0..p.len()).map(c).collect();
        let (e, p) = match self.profile_e {
            Some(range) => (range[0], &p[..]),
            None => (p[0], &p[1..]),
        };
        let (mu, rest) = match self.mode {
            Mode::Sliding => (p[0], &p[1..]),
            Mode::Sticking => (0.0, p),
        };
        let em = match self.branch {
            MomentBranch::Zero => 1.0,
            MomentBranch::Free => rest[0],
        };
        Theta { e, mu, em }
    }

    fn inside(&self, p: &[f64]) -> bool {
        p.iter()
            .zip(&self.dims)
            .all(|(v, d)| *v >= d.lo - 1e-12 && *v <= d.hi + 1e-12)
    }

    /// Evaluates a point: its coefficients (with the best e when e is profiled) and result.
    fn eval(
        &self,
        prep: &Prepared,
        p: &[f64],
        sign: f64,
        exact: bool,
        cutoff: f64,
    ) -> (Theta, Eval) {
        let theta = self.theta(p);
        match self.profile_e {
            Some(e_range) => prep.evaluate_profile(&LineAt {
                e_range,
                mu: theta.mu,
                em: theta.em,
                mode: self.mode,
                sign,
            }),
            None => (theta, prep.evaluate(&theta, self.mode, sign, exact, cutoff)),
        }
    }
}

/// The spaces of a branch; with `profile`, e is minimised exactly at every point instead of
/// being a dimension.
pub(crate) fn spaces(branch: MomentBranch, s: &FitSettings, profile: bool) -> Vec<Space> {
    let e = Dim {
        lo: s.e[0],
        hi: s.e[1],
        n: if s.e[0] < s.e[1] { s.grid[0] } else { 1 },
    };
    let mu = Dim {
        lo: s.mu[0],
        hi: s.mu[1],
        n: if s.mu[0] < s.mu[1] { s.grid[1] } else { 1 },
    };
    let em = Dim {
        lo: -1.0,
        hi: 0.0,
        n: s.grid[2],
    };
    let fine_e = Dim {
        n: if e.n > 1 { 2 * e.n + 1 } else { 1 },
        ..e
    };
    let space = |mode: Mode, mut dims: Vec<Dim>| {
        if profile {
            dims.remove(0);
        }
        Space {
            branch,
            mode,
            dims,
            profile_e: profile.then_some(s.e),
        }
    };
    match branch {
        MomentBranch::Zero => vec![
            space(Mode::Sliding, vec![e, mu]),
            space(Mode::Sticking, vec![fine_e]),
        ],
        MomentBranch::Free => vec![
            space(Mode::Sliding, vec![e, mu, em]),
            space(Mode::Sticking, vec![fine_e, em]),
        ],
    }
}

/// A solved point of a search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Point {
    pub mode: Mode,
    pub theta: Theta,
    pub sign: f64,
    pub candidate: Candidate,
}

/// Everything the search found for one branch.
#[derive(Debug, Clone, Default)]
pub(crate) struct Outcome {
    pub best: Option<Point>,
    /// Every exactly solved feasible point: (e, mu_eff, em, cost, speed1, speed2, flat).
    pub samples: Vec<[f64; 7]>,
    pub grid_points: usize,
    pub evaluations: usize,
    pub exact_solves: usize,
    pub qp_solves: usize,
    pub refinements: usize,
    pub refinements_agreeing: usize,
    /// A refinement that hit its iteration limit produced the optimum, and no other agrees.
    pub limit_reached: bool,
    /// Final cost of each refinement and whether it hit its iteration limit.
    finals: Vec<(f64, bool)>,
    pub uncertified: usize,
    /// Violations met at infeasible grid points, counted.
    pub violations: BTreeMap<Violation, usize>,
    /// Sum of weight x target^2 of the data (a scale for cost tolerances).
    pub data_scale: f64,
    /// e was minimised exactly at every point rather than searched.
    pub profiled_e: bool,
}

impl Outcome {
    /// Records a feasible grid point and keeps the best value of its grid cell.
    fn record_grid(
        &mut self,
        mode: Mode,
        theta: Theta,
        sign: f64,
        c: Candidate,
        value: &mut Option<f64>,
    ) {
        self.record(Point {
            mode,
            theta,
            sign,
            candidate: c,
        });
        if value.is_none_or(|v| c.cost < v) {
            *value = Some(c.cost);
        }
    }

    fn record(&mut self, p: Point) {
        let c = p.candidate;
        let speed = |i: usize| c.x[i].hypot(c.x[i + 1]);
        self.samples.push([
            p.theta.e,
            c.mu_eff,
            p.theta.em,
            c.cost,
            speed(0),
            speed(3),
            if c.flat { 1.0 } else { 0.0 },
        ]);
        if c.qp {
            self.qp_solves += 1;
        }
        if self.best.is_none_or(|b| c.cost < b.candidate.cost) {
            self.best = Some(p);
        }
    }
}

fn grid_axis(d: &Dim) -> Vec<f64> {
    if d.n <= 1 {
        return vec![d.lo];
    }
    (0..d.n)
        .map(|i| d.lo + (d.hi - d.lo) * i as f64 / (d.n - 1) as f64)
        .collect()
}

fn grid(space: &Space) -> Vec<Vec<f64>> {
    let mut pts: Vec<Vec<f64>> = vec![Vec::new()];
    for d in &space.dims {
        let axis = grid_axis(d);
        pts = pts
            .into_iter()
            .flat_map(|p| {
                axis.iter().map(move |&v| {
                    let mut q = p.clone();
                    q.push(v);
                    q
                })
            })
            .collect();
    }
    pts
}

/// Value of a point for the refinement: the exact value (best over friction signs), or a lower
/// bound that already loses against the incumbent.
fn value(prep: &Prepared, space: &Space, p: &[f64], out: &mut Outcome) -> f64 {
    let incumbent = out.best.map_or(f64::INFINITY, |b| b.candidate.cost);
    let mut v = f64::INFINITY;
    for &sign in prep.signs() {
        out.evaluations += 1;
        let (theta, eval) = space.eval(prep, p, sign, true, incumbent);
        match eval {
            Eval::Feasible(c) => {
                out.exact_solves += 1;
                out.record(Point {
                    mode: space.mode,
                    theta,
                    sign,
                    candidate: c,
                });
                v = v.min(c.cost);
            }
            Eval::Pending { lower_bound, .. } => v = v.min(lower_bound),
            Eval::Infeasible(Violation::EnergyUncertified) => out.uncertified += 1,
            Eval::Infeasible(_) => {}
        }
    }
    v
}

/// Exact value of a point: the best over friction signs.
fn exact(prep: &Prepared, space: &Space, p: &[f64], out: &mut Outcome) -> Option<Point> {
    let mut best: Option<Point> = None;
    for &sign in prep.signs() {
        out.evaluations += 1;
        out.exact_solves += 1;
        let (theta, eval) = space.eval(prep, p, sign, true, f64::INFINITY);
        match eval {
            Eval::Feasible(c) => {
                let pt = Point {
                    mode: space.mode,
                    theta,
                    sign,
                    candidate: c,
                };
                out.record(pt);
                if best.is_none_or(|b| c.cost < b.candidate.cost) {
                    best = Some(pt);
                }
            }
            Eval::Infeasible(Violation::EnergyUncertified) => out.uncertified += 1,
            _ => {}
        }
    }
    best
}

struct Objective<'a> {
    prep: &'a Prepared,
    space: &'a Space,
    out: std::cell::RefCell<&'a mut Outcome>,
}

impl CostFunction for Objective<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, p: &Self::Param) -> Result<f64, ArgminError> {
        if !self.space.inside(p) {
            return Ok(f64::INFINITY);
        }
        let mut out = self.out.borrow_mut();
        Ok(value(self.prep, self.space, p, &mut out))
    }
}

/// Nelder-Mead from `start`; returns the best point and whether the iteration limit was hit.
fn refine(
    prep: &Prepared,
    space: &Space,
    start: &[f64],
    sd_tolerance: f64,
    out: &mut Outcome,
) -> (Option<Vec<f64>>, bool) {
    let dim = start.len();
    let mut simplex = vec![start.to_vec()];
    for (k, d) in space.dims.iter().enumerate() {
        let step = if d.n > 1 {
            (d.hi - d.lo) / (d.n - 1) as f64 * 0.5
        } else {
            0.0
        };
        let mut v = start.to_vec();
        // Step inwards so that the simplex starts inside the box.
        v[k] = if v[k] + step <= d.hi {
            v[k] + step
        } else {
            v[k] - step
        };
        if step == 0.0 {
            v[k] += 1e-6;
        }
        simplex.push(v);
    }
    let max_iters = 100 * dim as u64 + 100;
    let solver = match NelderMead::new(simplex).with_sd_tolerance(sd_tolerance) {
        Ok(s) => s,
        Err(_) => return (None, false),
    };
    let obj = Objective {
        prep,
        space,
        out: std::cell::RefCell::new(out),
    };
    let res = Executor::new(obj, solver)
        .configure(|s| s.max_iters(max_iters))
        .timer(false)
        .run();
    match res {
        Ok(r) => {
            let st = r.state();
            let hit = st.get_iter() >= max_iters;
            (st.get_best_param().cloned(), hit)
        }
        Err(_) => (None, false),
    }
}

/// Compass (pattern) search with step halving, inside the box; returns the point and its cost.
fn polish(
    prep: &Prepared,
    space: &Space,
    mut p: Vec<f64>,
    mut cost: f64,
    out: &mut Outcome,
) -> (Vec<f64>, f64) {
    let mut step: Vec<f64> = space
        .dims
        .iter()
        .map(|d| {
            if d.n > 1 {
                (d.hi - d.lo) / (d.n - 1) as f64 / 16.0
            } else {
                0.0
            }
        })
        .collect();
    let min_step: Vec<f64> = space.dims.iter().map(|d| (d.hi - d.lo) * 1e-7).collect();
    for _ in 0..400 {
        let mut improved = false;
        for k in 0..p.len() {
            if step[k] <= 0.0 {
                continue;
            }
            for dir in [-1.0, 1.0] {
                let mut q = p.clone();
                q[k] = (q[k] + dir * step[k]).clamp(space.dims[k].lo, space.dims[k].hi);
                if let Some(pt) = exact(prep, space, &q, out) {
                    if pt.candidate.cost < cost {
                        // Moves that gain less than a relative 1e-10 (creeping along a
                        // boundary) are taken but do not hold the step size.
                        improved |= cost - pt.candidate.cost > 1e-10 * (1.0 + cost.abs());
                        cost = pt.candidate.cost;
                        p = q;
                    }
                }
            }
        }
        if !improved {
            step.iter_mut().for_each(|s| *s *= 0.5);
            if step.iter().zip(&min_step).all(|(s, m)| *s <= *m) {
                break;
            }
        }
    }
    (p, cost)
}

/// The largest cost counted as near the optimum `best` for the identifiability ranges: the
/// relative tolerance, with a floor for a (near) perfect fit of 1e-6 of the data's own size.
pub(crate) fn near_limit(best: f64, tolerance: f64, data_scale: f64) -> f64 {
    best * (1.0 + tolerance) + 1e-6 * (1.0 + data_scale)
}

/// Searches one branch.
pub(crate) fn search_branch(
    prep: &Prepared,
    settings: &FitSettings,
    branch: MomentBranch,
) -> Outcome {
    let mut out = Outcome {
        data_scale: prep.data_scale(),
        ..Outcome::default()
    };
    out.profiled_e = prep.profiles();
    for space in spaces(branch, settings, out.profiled_e) {
        let pts = grid(&space);
        out.grid_points += pts.len();
        // 1. Relaxed grid.
        let mut values: Vec<Option<f64>> = vec![None; pts.len()];
        let mut pending: Vec<(f64, usize, f64)> = Vec::new();
        for (i, p) in pts.iter().enumerate() {
            for &sign in prep.signs() {
                out.evaluations += 1;
                let (theta, eval) = space.eval(prep, p, sign, false, f64::INFINITY);
                match eval {
                    Eval::Feasible(c) => {
                        out.record_grid(space.mode, theta, sign, c, &mut values[i])
                    }
                    Eval::Pending {
                        lower_bound,
                        violation,
                    } => {
                        pending.push((lower_bound, i, sign));
                        *out.violations.entry(violation).or_default() += 1;
                    }
                    Eval::Infeasible(v) => *out.violations.entry(v).or_default() += 1,
                }
            }
        }
        // 2. Exact solves where the lower bound could still win.
        pending.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (lb, i, sign) in pending {
            let best = out.best.map_or(f64::INFINITY, |b| b.candidate.cost);
            if lb >= best {
                continue;
            }
            out.evaluations += 1;
            out.exact_solves += 1;
            let (theta, eval) = space.eval(prep, &pts[i], sign, true, best);
            match eval {
                Eval::Feasible(c) => out.record_grid(space.mode, theta, sign, c, &mut values[i]),
                Eval::Infeasible(Violation::EnergyUncertified) => out.uncertified += 1,
                Eval::Infeasible(_) | Eval::Pending { .. } => {}
            }
        }
        // 3. Refine from the best grid points that are local minima of the grid.
        let mut order: Vec<usize> = (0..pts.len()).filter(|&i| values[i].is_some()).collect();
        order.sort_by(|&a, &b| values[a].unwrap().total_cmp(&values[b].unwrap()));
        let spacing: Vec<f64> = space
            .dims
            .iter()
            .map(|d| {
                if d.n > 1 {
                    (d.hi - d.lo) / (d.n - 1) as f64
                } else {
                    1.0
                }
            })
            .collect();
        let mut starts: Vec<usize> = Vec::new();
        for &i in &order {
            if space.dims.is_empty() {
                // A single point, solved exactly: nothing to refine.
                break;
            }
            if starts.len() >= 2 {
                break;
            }
            // Distinct from the starts already taken: more than one cell apart.
            let far = starts.iter().all(|&j| {
                pts[i]
                    .iter()
                    .zip(&pts[j])
                    .zip(&spacing)
                    .any(|((a, b), s)| (a - b).abs() > 1.5 * s)
            });
            if far {
                starts.push(i);
            }
        }
        let mut refined: Vec<(Vec<f64>, f64, bool)> = Vec::new();
        for &i in &starts {
            out.refinements += 1;
            // Stop when the simplex values agree to a relative 1e-6: the compass polish that
            // follows takes the point to the optimum.
            let tol = 1e-6 * (1.0 + values[i].unwrap_or(0.0));
            let (best, hit) = refine(prep, &space, &pts[i], tol, &mut out);
            if let Some(b) = best {
                if let Some(p) = exact(prep, &space, &b, &mut out) {
                    refined.push((b, p.candidate.cost, hit));
                }
            }
        }
        // Compass search from every refined point that ended near the best one (the others
        // are distinct local minima): it finishes what Nelder-Mead, stopped at a loose
        // tolerance, leaves, and is robust where Nelder-Mead stalls on a kink or a face of the
        // box.
        refined.sort_by(|a, b| a.1.total_cmp(&b.1));
        let lead = refined.first().map_or(f64::INFINITY, |r| r.1);
        for (p, cost, hit) in refined {
            if cost <= lead + 1e-3 * (1.0 + lead.abs()) {
                let (_, polished) = polish(prep, &space, p, cost, &mut out);
                out.finals.push((polished, hit && polished >= cost));
            } else {
                out.finals.push((cost, hit));
            }
        }
    }
    // Agreement of the refinements with the optimum.
    if let Some(best) = out.best {
        let m = best.candidate.cost;
        let close = |f: f64| f <= m + 1e-6 * (1.0 + m);
        out.refinements_agreeing = out.finals.iter().filter(|(f, _)| close(*f)).count();
        out.limit_reached =
            out.refinements_agreeing == 1 && out.finals.iter().any(|(f, hit)| close(*f) && *hit);
    }
    // 4. Scan each coefficient through the optimum (for the identifiability ranges).
    if let (Some(best), true) = (out.best, out.profiled_e) {
        // Profiled: along (mu, em) through the optimum, each point at its best e, and on each of
        // those lines the exact ends of the e interval where the cost stays near the optimum.
        // A sticking optimum is also scanned in the sliding mode through mu = its mu_max.
        let mut modes = vec![best.mode];
        if best.mode == Mode::Sticking {
            modes.push(Mode::Sliding);
        }
        let mut lines: Vec<(LineAt, f64)> = Vec::new();
        for space in spaces(branch, settings, true)
            .into_iter()
            .filter(|s| modes.contains(&s.mode))
        {
            let mu = best.candidate.mu_eff;
            let centre: Vec<f64> = match (space.mode, branch) {
                (Mode::Sliding, MomentBranch::Free) => vec![mu, best.theta.em],
                (Mode::Sliding, MomentBranch::Zero) => vec![mu],
                (Mode::Sticking, MomentBranch::Free) => vec![best.theta.em],
                (Mode::Sticking, MomentBranch::Zero) => vec![],
            };
            let mut points = vec![centre.clone()];
            for (k, d) in space.dims.iter().enumerate() {
                for v in grid_axis(&Dim { n: 13, ..*d }) {
                    let mut p = centre.clone();
                    p[k] = v;
                    points.push(p);
                }
            }
            for p in points {
                for &sign in prep.signs() {
                    out.evaluations += 1;
                    out.exact_solves += 1;
                    let (theta, eval) = space.eval(prep, &p, sign, true, f64::INFINITY);
                    let Eval::Feasible(candidate) = eval else {
                        continue;
                    };
                    out.record(Point {
                        mode: space.mode,
                        theta,
                        sign,
                        candidate,
                    });
                    let at = LineAt {
                        e_range: settings.e,
                        mu: theta.mu,
                        em: theta.em,
                        mode: space.mode,
                        sign,
                    };
                    lines.push((at, candidate.cost));
                }
            }
        }
        // The limit of the final optimum (a scan point may have improved it a little), pulled
        // in by a relative 1e-12 so that the ends stay inside it after round-off.
        let best_cost = out.best.map_or(best.candidate.cost, |b| b.candidate.cost);
        let limit = near_limit(
            best_cost,
            settings.identifiability_tolerance,
            out.data_scale,
        ) * (1.0 - 1e-12);
        for (at, line_best) in lines {
            if line_best > limit {
                // Even the best e of this line is not near the optimum.
                continue;
            }
            for (theta, candidate) in prep.profile_level_ends(&at, limit) {
                out.record(Point {
                    mode: at.mode,
                    theta,
                    sign: at.sign,
                    candidate,
                });
            }
        }
    }
    if let (Some(best), false) = (out.best, out.profiled_e) {
        let space = spaces(branch, settings, false)
            .into_iter()
            .find(|s| s.mode == best.mode)
            .expect("mode space");
        let centre: Vec<f64> = match (best.mode, branch) {
            (Mode::Sliding, MomentBranch::Free) => vec![best.theta.e, best.theta.mu, best.theta.em],
            (Mode::Sliding, MomentBranch::Zero) => vec![best.theta.e, best.theta.mu],
            (Mode::Sticking, MomentBranch::Free) => vec![best.theta.e, best.theta.em],
            (Mode::Sticking, MomentBranch::Zero) => vec![best.theta.e],
        };
        for (k, d) in space.dims.iter().enumerate() {
            for v in grid_axis(&Dim { n: 13, ..*d }) {
                let mut p = centre.clone();
                p[k] = v;
                exact(prep, &space, &p, &mut out);
            }
        }
        if best.mode == Mode::Sticking {
            // The sliding mode through the same point (mu = the optimum's mu_max): along mu
            // (mu away from mu_max), and along e and em at that mu, where the data may trade
            // restitution against approach speed just as well while sliding.
            if let Some(sl) = spaces(branch, settings, false)
                .into_iter()
                .find(|s| s.mode == Mode::Sliding)
            {
                let mut centre = vec![best.theta.e, best.candidate.mu_eff];
                if branch == MomentBranch::Free {
                    centre.push(best.theta.em);
                }
                for (k, d) in sl.dims.iter().enumerate() {
                    let n = if k == 1 { 17 } else { 13 };
                    for v in grid_axis(&Dim { n, ..*d }) {
                        let mut p = centre.clone();
                        p[k] = v;
                        exact(prep, &sl, &p, &mut out);
                    }
                }
            }
        }
    }
    out
}
