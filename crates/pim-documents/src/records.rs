//! The JSON documents of a solve, a sensitivity study and a fit: one schema for every front end.

use pim_core::{ImpactReport, SensitivityStudy, Velocities};
use serde::Serialize;

/// One vehicle's velocity in the output.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct VelocityOut {
    /// m/s.
    pub vx: f64,
    /// m/s.
    pub vy: f64,
    /// rad/s.
    pub omega: f64,
}

/// Both vehicles' velocities.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct StateOut {
    /// Vehicle 1.
    pub vehicle1: VelocityOut,
    /// Vehicle 2.
    pub vehicle2: VelocityOut,
}

impl StateOut {
    /// `(v1x, v1y, w1, v2x, v2y, w2)`.
    pub fn to_array(&self) -> [f64; 6] {
        let (a, b) = (&self.vehicle1, &self.vehicle2);
        [a.vx, a.vy, a.omega, b.vx, b.vy, b.omega]
    }
}

impl From<&Velocities> for StateOut {
    fn from(v: &Velocities) -> Self {
        let f = |x: &pim_core::VehicleVelocity| VelocityOut {
            vx: x.vx,
            vy: x.vy,
            omega: x.omega,
        };
        StateOut {
            vehicle1: f(&v.vehicle1),
            vehicle2: f(&v.vehicle2),
        }
    }
}

/// Delta-V magnitudes, m/s.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct DeltaVOut {
    /// |V1 - v1|.
    pub vehicle1: f64,
    /// |V2 - v2|.
    pub vehicle2: f64,
}

/// Energy balance.
#[derive(Debug, Clone, Copy, Serialize, schemars::JsonSchema)]
pub struct EnergyOut {
    /// J.
    pub initial: f64,
    /// J.
    #[serde(rename = "final")]
    pub final_: f64,
    /// initial - final, J.
    pub loss: f64,
    /// Percent.
    pub loss_percent: f64,
}

/// The units of every number of a JSON document: SI, angles in degrees, in the natural frame
/// (x, y with y to the left of x, angles and yaw counter-clockwise), whatever the case's
/// `[units]` and `convention` (the tables and figures show those).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SiUnits;

pim_core::json_schema_as!(SiUnits, {"type": "object", "description": "The units of every number of the document: SI, angles in degrees, the natural frame.", "additionalProperties": {"type": "string"}});

impl Serialize for SiUnits {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(Some(9))?;
        for (k, v) in [
            ("system", "SI"),
            ("speed", "m/s"),
            ("length", "m"),
            ("mass", "kg"),
            ("yaw_rate", "rad/s"),
            ("energy", "J"),
            ("impulse", "N s"),
            ("angle", "deg"),
            (
                "frame",
                "natural: y to the left of x, angles and yaw counter-clockwise",
            ),
        ] {
            m.serialize_entry(k, v)?;
        }
        m.end()
    }
}

