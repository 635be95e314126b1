//! The inner problem prepared once per fit (everything that does not depend on the
//! coefficients), the point where it is evaluated and what an evaluation returns.

use super::constraints::{rows_over_u, ConstraintSet, Impulses, Linear, Ratio, RowU};
use super::objective::Objective;
use crate::family::{Family, Friction, Sticking};
use crate::problem::FitProblem;
use crate::report::Violation;
use crate::settings::{FitSettings, SearchSettings};
use nalgebra::{Matrix2x6, Matrix6, RowVector6, Vector6};
use pim_core::equations::{impulse_rows, normal_velocity_row, tangential_velocity_row};
use pim_core::reduction::{CriticalRows, KnownState, Reduction};
use pim_core::{Coefficients, CriticalImpulse, FrictionSign, Impact, TangentialCondition};

/// Where a candidate is evaluated: coefficients (mu unused when sticking), tangential condition
/// and friction sign. In the tangential model `NoSlip` is its sticking mode with tangential
/// restitution `et`, and `Sliding` its sliding mode with friction limit `c.mu` on the side
/// `sign` (the impulse ratio is `c.mu sign`), admissible when the sticking impulse at `et`
/// would exceed the limit on that side (the friction rule).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct At {
    pub c: Coefficients,
    pub mode: TangentialCondition,
    pub sign: FrictionSign,
    /// Tangential restitution (tangential model; 0 for PIM).
    pub et: f64,
}

/// A solved candidate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Candidate {
    pub cost: f64,
    pub x: Vector6<f64>,
    pub xf: Vector6<f64>,
    /// Friction ratio in the convention of equation 5 (mu itself, or mu_max when sticking).
    pub mu_eff: f64,
    /// True when the QP solver was needed.
    pub qp: bool,
    /// Lagrange multiplier of the energy constraint (0 when inactive).
    pub lambda: f64,
    /// The cost is flat along some direction of x at these coefficients: the data leave part
    /// of the velocities undetermined (x is then the smallest-norm choice).
    pub flat: bool,
}

/// Outcome of an evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Eval {
    Feasible(Candidate),
    /// Only from a relaxed evaluation: the equality-only optimum `lower_bound` violates a
    /// constraint; the exact value is at least that.
    Pending {
        lower_bound: f64,
        violation: Violation,
    },
    Infeasible(Violation),
}

/// Everything about a problem that does not depend on the coefficients.
pub(crate) struct Inner {
    pub impact: Impact,
    pub(super) reduction: Reduction,
    pub objective: Objective,
    /// The reduced solve, when one whole state is known (Q1, Q2).
    pub(super) known: Option<KnownState>,
    /// That state, and whether it is the contact state.
    pub(super) known_state: Option<(Vector6<f64>, bool)>,
    /// Sliding direction of the contact state when it is fully known and slides at contact
    /// (`None` when it is not known or does not slide: then both signs are searched, and the
    /// friction rule picks the no-slip impulse's side through the ratio condition).
    pub(super) known_sign: Option<FrictionSign>,
    /// The linear conditions for each friction sign (positive, negative).
    pub(super) linear: [Vec<Linear>; 2],
    /// The linear conditions without the sliding direction: the tangential model's sliding
    /// mode, whose sign is the side of the sticking impulse, not the sliding direction.
    pub(super) linear_any: Vec<Linear>,
    pub(super) impulse: (RowVector6<f64>, RowVector6<f64>),
    pub(super) mass: Vector6<f64>,
    pub mu_bounds: [f64; 2],
    /// Whether mu must lie between 0 and mu_max (`FitSettings::mu_max_condition`).
    pub mu_max_condition: bool,
    pub e_range: [f64; 2],
    /// What the fit asks of the model fitted.
    pub family: &'static dyn Family,
    /// Friction-limit range of the tangential model.
    pub friction: [f64; 2],
    /// et range of the tangential model.
    pub et_range: [f64; 2],
    /// The tangential model's sticking transfer as an affine map of `(e, et)`, and the impulse
    /// rows of its two parts (`None` for PIM or a singular collision matrix).
    stick: Option<(pim_core::StickMaps, Matrix2x6<f64>, Matrix2x6<f64>)>,
    pub settings: SearchSettings,
    /// Feasibility tolerance, m/s.
    pub(super) tol: f64,
    /// Elementary operations spent so far: linear solves of the inner problem and iterations
    /// of its QP solvers (see [`crate::Certificate::operations`]).
    pub(crate) operations: std::sync::atomic::AtomicU64,
}

