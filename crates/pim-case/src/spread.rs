//! The `[uncertainty]` section of a case file: the spread of each input the fit takes as exact.

use crate::ranges::short;
use rand::Rng;
use serde::Deserialize;

/// The spread of one input: a number is the standard deviation of a normal distribution about
/// the case's value; `{ uniform = [lo, hi] }` draws uniformly between the two values.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(untagged)]
pub enum Spread {
    /// Normal, with this standard deviation (the input's unit).
    Normal(f64),
    /// Uniform between two values (the input's unit).
    Uniform {
        /// `[lo, hi]`.
        uniform: [f64; 2],
    },
}

impl Spread {
    /// The spread of `k` times the quantity (a change of unit).
    pub fn scaled(self, k: f64) -> Self {
        match self {
            Spread::Normal(s) => Spread::Normal(s * k),
            Spread::Uniform { uniform: [a, b] } => Spread::Uniform {
                uniform: [a * k, b * k],
            },
        }
    }

    /// One draw around `nominal`: a normal deviate times the standard deviation added, or a
    /// uniform value on the stated interval.
    pub fn draw(self, nominal: f64, rng: &mut impl Rng) -> f64 {
        match self {
            Spread::Normal(s) => nominal + s * standard_normal(rng),
            Spread::Uniform { uniform: [a, b] } => a + (b - a) * rng.random::<f64>(),
        }
    }

    /// Standard deviation.
    pub fn sd(self) -> f64 {
        match self {
            Spread::Normal(s) => s,
            Spread::Uniform { uniform: [a, b] } => (b - a) / 12f64.sqrt(),
        }
    }

    /// Checks the spread against the value it qualifies (in SI): a positive quantity (mass,
    /// inertia, distance) needs a standard deviation smaller than the value and a uniform range
    /// above 0; an angle a standard deviation of at most 90 deg and a range within one turn.
    /// `what` names the quantity in the message.
    pub fn check_against(
        self,
        what: &str,
        nominal: f64,
        positive: bool,
    ) -> std::result::Result<(), SpreadError> {
        self.check_own()?;
        let bad = match (positive, self) {
            (true, Spread::Normal(sigma)) => {
                (sigma >= nominal).then(|| SpreadError::WiderThanValue {
                    sigma,
                    nominal,
                    what: what.to_string(),
                })
            }
            (true, Spread::Uniform { uniform: [lo, _] }) => {
                (lo <= 0.0).then_some(SpreadError::NotAboveZero { lo })
            }
            (false, Spread::Normal(sigma)) => {
                (sigma > 90.0).then_some(SpreadError::AngleTooWide { sigma })
            }
            (false, Spread::Uniform { uniform: [lo, hi] }) => {
                (lo < -360.0 || hi > 360.0).then_some(SpreadError::BeyondATurn { lo, hi })
            }
        };
        bad.map_or(Ok(()), Err)
    }

    /// A standard deviation >= 0, or a uniform range with low <= high, both finite.
    pub fn check_own(self) -> std::result::Result<(), SpreadError> {
        let ok = match self {
            Spread::Normal(s) => s.is_finite() && s >= 0.0,
            Spread::Uniform { uniform: [a, b] } => a.is_finite() && b.is_finite() && a <= b,
        };
        if ok {
            Ok(())
        } else {
            Err(SpreadError::Malformed)
        }
    }
}

/// A spread that cannot qualify its value ([`Spread::check_own`], [`Spread::check_against`]).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SpreadError {
    /// Not a standard deviation >= 0 nor a uniform range low <= high, both finite.
    #[error("a standard deviation >= 0 or {{ uniform = [lo, hi] }} with lo <= hi")]
    Malformed,
    /// A positive quantity's standard deviation not below its value.
    #[error(
        "standard deviation {sigma} is not smaller than the value {nominal}: most draws would \
         not be a {what} at all"
    )]
    WiderThanValue {
        /// The standard deviation.
        sigma: f64,
        /// The value.
        nominal: f64,
        /// What the value is.
        what: String,
    },
    /// A positive quantity's uniform range reaching 0 or below.
    #[error("uniform = [{}, ...] must lie above 0", short(*.lo))]
    NotAboveZero {
        /// Its low end.
        lo: f64,
    },
    /// An angle's standard deviation above 90 deg.
    #[error("standard deviation {sigma} deg is more than 90 deg")]
    AngleTooWide {
        /// The standard deviation, deg.
        sigma: f64,
    },
    /// An angle's uniform range beyond -360 to 360 deg.
    #[error("uniform = [{}, {}] deg must lie within -360 and 360 deg", short(*.lo), short(*.hi))]
    BeyondATurn {
        /// Its low end, deg.
        lo: f64,
        /// Its high end, deg.
        hi: f64,
    },
}