/// The JSON record of one forward or backward solve.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct SolveOut {
    /// The units of the document's numbers (always SI; see [`SiUnits`]).
    pub units: SiUnits,
    /// `forward` or `backward`.
    pub direction: &'static str,
    /// With `[coefficients] e, et, friction`: the tangential-restitution model, its mode and
    /// impulse ratio (`coefficients` are then PIM's equivalent: e, mu = the impulse ratio
    /// relative to the sliding direction, em = 1).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<ModelOut>,
    /// Present (true) when vehicle 2 is a fixed rigid barrier: its velocities are 0 and the
    /// energy is vehicle 1's.
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub barrier: bool,
    /// Coefficients used.
    pub coefficients: pim_core::Coefficients,
    /// Which side of the crush surface vehicle 1 lies on, and what that rests on.
    pub side: SideOut,
    /// Moment form and tangential condition.
    pub options: pim_core::SolveOptions,
    /// Velocities at contact.
    pub initial: StateOut,
    /// Velocities at separation.
    #[serde(rename = "final")]
    pub final_: StateOut,
    /// Delta-V magnitudes.
    pub delta_v: DeltaVOut,
    /// Delta-V components and directions per vehicle (fixed frame).
    pub delta_v_detail: [pim_core::DeltaV; 2],
    /// Per vehicle: nose heading (deg), speeds at contact and separation (m/s), delta-V and its
    /// components along the vehicle's forward and left axes (m/s), PDOF (deg clockwise from
    /// the nose) and clock direction, yaw-rate change (rad/s).
    pub vehicles: [pim_core::VehicleResult; 2],
    /// Energy balance.
    pub energy: EnergyOut,
    /// Impulses on vehicle 1.
    pub impulse: pim_core::Impulse,
    /// Relative velocities at C.
    pub relative_velocity: pim_core::RelativeVelocity,
    /// Material-point velocities at C.
    pub contact_points: pim_core::ContactPoints,
    /// The crush against PIM's energy loss and delta-V (with `[damage]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damage: Option<crate::damage_assess::Assessment>,
    /// The sign factor of equation 5 (`1` or `-1`): mu' = mu times this.
    pub friction_sign: pim_core::FrictionSign,
    /// `sliding` when it is the sliding direction at contact, `no_slip_impulse` when the
    /// contact point does not slide at contact and friction takes the no-slip impulse's side.
    pub friction_basis: pim_core::FrictionBasis,
    /// Signed critical impulse ratio (null when undefined).
    pub mu_max: Option<f64>,
    /// mu / mu_max.
    pub mu_ratio: Option<f64>,
    /// sliding, sticking or reversed.
    pub tangential: pim_core::TangentialOutcome,
    /// Still sliding at separation.
    pub sliding: bool,
    /// Physically admissible.
    pub admissible: bool,
    /// Why not, when not admissible.
    pub reasons: Vec<String>,
    /// Largest relative equation residual.
    pub max_residual: f64,
}

impl SolveOut {
    /// Builds the record from a pim-core report.
    pub fn new(impact: &pim_core::Impact, r: &ImpactReport, forward: bool) -> Self {
        SolveOut {
            units: SiUnits,
            direction: if forward { "forward" } else { "backward" },
            model: None,
            barrier: impact.is_barrier(),
            coefficients: r.coefficients,
            side: SideOut::of(impact),
            options: r.options,
            initial: (&r.initial).into(),
            final_: (&r.separation).into(),
            delta_v: DeltaVOut {
                vehicle1: r.delta_v[0].magnitude,
                vehicle2: r.delta_v[1].magnitude,
            },
            delta_v_detail: r.delta_v,
            vehicles: r.vehicles,
            energy: EnergyOut {
                initial: r.energy.initial,
                final_: r.energy.final_,
                loss: r.energy.loss,
                loss_percent: r.energy.loss_percent,
            },
            impulse: r.impulse,
            relative_velocity: r.relative,
            contact_points: r.contact_points,
            damage: None,
            friction_sign: r.friction_sign,
            friction_basis: r.friction_basis,
            mu_max: r.mu_max,
            mu_ratio: r.mu_ratio,
            tangential: r.tangential,
            sliding: r.sliding,
            admissible: r.admissibility.admissible,
            reasons: r.inadmissibility_reasons(),
            max_residual: r.residuals(impact).max_relative(),
        }
    }
}

/// One combination of a sensitivity study.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct SensitivityCaseOut {
    /// Levels of e, mu, em (`low`, `high`, `nominal`).
    pub levels: [pim_core::Level; 3],
    /// The full solve record (its `coefficients` are this combination's).
    #[serde(flatten)]
    pub solve: SolveOut,
}

/// The JSON of `pim sensitivity`.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct SensitivityOut {
    /// p, percent.
    pub percent: f64,
    /// The nominal solve.
    pub nominal: SolveOut,
    /// Every combination.
    pub combinations: Vec<SensitivityCaseOut>,
    /// Averages per coefficient level.
    pub averages: Vec<pim_core::LevelAverage>,
}