/// The linear constraint set of a sign.
pub(super) fn sign_index(s: FrictionSign) -> usize {
    match s {
        FrictionSign::Positive => 0,
        FrictionSign::Negative => 1,
    }
}

impl Inner {
    /// Counts `n` elementary operations.
    pub(crate) fn spend(&self, n: u64) {
        self.operations
            .fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    }

    pub fn new(problem: &FitProblem, settings: &FitSettings) -> Self {
        let impact = problem.impact;
        let objective = Objective::new(problem);
        let family = settings.model.family();
        // The tangential model has no moment impulse: its sliding mode is PIM's with e_m = 1,
        // where the moment forms agree (and so is its reduced known-state solve); its sticking
        // mode solves a known state through its own transfer matrix.
        let moment_form = family.moment_form(settings.moment_form);
        let known_state = objective.known_state();
        let known =
            known_state.map(|(v, forward)| KnownState::new(&impact, moment_form, v, forward));
        let known_sign = objective
            .fixed_contact()
            .and_then(|x| impact.sliding_sign(&pim_core::Velocities::from_vector(&x)));
        let side = if impact.side() == 0.0 {
            1.0
        } else {
            impact.side()
        };
        let nrow = normal_velocity_row(&impact);
        let trow = tangential_velocity_row(&impact);
        let linear_for = |sign: FrictionSign| {
            let mut v: Vec<Linear> = (0..12)
                .map(|k| Linear::Bound {
                    k,
                    limit: if k % 3 == 2 {
                        settings.yaw_rate_bound
                    } else {
                        settings.velocity_bound
                    },
                })
                .collect();
            // Approach: side * vn <= -min_approach_speed.
            v.push(Linear::Contact {
                row: nrow * side,
                rhs: -settings.search.min_approach_speed,
                kind: Violation::NotApproaching,
            });
            // Sliding direction: sgn(vt) = sign sgn(vn) = -sign side.
            let sigma = -sign.value() * side;
            v.push(Linear::Contact {
                row: -trow * sigma,
                rhs: 0.0,
                kind: Violation::SlidingDirection,
            });
            v
        };
        let [m1, m2] = impact.masses();
        let [i1, i2] = impact.inertias();
        // A barrier does not move: its (infinite) mass carries no kinetic energy.
        let (m2, i2) = if impact.is_barrier() {
            (0.0, 0.0)
        } else {
            (m2, i2)
        };
        let tol = settings.search.feasibility_tolerance * objective.scale;
        let impulse = impulse_rows(&impact);
        let rows = |d: &Matrix6<f64>| {
            let mut m = Matrix2x6::zeros();
            m.set_row(0, &(impulse.0 * d));
            m.set_row(1, &(impulse.1 * d));
            m
        };
        let stick = (family.sticking() == Sticking::Restitution)
            .then(|| pim_core::StickMaps::new(&impact))
            .flatten()
            .map(|maps| (maps, rows(&maps.a), rows(&maps.b)));
        Inner {
            operations: std::sync::atomic::AtomicU64::new(0),
            reduction: Reduction::new(&impact, moment_form),
            known,
            known_state,
            known_sign,
            linear_any: linear_for(FrictionSign::Positive)
                .into_iter()
                .filter(|c| {
                    !matches!(
                        c,
                        Linear::Contact {
                            kind: Violation::SlidingDirection,
                            ..
                        }
                    )
                })
                .collect(),
            linear: [
                linear_for(FrictionSign::Positive),
                linear_for(FrictionSign::Negative),
            ],
            impulse,
            stick,
            mass: Vector6::new(m1, m1, i1, m2, m2, i2),
            mu_bounds: settings.mu,
            mu_max_condition: settings.mu_max_condition,
            e_range: settings.e,
            family,
            friction: settings.friction,
            et_range: settings.et,
            settings: settings.search,
            tol,
            objective,
            impact,
        }
    }

