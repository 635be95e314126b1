//! What the search of one branch found: the best point, every solved sample, the counts of the
//! certificate and the violations met.

use super::space::Space;
use crate::inner::{At, Candidate, Eval, Inner};
use crate::report::{Quantity, Violation};
use std::collections::BTreeMap;

/// A solved point of a search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Point {
    pub at: At,
    pub candidate: Candidate,
}

/// One exactly solved feasible point, as the identifiability ranges read it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Sample {
    pub e: f64,
    /// mu, or mu_max when sticking.
    pub mu: f64,
    pub em: f64,
    /// Tangential model: et (sticking), or an et at which Routh's rule slides.
    pub et: f64,
    /// Tangential model: the friction limits that give this answer (sticking: from the
    /// impulse ratio to the largest limit; sliding: the limit itself).
    pub friction: [f64; 2],
    pub cost: f64,
    /// Speed of vehicle 1 at contact, m/s.
    pub speed1: f64,
    /// Speed of vehicle 2 at contact, m/s.
    pub speed2: f64,
    /// The cost is flat along some velocity direction at this point.
    pub flat: bool,
}

impl Sample {
    /// The value of a reported quantity at this sample.
    pub fn get(&self, q: Quantity) -> f64 {
        match q {
            Quantity::E => self.e,
            Quantity::Mu => self.mu,
            Quantity::Em => self.em,
            Quantity::Et => self.et,
            Quantity::Friction => self.friction[0],
            Quantity::Speed1 => self.speed1,
            Quantity::Speed2 => self.speed2,
        }
    }

    /// The values of a quantity this sample stands for (one value but for the friction limit
    /// of a sticking sample).
    pub fn span(&self, q: Quantity) -> [f64; 2] {
        match q {
            Quantity::Friction => self.friction,
            _ => [self.get(q); 2],
        }
    }
}

/// Everything the search found for one branch.
#[derive(Debug, Clone, Default)]
pub(crate) struct Outcome {
    pub best: Option<Point>,
    pub samples: Vec<Sample>,
    pub grid_points: usize,
    pub evaluations: usize,
    pub exact_solves: usize,
    pub qp_solves: usize,
    pub refinements: usize,
    pub refinements_agreeing: usize,
    /// A refinement that hit its iteration limit produced the optimum, and no other agrees.
    pub limit_reached: bool,
    /// Final cost of each refinement and whether it hit its iteration limit.
    pub finals: Vec<(f64, bool)>,
    pub uncertified: usize,
    /// Violations met at infeasible grid points, counted.
    pub violations: BTreeMap<Violation, usize>,
    /// Sum of weight x target^2 of the data (a scale for cost tolerances).
    pub data_scale: f64,
    /// e was minimised exactly at every point rather than searched.
    pub profiled_e: bool,
    /// Tangential model: the largest friction limit (`None` for PIM).
    pub friction_max: Option<f64>,
    /// The optimum came from the convex solve over the contact state and the impulse.
    pub convex: Option<crate::convex::Counts>,
    /// Why the convex route did not decide the branch (`None` when it did).
    pub fallback: Option<crate::certificate::Fallback>,
}

impl Outcome {
    /// Records a solved feasible point.
    pub fn record(&mut self, p: Point) {
        let c = p.candidate;
        let speed = |i: usize| c.x[i].hypot(c.x[i + 1]);
        let friction = match (self.friction_max, p.at.mode) {
            (None, _) => [f64::NAN; 2],
            (Some(_), pim_core::TangentialCondition::Sliding) => [p.at.c.mu; 2],
            (Some(max), pim_core::TangentialCondition::NoSlip) => [c.mu_eff.abs(), max],
        };
        self.samples.push(Sample {
            e: p.at.c.e,
            mu: c.mu_eff,
            em: p.at.c.em,
            et: p.at.et,
            friction,
            cost: c.cost,
            speed1: speed(0),
            speed2: speed(3),
            flat: c.flat,
        });
        if c.qp {
            self.qp_solves += 1;
        }
        if self.best.is_none_or(|b| c.cost < b.candidate.cost) {
            self.best = Some(p);
        }
    }

    /// The incumbent cost (infinite before the first feasible point).
    pub fn incumbent(&self) -> f64 {
        self.best.map_or(f64::INFINITY, |b| b.candidate.cost)
    }

    /// Exact value of a point: the best over friction signs, every feasible one recorded.
    pub fn exact(&mut self, inner: &Inner, space: &Space, p: &[f64]) -> Option<Point> {
        self.exact_below(inner, space, p, f64::INFINITY)
    }

    /// As [`Outcome::exact`], for a caller that only needs the point when its cost is below
    /// `cutoff`: a friction sign whose lower bound reaches the cutoff is not solved exactly.
    pub fn exact_below(
        &mut self,
        inner: &Inner,
        space: &Space,
        p: &[f64],
        cutoff: f64,
    ) -> Option<Point> {
        let mut best: Option<Point> = None;
        for &sign in inner.signs_in(space.mode) {
            self.evaluations += 1;
            self.exact_solves += 1;
            let (at, eval) = space.eval(inner, p, sign, true, cutoff);
            match eval {
                Eval::Feasible(candidate) => {
                    let pt = Point { at, candidate };
                    self.record(pt);
                    if best.is_none_or(|b| candidate.cost < b.candidate.cost) {
                        best = Some(pt);
                    }
                }
                Eval::Infeasible(Violation::EnergyUncertified) => self.uncertified += 1,
                _ => {}
            }
        }
        best
    }

    /// Value of a point for the refinement: the exact value (best over friction signs), or a
    /// lower bound that already loses against the incumbent.
    pub fn value(&mut self, inner: &Inner, space: &Space, p: &[f64]) -> f64 {
        let incumbent = self.incumbent();
        let mut v = f64::INFINITY;
        for &sign in inner.signs_in(space.mode) {
            self.evaluations += 1;
            let (at, eval) = space.eval(inner, p, sign, true, incumbent);
            match eval {
                Eval::Feasible(candidate) => {
                    self.exact_solves += 1;
                    self.record(Point { at, candidate });
                    v = v.min(candidate.cost);
                }
                Eval::Pending { lower_bound, .. } => v = v.min(lower_bound),
                Eval::Infeasible(Violation::EnergyUncertified) => self.uncertified += 1,
                Eval::Infeasible(_) => {}
            }
        }
        v
    }
}

/// The largest cost counted as near the optimum `best` for the identifiability ranges: the
/// relative tolerance, with a floor for a (near) perfect fit of 1e-6 of the data's own size.
pub(crate) fn near_limit(best: f64, tolerance: f64, data_scale: f64) -> f64 {
    best * (1.0 + tolerance) + 1e-6 * (1.0 + data_scale)
}
