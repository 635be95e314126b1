//! The error type of pim-core.

use std::fmt;

/// Which of the two vehicles a message is about.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
pub enum VehicleId {
    /// Vehicle 1 (the papers' vehicle A).
    One,
    /// Vehicle 2 (the papers' vehicle B).
    Two,
}

impl VehicleId {
    /// Index 0 or 1, for arrays of two vehicles.
    pub fn index(self) -> usize {
        match self {
            VehicleId::One => 0,
            VehicleId::Two => 1,
        }
    }

    /// The vehicle with the given index (0 or 1).
    pub fn from_index(i: usize) -> Self {
        if i == 0 {
            VehicleId::One
        } else {
            VehicleId::Two
        }
    }
}

impl fmt::Display for VehicleId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            VehicleId::One => write!(f, "vehicle1"),
            VehicleId::Two => write!(f, "vehicle2"),
        }
    }
}

/// One of the six impact equations (numbered as in Brach 1983 and in this crate's documentation).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Equation {
    /// (1) conservation of linear momentum along x.
    MomentumX,
    /// (2) conservation of linear momentum along y.
    MomentumY,
    /// (3) conservation of angular momentum.
    AngularMomentum,
    /// (4) restitution normal to the crush surface.
    Restitution,
    /// (5) tangential impulse = mu' x normal impulse (sliding).
    Friction,
    /// (5a) no relative tangential velocity at separation (no slip).
    NoSlip,
    /// (6) moment restitution.
    MomentRestitution,
}

impl Equation {
    /// The equation's number in the papers ("1" .. "6", "5a").
    pub fn number(self) -> &'static str {
        match self {
            Equation::MomentumX => "1",
            Equation::MomentumY => "2",
            Equation::AngularMomentum => "3",
            Equation::Restitution => "4",
            Equation::Friction => "5",
            Equation::NoSlip => "5a",
            Equation::MomentRestitution => "6",
        }
    }

    /// A short human-readable name.
    pub fn name(self) -> &'static str {
        match self {
            Equation::MomentumX => "momentum along x",
            Equation::MomentumY => "momentum along y",
            Equation::AngularMomentum => "angular momentum",
            Equation::Restitution => "restitution",
            Equation::Friction => "friction (sliding)",
            Equation::NoSlip => "no slip",
            Equation::MomentRestitution => "moment restitution",
        }
    }
}

impl fmt::Display for Equation {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "equation {} ({})", self.number(), self.name())
    }
}

/// Everything that can go wrong in pim-core. Every variant names the culprit.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum PimError {
    /// A vehicle property or velocity is NaN or infinite.
    #[error("{vehicle}.{field} is not a finite number (got {value})")]
    NonFinite {
        /// The vehicle the field belongs to.
        vehicle: VehicleId,
        /// The field's name as in the case file.
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A value that is not attached to one vehicle (crush angle, a coefficient) is not finite.
    #[error("{field} is not a finite number (got {value})")]
    NonFiniteValue {
        /// The field's name as in the case file.
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// Mass or yaw inertia is zero or negative.
    #[error("{vehicle}.{field} must be greater than 0 (got {value})")]
    NotPositive {
        /// The vehicle the field belongs to.
        vehicle: VehicleId,
        /// `mass` or `yaw_inertia`.
        field: &'static str,
        /// The offending value.
        value: f64,
    },
    /// The distance from the CG to the impact centre is negative.
    #[error("{vehicle}.d must be 0 or more (got {value} m)")]
    NegativeDistance {
        /// The vehicle.
        vehicle: VehicleId,
        /// The offending value, m.
        value: f64,
    },
    /// A coefficient lies outside the domain of the model.
    #[error("{name} = {value} is outside its domain: {domain}")]
    CoefficientOutOfRange {
        /// `e`, `mu` or `em`.
        name: &'static str,
        /// The offending value.
        value: f64,
        /// The admissible set, in words.
        domain: &'static str,
    },
    /// The relative velocity of the two vehicles at the impact centre does not close the gap.
    #[error(
        "the vehicles do not approach each other at the impact centre: the normal relative \
         velocity there is {normal_velocity:.4} m/s, {direction} (no impact)"
    )]
    NotApproaching {
        /// Normal relative velocity vn at contact, m/s (vehicle 1 minus vehicle 2, along n).
        normal_velocity: f64,
        /// Words saying which way the vehicles move.
        direction: &'static str,
    },
    /// The six equations are linearly dependent for these inputs.
    #[error("the impact equations are singular: {equation} degenerates ({hint})")]
    Singular {
        /// The equation that carries the dependency.
        equation: Equation,
        /// What makes it degenerate, in words.
        hint: String,
    },
    /// Solving backwards, no friction direction is consistent with the recovered contact velocities.
    #[error("{0}")]
    InconsistentSliding(String),
    /// A barrier given inconsistently (only vehicle 2 can be one, with infinite mass and
    /// inertia, at rest).
    #[error("{0}")]
    Barrier(String),
    /// A sensitivity study asked for a coefficient level outside the model's domain.
    #[error(
        "sensitivity level {name} x {factor} = {value} is outside its domain {domain}; \
         use a smaller percentage"
    )]
    SensitivityLevelOutOfRange {
        /// `e` or `em`.
        name: &'static str,
        /// The factor (1 - p or 1 + p).
        factor: f64,
        /// The resulting coefficient value.
        value: f64,
        /// The admissible set, in words.
        domain: &'static str,
    },
    /// A value is finite but beyond any plausible size (it would overflow the arithmetic).
    #[error("{what} = {value} is beyond the plausible range (|value| <= {limit} {unit})")]
    Implausible {
        /// The field.
        what: String,
        /// The offending value.
        value: f64,
        /// The largest accepted magnitude.
        limit: f64,
        /// Its unit.
        unit: &'static str,
    },
    /// The sensitivity percentage is not a finite number in [0, 100).
    #[error("the sensitivity percentage must be a finite number in [0, 100) (got {0})")]
    BadPercentage(f64),

    /// The model cannot do what was asked (e.g. solve backwards).
    #[error("{0}")]
    Unsupported(String),
}

/// Result alias of pim-core.
pub type Result<T> = std::result::Result<T, PimError>;
