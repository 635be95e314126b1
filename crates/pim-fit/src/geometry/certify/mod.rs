//! A proof of the optimum over the geometry box: branch-and-bound over boxes of the estimated
//! inputs (and, in the free branch, intervals of e_m), each box bounded below by weak duality.
//!
//! For a box, every convex piece of the branch (PIM's sign patterns, written over U with the
//! geometry's ranges over the box, [`leaf`]) is bounded by the Lagrangian of its own
//! multipliers at the box's centre, enclosed over the box by the mean-value form ([`bound`]);
//! the box's bound is the least of its pieces'. A box whose bound is within the tolerance of
//! the best cost found is closed; otherwise it is halved along its widest side, or, in the
//! free branch, at the e_m where the centre's line of impulses has a pole of its ratios when
//! the box's e_m interval holds one. The best cost comes from complete fits at the centres of
//! open boxes (and from the search before), so when every box is closed the best point is
//! proven optimal over the whole box to the tolerance. A piece whose bound already closes a box
//! keeps it (and its multipliers) for the halves (their pieces are contained in it). Budgets:
//! [`MAX_BOXES`], [`MAX_SOLVES`], [`MAX_FITS`], [`MAX_BOXES_NO_ANSWER`].
//!
//! The bound needs a cost that is strictly convex in the free components and couples none of
//! them (Q1, Q2, Q3 and weighted estimates; observations such as delta-V couple components)
//! and PIM with the mu_max condition; other problems are not proven.

mod bound;
mod enclose;
mod interval;
mod leaf;
mod poly;
mod unproved;

use crate::family::Friction;
use crate::geometry::types::GeometryBound;
use crate::problem::{FitProblem, MomentBranch};
use crate::settings::FitSettings;
use bound::{Around, Cost};
use enclose::Enclosure;
use interval::Iv;
use leaf::{Forms, Leaf};
use pim_core::Impact;
use poly::{Inertia, MonoBox};
use std::cmp::Ordering;
use std::collections::{BinaryHeap, HashMap};
use std::sync::atomic::Ordering::Relaxed;
pub(crate) use unproved::Unproved;

/// Relative tolerance of the proof: the best point is within it of the optimum (or within
/// [`ABSOLUTE`] times `1 + sum w t^2` of the data, the fit's own floor for comparing costs, when
/// that is larger: a cost near zero is not proven to a relative 1e-4 of itself).
pub(crate) const TOLERANCE: f64 = 1e-4;

/// The absolute floor of the tolerance, per unit of `1 + sum w t^2` of the data.
const ABSOLUTE: f64 = 1e-6;

/// What the branch-and-bound proved.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Proof {
    /// A proven lower bound of the branch's optimal cost over the geometry box.
    pub lower: f64,
    /// The best cost found (the search's, or better at a box's centre) and where (unit-cube
    /// coordinates of the inputs).
    pub upper: f64,
    pub at: Vec<f64>,
    /// Boxes bounded, complete fits run at their centres, and whether every box was closed
    /// (else `reason`).
    pub boxes: usize,
    pub reason: Option<String>,
    pub fits: usize,
    pub closed: bool,
}

/// Boxes bounded before the branch-and-bound stops (RICSAC 6's five inputs take 150-5,200).
pub(crate) const MAX_BOXES: usize = 20_000;

/// Complete fits at the centres of open boxes (best first), to lower the best cost.
pub(crate) const MAX_FITS: usize = 256;

/// Interior-point solves (for pieces empty at a box's centre) before it stops: they cost about
/// 0.1 ms each, the dual active-set solves of the other pieces a few microseconds.
pub(crate) const MAX_SOLVES: usize = 30_000;

/// Boxes bounded when no point of the box has an answer yet: only pieces proven empty close a
/// box then, and a piece whose relaxation keeps points the fit rejects (the energy condition,
/// which the bound leaves out) never closes; the effort is kept small.
pub(crate) const MAX_BOXES_NO_ANSWER: usize = 100;

/// The absolute floor of the tolerance for a problem: [`ABSOLUTE`] times `1 + sum w t^2`.
pub(crate) fn absolute_tolerance(problem: &FitProblem) -> f64 {
    ABSOLUTE * (1.0 + crate::inner::data_scale_of(problem))
}

