//! The fit report: statuses, reasons and active constraints are types; their words are made by
//! `Display` (and serialised as those words) at the edge.

use crate::certificate::Certificate;
use crate::problem::{Component, MomentBranch};
use pim_core::{DeltaV, FrictionSign, Impulse, PimError, Residuals, Velocities};
use serde::{Deserialize, Serialize, Serializer};
use std::fmt;

/// Serialises a value by its `Display` words.
fn as_words<T: fmt::Display, S: Serializer>(v: &T, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(&v.to_string())
}

/// Outcome of a branch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// The global optimum within the stated tolerances was found.
    Optimal,
    /// No coefficients in the box and no velocities within the bounds satisfy every constraint.
    Infeasible,
    /// A solution was found but a local refinement hit its iteration limit.
    LimitReached,
    /// The best point found failed pim-core's own check of the equations and admissibility;
    /// a defect of the search, reported instead of a wrong optimum.
    CheckFailed,
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.pad(match self {
            Status::Optimal => "optimal",
            Status::Infeasible => "infeasible",
            Status::LimitReached => "limit_reached",
            Status::CheckFailed => "check_failed",
        })
    }
}

/// Why a candidate point of the search is not admissible.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Violation {
    /// A velocity component exceeds its bound.
    Bound(Component),
    /// The vehicles do not approach at C at contact (by the minimum closing speed).
    NotApproaching,
    /// The contact state slides the other way than the friction sign assumes.
    SlidingDirection,
    /// mu is not between 0 and mu_max.
    Friction,
    /// Sticking needs a friction ratio outside the mu bounds.
    MuBound,
    /// Tangential model: the sticking impulse needs a ratio above the friction limit's bound.
    FrictionLimit,
    /// Tangential model: sliding at this friction, although the sticking impulse stays within
    /// the friction limit (the model would stick).
    StickWithinFriction,
    /// The solution creates kinetic energy.
    Energy,
    /// The equations are singular for these coefficients.
    Singular,
    /// The constraints together admit no solution (found by the QP).
    Infeasible,
    /// The energy-constrained problem could not be solved exactly.
    EnergyUncertified,
    /// The known components contradict an equation that does not involve the unknown ones.
    Inconsistent,
}

/// The bounds a reason refers to (for its words).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// |v| bound, m/s.
    pub velocity: f64,
    /// |omega| bound, rad/s.
    pub yaw_rate: f64,
    /// mu range.
    pub mu: [f64; 2],
    /// e range.
    pub e: [f64; 2],
    /// Friction-limit range of the tangential model.
    pub friction: [f64; 2],
}

impl Limits {
    /// The bounds of a fit's settings.
    pub fn of(settings: &crate::settings::FitSettings) -> Limits {
        Limits {
            velocity: settings.velocity_bound,
            yaw_rate: settings.yaw_rate_bound,
            mu: settings.mu,
            e: settings.e,
            friction: settings.friction,
        }
    }
}

impl Violation {
    /// The violation in words.
    pub fn describe(self, limits: &Limits) -> String {
        match self {
            Violation::Bound(k) => format!(
                "the velocities would exceed the bound on {k} (|v| <= {} m/s, |omega| <= {} rad/s)",
                limits.velocity, limits.yaw_rate
            ),
            Violation::NotApproaching => {
                "the contact velocities would not approach at the impact centre".to_string()
            }
            Violation::SlidingDirection | Violation::Friction => "the tangential impulse would \
                reverse the sliding direction, so no mu between 0 and mu_max fits"
                .to_string(),
            Violation::MuBound => format!(
                "stopping the sliding would need a friction ratio outside [{}, {}]",
                limits.mu[0], limits.mu[1]
            ),
            Violation::FrictionLimit => format!(
                "the tangential restitution would need an impulse ratio above the largest \
                 friction limit {}",
                limits.friction[1]
            ),
            Violation::StickWithinFriction => "sliding at that friction limit would need a \
                sticking impulse beyond it (Routh's rule would stick instead)"
                .to_string(),
            Violation::Energy => "the solution would create kinetic energy".to_string(),
            Violation::Singular => "the impact equations are singular".to_string(),
            Violation::Infeasible => {
                "the bounds, approach and sliding conditions admit no velocities together"
                    .to_string()
            }
            Violation::EnergyUncertified => {
                "the energy condition could not be enforced exactly".to_string()
            }
            Violation::Inconsistent => "the components held fixed contradict an equation on \
                their own (sticking needs no tangential relative velocity at separation, e = 0 \
                no normal one, em = 0 equal yaw rates)"
                .to_string(),
        }
    }
}

