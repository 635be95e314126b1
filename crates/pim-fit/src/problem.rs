//! The fit problem: what is known, estimated or observed, and the settings of the search.

use crate::error::{FitError, Result};
use nalgebra::SVector;
use pim_core::{Impact, VehicleId, Velocities};
use serde::{Deserialize, Serialize};
use std::fmt;

/// A vector over the twelve velocity components
/// `U = (v1x, v1y, w1, v2x, v2y, w2, V1x, V1y, W1, V2x, V2y, W2)`.
pub type Vector12 = SVector<f64, 12>;

/// Names of the twelve components of U, in order.
pub const COMPONENT_NAMES: [&str; 12] = [
    "initial.vehicle1.vx",
    "initial.vehicle1.vy",
    "initial.vehicle1.omega",
    "initial.vehicle2.vx",
    "initial.vehicle2.vy",
    "initial.vehicle2.omega",
    "final.vehicle1.vx",
    "final.vehicle1.vy",
    "final.vehicle1.omega",
    "final.vehicle2.vx",
    "final.vehicle2.vy",
    "final.vehicle2.omega",
];

/// One of the twelve components of U, by index (0..12). Displayed and serialised by its name
/// (`initial.vehicle1.vx`, ...).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Component(pub usize);

impl Component {
    /// The component's name.
    pub fn name(self) -> &'static str {
        COMPONENT_NAMES[self.0]
    }

    /// True for a yaw rate (rad/s), false for a linear velocity (m/s).
    pub fn is_yaw_rate(self) -> bool {
        self.0 % 3 == 2
    }

    /// True for a component of the contact state, false for the separation state.
    pub fn is_initial(self) -> bool {
        self.0 < 6
    }
}

impl fmt::Display for Component {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

pim_core::json_schema_as!(Component, {
    "type": "string",
    "description": "A velocity component, by its path in the case file.",
    "enum": COMPONENT_NAMES
});

impl Serialize for Component {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// What is known about one velocity component.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Knowledge {
    /// Known exactly: held fixed at this value (m/s or rad/s).
    Known {
        /// The value.
        value: f64,
    },
    /// Estimated: the cost contains `weight (U_k - value)^2`.
    Estimated {
        /// The estimate.
        value: f64,
        /// Confidence weight in (0, 1].
        weight: f64,
    },
    /// Nothing known: free, subject only to the equations and bounds.
    Unknown,
}

/// The cost-function presets of Vossou & Koulocheris (eq. 9-11).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum CostPreset {
    /// Separation velocities known exactly, contact velocities estimated.
    Q1,
    /// Contact velocities known exactly, separation velocities estimated (Brach's fits).
    Q2,
    /// Everything estimated.
    Q3,
}

impl CostPreset {
    /// All three presets.
    pub const ALL: [CostPreset; 3] = [CostPreset::Q1, CostPreset::Q2, CostPreset::Q3];

    /// Lower-case name (`q1`, `q2`, `q3`).
    pub fn name(self) -> &'static str {
        match self {
            CostPreset::Q1 => "q1",
            CostPreset::Q2 => "q2",
            CostPreset::Q3 => "q3",
        }
    }

    /// What the preset holds and estimates, in a line.
    pub fn description(self) -> &'static str {
        match self {
            CostPreset::Q1 => "Separation velocities known, contact velocities estimated",
            CostPreset::Q2 => "Contact velocities known, separation velocities estimated",
            CostPreset::Q3 => "All twelve estimated",
        }
    }

    /// Whether the preset holds component k of U fixed at its estimate (the one place this rule
    /// is written): Q1 the separation state, Q2 the contact state, Q3 nothing.
    pub fn holds_fixed(self, k: usize) -> bool {
        match self {
            CostPreset::Q1 => k >= 6,
            CostPreset::Q2 => k < 6,
            CostPreset::Q3 => false,
        }
    }

    /// Builds the component knowledge from estimates of both states and weights (1 when `None`).
    pub fn knowledge(
        self,
        initial: &Velocities,
        separation: &Velocities,
        weights: Option<&[f64; 12]>,
    ) -> [Knowledge; 12] {
        let u = state_vector(initial, separation);
        std::array::from_fn(|k| {
            if self.holds_fixed(k) {
                Knowledge::Known { value: u[k] }
            } else {
                Knowledge::Estimated {
                    value: u[k],
                    weight: weights.map_or(1.0, |w| w[k]),
                }
            }
        })
    }
}

