//! The constraint set of the inner problem, written once as data.
//!
//! Every solve path reads the same set: the point check of a candidate ([`ConstraintSet::check`]),
//! the QP rows over the contact state ([`ConstraintSet::rows_over_x`], [`ConstraintSet::wedge`]),
//! the admissible intervals along a profile line ([`ConstraintSet::along`]) and the list of active
//! constraints ([`ConstraintSet::active`]).
//!
//! - Linear conditions ([`Linear`]): velocity bounds on the twelve components, approach at C (a
//!   minimum closing speed) and the sliding direction at contact that the friction sign assumes.
//! - One impulse-ratio condition ([`Ratio`]): `mu_max = sign Pt / Pn` of an impulse within a
//!   range. Sliding: the no-slip (critical) impulse of the contact state, and mu between 0 and
//!   mu_max, decided by pim-core's [`classify_friction`]. Sticking: the impulse itself, and
//!   mu_max within the mu bounds. The ratio of two linear forms is not convex; its admissible set
//!   is the union of two polyhedra ("wedges"), one for each sign of Pn, each linear.
//! - No kinetic energy created, decided by pim-core's [`creates_energy`].

pub(crate) use super::linear::{rows_over_u, Linear, RowOf, RowU};
use crate::problem::Component;
use crate::report::{ActiveConstraint, Violation};
use nalgebra::{Matrix6, RowVector6, Vector6};
use pim_core::reduction::{CriticalRows, Line};
use pim_core::{classify_friction, creates_energy, CriticalImpulse, FrictionSign};

/// Where the impulses of a ratio condition come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Impulses {
    /// The impulse of the candidate itself, `P = m1 (V1 - v1)` (sticking: mu_eff = mu_max).
    Actual,
    /// The no-slip impulse of the contact state at the candidate's e and e_m (sliding).
    Critical(CriticalRows),
    /// The no-slip system is singular: mu_max is undefined.
    Undefined,
}

/// `mu_max = sign Pt / Pn` within `[lo, hi]` (one end may be infinite).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Ratio {
    pub source: Impulses,
    pub lo: f64,
    pub hi: f64,
    /// `Friction` (sliding, mu between 0 and mu_max) or `MuBound` (sticking).
    pub kind: Violation,
    /// The candidate's mu (sliding; the friction limit of the tangential model's sliding).
    pub mu: f64,
    /// The condition is on the inverse ratio `Pn / (sign Pt)` within `[lo, hi]` (the
    /// tangential model's sliding: `|Pt| >= friction |Pn|`).
    pub inverse: bool,
}

/// Result of a point check.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Check {
    /// First violated linear condition.
    pub linear: Option<Violation>,
    /// The ratio condition holds.
    pub ratio_ok: bool,
    /// No kinetic energy created.
    pub energy_ok: bool,
}

impl Check {
    /// Every condition holds.
    pub fn ok(&self) -> bool {
        self.linear.is_none() && self.ratio_ok && self.energy_ok
    }
}

/// The constraint set of one candidate point (coefficients, tangential condition, sign).
#[derive(Debug, Clone)]
pub(crate) struct ConstraintSet<'a> {
    pub linear: &'a [Linear],
    pub ratio: Option<Ratio>,
    pub sign: FrictionSign,
    /// Impulse rows over the change X - x (pim-core's projection).
    pub impulse: (RowVector6<f64>, RowVector6<f64>),
    /// Masses and inertias `(m1, m1, I1, m2, m2, I2)`, for the kinetic energy.
    pub mass: Vector6<f64>,
    /// Feasibility tolerance, m/s (the check accepts twice this; constructions aim inside).
    pub tol: f64,
    /// Smallest |Pn| of a wedge, N s.
    pub pn_floor: f64,
}

/// A row over x and its right-hand side: `row . x <= rhs`.
pub(crate) type RowX = (RowVector6<f64>, f64, Violation);