    /// The smallest |Pn| of a friction wedge, N s.
    pub fn pn_floor(&self) -> f64 {
        1e-9 * self.mass[0] * self.objective.scale
    }

    /// The linear conditions as rows over `U = (x, X)` (see [`rows_over_u`]): of a friction
    /// sign (bounds, approach and the sliding direction of that sign), or without a sign (bounds
    /// and approach only).
    pub(crate) fn linear_rows(&self, sign: Option<FrictionSign>) -> Vec<RowU> {
        let linear = match sign {
            Some(s) => &self.linear[sign_index(s)],
            None => &self.linear_any,
        };
        rows_over_u(linear, self.tol).collect()
    }

    /// Sum of weight x target^2 over the data.
    pub fn data_scale(&self) -> f64 {
        self.objective.data_scale()
    }

    /// The friction signs to try: the sliding direction of a known contact state that slides,
    /// else both (a known contact state with `vt = 0` takes the sign of its no-slip impulse,
    /// which the ratio condition of each sign decides; the tangential model's sliding sign is
    /// the side of its sticking impulse, so it always tries both).
    pub fn signs(&self) -> &'static [FrictionSign] {
        match self
            .known_sign
            .filter(|_| self.family.sign_follows_sliding())
        {
            Some(FrictionSign::Positive) => &[FrictionSign::Positive],
            Some(FrictionSign::Negative) => &[FrictionSign::Negative],
            None => &FrictionSign::BOTH,
        }
    }

    /// The friction signs to try in a mode: those of [`Inner::signs`], except in the tangential
    /// model's sticking mode, where no sign enters (the contact state may slide either way; one
    /// evaluation covers both).
    pub fn signs_in(&self, mode: TangentialCondition) -> &'static [FrictionSign] {
        if self.family.friction() == Friction::Limit && mode == TangentialCondition::NoSlip {
            &[FrictionSign::Positive]
        } else {
            self.signs()
        }
    }

    /// The transfer matrix `X = R x` of a candidate point.
    pub fn transfer(&self, at: &At) -> Option<Matrix6<f64>> {
        match (self.family.sticking(), at.mode) {
            (Sticking::Restitution, TangentialCondition::NoSlip) => {
                self.stick.map(|(maps, ..)| maps.transfer(at.c.e, at.et))
            }
            _ => self.reduction.transfer(&at.c, at.mode, at.sign),
        }
    }

    /// The tangential model's sticking impulse at `et` as rows over x, `(l0 + e l1) x`: the
    /// impulse of `R(e, et) - I = (1 + e) A + (1 - et) B`.
    pub(super) fn stick_rows(&self, et: f64) -> Option<CriticalRows> {
        let (_, a, b) = self.stick?;
        Some(CriticalRows {
            l0: a + b * (1.0 - et),
            l1: a,
        })
    }

    /// The impulse-ratio condition of the tangential model: sticking within the largest
    /// friction limit, or sliding where sticking at `et` would exceed the friction limit on the
    /// side of the candidate's sign (the friction rule: `sign Pt / Pn >= friction` for the
    /// sticking impulse, written as `Pn / (sign Pt)` within `[0, 1 / friction]`).
    pub(super) fn tangential_ratio(&self, at: &At) -> Ratio {
        match at.mode {
            TangentialCondition::NoSlip => Ratio {
                source: Impulses::Actual,
                lo: -self.friction[1],
                hi: self.friction[1],
                kind: Violation::FrictionLimit,
                mu: 0.0,
                inverse: false,
            },
            TangentialCondition::Sliding => {
                let f = at.c.mu;
                let bound = if f > 0.0 { 1.0 / f } else { f64::INFINITY };
                Ratio {
                    source: self
                        .stick_rows(at.et)
                        .map_or(Impulses::Undefined, Impulses::Critical),
                    lo: 0.0,
                    hi: bound,
                    kind: Violation::StickWithinFriction,
                    mu: f,
                    inverse: true,
                }
            }
        }
    }

    /// The constraint set of a candidate point.
    pub fn constraints(&self, at: &At) -> ConstraintSet<'_> {
        let ratio = match at.mode {
            _ if self.family.friction() == Friction::Limit => Some(self.tangential_ratio(at)),
            TangentialCondition::NoSlip => Some(Ratio {
                source: Impulses::Actual,
                lo: self.mu_bounds[0],
                hi: self.mu_bounds[1],
                kind: Violation::MuBound,
                mu: 0.0,
                inverse: false,
            }),
            TangentialCondition::Sliding if at.c.mu == 0.0 || !self.mu_max_condition => None,
            TangentialCondition::Sliding => {
                let source = match self.reduction.critical_rows(at.c.em) {
                    Some(rows) => Impulses::Critical(rows),
                    None => Impulses::Undefined,
                };
                let mu = at.c.mu;
                let (lo, hi) = if mu > 0.0 {
                    (mu, f64::INFINITY)
                } else {
                    (f64::NEG_INFINITY, mu)
                };
                Some(Ratio {
                    source,
                    lo,
                    hi,
                    kind: Violation::Friction,
                    mu,
                    inverse: false,
                })
            }
        };
        // The tangential model's sign is no sliding direction: in sliding it is the side of
        // the sticking impulse, in sticking none.
        ConstraintSet {
            linear: if self.family.friction() == Friction::Limit {
                &self.linear_any
            } else {
                &self.linear[sign_index(at.sign)]
            },
            ratio,
            sign: at.sign,
            impulse: self.impulse,
            mass: self.mass,
            tol: self.tol,
            pn_floor: self.pn_floor(),
        }
    }

    /// The friction ratio of a candidate in the convention of equation 5: mu itself, or the
    /// ratio of its impulse (mu_max) when it sticks.
    pub(super) fn mu_eff(&self, at: &At, x: &Vector6<f64>, xf: &Vector6<f64>) -> f64 {
        match at.mode {
            TangentialCondition::Sliding => at.c.mu,
            TangentialCondition::NoSlip => {
                let d = xf - x;
                CriticalImpulse {
                    normal: (self.impulse.0 * d)[0],
                    tangential: (self.impulse.1 * d)[0],
                }
                .mu_max(at.sign)
                .unwrap_or(0.0)
            }
        }
    }

    /// mu_max of a candidate's contact state at its e and em (`None` when undefined).
    pub fn mu_max(&self, at: &At, c: &Candidate) -> Option<f64> {
        if self.family.friction() != Friction::Equivalent {
            return None;
        }
        self.reduction
            .critical_rows(at.c.em)?
            .at(at.c.e, &c.x)
            .mu_max(at.sign)
    }

    /// Evaluates a candidate. `exact = false` stops at the equality-only optimum and returns
    /// [`Eval::Pending`] with its cost, a lower bound of the exact value, when a constraint is
    /// violated; so does a lower bound at or above `cutoff` (the incumbent of the search).
    pub fn evaluate(&self, at: &At, exact: bool, cutoff: f64) -> Eval {
        if let Some(eval) = self.evaluate_known(at) {
            return eval;
        }
        self.evaluate_general(at, exact, cutoff)
    }

    /// The faces of the box where a known separation state leaves the contact state a family.
    pub fn singular_faces(&self) -> pim_core::reduction::SingularFaces {
        self.known
            .as_ref()
            .filter(|_| self.family.moment_impulse())
            .map(|k| k.singular_faces())
            .unwrap_or_default()
    }

    /// True when the search may profile e out (see [`Inner::evaluate_profile`]; PIM only).
    pub fn profiles(&self) -> bool {
        self.family.moment_impulse() && self.known.as_ref().is_some_and(|d| d.profiles())
    }
}