/// Why a branch is not optimal, or a caveat on an optimal one.
#[derive(Debug, Clone, PartialEq)]
pub enum Reason {
    /// The fixed separation velocities still approach at C: a negative restitution.
    SeparationApproaches {
        /// Normal relative velocity at separation, m/s.
        normal_velocity: f64,
        /// The e range searched.
        e_range: [f64; 2],
    },
    /// The fixed separation velocities slide the other way than at contact.
    SeparationReversesSliding {
        /// Tangential relative velocity at separation, m/s.
        tangential_velocity: f64,
    },
    /// The fixed contact velocities do not approach at C.
    ContactNotApproaching(PimError),
    /// No candidate of the box satisfied the constraints, and none was even evaluated.
    NoCandidate,
    /// No candidate of the box satisfies every constraint: the most frequent violations with
    /// their share of the candidates, percent.
    Constraints {
        /// The most frequent violation and its share.
        main: (Violation, f64),
        /// The second, if any.
        second: Option<(Violation, f64)>,
        /// The bounds the words refer to.
        limits: Limits,
    },
    /// The data leave these velocity components undetermined (the values shown are the
    /// smallest-norm choice).
    Undetermined(Vec<Component>),
    /// The refinement that found the point hit its iteration limit and no other agrees.
    LimitReached {
        /// Refinements other than the one that found the point.
        other_refinements: usize,
    },
    /// pim-core's check of the answer failed, with its words.
    CheckFailed(Vec<String>),
}

impl fmt::Display for Reason {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Reason::SeparationApproaches {
                normal_velocity,
                e_range,
            } => write!(
                f,
                "the fixed separation velocities still approach at the impact centre (normal \
                 relative velocity {normal_velocity:.3} m/s towards each other), which would need \
                 a negative restitution; no e in [{}, {}] fits them",
                e_range[0], e_range[1]
            ),
            Reason::SeparationReversesSliding {
                tangential_velocity,
            } => write!(
                f,
                "the fixed separation velocities reverse the sliding direction (tangential \
                 relative velocity at separation {tangential_velocity:.3} m/s), so no mu <= mu_max \
                 fits them"
            ),
            Reason::ContactNotApproaching(e) => {
                write!(f, "the fixed contact velocities admit no impact: {e}")
            }
            Reason::NoCandidate => {
                f.write_str("no candidate in the coefficient box satisfies the constraints")
            }
            Reason::Constraints {
                main,
                second,
                limits,
            } => {
                write!(
                    f,
                    "no coefficients in the box satisfy every constraint: {} ({:.0} % of the \
                     candidates)",
                    main.0.describe(limits),
                    main.1
                )?;
                if let Some((v, pct)) = second {
                    write!(f, "; {} ({pct:.0} %)", v.describe(limits))?;
                }
                Ok(())
            }
            Reason::Undetermined(list) => {
                let names: Vec<&str> = list.iter().map(|c| c.name()).collect();
                write!(
                    f,
                    "the data do not determine {}: equally good solutions differ along them, and \
                     the values shown are the smallest-norm choice",
                    names.join(", ")
                )
            }
            Reason::LimitReached { other_refinements } => write!(
                f,
                "the refinement that found this point reached its iteration limit and none of \
                 the other {other_refinements} refinements reached the same cost; it is the best \
                 point found"
            ),
            Reason::CheckFailed(words) => write!(
                f,
                "the best point found fails pim-core's check: {}",
                words.join("; ")
            ),
        }
    }
}

