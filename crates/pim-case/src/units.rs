//! Units: the `[units]` section of a case file (input) and the unit systems of printed tables
//! (output). Everything inside the toolkit is SI (kg, kg m^2, m, m/s, rad/s, J); conversions
//! happen only here, at the edge.

use serde::{Deserialize, Serialize};

/// Metres per foot (exact).
pub const FOOT: f64 = 0.3048;
/// Kilograms per pound (avoirdupois, exact).
pub const POUND: f64 = 0.453_592_37;
/// Metres per second per mile per hour (exact).
pub const MPH: f64 = 0.447_04;
/// Metres per second per kilometre per hour.
pub const KMH: f64 = 1.0 / 3.6;
/// Newtons per pound-force (exact).
pub const POUND_FORCE: f64 = 4.448_221_615_260_5;
/// Kilograms per slug (one pound-force second squared per foot).
pub const SLUG: f64 = POUND_FORCE / FOOT;

/// Speed unit of a case file.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum SpeedUnit {
    /// Metres per second (default).
    #[default]
    #[serde(rename = "m/s")]
    MetresPerSecond,
    /// Kilometres per hour.
    #[serde(rename = "km/h")]
    KilometresPerHour,
    /// Miles per hour.
    #[serde(rename = "mph")]
    MilesPerHour,
}

impl SpeedUnit {
    /// m/s per unit.
    pub fn to_si(self) -> f64 {
        match self {
            SpeedUnit::MetresPerSecond => 1.0,
            SpeedUnit::KilometresPerHour => KMH,
            SpeedUnit::MilesPerHour => MPH,
        }
    }
}

/// Length unit of a case file.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum LengthUnit {
    /// Metres (default).
    #[default]
    #[serde(rename = "m")]
    Metre,
    /// Feet.
    #[serde(rename = "ft")]
    Foot,
}

impl LengthUnit {
    /// m per unit.
    pub fn to_si(self) -> f64 {
        match self {
            LengthUnit::Metre => 1.0,
            LengthUnit::Foot => FOOT,
        }
    }

    /// Its symbol (`m`, `ft`).
    pub fn label(self) -> &'static str {
        match self {
            LengthUnit::Metre => "m",
            LengthUnit::Foot => "ft",
        }
    }
}

/// Mass unit of a case file (`lb` is the pound mass: a vehicle's weight in pounds).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum MassUnit {
    /// Kilograms (default).
    #[default]
    #[serde(rename = "kg")]
    Kilogram,
    /// Pounds (mass).
    #[serde(rename = "lb")]
    Pound,
}

impl MassUnit {
    /// kg per unit.
    pub fn to_si(self) -> f64 {
        match self {
            MassUnit::Kilogram => 1.0,
            MassUnit::Pound => POUND,
        }
    }
}

/// Yaw-inertia unit of a case file.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum InertiaUnit {
    /// kg m^2 (default).
    #[default]
    #[serde(rename = "kg m^2")]
    KilogramMetreSquared,
    /// slug ft^2 (= lbf ft s^2, the unit of US vehicle data sheets).
    #[serde(rename = "slug ft^2", alias = "lb ft s^2", alias = "lbf ft s^2")]
    SlugFootSquared,
}

impl InertiaUnit {
    /// kg m^2 per unit.
    pub fn to_si(self) -> f64 {
        match self {
            InertiaUnit::KilogramMetreSquared => 1.0,
            InertiaUnit::SlugFootSquared => SLUG * FOOT * FOOT,
        }
    }
}

/// Yaw-rate unit of a case file.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum YawRateUnit {
    /// Radians per second (default).
    #[default]
    #[serde(rename = "rad/s")]
    RadiansPerSecond,
    /// Degrees per second.
    #[serde(rename = "deg/s")]
    DegreesPerSecond,
}

impl YawRateUnit {
    /// rad/s per unit.
    pub fn to_si(self) -> f64 {
        match self {
            YawRateUnit::RadiansPerSecond => 1.0,
            YawRateUnit::DegreesPerSecond => std::f64::consts::PI / 180.0,
        }
    }
}

/// Unit of the stiffness coefficients (`[units] stiffness`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
pub enum StiffnessUnit {
    /// A in N/m, B in N/m^2 (default).
    #[default]
    #[serde(rename = "N/m")]
    NewtonPerMetre,
    /// A in N/cm, B in N/cm^2 (the unit of Neades' RICSAC table).
    #[serde(rename = "N/cm")]
    NewtonPerCentimetre,
    /// A in lbf/in, B in lbf/in^2 (CRASH3's tables).
    #[serde(rename = "lbf/in")]
    PoundPerInch,
}