impl ConstraintSet<'_> {
    fn impulses(
        &self,
        source: &Impulses,
        e: f64,
        x: &Vector6<f64>,
        xf: &Vector6<f64>,
    ) -> Option<CriticalImpulse> {
        match source {
            Impulses::Actual => {
                let d = xf - x;
                Some(CriticalImpulse {
                    normal: (self.impulse.0 * d)[0],
                    tangential: (self.impulse.1 * d)[0],
                })
            }
            Impulses::Critical(rows) => Some(rows.at(e, x)),
            Impulses::Undefined => None,
        }
    }

    /// Whether the ratio condition holds at a ratio value (pim-core decides friction).
    fn ratio_holds(&self, r: &Ratio, p: Option<CriticalImpulse>) -> bool {
        if r.inverse {
            // sign Pt / Pn >= friction: the sticking impulse exceeds the limit on the side of
            // the sign (the slack of the forward model's own stick/slide decision).
            let s = self.sign.value();
            return p.is_some_and(|p| {
                let n = p.normal.abs();
                let t = s * p.tangential * p.normal.signum();
                t - r.mu * n >= -pim_core::tangential::RATIO_TOL * (t.abs() + r.mu * n)
            });
        }
        let mu_max = p.and_then(|p| p.mu_max(self.sign));
        match r.kind {
            Violation::Friction => classify_friction(r.mu, mu_max).admissible,
            _ => mu_max.is_some_and(|m| {
                let slack = 1e-9 * (1.0 + m.abs());
                m >= r.lo - slack && m <= r.hi + slack
            }),
        }
    }

    /// The kinetic energy of a state, J.
    pub fn energy(&self, v: &Vector6<f64>) -> f64 {
        0.5 * v.component_mul(v).dot(&self.mass)
    }

    /// Checks every condition at a candidate `(x, X)` with restitution e.
    pub fn check(&self, e: f64, x: &Vector6<f64>, xf: &Vector6<f64>) -> Check {
        let slack = 2.0 * self.tol;
        let mut linear = None;
        let mut direction = false;
        for c in self.linear {
            let (bad, kind) = match *c {
                Linear::Bound { k, limit } => {
                    let v = if k < 6 { x[k] } else { xf[k - 6] };
                    (v.abs() > limit + slack, Violation::Bound(Component(k)))
                }
                // The sliding direction holds to round-off only: a contact state must slide the
                // way its friction sign says, or not slide at all (vt = 0 within pim-core's
                // NO_SLIDING_TOL, where the friction rule takes the no-slip impulse's side,
                // which the ratio condition of this sign checks); otherwise pim-core would read
                // the other sign from it.
                Linear::Contact { row, rhs, kind } if kind == Violation::SlidingDirection => {
                    let slack = 0.25 * pim_core::NO_SLIDING_TOL * (row.abs() * x.abs())[0];
                    ((row * x)[0] > rhs + slack, kind)
                }
                Linear::Contact { row, rhs, kind } => ((row * x)[0] > rhs + slack, kind),
            };
            if !bad {
                continue;
            }
            if kind == Violation::SlidingDirection {
                direction = true;
            } else if linear.is_none() {
                linear = Some(kind);
            }
        }
        if direction && linear.is_none() {
            linear = Some(Violation::SlidingDirection);
        }
        let ratio_ok = self.ratio.is_none_or(|r| {
            let p = self.impulses(&r.source, e, x, xf);
            self.ratio_holds(&r, p)
        });
        Check {
            linear,
            ratio_ok,
            energy_ok: !creates_energy(self.energy(x), self.energy(xf)),
        }
    }

    /// The linear conditions as rows over x for `X = R x`, aimed inside by the tolerance.
    pub fn rows_over_x(&self, r: &Matrix6<f64>) -> Vec<RowX> {
        rows_over_u(self.linear, self.tol)
            .map(|(row, rhs, kind)| {
                let row = match row {
                    RowOf::Component { k, sign } if k < 6 => {
                        let mut e = RowVector6::zeros();
                        e[k] = sign;
                        e
                    }
                    RowOf::Component { k, sign } => r.row(k - 6) * sign,
                    RowOf::Contact(row) => row,
                };
                (row, rhs, kind)
            })
            .collect()
    }

    /// `(Pn, sign Pt)` of the ratio condition as rows over x, for `X = R x` at restitution e
    /// (swapped for an inverse ratio).
    fn ratio_rows(
        &self,
        r: &Ratio,
        rt: &Matrix6<f64>,
        e: f64,
    ) -> Option<(RowVector6<f64>, RowVector6<f64>)> {
        let s = self.sign.value();
        let (pn, pt) = match &r.source {
            Impulses::Actual => {
                let d = rt - Matrix6::identity();
                (self.impulse.0 * d, self.impulse.1 * d * s)
            }
            Impulses::Critical(rows) => {
                let m = rows.rows(e);
                (m.row(0).into_owned(), m.row(1) * s)
            }
            Impulses::Undefined => return None,
        };
        // The inverse ratio Pn / (sign Pt): the roles of the rows swap.
        Some(if r.inverse { (pt, pn) } else { (pn, pt) })
    }

    /// The rows of one wedge of the ratio condition (`side` = the sign of Pn), aimed inside:
    /// `side Pn >= floor`, `side (sign Pt - lo Pn) >= 0`, `side (hi Pn - sign Pt) >= 0`. `None`
    /// when there is no ratio condition or it cannot hold.
    pub fn wedge(&self, rt: &Matrix6<f64>, e: f64, side: f64) -> Option<Vec<RowX>> {
        let r = self.ratio?;
        let (pn, pt) = self.ratio_rows(&r, rt, e)?;
        let v = r.kind;
        let mut rows = vec![(-pn * side, -self.pn_floor, v)];
        if r.lo.is_finite() {
            rows.push(((pn * r.lo - pt) * side, 0.0, v));
        }
        if r.hi.is_finite() {
            rows.push(((pt - pn * r.hi) * side, 0.0, v));
        }
        Some(rows)
    }

    /// The pieces of a profile line (`t` in `[lo, hi]`) where every linear condition and the
    /// ratio condition hold, by the same point tests as [`ConstraintSet::check`] between the
    /// roots of their forms along the line.
    pub fn along(
        &self,
        line: &Line,
        forward: bool,
        lo: f64,
        hi: f64,
    ) -> (Intervals, Option<Violation>) {
        // The linear conditions are convex along the line: their common set is one interval.
        let mut range = Some((lo, hi));
        let meet = |range: Option<(f64, f64)>, piece: Option<(f64, f64)>| match (range, piece) {
            (Some((a, b)), Some((c, d))) if a.max(c) <= b.min(d) => Some((a.max(c), b.min(d))),
            _ => None,
        };
        let u = |t: f64| line.at(t);
        for c in self.linear {
            let (kind, a, b) = match *c {
                Linear::Bound { k, limit } => {
                    let (v0, v1) = if k < 6 {
                        (line.x0[k], line.x1[k])
                    } else {
                        (line.xf0[k - 6], line.xf1[k - 6])
                    };
                    // |v0 + t v1| <= limit + tol.
                    let roots = [(limit - v0) / v1, (-limit - v0) / v1];
                    let test = |t: f64| (v0 + t * v1).abs() <= limit + self.tol;
                    range = meet(range, Intervals::convex_where_holds(lo, hi, &roots, test));
                    (Violation::Bound(Component(k)), 0.0, 0.0)
                }
                Linear::Contact { row, rhs, kind } => {
                    let a = (row * line.x0)[0] - rhs;
                    let b = (row * line.x1)[0];
                    (kind, a, b)
                }
            };
            if let Linear::Contact { kind, .. } = c {
                let slack = if *kind == Violation::SlidingDirection {
                    0.0
                } else {
                    self.tol
                };
                let test = |t: f64| a + b * t <= slack;
                range = meet(
                    range,
                    Intervals::convex_where_holds(lo, hi, &[-a / b], test),
                );
            }
            if range.is_none() {
                return (Intervals(Vec::new()), Some(kind));
            }
        }
        let Some((a, b)) = range else {
            return (Intervals(Vec::new()), None);
        };
        let mut set = Intervals::single(a, b);
        if let Some(r) = self.ratio {
            let (pn, pt) = self.ratio_polynomials(&r, line, forward);
            let mut roots = Vec::new();
            let combo = |a: f64, p: [f64; 3], b: f64, q: [f64; 3]| {
                [
                    a * p[0] + b * q[0],
                    a * p[1] + b * q[1],
                    a * p[2] + b * q[2],
                ]
            };
            // The ratio is num / den: sign Pt / Pn, or Pn / (sign Pt) for an inverse ratio.
            let s = self.sign.value();
            let spt = pt.map(|c| s * c);
            let (den, num) = if r.inverse { (spt, pn) } else { (pn, spt) };
            roots.extend(quadratic_roots(den));
            if r.lo.is_finite() {
                roots.extend(quadratic_roots(combo(1.0, num, -r.lo, den)));
            }
            if r.hi.is_finite() {
                roots.extend(quadratic_roots(combo(r.hi, den, -1.0, num)));
            }
            let test = |t: f64| {
                let e = Line::e_of_t(t, forward);
                let (x, xf) = u(t);
                let p = self.impulses(&r.source, e, &x, &xf);
                self.ratio_holds(&r, p)
            };
            set = set.intersect(&Intervals::where_holds(lo, hi, &roots, test));
            if set.is_empty() {
                return (set, Some(r.kind));
            }
        }
        (set, None)
    }

    /// `(Pn, Pt)` of the ratio condition along a line as quadratics in t (coefficients of
    /// 1, t, t^2), up to a common positive factor.
    fn ratio_polynomials(&self, r: &Ratio, line: &Line, forward: bool) -> ([f64; 3], [f64; 3]) {
        let lin = |row: &RowVector6<f64>, a: &Vector6<f64>, b: &Vector6<f64>| {
            [(row * a)[0], (row * b)[0], 0.0]
        };
        match &r.source {
            Impulses::Actual => {
                let d0 = line.xf0 - line.x0;
                let d1 = line.xf1 - line.x1;
                (
                    lin(&self.impulse.0, &d0, &d1),
                    lin(&self.impulse.1, &d0, &d1),
                )
            }
            Impulses::Critical(rows) => {
                let (l0, l1) = (rows.l0, rows.l1);
                let poly = |i: usize| -> [f64; 3] {
                    let (a, b) = (l0.row(i), l1.row(i));
                    if forward {
                        // (l0 + t l1) x0 (x known, x1 = 0).
                        [(a * line.x0)[0], (b * line.x0)[0], 0.0]
                    } else {
                        // (t - 1)(l0 + l1 / (t - 1)) (x0 + t x1), with t - 1 > 0.
                        let (ax0, ax1) = ((a * line.x0)[0], (a * line.x1)[0]);
                        let (bx0, bx1) = ((b * line.x0)[0], (b * line.x1)[0]);
                        [bx0 - ax0, ax0 - ax1 + bx1, ax1]
                    }
                };
                (poly(0), poly(1))
            }
            Impulses::Undefined => ([0.0; 3], [0.0; 3]),
        }
    }

    /// The constraints that hold with equality at a candidate (within `tol_active`, relative to
    /// the velocity scale `scale`).
    pub fn active(
        &self,
        e: f64,
        x: &Vector6<f64>,
        xf: &Vector6<f64>,
        tol_active: f64,
    ) -> Vec<ActiveConstraint> {
        let mut out = Vec::new();
        for c in self.linear {
            let item = match *c {
                Linear::Bound { k, limit } => {
                    let v = if k < 6 { x[k] } else { xf[k - 6] };
                    ((v.abs() - limit).abs() <= tol_active)
                        .then_some(ActiveConstraint::VelocityBound(Component(k)))
                }
                Linear::Contact { row, rhs, kind } => (((row * x)[0] - rhs).abs()
                    <= tol_active * (1.0 + row.amax()))
                .then_some(match kind {
                    Violation::NotApproaching => ActiveConstraint::MinimumApproach,
                    _ => ActiveConstraint::SlidingDirection,
                }),
            };
            if let Some(a) = item {
                if !out.contains(&a) {
                    out.push(a);
                }
            }
        }
        if let Some(r) = self.ratio.filter(|r| r.inverse) {
            if let Some(p) = self.impulses(&r.source, e, x, xf) {
                let (n, t) = (p.normal.abs(), p.tangential.abs());
                if (t - r.mu * n).abs() <= 1e-6 * (t + r.mu * n) {
                    out.push(ActiveConstraint::StickSlide);
                }
            }
        }
        if let Some(r) = self.ratio.filter(|r| !r.inverse) {
            let m = self
                .impulses(&r.source, e, x, xf)
                .and_then(|p| p.mu_max(self.sign));
            if let Some(m) = m {
                let near = |b: f64| b.is_finite() && (m - b).abs() <= 1e-6 * (1.0 + b.abs());
                match r.kind {
                    Violation::Friction if near(r.mu) => out.push(ActiveConstraint::MuMax),
                    Violation::MuBound if near(r.lo) || near(r.hi) => {
                        out.push(ActiveConstraint::StickingMuBound)
                    }
                    Violation::FrictionLimit if near(r.lo) || near(r.hi) => {
                        out.push(ActiveConstraint::FrictionBound)
                    }
                    _ => {}
                }
            }
        }
        let (t0, t1) = (self.energy(x), self.energy(xf));
        if (t1 - t0).abs() <= 1e-7 * t0.max(1.0) {
            out.push(ActiveConstraint::Energy);
        }
        out
    }
}