pim_core::json_schema_as!(Reason, {"type": "string", "description": "Why the fit is not identifiable, in words."});

impl Serialize for Reason {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        as_words(self, s)
    }
}

/// A constraint that holds with equality at a fitted solution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActiveConstraint {
    /// A velocity component is at its bound.
    VelocityBound(Component),
    /// The closing speed at C is at its minimum.
    MinimumApproach,
    /// No sliding at contact (vt = 0): friction takes the no-slip impulse's side.
    SlidingDirection,
    /// mu = mu_max: sliding just stops at separation.
    MuMax,
    /// The friction ratio of a sticking solution is at a mu bound.
    StickingMuBound,
    /// Tangential model: the sticking impulse ratio is at the largest friction limit.
    FrictionBound,
    /// Tangential model: the friction limit of a sliding answer at the lower end of its range.
    FrictionLow,
    /// Tangential model: the friction limit of a sliding answer at the upper end of its range.
    FrictionHigh,
    /// Tangential model: et of a sticking answer at the lower end of its range.
    EtLow,
    /// Tangential model: et of a sticking answer at the upper end of its range.
    EtHigh,
    /// Tangential model: the sticking impulse at et is exactly at the friction limit (sticking
    /// and sliding give the same answer).
    StickSlide,
    /// No kinetic energy created: T1 = T0.
    Energy,
    /// e at the lower end of its range.
    ELow,
    /// e at the upper end of its range.
    EHigh,
    /// e_m = -1.
    EmLow,
    /// e_m = 0.
    EmHigh,
    /// mu at the lower end of its range.
    MuLow,
    /// mu at the upper end of its range.
    MuHigh,
    /// mu = 0.
    MuZero,
}

impl fmt::Display for ActiveConstraint {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ActiveConstraint::VelocityBound(k) => write!(f, "bound on {k}"),
            ActiveConstraint::MinimumApproach => f.write_str("minimum approach speed at C"),
            ActiveConstraint::SlidingDirection => {
                f.write_str("sliding direction at contact (vt = 0)")
            }
            ActiveConstraint::MuMax => f.write_str("mu = mu_max (sliding just stops)"),
            ActiveConstraint::StickingMuBound => f.write_str("mu bound"),
            ActiveConstraint::FrictionBound => {
                f.write_str("impulse ratio at the largest friction limit")
            }
            ActiveConstraint::StickSlide => {
                f.write_str("sticking impulse at the friction limit (stick = slide)")
            }
            ActiveConstraint::FrictionLow => f.write_str("friction limit at its lower bound"),
            ActiveConstraint::FrictionHigh => f.write_str("friction limit at its upper bound"),
            ActiveConstraint::EtLow => f.write_str("et at its lower bound"),
            ActiveConstraint::EtHigh => f.write_str("et at its upper bound"),
            ActiveConstraint::Energy => f.write_str("no kinetic energy created (T1 = T0)"),
            ActiveConstraint::ELow => f.write_str("e at its lower bound"),
            ActiveConstraint::EHigh => f.write_str("e at its upper bound"),
            ActiveConstraint::EmLow => f.write_str("em = -1"),
            ActiveConstraint::EmHigh => f.write_str("em = 0"),
            ActiveConstraint::MuLow => f.write_str("mu at its lower bound"),
            ActiveConstraint::MuHigh => f.write_str("mu at its upper bound"),
            ActiveConstraint::MuZero => f.write_str("mu = 0"),
        }
    }
}