impl StiffnessUnit {
    /// The length of the unit, m (A per unit: force / that length; B: force / its square).
    fn length(self) -> f64 {
        match self {
            StiffnessUnit::NewtonPerMetre => 1.0,
            StiffnessUnit::NewtonPerCentimetre => 0.01,
            StiffnessUnit::PoundPerInch => 0.0254,
        }
    }

    fn force(self) -> f64 {
        match self {
            StiffnessUnit::PoundPerInch => POUND_FORCE,
            _ => 1.0,
        }
    }

    /// N/m per unit of A.
    pub fn a_to_si(self) -> f64 {
        self.force() / self.length()
    }

    /// N/m^2 per unit of B.
    pub fn b_to_si(self) -> f64 {
        self.force() / (self.length() * self.length())
    }
}

/// Unit of crush depths, damage widths and offsets (`[units] crush`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub enum CrushUnit {
    /// Metres.
    #[serde(rename = "m")]
    Metre,
    /// Centimetres.
    #[serde(rename = "cm")]
    Centimetre,
    /// Millimetres.
    #[serde(rename = "mm")]
    Millimetre,
    /// Inches.
    #[serde(rename = "in")]
    Inch,
    /// Feet.
    #[serde(rename = "ft")]
    Foot,
}

impl CrushUnit {
    /// m per unit.
    pub fn to_si(self) -> f64 {
        match self {
            CrushUnit::Metre => 1.0,
            CrushUnit::Centimetre => 0.01,
            CrushUnit::Millimetre => 0.001,
            CrushUnit::Inch => 0.0254,
            CrushUnit::Foot => FOOT,
        }
    }
}

/// `[units]` of a case file: the unit of every number of its kind in the file. Angles are
/// always degrees; coefficients and weights have no unit.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(deny_unknown_fields)]
pub struct UnitsSection {
    /// Velocities, delta-V observations and the velocity bound: `m/s`, `km/h` or `mph`.
    #[serde(default)]
    pub speed: SpeedUnit,
    /// Distances (`d`, `impact_point`, `length`, `width`, `cg_to_front`): `m` or `ft`.
    #[serde(default)]
    pub length: LengthUnit,
    /// Masses: `kg` or `lb`.
    #[serde(default)]
    pub mass: MassUnit,
    /// Yaw inertias: `kg m^2` or `slug ft^2`.
    #[serde(default)]
    pub yaw_inertia: InertiaUnit,
    /// Yaw rates (`omega`, the yaw-rate bound): `rad/s` or `deg/s`.
    #[serde(default)]
    pub yaw_rate: YawRateUnit,
    /// Crush stiffness A and B (`[damage]`): `N/m` (N/m, N/m^2), `N/cm` (N/cm, N/cm^2) or
    /// `lbf/in` (lbf/in, lbf/in^2).
    #[serde(default)]
    pub stiffness: StiffnessUnit,
    /// Crush depths, damage widths and offsets (`[damage]`): `m`, `cm`, `mm`, `in` or `ft`
    /// (default: the length unit).
    #[serde(default)]
    pub crush: Option<CrushUnit>,
}

/// A unit as the file writes it (`"slug ft^2"`, `"mph"`).
pub(crate) fn unit_label<T: serde::Serialize>(u: T) -> String {
    toml::Value::try_from(u)
        .ok()
        .and_then(|v| v.as_str().map(str::to_string))
        .unwrap_or_default()
}

impl UnitsSection {
    /// The units in a line: `speed mph, length ft, mass lb, yaw inertia slug ft^2, yaw rate
    /// deg/s`.
    pub fn describe(&self) -> String {
        let v = toml::Value::try_from(self).ok();
        let name = |k: &str| {
            v.as_ref()
                .and_then(|v| v.get(k))
                .and_then(|x| x.as_str())
                .unwrap_or("?")
                .to_string()
        };
        format!(
            "speed {}, length {}, mass {}, yaw inertia {}, yaw rate {}",
            name("speed"),
            name("length"),
            name("mass"),
            name("yaw_inertia"),
            name("yaw_rate")
        )
    }
}

