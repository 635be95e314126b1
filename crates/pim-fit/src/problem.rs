//! The fit problem: what is known, estimated or observed, and the settings of the search.

use crate::error::{FitError, Result};
use nalgebra::SVector;
use pim_core::{Impact, MomentForm, VehicleId, Velocities};
use serde::{Deserialize, Serialize};

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

/// What is known about one velocity component.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
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

    /// Builds the component knowledge from estimates of both states and weights (1 when `None`).
    pub fn knowledge(
        self,
        initial: &Velocities,
        separation: &Velocities,
        weights: Option<&[f64; 12]>,
    ) -> [Knowledge; 12] {
        let u = state_vector(initial, separation);
        let mut out = [Knowledge::Unknown; 12];
        for (k, slot) in out.iter_mut().enumerate() {
            let weight = weights.map_or(1.0, |w| w[k]);
            let estimated = Knowledge::Estimated {
                value: u[k],
                weight,
            };
            let known = Knowledge::Known { value: u[k] };
            *slot = match (self, k < 6) {
                (CostPreset::Q1, true) | (CostPreset::Q2, false) | (CostPreset::Q3, _) => estimated,
                (CostPreset::Q1, false) | (CostPreset::Q2, true) => known,
            };
        }
        out
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
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

/// An observation: a linear function of U with a target and a weight.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
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
    let c = impact.collision();
    let (theta, flip) = match vehicle {
        VehicleId::One => (c.vehicle1.heading, -1.0),
        VehicleId::Two => (c.vehicle2.heading, 1.0),
    };
    let (s, co) = theta.to_radians().sin_cos();
    [flip * co, flip * s]
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

/// A fit problem: the collision, what is known of each velocity component, extra observations.
#[derive(Debug, Clone, PartialEq)]
pub struct FitProblem {
    /// The checked collision.
    pub impact: Impact,
    /// Knowledge of each component of U.
    pub components: [Knowledge; 12],
    /// Extra linear observations.
    pub observations: Vec<Observation>,
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
        }
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
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
}

/// Settings of a fit, before checking.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FitSettings {
    /// Range of e (default [0, 0.2]).
    pub e: [f64; 2],
    /// Range of mu (default [-1.2, 1.2]); mu must also lie between 0 and mu_max.
    pub mu: [f64; 2],
    /// Bound on every linear velocity component, m/s (default 20).
    pub velocity_bound: f64,
    /// Bound on every yaw rate, rad/s (default 5).
    pub yaw_rate_bound: f64,
    /// Form of the moment equation (default corrected).
    pub moment_form: MomentForm,
    /// Branches to fit (default both).
    pub branches: Vec<MomentBranch>,
    /// Grid resolution of the global search: points along e, mu and em.
    pub grid: [usize; 3],
    /// Relative cost tolerance of the identifiability ranges (default 0.01 = 1 %).
    pub identifiability_tolerance: f64,
}

impl Default for FitSettings {
    fn default() -> Self {
        FitSettings {
            e: [0.0, 0.2],
            mu: [-1.2, 1.2],
            velocity_bound: 20.0,
            yaw_rate_bound: 5.0,
            moment_form: MomentForm::Corrected,
            branches: MomentBranch::ALL.to_vec(),
            grid: [5, 17, 6],
            identifiability_tolerance: 0.01,
        }
    }
}

/// Settings that passed [`FitSettings::check`].
#[derive(Debug, Clone, PartialEq)]
pub struct ValidSettings(pub(crate) FitSettings);

impl ValidSettings {
    /// The settings.
    pub fn get(&self) -> &FitSettings {
        &self.0
    }
}

impl FitSettings {
    /// Checks the settings once, so that a fit only runs on valid ones.
    pub fn check(self) -> Result<ValidSettings> {
        let [elo, ehi] = self.e;
        if !(elo.is_finite() && ehi.is_finite() && 0.0 <= elo && elo <= ehi && ehi <= 1.0) {
            return Err(FitError::BadBounds(format!(
                "e = [{elo}, {ehi}] must satisfy 0 <= low <= high <= 1"
            )));
        }
        let [mlo, mhi] = self.mu;
        if !(mlo.is_finite() && mhi.is_finite() && mlo <= mhi && mlo >= -100.0 && mhi <= 100.0) {
            return Err(FitError::BadBounds(format!(
                "mu = [{mlo}, {mhi}] must satisfy -100 <= low <= high <= 100"
            )));
        }
        for (name, b, limit) in [
            ("velocity_bound", self.velocity_bound, pim_core::MAX_SPEED),
            (
                "yaw_rate_bound",
                self.yaw_rate_bound,
                pim_core::MAX_YAW_RATE,
            ),
        ] {
            if !(b.is_finite() && b > 0.0 && b <= limit) {
                return Err(FitError::BadBounds(format!(
                    "{name} = {b} must be > 0 and <= {limit}"
                )));
            }
        }
        if self.branches.is_empty() {
            return Err(FitError::BadBounds("no moment branch selected".into()));
        }
        if self.grid.iter().any(|&n| !(2..=400).contains(&n)) {
            return Err(FitError::BadBounds(format!(
                "grid {:?}: each count must be between 2 and 400",
                self.grid
            )));
        }
        let t = self.identifiability_tolerance;
        if !(t.is_finite() && t > 0.0) {
            return Err(FitError::BadBounds(format!(
                "identifiability_tolerance = {t} must be > 0"
            )));
        }
        Ok(ValidSettings(self))
    }
}