impl ActiveConstraint {
    /// A compact label for tables (`e=max`, `em=-1`, `vt=0`, `|vf1x|=bound`, ...).
    pub fn short(&self) -> String {
        const SHORT: [&str; 12] = [
            "vi1x", "vi1y", "wi1", "vi2x", "vi2y", "wi2", "vf1x", "vf1y", "wf1", "vf2x", "vf2y",
            "wf2",
        ];
        match self {
            ActiveConstraint::VelocityBound(k) => format!("|{}|=bound", SHORT[k.0]),
            ActiveConstraint::MinimumApproach => "approach".into(),
            ActiveConstraint::SlidingDirection => "vt=0".into(),
            ActiveConstraint::MuMax => "mu=mu_max".into(),
            ActiveConstraint::StickingMuBound => "mu_max=bound".into(),
            ActiveConstraint::FrictionBound => "ratio=friction_max".into(),
            ActiveConstraint::StickSlide => "stick=slide".into(),
            ActiveConstraint::FrictionLow => "friction=min".into(),
            ActiveConstraint::FrictionHigh => "friction=max".into(),
            ActiveConstraint::EtLow => "et=min".into(),
            ActiveConstraint::EtHigh => "et=max".into(),
            ActiveConstraint::Energy => "T1=T0".into(),
            ActiveConstraint::ELow => "e=min".into(),
            ActiveConstraint::EHigh => "e=max".into(),
            ActiveConstraint::EmLow => "em=-1".into(),
            ActiveConstraint::EmHigh => "em=0".into(),
            ActiveConstraint::MuLow => "mu=min".into(),
            ActiveConstraint::MuHigh => "mu=max".into(),
            ActiveConstraint::MuZero => "mu=0".into(),
        }
    }
}

pim_core::json_schema_as!(ActiveConstraint, {"type": "string", "description": "A constraint that holds with equality at the solution, in words."});

impl Serialize for ActiveConstraint {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        as_words(self, s)
    }
}

/// A quantity whose identifiability is reported.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Quantity {
    /// Restitution.
    E,
    /// Friction ratio.
    Mu,
    /// Moment restitution.
    Em,
    /// Tangential restitution (tangential model).
    Et,
    /// Friction limit (tangential model).
    Friction,
    /// Speed of vehicle 1 at contact, m/s.
    Speed1,
    /// Speed of vehicle 2 at contact, m/s.
    Speed2,
}

impl fmt::Display for Quantity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Quantity::E => "e",
            Quantity::Mu => "mu",
            Quantity::Em => "em",
            Quantity::Et => "et",
            Quantity::Friction => "friction",
            Quantity::Speed1 => "speed1",
            Quantity::Speed2 => "speed2",
        })
    }
}

/// How well the data pin one coefficient (or contact speed) down.
///
/// The range is that of the points seen by the search and by scans through the optimum along
/// each coefficient. When one whole state is known (Q1, Q2) those scans run along mu and em with
/// e at its best, and on each scanned line the ends of the e interval whose cost is within the
/// tolerance are computed exactly (the cost is a quadratic along e there).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Identifiability {
    /// `e`, `mu`, `em`, or `speed1` / `speed2` (speed of each vehicle at contact, m/s).
    pub coefficient: Quantity,
    /// Smallest value seen whose cost is within the tolerance of the optimum.
    pub low: f64,
    /// Largest such value.
    pub high: f64,
    /// The relative cost tolerance used.
    pub tolerance: f64,
    /// False when that range covers half of the coefficient's box or more (flat cost); for a
    /// speed, when it spans more than 10 % of the speed or the cost is flat along it.
    pub identifiable: bool,
    /// The cost is exactly flat along a velocity direction near the optimum: the range seen is
    /// only part of the set of equally good values (a speed is then at least `low`).
    pub open_ended: bool,
}

/// The tangential model's reading of a fitted solution.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TangentialFit {
    /// Sticking or sliding.
    pub mode: pim_core::ContactMode,
    /// Tangential restitution: sticking, `vt' = et vt`; sliding, one value at which Routh's
    /// rule slides (the answer does not depend on it; its range is in the identifiability).
    pub et: f64,
    /// The smallest friction limit that gives this answer: sliding, the limit itself;
    /// sticking, the impulse ratio `|Pt / Pn|`.
    pub friction: f64,
    /// The largest such limit: sliding, the same; sticking, the upper end of the friction
    /// bounds (every limit at least the impulse ratio sticks the same way).
    pub friction_max: f64,
    /// The impulse ratio `Pt / Pn` that acted.
    pub impulse_ratio: f64,
    /// The impulse ratio sticking at `et` would need.
    pub stick_ratio: f64,
}