impl SensitivityOut {
    /// Builds the record.
    pub fn new(impact: &pim_core::Impact, s: &SensitivityStudy) -> Self {
        SensitivityOut {
            percent: s.percent,
            nominal: SolveOut::new(impact, &s.nominal, true),
            combinations: s
                .cases
                .iter()
                .map(|c| SensitivityCaseOut {
                    levels: c.levels,
                    solve: SolveOut::new(impact, &c.report, true),
                })
                .collect(),
            averages: s.averages.clone(),
        }
    }
}

/// One fitted branch as a flat record (the JSON of `pim fit` and of `pim batch`).
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct BranchRecord {
    /// `free` (em in [-1, 0]) or `zero` (em = 1).
    pub moment: pim_fit::MomentBranch,
    /// `optimal`, `infeasible` or `limit_reached`.
    pub status: pim_fit::Status,
    /// Words: why not optimal, or a caveat.
    pub reason: Option<pim_fit::Reason>,
    /// Restitution.
    pub e: Option<f64>,
    /// Friction ratio of equation 5 (mu_max when sticking).
    pub mu: Option<f64>,
    /// Moment restitution.
    pub em: Option<f64>,
    /// Weighted sum of squares.
    pub cost: Option<f64>,
    /// Fitted contact velocities.
    pub initial: Option<StateOut>,
    /// Fitted separation velocities.
    #[serde(rename = "final")]
    pub final_: Option<StateOut>,
    /// Largest relative residual of the six equations.
    pub max_residual: Option<f64>,
    /// Kinetic energy loss, percent.
    pub energy_loss_percent: Option<f64>,
    /// Kinetic energy loss, J.
    pub energy_loss: Option<f64>,
    /// Signed critical friction of the fitted contact state.
    pub mu_max: Option<f64>,
    /// mu / mu_max.
    pub mu_ratio: Option<f64>,
    /// Per vehicle: speeds, delta-V in the vehicle's axes, PDOF, yaw-rate change (SI).
    pub vehicles: Option<[pim_core::VehicleResult; 2]>,
    /// True when the vehicles stick (mu = mu_max).
    pub sticking: Option<bool>,
    /// Delta-V magnitudes, m/s.
    pub delta_v: Option<DeltaVOut>,
    /// Impulses on vehicle 1.
    pub impulse: Option<pim_core::Impulse>,
    /// Constraints active at the optimum.
    pub active_constraints: Vec<pim_fit::ActiveConstraint>,
    /// Velocity components the data leave undetermined.
    pub undetermined: Vec<pim_fit::Component>,
    /// Physically admissible (pim-core's own check).
    pub admissible: Option<bool>,
    /// Identifiability ranges.
    pub identifiability: Vec<pim_fit::Identifiability>,
    /// How the optimum was established.
    pub certificate: pim_fit::Certificate,
    /// The cost as a chi-square, when the case gives standard deviations (`[sigma]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chi_square: Option<pim_fit::ChiSquare>,
    /// With geometry bounds: the estimated impact centres and crush-surface angle (`vehicle1`
    /// / `vehicle2` `{d, phi}`, `crush_angle`), their ranges and the search over them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub geometry: Option<pim_fit::GeometryEstimate>,
    /// The tangential model's coefficients (`pim fit --model tangential`): mode, et, the
    /// friction limits that give the answer, the impulse ratio; `e` above is its restitution,
    /// `mu` its impulse ratio relative to the sliding direction and `em` = 1.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tangential: Option<pim_fit::TangentialFit>,
    /// The search bounds the answer rests on (a bound, not the data, ends it), each with
    /// where it came from; absent when none.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub bounds_reached: Vec<BoundReached>,
    /// Each estimate and observation against its fitted value (see
    /// [`crate::residuals`]); absent in batch records and without a solution.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub residuals: Vec<crate::residuals::Residual>,
}