/// U from the two states.
pub fn state_vector(initial: &Velocities, separation: &Velocities) -> Vector12 {
    let mut u = Vector12::zeros();
    u.fixed_rows_mut::<6>(0).copy_from(&initial.to_vector());
    u.fixed_rows_mut::<6>(6).copy_from(&separation.to_vector());
    u
}

/// What an observation measures (all linear in U).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ObservationKind {
    /// Velocity change along the vehicle's forward axis, m/s (what an EDR records).
    DeltaVLongitudinal,
    /// Velocity change along the vehicle's left axis, m/s.
    DeltaVLateral,
    /// Velocity at contact along the vehicle's forward axis (pre-impact speed), m/s.
    SpeedAlongHeading,
    /// Velocity at contact along the vehicle's left axis (0 when it moved straight), m/s.
    LateralVelocity,
}

impl ObservationKind {
    /// Its name as a case file writes it (`speed_along_heading`, ...).
    pub fn name(self) -> &'static str {
        match self {
            ObservationKind::DeltaVLongitudinal => "delta_v_longitudinal",
            ObservationKind::DeltaVLateral => "delta_v_lateral",
            ObservationKind::SpeedAlongHeading => "speed_along_heading",
            ObservationKind::LateralVelocity => "lateral_velocity",
        }
    }

    /// Whether the observed quantity lies across the vehicle (its sign follows the side the
    /// lateral axis points to, and changes with a mirrored frame).
    pub fn is_lateral(self) -> bool {
        matches!(
            self,
            ObservationKind::DeltaVLateral | ObservationKind::LateralVelocity
        )
    }
}

/// An observation: a linear function of U with a target and a weight.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Observation {
    /// What is observed.
    pub kind: ObservationKind,
    /// Of which vehicle.
    pub vehicle: VehicleId,
    /// The observed value, m/s.
    pub value: f64,
    /// Weight in (0, 1].
    pub weight: f64,
}

/// The forward axis of a vehicle in the fixed frame: vehicle 2 heads along theta2; in the papers'
/// convention (impact centre at `r1 = -(D4, D3)`) vehicle 1's forward direction is theta1 + 180 deg,
/// as every RICSAC vehicle 1 confirms by moving along it.
pub fn forward_axis(impact: &Impact, vehicle: VehicleId) -> [f64; 2] {
    impact.forward_axis(vehicle)
}

impl Observation {
    /// The observation as a row over U: `value = row . U`.
    pub fn row(&self, impact: &Impact) -> Vector12 {
        let f = forward_axis(impact, self.vehicle);
        let left = [-f[1], f[0]];
        let axis = match self.kind {
            ObservationKind::DeltaVLongitudinal | ObservationKind::SpeedAlongHeading => f,
            ObservationKind::DeltaVLateral | ObservationKind::LateralVelocity => left,
        };
        let base = 3 * self.vehicle.index();
        let mut row = Vector12::zeros();
        match self.kind {
            ObservationKind::DeltaVLongitudinal | ObservationKind::DeltaVLateral => {
                row[base] = -axis[0];
                row[base + 1] = -axis[1];
                row[6 + base] = axis[0];
                row[6 + base + 1] = axis[1];
            }
            ObservationKind::SpeedAlongHeading | ObservationKind::LateralVelocity => {
                row[base] = axis[0];
                row[base + 1] = axis[1];
            }
        }
        row
    }
}