/// The fitted solution of one moment branch.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Solution {
    /// Restitution.
    pub e: f64,
    /// Friction ratio of equation 5 (equals mu_max when the vehicles stick).
    pub mu: f64,
    /// Moment restitution.
    pub em: f64,
    /// Weighted sum of squares at the optimum.
    pub cost: f64,
    /// Fitted velocities at contact.
    pub initial: Velocities,
    /// Fitted velocities at separation.
    #[serde(rename = "final")]
    pub separation: Velocities,
    /// True when the optimum sticks (mu = mu_max, equation 5a).
    pub sticking: bool,
    /// Friction sign sgn(vn) sgn(vt) at contact (`1` or `-1` in JSON).
    pub friction_sign: FrictionSign,
    /// Residuals of the six equations.
    pub residuals: Residuals,
    /// Largest relative residual.
    pub max_residual: f64,
    /// Constraints active at the optimum: velocity bounds, approach, sliding direction,
    /// mu = mu_max, energy, and coefficients on the ends of their ranges.
    pub active_constraints: Vec<ActiveConstraint>,
    /// Kinetic energy loss, percent.
    pub energy_loss_percent: f64,
    /// Signed critical friction of the fitted contact state.
    pub mu_max: Option<f64>,
    /// mu / mu_max.
    pub mu_ratio: Option<f64>,
    /// Delta-V of both vehicles.
    pub delta_v: [DeltaV; 2],
    /// Speeds, delta-V in each vehicle's axes, PDOF and yaw-rate change, per vehicle.
    pub vehicles: [pim_core::VehicleResult; 2],
    /// Kinetic energy loss, J.
    pub energy_loss: f64,
    /// Impulses on vehicle 1.
    pub impulse: Impulse,
    /// Physically admissible by pim-core's own check (friction domain, energy).
    pub admissible: bool,
    /// Velocity components the data leave undetermined (the cost is flat along a combination
    /// of them); empty when the fitted velocities are unique. The values shown are then the
    /// smallest-norm choice among equally good ones.
    pub undetermined: Vec<Component>,
    /// The tangential model's coefficients (`None` for PIM, whose `e`, `mu`, `em` above are
    /// then the model's own; for the tangential model they are its PIM equivalent: `mu` the
    /// impulse ratio relative to the sliding direction, `em = 1`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential: Option<TangentialFit>,
}

/// The result of one moment branch.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BranchReport {
    /// The branch.
    pub moment: MomentBranch,
    /// Outcome.
    pub status: Status,
    /// Why, in words, when not optimal; for an optimal branch, a caveat (undetermined
    /// velocities) when there is one.
    pub reason: Option<Reason>,
    /// The solution (none when infeasible).
    pub solution: Option<Solution>,
    /// Identifiability of each coefficient (empty when infeasible).
    pub identifiability: Vec<Identifiability>,
    /// How the optimum was established.
    pub certificate: Certificate,
    /// With geometry bounds ([`crate::fit_geometry`]): the estimated impact centres and
    /// crush-surface angle, their ranges and the search over them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub geometry: Option<crate::geometry::types::GeometryEstimate>,
}

/// The result of a fit.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct FitReport {
    /// The model fitted.
    pub model: crate::FitModel,
    /// One report per branch, in the order asked.
    pub branches: Vec<BranchReport>,
    /// The optimal branch with the lower cost, if any; on a tie (costs within 1e-6 relative)
    /// the zero branch, which has one coefficient fewer.
    pub best: Option<MomentBranch>,
    /// Remarks on the whole fit, for example that both branches fit equally well.
    pub notes: Vec<String>,
}

impl FitReport {
    /// The report of the best branch.
    pub fn best_branch(&self) -> Option<&BranchReport> {
        self.best
            .and_then(|b| self.branches.iter().find(|r| r.moment == b))
    }
}