/// Where a search bound came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum BoundSource {
    /// The case's `[bounds]` (or a batch's stated conditions) set it.
    Case,
    /// The program's default: no one chose it for this crash.
    Default,
}

impl BoundSource {
    /// `Case` when the case sets the bound itself, else `Default`.
    pub fn of(set_by_case: bool) -> Self {
        if set_by_case {
            BoundSource::Case
        } else {
            BoundSource::Default
        }
    }
}

/// The search bounds a fitted branch rests on: its active constraints that are search bounds
/// under `settings`, and the geometry estimates that lie on their bounds (always the case's
/// own). `set_by_case` says which bounds the case itself sets.
pub fn bounds_reached(
    b: &pim_fit::BranchReport,
    settings: &pim_fit::FitSettings,
    set_by_case: &dyn Fn(pim_fit::SearchBound) -> bool,
) -> Vec<BoundReached> {
    let mut out = Vec::new();
    for a in b.solution.iter().flat_map(|s| &s.active_constraints) {
        if let Some((bound, limit)) = a.search_bound(settings) {
            out.push(BoundReached {
                bound: bound.name().to_string(),
                limit,
                at: a.short(),
                source: BoundSource::of(set_by_case(bound)),
            });
        }
    }
    for r in b.geometry.iter().flat_map(|g| &g.ranges) {
        if r.at_bound {
            let lower = (r.value - r.bounds[0]).abs() <= (r.value - r.bounds[1]).abs();
            out.push(BoundReached {
                bound: r.input.clone(),
                limit: if lower { r.bounds[0] } else { r.bounds[1] },
                at: r.input.clone(),
                source: BoundSource::Case,
            });
        }
    }
    out
}

/// A search bound a fitted answer rests on.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BoundReached {
    /// The `[bounds]` key: `e`, `mu`, `et`, `friction`, `velocity`, `yaw_rate`, or a geometry
    /// input (`vehicle1.d`, `crush_angle`, ...).
    pub bound: String,
    /// The limit reached, SI (m/s, rad/s, m; the coefficients as they are; angles in degrees).
    pub limit: f64,
    /// What is at the limit (`|vi1x|=bound`, `e=max`, the geometry input).
    pub at: String,
    /// Who set the bound.
    pub source: BoundSource,
}

impl BranchRecord {
    /// Adds the chi-square reading of the cost (weights `unit / sigma^2`).
    pub fn with_chi_square(mut self, problem: &pim_fit::FitProblem, unit: Option<f64>) -> Self {
        if let (Some(u), Some(cost)) = (unit, self.cost) {
            let geometry = self.geometry.as_ref().map_or(0, |g| g.estimated_inputs());
            self.chi_square = Some(
                pim_fit::ChiSquare::new(problem, self.moment, cost, u)
                    .with_more_parameters(geometry),
            );
        }
        self
    }

    /// Flattens a branch report.
    pub fn new(b: &pim_fit::BranchReport) -> Self {
        let s = b.solution.as_ref();
        BranchRecord {
            moment: b.moment,
            status: b.status,
            reason: b.reason.clone(),
            e: s.map(|s| s.e),
            mu: s.map(|s| s.mu),
            em: s.map(|s| s.em),
            cost: s.map(|s| s.cost),
            initial: s.map(|s| (&s.initial).into()),
            final_: s.map(|s| (&s.separation).into()),
            max_residual: s.map(|s| s.max_residual),
            energy_loss_percent: s.map(|s| s.energy_loss_percent),
            energy_loss: s.map(|s| s.energy_loss),
            vehicles: s.map(|s| s.vehicles),
            mu_max: s.and_then(|s| s.mu_max),
            mu_ratio: s.and_then(|s| s.mu_ratio),
            sticking: s.map(|s| s.sticking),
            delta_v: s.map(|s| DeltaVOut {
                vehicle1: s.delta_v[0].magnitude,
                vehicle2: s.delta_v[1].magnitude,
            }),
            impulse: s.map(|s| s.impulse),
            active_constraints: s.map_or_else(Vec::new, |s| s.active_constraints.clone()),
            undetermined: s.map_or_else(Vec::new, |s| s.undetermined.clone()),
            admissible: s.map(|s| s.admissible),
            identifiability: b.identifiability.clone(),
            certificate: b.certificate.clone(),
            chi_square: None,
            geometry: b.geometry.clone(),
            tangential: s.and_then(|s| s.tangential.clone()),
            bounds_reached: Vec::new(),
            residuals: Vec::new(),
        }
    }