/// The unit system of printed tables (`--units`). JSON and CSV output stay SI.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum UnitSystem {
    /// m/s, m, kg, rad/s.
    #[default]
    Si,
    /// mph, ft, lb, deg/s.
    Us,
    /// km/h, m, kg, deg/s.
    Kmh,
}

impl UnitSystem {
    /// The system a case's `[units]` reads in, by its speed unit (mph: US; km/h: km/h; else SI).
    pub fn of(units: &UnitsSection) -> Self {
        match units.speed {
            SpeedUnit::MilesPerHour => UnitSystem::Us,
            SpeedUnit::KilometresPerHour => UnitSystem::Kmh,
            _ => UnitSystem::Si,
        }
    }

    /// A speed in m/s in this system, and its label.
    pub fn speed(self, v: f64) -> f64 {
        match self {
            UnitSystem::Si => v,
            UnitSystem::Us => v / MPH,
            UnitSystem::Kmh => v / KMH,
        }
    }

    /// Label of speeds.
    pub fn speed_label(self) -> &'static str {
        match self {
            UnitSystem::Si => "m/s",
            UnitSystem::Us => "mph",
            UnitSystem::Kmh => "km/h",
        }
    }

    /// A length in m in this system.
    pub fn length(self, x: f64) -> f64 {
        match self {
            UnitSystem::Us => x / FOOT,
            _ => x,
        }
    }

    /// Label of lengths.
    pub fn length_label(self) -> &'static str {
        match self {
            UnitSystem::Us => "ft",
            _ => "m",
        }
    }

    /// A mass in kg in this system.
    pub fn mass(self, m: f64) -> f64 {
        match self {
            UnitSystem::Us => m / POUND,
            _ => m,
        }
    }

    /// Label of masses.
    pub fn mass_label(self) -> &'static str {
        match self {
            UnitSystem::Us => "lb",
            _ => "kg",
        }
    }

    /// A yaw inertia in kg m^2 in this system (US: slug ft^2).
    pub fn yaw_inertia(self, i: f64) -> f64 {
        match self {
            UnitSystem::Us => i / InertiaUnit::SlugFootSquared.to_si(),
            _ => i,
        }
    }

    /// Label of yaw inertias.
    pub fn yaw_inertia_label(self) -> &'static str {
        match self {
            UnitSystem::Us => "slug ft^2",
            _ => "kg m^2",
        }
    }

    /// A yaw rate in rad/s in this system.
    pub fn yaw_rate(self, w: f64) -> f64 {
        match self {
            UnitSystem::Si => w,
            _ => w.to_degrees(),
        }
    }

    /// Label of yaw rates.
    pub fn yaw_rate_label(self) -> &'static str {
        match self {
            UnitSystem::Si => "rad/s",
            _ => "deg/s",
        }
    }

    /// An energy in J in this system (US: ft lbf).
    pub fn energy(self, e: f64) -> f64 {
        match self {
            UnitSystem::Us => e / (FOOT * POUND_FORCE),
            _ => e,
        }
    }

    /// Label of energies.
    pub fn energy_label(self) -> &'static str {
        match self {
            UnitSystem::Us => "ft lbf",
            _ => "J",
        }
    }

    /// An impulse in N s in this system (US: lbf s).
    pub fn impulse(self, p: f64) -> f64 {
        match self {
            UnitSystem::Us => p / POUND_FORCE,
            _ => p,
        }
    }

    /// Label of impulses (and, times a length, of moment impulses).
    pub fn impulse_label(self) -> &'static str {
        match self {
            UnitSystem::Us => "lbf s",
            _ => "N s",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn conversion_factors() {
        // 1 slug ft^2 = 1.355818 kg m^2 (NIST SP 811).
        assert!((InertiaUnit::SlugFootSquared.to_si() - 1.355_818).abs() < 1e-6);
        // 1 slug = 14.5939 kg.
        assert!((SLUG - 14.593_90).abs() < 1e-4);
        assert!((SpeedUnit::MilesPerHour.to_si() * 60.0 - 26.8224).abs() < 1e-12);
        assert!((SpeedUnit::KilometresPerHour.to_si() * 36.0 - 10.0).abs() < 1e-12);
        assert!((MassUnit::Pound.to_si() * 3000.0 - 1_360.777_11).abs() < 1e-5);
        assert!((UnitSystem::Us.speed(MPH * 30.0) - 30.0).abs() < 1e-12);
        assert!(
            (YawRateUnit::DegreesPerSecond.to_si() * 180.0 - std::f64::consts::PI).abs() < 1e-15
        );
    }
}