/// The cost of a fit read as a chi-square, when its weights are inverse variances
/// (`w_k = u / sigma_k^2` with one common unit `u`, m^2/s^2).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ChiSquare {
    /// `sum (r_k / sigma_k)^2 = cost / u`.
    pub value: f64,
    /// Data (estimated components and observations) minus free parameters: the unknown
    /// velocity components plus the branch's coefficients (3 free, 2 zero) minus the six
    /// equations. Active bounds are not subtracted.
    pub degrees_of_freedom: i64,
    /// `P(chi^2_nu >= value)` with `nu` = [`judged_dof`] of the degrees of freedom: the
    /// probability of a misfit at least this large if the model and the stated sigmas are right
    /// (none only for a value that is not a finite number).
    pub p_value: Option<f64>,
}

impl ChiSquare {
    /// The same chi-square with `n` more estimated parameters (e.g. geometry inputs): `n`
    /// degrees of freedom fewer.
    pub fn with_more_parameters(self, n: usize) -> Self {
        let dof = self.degrees_of_freedom - n as i64;
        ChiSquare {
            value: self.value,
            degrees_of_freedom: dof,
            p_value: p_value(dof, self.value),
        }
    }

    /// The chi-square of a branch's `cost` for `problem`, whose weights are `unit / sigma^2`.
    pub fn new(problem: &crate::FitProblem, branch: MomentBranch, cost: f64, unit: f64) -> Self {
        use crate::Knowledge;
        let data = problem
            .components
            .iter()
            .filter(|k| matches!(k, Knowledge::Estimated { .. }))
            .count()
            + problem.observations.len()
            + problem.combinations.len();
        let free = problem
            .components
            .iter()
            .filter(|k| !matches!(k, Knowledge::Known { .. }))
            .count();
        let coefficients = match branch {
            MomentBranch::Free => 3,
            MomentBranch::Zero => 2,
        };
        let dof = data as i64 - (free as i64 + coefficients - 6);
        let value = cost / unit;
        ChiSquare {
            value,
            degrees_of_freedom: dof,
            p_value: p_value(dof, value),
        }
    }
}

impl ChiSquare {
    /// The upper-tail probability of a chi-square `value` with `dof` degrees of freedom, judged
    /// with [`judged_dof`] (none for a value that is not a finite number).
    pub fn p_value_of(dof: i64, value: f64) -> Option<f64> {
        p_value(dof, value)
    }

    /// The number of unknowns the evidence does not determine by count alone: `-dof` for
    /// `dof < 0`, else 0 (combinations of the unknowns that the evidence leaves free; the answer
    /// is one of a family along them, unless a bound or the physics holds it).
    pub fn unknowns_undetermined(dof: i64) -> i64 {
        (-dof).max(0)
    }
}

/// The degrees of freedom a chi-square is judged with: its own when positive, otherwise 1.
///
/// With no degrees of freedom left (as many unknowns as pieces of evidence, or more) a fit meets
/// consistent evidence exactly: its chi-square is 0 unless a bound or the physics (admissible
/// friction, no energy created) keeps it from the evidence. What it still misses is then judged
/// as one degree of freedom, the strictest reading (for a given chi-square, the smallest
/// probability), so that a miss is never excused by a shortage of evidence. One rule for every
/// fit and reconstruction: the probability of a chi-square `x` is `P(chi^2_nu >= x)` with
/// `nu = max(dof, 1)`.
pub fn judged_dof(dof: i64) -> i64 {
    dof.max(1)
}

/// The upper-tail probability of a chi-square `value` with `dof` degrees of freedom, judged
/// with [`judged_dof`].
fn p_value(dof: i64, value: f64) -> Option<f64> {
    if !value.is_finite() {
        return None;
    }
    statrs::distribution::ChiSquared::new(judged_dof(dof) as f64)
        .ok()
        .map(|d| statrs::distribution::ContinuousCDF::sf(&d, value.max(0.0)))
}
