//! Local refinement of grid points: Nelder-Mead (argmin, behind this adaptor) on the exact inner
//! value, then a compass search that finishes what Nelder-Mead, stopped at a loose tolerance,
//! leaves, and is robust where Nelder-Mead stalls on a kink or a face of the box.

use super::outcome::Outcome;
use super::space::Space;
use crate::inner::Inner;
use crate::settings::SearchSettings;
use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;

struct Objective<'a> {
    inner: &'a Inner,
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
        Ok(out.value(self.inner, self.space, p))
    }
}

/// Nelder-Mead from `start` with a first simplex of half of `steps` along each axis (the grid
/// spacing, or less in a narrow friction band), stopped when the simplex values agree to
/// `sd_tolerance`; returns the best point and whether the iteration limit was hit.
pub(crate) fn nelder_mead(
    inner: &Inner,
    space: &Space,
    start: &[f64],
    steps: &[f64],
    sd_tolerance: f64,
    settings: &SearchSettings,
    out: &mut Outcome,
) -> (Option<Vec<f64>>, bool) {
    let dim = start.len();
    let mut simplex = vec![start.to_vec()];
    for (k, d) in space.dims.iter().enumerate() {
        let step = if d.n > 1 { steps[k] * 0.5 } else { 0.0 };
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
    let max_iters = settings.nelder_mead_iterations_per_dimension * dim as u64 + 100;
    let Ok(solver) = NelderMead::new(simplex).with_sd_tolerance(sd_tolerance) else {
        return (None, false);
    };
    let obj = Objective {
        inner,
        space,
        out: std::cell::RefCell::new(out),
    };
    match Executor::new(obj, solver)
        .configure(|s| s.max_iters(max_iters))
        .timer(false)
        .run()
    {
        Ok(r) => {
            let st = r.state();
            (st.get_best_param().cloned(), st.get_iter() >= max_iters)
        }
        Err(_) => (None, false),
    }
}

/// Compass (pattern) search with step halving, inside the box; returns the point and its cost.
pub(crate) fn compass(
    inner: &Inner,
    space: &Space,
    mut p: Vec<f64>,
    mut cost: f64,
    settings: &SearchSettings,
    out: &mut Outcome,
) -> (Vec<f64>, f64) {
    let mut step: Vec<f64> = space
        .dims
        .iter()
        .map(|d| {
            if d.n > 1 {
                d.spacing() * settings.polish_first_step
            } else {
                0.0
            }
        })
        .collect();
    let min_step: Vec<f64> = space
        .dims
        .iter()
        .map(|d| (d.hi - d.lo) * settings.polish_last_step)
        .collect();
    // The axes, then the diagonals (every combination of signs of the active axes): the
    // admissible set can be a thin curved sliver along which no axis move improves. The
    // diagonals are tried only in rounds where no axis move gains.
    let axes: Vec<usize> = (0..p.len()).filter(|&k| step[k] > 0.0).collect();
    let mut along_axes: Vec<Vec<f64>> = Vec::new();
    for &k in &axes {
        for dir in [-1.0, 1.0] {
            let mut d = vec![0.0; p.len()];
            d[k] = dir;
            along_axes.push(d);
        }
    }
    let mut diagonals: Vec<Vec<f64>> = Vec::new();
    if settings.polish_diagonals && axes.len() > 1 {
        for bits in 0..(1usize << axes.len()) {
            let mut d = vec![0.0; p.len()];
            for (i, &k) in axes.iter().enumerate() {
                d[k] = if bits >> i & 1 == 1 { 1.0 } else { -1.0 };
            }
            diagonals.push(d);
        }
    }
    for _ in 0..settings.polish_rounds {
        let mut improved = false;
        let base = p.clone();
        for directions in [&along_axes, &diagonals] {
            for d in directions {
                let q: Vec<f64> = p
                    .iter()
                    .enumerate()
                    .map(|(k, v)| (v + d[k] * step[k]).clamp(space.dims[k].lo, space.dims[k].hi))
                    .collect();
                if let Some(pt) = out.exact_below(inner, space, &q, cost) {
                    if pt.candidate.cost < cost {
                        // Moves that gain less than the creep tolerance (creeping along a
                        // boundary) are taken but do not hold the step size.
                        improved |=
                            cost - pt.candidate.cost > settings.polish_creep * (1.0 + cost.abs());
                        cost = pt.candidate.cost;
                        p = q;
                    }
                }
            }
            if improved {
                break;
            }
        }
        if improved {
            // Hooke-Jeeves pattern moves: repeat the round's displacement, doubling it, while
            // that gains (a ridge is followed in a few moves, not one step per round).
            let mut m: Vec<f64> = p.iter().zip(&base).map(|(a, b)| a - b).collect();
            loop {
                let q: Vec<f64> = p
                    .iter()
                    .zip(&m)
                    .enumerate()
                    .map(|(k, (v, d))| (v + d).clamp(space.dims[k].lo, space.dims[k].hi))
                    .collect();
                match out.exact_below(inner, space, &q, cost) {
                    Some(pt) if pt.candidate.cost < cost => {
                        cost = pt.candidate.cost;
                        p = q;
                        m.iter_mut().for_each(|d| *d *= 2.0);
                    }
                    _ => break,
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