    /// Adds the search bounds the branch's answer rests on (see [`bounds_reached`]).
    pub fn with_bounds(
        mut self,
        b: &pim_fit::BranchReport,
        settings: &pim_fit::FitSettings,
        set_by_case: &dyn Fn(pim_fit::SearchBound) -> bool,
    ) -> Self {
        self.bounds_reached = bounds_reached(b, settings, set_by_case);
        self
    }

    /// True when the answer rests on a bound that no one set for this crash.
    pub fn rests_on_default_bound(&self) -> bool {
        self.bounds_reached
            .iter()
            .any(|b| b.source == BoundSource::Default)
    }
}

/// The JSON of `pim fit`.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct FitOut {
    /// The units of the document's numbers (always SI; see [`SiUnits`]).
    pub units: SiUnits,
    /// The model fitted: `pim` or `tangential`.
    pub model: &'static str,
    /// `q1`, `q2`, `q3` or `custom`.
    pub cost_function: String,
    /// One record per branch.
    pub branches: Vec<BranchRecord>,
    /// The optimal branch with the lower cost.
    pub best: Option<pim_fit::MomentBranch>,
    /// Remarks on the whole fit.
    pub notes: Vec<String>,
    /// Which side of the crush surface vehicle 1 lies on at the case's geometry.
    pub side: SideOut,
    /// The damage (with `[damage]`): the crush at the fit's answer, and the fit with the crush
    /// energy as evidence.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub damage: Option<crate::damage_fit::FitDamage>,
}

/// Which side of the crush surface vehicle 1 lies on (the vehicles approach when the normal
/// relative velocity at C points the other way), and what that rests on.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct SideOut {
    /// `+n` or `-n` (n at the crush angle), `undecided` when nothing says.
    pub vehicle1: &'static str,
    /// `geometry` (the CGs on opposite sides of the crush plane), `mobility` (both on one side:
    /// read from their heights weighted by mobility) or `case` (`[impact] vehicle1_side`).
    pub basis: pim_core::SideBasis,
    /// Heights of vehicle 1's and vehicle 2's CG above the crush plane through C, along n, m.
    pub cg_heights: [f64; 2],
}

impl SideOut {
    /// The side of `impact`.
    pub fn of(impact: &pim_core::Impact) -> Self {
        let s = impact.side();
        SideOut {
            vehicle1: if s > 0.0 {
                "+n"
            } else if s < 0.0 {
                "-n"
            } else {
                "undecided"
            },
            basis: impact.side_basis(),
            cg_heights: impact.cg_heights(),
        }
    }
}

/// The second model's part of a solve document.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct ModelOut {
    /// The model's name (`tangential`, `impc`).
    pub name: &'static str,
    /// What the model is, in a line.
    pub description: &'static str,
    /// Its coefficients by name (e, et, friction; IMPC: e, friction).
    pub coefficients: std::collections::BTreeMap<&'static str, f64>,
    /// `stick` or `slide`.
    pub mode: pim_core::ContactMode,
    /// The impulse ratio Pt / Pn that acted.
    pub impulse_ratio: f64,
    /// The impulse ratio sticking would need.
    pub stick_ratio: f64,
}