/// Why a problem's geometry is not proven, as far as its model and collision say (its cost is
/// asked of [`cost_of`]).
fn unsupported(problem: &FitProblem, settings: &FitSettings) -> Option<Unproved> {
    if problem.impact.is_barrier() {
        return Some(Unproved::Barrier);
    }
    if settings.model.family().friction() != Friction::Equivalent {
        return Some(Unproved::NotPim);
    }
    if !settings.mu_max_condition {
        return Some(Unproved::NoMuMax);
    }
    if problem.impact.side_is_fixed() {
        return Some(Unproved::SideFixed);
    }
    None
}

/// The cost as the bound needs it: `None` when it couples components (observations) or leaves
/// a free component unweighted.
fn cost_of(problem: &FitProblem) -> Option<Cost> {
    let (hu, gu, c0, fixed) = crate::inner::quadratic_of(problem);
    let mut known = [None; 12];
    for (k, v) in fixed {
        known[k] = Some(v);
    }
    let diagonal = (0..12).all(|i| (0..12).all(|j| i == j || hu[(i, j)] == 0.0));
    let weighted = (0..12).all(|k| known[k].is_some() || hu[(k, k)] > 0.0);
    (diagonal && weighted).then(|| Cost {
        h: std::array::from_fn(|k| hu[(k, k)]),
        g: std::array::from_fn(|k| gu[k]),
        c0,
        known,
        limit: [f64::INFINITY; 12],
        solves: Default::default(),
    })
}

/// A box: unit-cube coordinates of the inputs, the e_m interval, the bounds its parent's
/// pieces proved, and its own bound.
struct Node {
    lo: Vec<f64>,
    hi: Vec<f64>,
    em: [f64; 2],
    inherited: std::sync::Arc<Proved>,
    bound: f64,
    /// Whether the centre's geometry was fitted already (an e_m half of its parent).
    fitted: bool,
}

impl PartialEq for Node {
    fn eq(&self, o: &Self) -> bool {
        self.bound == o.bound
    }
}
impl Eq for Node {}
impl PartialOrd for Node {
    fn partial_cmp(&self, o: &Self) -> Option<Ordering> {
        Some(self.cmp(o))
    }
}
impl Ord for Node {
    /// The lowest bound first (a max-heap of the negated bound).
    fn cmp(&self, o: &Self) -> Ordering {
        o.bound.total_cmp(&self.bound)
    }
}

/// The centre of the box `[lo, hi]`.
fn centre(lo: &[f64], hi: &[f64]) -> Vec<f64> {
    lo.iter().zip(hi).map(|(a, b)| 0.5 * (a + b)).collect()
}

/// Inherited bounds (and multipliers) of a box's pieces.
type Proved = HashMap<Leaf, (f64, Option<bound::Multipliers>)>;

/// One branch's problem over the geometry box, built once.
pub(crate) struct Context<'a> {
    geometry: &'a [GeometryBound],
    branch: MomentBranch,
    cost: Cost,
    forms: Forms,
    eqs: Vec<poly::Poly>,
    enclosure: Enclosure,
    /// The absolute floor of the tolerance.
    pub floor: f64,
}

/// A box's bound: the least of its pieces' (each with its multipliers), and where to split
/// its e_m interval (the centre's pole of the ratios, when the interval holds one that leaves
/// the ratios unbounded over the box).
pub(crate) struct BoxBound {
    pub low: f64,
    proved: Vec<(Leaf, (f64, Option<bound::Multipliers>))>,
    pole: Option<f64>,
}