/// Uncertain inputs of one vehicle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSpread {
    /// Mass (mass unit).
    pub mass: Option<Spread>,
    /// Yaw inertia (inertia unit).
    pub yaw_inertia: Option<Spread>,
    /// Heading, degrees.
    pub heading: Option<Spread>,
    /// CG to impact centre (length unit).
    pub d: Option<Spread>,
    /// Angle phi, degrees.
    pub phi: Option<Spread>,
    /// The impact point's x and y (length unit), instead of `d` / `phi`: each a spread (a
    /// standard deviation, or a uniform range of the coordinate). The point is in the
    /// vehicle's body axes (x forward, y to the left; SAE: to the right), also when the case
    /// places the vehicle by `position` and `[impact] centre`: a draw moves the impact centre
    /// on the vehicle, so the CG moves against the impact centre, which stays where the case
    /// puts it.
    pub impact_point: Option<PointSpread>,
    /// The pre-impact skid length (length unit, of `[pre_impact.vehicleN] skid`).
    pub skid: Option<Spread>,
    /// The pre-impact braking share (`[pre_impact.vehicleN] braking`).
    pub skid_braking: Option<Spread>,
    /// The pre-impact grade (percent, `[pre_impact.vehicleN] grade`).
    pub grade: Option<Spread>,
    /// The EDR's clock (s): one offset drawn for all of the vehicle's EDR times.
    pub edr_time: Option<Spread>,
    /// The run-out's braking share of the rolling wheels (`[runout.vehicleN] braking`).
    pub runout_braking: Option<Spread>,
    /// Wheelbase (length unit, `[runout.vehicleN] wheelbase`).
    pub wheelbase: Option<Spread>,
    /// Track (length unit).
    pub track: Option<Spread>,
    /// CG to the front axle (length unit): the CG's position along the wheelbase.
    pub cg_to_front_axle: Option<Spread>,
    /// CG height (length unit).
    pub cg_height: Option<Spread>,
    /// The run-out's rolling resistance (`[runout.vehicleN] rolling_resistance`, a fraction of
    /// the load).
    pub rolling_resistance: Option<Spread>,
}

/// The spreads of a point's two coordinates (either may be left out: not drawn).
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSpread {
    /// Forward of the CG (length unit).
    pub x: Option<Spread>,
    /// Left of the CG (length unit; SAE: to the right).
    pub y: Option<Spread>,
}

impl VehicleSpread {
    /// The names of the drawn inputs that only a reconstruction uses (the pre-impact and
    /// run-out inputs), as written.
    pub fn scene_only(&self) -> Vec<&'static str> {
        [
            ("skid", self.skid.is_some()),
            ("skid_braking", self.skid_braking.is_some()),
            ("grade", self.grade.is_some()),
            ("edr_time", self.edr_time.is_some()),
            ("runout_braking", self.runout_braking.is_some()),
            ("wheelbase", self.wheelbase.is_some()),
            ("track", self.track.is_some()),
            ("cg_to_front_axle", self.cg_to_front_axle.is_some()),
            ("cg_height", self.cg_height.is_some()),
            ("rolling_resistance", self.rolling_resistance.is_some()),
        ]
        .into_iter()
        .filter_map(|(n, given)| given.then_some(n))
        .collect()
    }
}

/// Uncertain crush-surface angle.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactSpread {
    /// Degrees.
    pub crush_angle: Option<Spread>,
}

/// `[uncertainty]` of a case file.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct UncertaintySection {
    /// Vehicle 1.
    #[serde(default)]
    pub vehicle1: VehicleSpread,
    /// Vehicle 2.
    #[serde(default)]
    pub vehicle2: VehicleSpread,
    /// The crush surface.
    #[serde(default)]
    pub impact: ImpactSpread,
}

impl UncertaintySection {
    /// Whether these spreads draw a geometry input (`vehicle1.d`, the crush angle, ...).
    pub fn draws_geometry(&self, input: pim_fit::GeometryInput) -> bool {
        use pim_fit::GeometryInput as G;
        let vehicle = |v: u8| if v == 1 { self.vehicle1 } else { self.vehicle2 };
        match input {
            G::D(v) => vehicle(v).d.is_some(),
            G::Phi(v) => vehicle(v).phi.is_some(),
            G::X(v) | G::Y(v) => vehicle(v).impact_point.is_some(),
            G::CrushAngle => self.impact.crush_angle.is_some(),
        }
    }

    /// Converts the file's units to SI (factors: mass, inertia, length).
    pub fn to_si(self, mass: f64, inertia: f64, length: f64) -> Self {
        let v = |s: VehicleSpread| VehicleSpread {
            mass: s.mass.map(|x| x.scaled(mass)),
            yaw_inertia: s.yaw_inertia.map(|x| x.scaled(inertia)),
            d: s.d.map(|x| x.scaled(length)),
            impact_point: s.impact_point.map(|p| PointSpread {
                x: p.x.map(|x| x.scaled(length)),
                y: p.y.map(|y| y.scaled(length)),
            }),
            ..s
        };
        UncertaintySection {
            vehicle1: v(self.vehicle1),
            vehicle2: v(self.vehicle2),
            impact: self.impact,
        }
    }
}

/// A standard normal number (Box-Muller).
pub fn standard_normal(rng: &mut impl Rng) -> f64 {
    let u1: f64 = rng.random::<f64>().max(f64::MIN_POSITIVE);
    let u2: f64 = rng.random();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}