/// Any linear combination of the twelve components as evidence: the cost holds
/// `weight (row . U - value)^2`. This is how evidence that is not itself a velocity enters a
/// fit to first order (e.g. a rest position, through the derivatives of a run-out with respect
/// to the separation velocities).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Combination {
    /// The coefficients over U (units: the value's unit per m/s or per rad/s).
    pub row: Vector12,
    /// The target of `row . U`.
    pub value: f64,
    /// Weight in (0, 1].
    pub weight: f64,
}

/// A fit problem: the collision, what is known of each velocity component, extra observations.
#[derive(Debug, Clone, PartialEq)]
pub struct FitProblem {
    /// The checked collision.
    pub impact: Impact,
    /// Knowledge of each component of U.
    pub components: [Knowledge; 12],
    /// Extra linear observations.
    pub observations: Vec<Observation>,
    /// Linear combinations of the components as evidence (none in a fit of velocity estimates).
    pub combinations: Vec<Combination>,
}

impl FitProblem {
    /// A problem from a cost preset and estimates of both states (weights default to 1).
    pub fn from_preset(
        impact: Impact,
        preset: CostPreset,
        initial: &Velocities,
        separation: &Velocities,
        weights: Option<&[f64; 12]>,
    ) -> Self {
        FitProblem {
            impact,
            components: preset.knowledge(initial, separation, weights),
            observations: Vec::new(),
            combinations: Vec::new(),
        }
    }

    /// The problem as the search sees it: against a barrier, vehicle 2 is at rest, so its
    /// components are held at 0 in one state (the one whose vehicle-1 components are all held
    /// fixed, else the contact state); the equations (`V2 = v2`) hold them in the other.
    /// Non-zero values or observations of a barrier are refused.
    pub fn normalised(&self) -> Result<FitProblem> {
        let mut p = self.clone();
        if !p.impact.is_barrier() {
            return Ok(p);
        }
        for k in [3, 4, 5, 9, 10, 11] {
            match p.components[k] {
                Knowledge::Unknown => {}
                // Zero is what a barrier is (from_preset with a state at rest gives it).
                Knowledge::Known { value } | Knowledge::Estimated { value, .. } if value == 0.0 => {
                }
                _ => {
                    return Err(FitError::Barrier(format!(
                        "{} is given, but vehicle 2 is a fixed barrier at rest: leave its \
                         velocities out",
                        COMPONENT_NAMES[k]
                    )))
                }
            }
        }
        let of_two = |c: &Combination| [3, 4, 5, 9, 10, 11].iter().any(|&k| c.row[k] != 0.0);
        if p.observations.iter().any(|o| o.vehicle == VehicleId::Two)
            || p.combinations.iter().any(of_two)
        {
            return Err(FitError::Barrier(
                "an observation of vehicle 2, which is a fixed barrier".into(),
            ));
        }
        let held = |r: std::ops::Range<usize>| {
            p.components[r]
                .iter()
                .all(|c| matches!(c, Knowledge::Known { .. }))
        };
        let base = if held(6..9) && !held(0..3) { 9 } else { 3 };
        for k in [3, 4, 5, 9, 10, 11] {
            p.components[k] = if (base..base + 3).contains(&k) {
                Knowledge::Known { value: 0.0 }
            } else {
                Knowledge::Unknown
            };
        }
        Ok(p)
    }

    /// Every weight of the problem, to read or rescale: the estimated components', the
    /// observations', the combinations'.
    pub fn weights_mut(&mut self) -> impl Iterator<Item = &mut f64> {
        let components = self.components.iter_mut().filter_map(|c| match c {
            Knowledge::Estimated { weight, .. } => Some(weight),
            _ => None,
        });
        components
            .chain(self.observations.iter_mut().map(|o| &mut o.weight))
            .chain(self.combinations.iter_mut().map(|c| &mut c.weight))
    }