impl<'a> Context<'a> {
    /// Why not, when the bound is not written for the problem.
    pub fn new(
        problem: &FitProblem,
        geometry: &'a [GeometryBound],
        settings: &FitSettings,
        branch: MomentBranch,
    ) -> Result<Context<'a>, Unproved> {
        if let Some(why) = unsupported(problem, settings) {
            return Err(why);
        }
        let impact = &problem.impact;
        let forms = Forms::new(
            Inertia {
                m: impact.masses(),
                i: impact.inertias(),
            },
            settings,
        );
        let mut cost = cost_of(problem).ok_or(Unproved::CostNotSeparable)?;
        cost.limit = forms.limits();
        Ok(Context {
            geometry,
            branch,
            cost,
            eqs: forms.equalities(branch),
            forms,
            enclosure: Enclosure::new(impact.collision(), geometry),
            floor: absolute_tolerance(problem),
        })
    }

    /// The inputs (physical units) at unit-cube coordinates t.
    fn physical(&self, t: &[f64]) -> Vec<f64> {
        self.geometry
            .iter()
            .zip(t)
            .map(|(g, &v)| g.bounds[0] + v * (g.bounds[1] - g.bounds[0]))
            .collect()
    }

    /// A lower bound of the branch's optimal cost over the box `[lo, hi]` (unit-cube
    /// coordinates) with e_m in `em` (free branch), aiming at `goal` (pieces stop once their
    /// bound reaches it); `inherited`: the bounds of a box that contains this one.
    pub fn bound_box(
        &self,
        lo: &[f64],
        hi: &[f64],
        em: [f64; 2],
        goal: f64,
        inherited: &Proved,
    ) -> Result<BoxBound, Unproved> {
        let (plo, phi) = (self.physical(lo), self.physical(hi));
        let u_c = self.physical(&centre(lo, hi));
        let half: Vec<f64> = plo.iter().zip(&phi).map(|(a, b)| 0.5 * (b - a)).collect();
        let p_at = |u: &[f64]| -> Option<[f64; 6]> {
            let i = Impact::new(self.enclosure.collision(u)).ok()?;
            let (d, n) = (i.levers(), i.normal());
            Some([d[0], d[1], d[2], d[3], n[0], n[1]])
        };
        let pc = p_at(&u_c).ok_or(Unproved::InvalidCentre)?;
        let pbox = self.enclosure.over(&plo, &phi);
        // The centre's geometry (as pim-core rounds it) lies in the box's enclosure.
        let pbox_p: [Iv; 6] =
            std::array::from_fn(|j| Iv::new(pbox.p[j].lo.min(pc[j]), pbox.p[j].hi.max(pc[j])));
        let mono = MonoBox::new(&pbox_p);
        let relax = self.forms.relax(&mono, self.branch, em);
        let around = Around {
            centre: pc,
            centre_u: &u_c,
            p_at: &p_at,
            mono: &mono,
            dp: &pbox.dp,
            half: &half,
        };
        let reduced = self.cost.reduce(&self.eqs, &pc);
        let proved: Vec<(Leaf, (f64, Option<bound::Multipliers>))> = self
            .forms
            .leaves(&relax, self.branch)
            .into_iter()
            .map(|leaf| {
                let b = match inherited.get(&leaf) {
                    Some((b, m)) if *b >= goal => (*b, m.clone()),
                    other => self.cost.bound(
                        &self.eqs,
                        &self.forms.rows(&leaf, &relax, self.branch),
                        &around,
                        goal,
                        other.and_then(|(_, m)| m.as_ref()),
                        reduced.as_ref(),
                    ),
                };
                (leaf, b)
            })
            .collect();
        let low = proved
            .iter()
            .map(|(_, (b, _))| *b)
            .fold(f64::INFINITY, f64::min);
        // An e_m interval with a pole of the ratios inside (their ranges unbounded, or the
        // sign of kappa open) is split at the centre's pole.
        let open = !(relax
            .rho_a
            .iter()
            .chain(&relax.rho_b)
            .all(|v| v.is_finite()))
            || relax.kappas.len() > 1;
        let width = em[1] - em[0];
        let pole = match self.branch {
            MomentBranch::Free if open => self
                .forms
                .poles(&MonoBox::new(&pc.map(Iv::point)), em)
                .into_iter()
                .find(|&e| e > em[0] + 1e-3 * width && e < em[1] - 1e-3 * width),
            _ => None,
        };
        Ok(BoxBound { low, proved, pole })
    }
}