/// Real roots of `c0 + c1 t + c2 t^2` (none when it is identically zero).
pub(crate) fn quadratic_roots(c: [f64; 3]) -> Vec<f64> {
    let [c0, c1, c2] = c;
    let size = c0.abs().max(c1.abs()).max(c2.abs());
    if size == 0.0 {
        return Vec::new();
    }
    if c2.abs() <= 1e-14 * size {
        return if c1 == 0.0 {
            Vec::new()
        } else {
            vec![-c0 / c1]
        };
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    if disc < 0.0 {
        return Vec::new();
    }
    let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
    if q == 0.0 {
        return vec![0.0];
    }
    vec![q / c2, c0 / q]
}

/// A union of disjoint closed intervals of t, sorted.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Intervals(pub Vec<(f64, f64)>);

impl Intervals {
    /// `[lo, hi]` (empty when lo > hi).
    pub fn single(lo: f64, hi: f64) -> Self {
        Intervals(if lo <= hi { vec![(lo, hi)] } else { Vec::new() })
    }

    /// True when empty.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The parts of `[lo, hi]` where `test` holds, for a condition that can only change at the
    /// given breakpoints: each piece between breakpoints is kept when `test` holds at its
    /// middle; ends at breakpoints are moved inwards by a relative 1e-12 (so that round-off
    /// cannot put a chosen point outside) and kept only where `test` holds there too.
    pub fn where_holds(lo: f64, hi: f64, breakpoints: &[f64], test: impl Fn(f64) -> bool) -> Self {
        let mut out = Vec::new();
        pieces(lo, hi, breakpoints, test, |a, b| out.push((a, b)));
        Intervals(out)
    }

    /// [`Intervals::where_holds`] for a condition whose set is one interval (a convex condition
    /// such as a linear or an absolute-value bound), without allocating.
    pub fn convex_where_holds(
        lo: f64,
        hi: f64,
        breakpoints: &[f64],
        test: impl Fn(f64) -> bool,
    ) -> Option<(f64, f64)> {
        let mut hull: Option<(f64, f64)> = None;
        pieces(lo, hi, breakpoints, test, |a, b| {
            hull = Some(hull.map_or((a, b), |(c, _)| (c, b)));
        });
        hull
    }

    /// The intersection of two sets.
    pub fn intersect(&self, other: &Intervals) -> Intervals {
        let mut out = Vec::new();
        for &(a, b) in &self.0 {
            for &(c, d) in &other.0 {
                let (p, q) = (a.max(c), b.min(d));
                if p <= q {
                    out.push((p, q));
                }
            }
        }
        out.sort_by(|x, y| x.0.total_cmp(&y.0));
        Intervals(out)
    }

    /// The parts where `c0 + c1 t + c2 t^2 <= 0`.
    pub fn quadratic_nonpositive(&self, c: [f64; 3]) -> Intervals {
        let roots = quadratic_roots(c);
        let f = |t: f64| c[0] + t * (c[1] + t * c[2]);
        let mut out = Intervals(Vec::new());
        for &(a, b) in &self.0 {
            let piece = Intervals::where_holds(a, b, &roots, |t| f(t) <= 0.0);
            out.0.extend(piece.0);
        }
        out
    }
}

/// The pieces of [`Intervals::where_holds`], in order, handed to `emit`.
fn pieces(
    lo: f64,
    hi: f64,
    breakpoints: &[f64],
    test: impl Fn(f64) -> bool,
    mut emit: impl FnMut(f64, f64),
) {
    if lo > hi {
        return;
    }
    // Sorted breakpoints inside (lo, hi), then the ends: on the stack for the usual few.
    let mut buffer = [0.0; 10];
    let mut heap = Vec::new();
    let ends: &mut [f64] = if breakpoints.len() <= 8 {
        &mut buffer[..]
    } else {
        heap.resize(breakpoints.len() + 2, 0.0);
        &mut heap[..]
    };
    let mut n = 0;
    ends[n] = lo;
    n += 1;
    for &b in breakpoints {
        if b.is_finite() && b > lo && b < hi {
            ends[n] = b;
            n += 1;
        }
    }
    ends[1..n].sort_by(f64::total_cmp);
    ends[n] = hi;
    n += 1;
    let ends = &ends[..n];
    // An end at a breakpoint moves inwards until the test holds there too: first by a
    // relative 1e-12 (so that round-off cannot put a chosen point outside), then by growing
    // steps up to the middle of its piece.
    let end = |b: f64, mid: f64| -> f64 {
        let mut d = 1e-12 * (1.0 + b.abs());
        loop {
            let t = if mid > b { b + d } else { b - d };
            if (mid - t) * (mid - b) <= 0.0 {
                return mid;
            }
            if test(t) {
                return t;
            }
            d *= 8.0;
        }
    };
    let mut current: Option<(f64, f64)> = None;
    let mut flush = |piece: Option<(f64, f64)>| {
        if let Some((a, b)) = piece {
            if a <= b {
                emit(a, b);
            }
        }
    };
    let mut previous_kept = false;
    for (i, w) in ends.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let mid = if b.is_finite() {
            0.5 * (a + b)
        } else {
            a + 1.0 + a.abs()
        };
        let kept = test(mid);
        if kept {
            let b2 = if i + 2 == ends.len() { b } else { end(b, mid) };
            match current.as_mut() {
                // A breakpoint where the condition does not change: one piece.
                Some(last) if previous_kept => last.1 = b2,
                _ => {
                    flush(current.take());
                    current = Some((if i == 0 { a } else { end(a, mid) }, b2));
                }
            }
        }
        previous_kept = kept;
    }
    flush(current);
}