    /// Checks values and weights.
    pub fn check(&self) -> Result<()> {
        let mut anything = false;
        for (k, c) in self.components.iter().enumerate() {
            match *c {
                Knowledge::Known { value } => finite(COMPONENT_NAMES[k], value)?,
                Knowledge::Estimated { value, weight } => {
                    finite(COMPONENT_NAMES[k], value)?;
                    check_weight(COMPONENT_NAMES[k], weight)?;
                    anything = true;
                }
                Knowledge::Unknown => {}
            }
        }
        for (i, o) in self.observations.iter().enumerate() {
            let what = format!("observation {} ({:?} of {})", i + 1, o.kind, o.vehicle);
            finite(&what, o.value)?;
            check_weight(&what, o.weight)?;
            anything = true;
        }
        for (i, c) in self.combinations.iter().enumerate() {
            let what = format!("combination {}", i + 1);
            finite(&what, c.value)?;
            if c.row.iter().any(|x| !x.is_finite()) || c.row.iter().all(|x| *x == 0.0) {
                return Err(FitError::NonFinite {
                    what: format!("{what}: its row"),
                    value: c.row.amax(),
                });
            }
            check_weight(&what, c.weight)?;
            anything = true;
        }
        let fixed_initial = self.components[..6]
            .iter()
            .filter(|c| matches!(c, Knowledge::Known { .. }))
            .count();
        let fixed_final = self.components[6..]
            .iter()
            .filter(|c| matches!(c, Knowledge::Known { .. }))
            .count();
        if fixed_initial + fixed_final > 6 {
            return Err(FitError::OverDetermined(format!(
                "{fixed_initial} contact and {fixed_final} separation components are held fixed; \
                 the six equations leave only six degrees of freedom, so at most six components \
                 can be known exactly (make the others estimates)"
            )));
        }
        if !anything {
            return Err(FitError::NothingToFit);
        }
        Ok(())
    }
}

fn finite(what: &str, value: f64) -> Result<()> {
    if value.is_finite() && value.abs() <= pim_core::MAX_SPEED {
        Ok(())
    } else {
        Err(FitError::NonFinite {
            what: what.to_string(),
            value,
        })
    }
}

fn check_weight(what: &str, w: f64) -> Result<()> {
    if w.is_finite() && w > 0.0 && w <= 1.0 {
        Ok(())
    } else {
        Err(FitError::BadWeight {
            what: what.to_string(),
            value: w,
        })
    }
}

/// The moment-coefficient branches (Brach 1984 Table 1 A and B).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum MomentBranch {
    /// e_m free in [-1, 0] (a moment impulse acts at the impact centre).
    Free,
    /// e_m = 1 (no moment impulse).
    Zero,
}

impl MomentBranch {
    /// Both branches.
    pub const ALL: [MomentBranch; 2] = [MomentBranch::Free, MomentBranch::Zero];

    /// `free` or `zero`.
    pub fn name(self) -> &'static str {
        match self {
            MomentBranch::Free => "free",
            MomentBranch::Zero => "zero",
        }
    }

    /// What the branch holds e_m to, in a line.
    pub fn description(self) -> &'static str {
        match self {
            MomentBranch::Free => "em in [-1, 0]",
            MomentBranch::Zero => "em = 1 (no moment impulse)",
        }
    }
}

impl std::str::FromStr for CostPreset {
    type Err = pim_core::UnknownName;
    /// By [`CostPreset::name`]; the error lists the accepted names.
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        pim_core::parse_name(s, &Self::ALL, Self::name)
    }
}

impl std::str::FromStr for MomentBranch {
    type Err = pim_core::UnknownName;
    /// By [`MomentBranch::name`]; the error lists the accepted names.
    fn from_str(s: &str) -> std::result::Result<Self, Self::Err> {
        pim_core::parse_name(s, &Self::ALL, Self::name)
    }
}