/// Proves (or bounds) the optimum of one branch over the geometry box.
///
/// `cost_at(t)` is the branch's optimal cost at unit-cube point t (a complete fit); `best` the
/// best point the search found and its cost. Stops after `max_boxes` boxes.
pub(crate) fn prove(
    context: &Context<'_>,
    best: (Vec<f64>, f64),
    cost_at: &(dyn Fn(&[f64]) -> f64 + Sync),
    max_boxes: usize,
) -> Result<Proof, Unproved> {
    let (geometry, branch) = (context.geometry, context.branch);
    let k = geometry.len();
    let (mut at, mut upper) = best;
    let floor = context.floor;
    let target = |upper: f64| {
        if upper.is_finite() {
            upper - (TOLERANCE * upper.abs()).max(floor)
        } else {
            f64::INFINITY
        }
    };
    let em0 = match branch {
        MomentBranch::Zero => [1.0, 1.0],
        MomentBranch::Free => [-1.0, 0.0],
    };
    let mut heap = BinaryHeap::new();
    heap.push(Node {
        lo: vec![0.0; k],
        hi: vec![1.0; k],
        em: em0,
        inherited: Default::default(),
        bound: f64::NEG_INFINITY,
        fitted: false,
    });
    let mut closed_low = f64::INFINITY;
    let mut boxes = 0;
    let mut fits = 0;
    while let Some(node) = heap.pop() {
        if node.bound >= target(upper) {
            closed_low = closed_low.min(node.bound);
            continue;
        }
        if boxes >= max_boxes || context.cost.solves.load(Relaxed) >= MAX_SOLVES {
            heap.push(node);
            break;
        }
        boxes += 1;
        let b = context.bound_box(&node.lo, &node.hi, node.em, target(upper), &node.inherited)?;
        let low = b.low;
        if low >= target(upper) {
            closed_low = closed_low.min(low);
            continue;
        }
        // An open box: its centre's complete fit may lower the best cost (once per geometry
        // box, an e_m half sharing its parent's centre; at most MAX_FITS, as a fit that falls
        // back to the grid search takes tens of milliseconds).
        if !node.fitted && fits < MAX_FITS {
            let t_c = centre(&node.lo, &node.hi);
            let c = cost_at(&t_c);
            fits += 1;
            if c < upper {
                upper = c;
                at = t_c;
                if low >= target(upper) {
                    closed_low = closed_low.min(low);
                    continue;
                }
            }
        }
        let proved: Proved = b.proved.into_iter().collect();
        split(&mut heap, &node, (low, b.pole, proved), context);
    }
    let open_low = heap.iter().map(|n| n.bound).fold(f64::INFINITY, f64::min);
    let closed = heap.iter().all(|n| n.bound >= target(upper));
    let reason = (!closed).then(|| {
        if boxes >= max_boxes {
            format!("the branch-and-bound stopped at its limit of {max_boxes} boxes")
        } else {
            format!(
                "the branch-and-bound stopped at its limit of {MAX_SOLVES} interior-point \
                 solves, after {boxes} boxes"
            )
        }
    });
    Ok(Proof {
        reason,
        lower: closed_low.min(open_low).min(upper),
        upper,
        at,
        boxes,
        fits,
        closed,
    })
}

/// The open box `node` (its bound `low`, the pole of e_m where its bound found one, what it
/// proved for its children to inherit) split in two onto `heap`: e_m's range at its pole or
/// middle where that is the widest side (counted as one unit) or has a pole, else the widest
/// geometry side at its middle.
fn split(
    heap: &mut BinaryHeap<Node>,
    node: &Node,
    (low, pole, proved): (f64, Option<f64>, Proved),
    context: &Context<'_>,
) {
    let (geometry, branch) = (context.geometry, context.branch);
    // Halve the widest side (e_m's range counts as one unit).
    let mut widest = (0usize, -1.0);
    for (i, g) in geometry.iter().enumerate() {
        let w = node.hi[i] - node.lo[i];
        if g.bounds[1] > g.bounds[0] && w > widest.1 {
            widest = (i, w);
        }
    }
    let inherited = std::sync::Arc::new(proved);
    let em_width = node.em[1] - node.em[0];
    if branch == MomentBranch::Free && em_width > 1e-9 && (pole.is_some() || em_width > widest.1) {
        let mid = pole.unwrap_or(0.5 * (node.em[0] + node.em[1]));
        for em in [[node.em[0], mid], [mid, node.em[1]]] {
            heap.push(Node {
                lo: node.lo.clone(),
                hi: node.hi.clone(),
                em,
                inherited: inherited.clone(),
                bound: low,
                fitted: true,
            });
        }
    } else {
        let i = widest.0;
        let mid = 0.5 * (node.lo[i] + node.hi[i]);
        let mut left = node.hi.clone();
        left[i] = mid;
        let mut right = node.lo.clone();
        right[i] = mid;
        heap.push(Node {
            lo: node.lo.clone(),
            hi: left,
            em: node.em,
            inherited: inherited.clone(),
            bound: low,
            fitted: false,
        });
        heap.push(Node {
            lo: right,
            hi: node.hi.clone(),
            em: node.em,
            inherited,
            bound: low,
            fitted: false,
        });
    }
}

#[cfg(test)]
mod tests;
