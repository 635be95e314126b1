//! The sections of a TOML case file: vehicles, impact, coefficients, states, partial states,
//! bounds and observations, as written (in the file's units).

use pim_core::{Coefficients, VehicleVelocity, Velocities};
use serde::Deserialize;

/// A point in a vehicle's own frame: `x` forward, `y` to the left, from the CG.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointSection {
    /// Forward of the CG (length unit).
    pub x: f64,
    /// Left of the CG (length unit).
    pub y: f64,
}

/// The impact centre in the scene's frame: `{ x, y }` (length unit), with the survey point it
/// was placed on, if any (see [`crate::survey`]).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentreSection {
    /// x (length unit).
    pub x: f64,
    /// y (length unit).
    pub y: f64,
    /// The survey point it was placed on (`[survey]`'s id), if any.
    #[serde(default)]
    pub point: Option<String>,
}

/// One vehicle as written in the case file. After loading
/// ([`Case::from_text`](crate::case::Case::from_text)) every number
/// is SI and `d`, `phi` are set whichever form the file used.
///
/// `[vehicle2] barrier = true` makes vehicle 2 a fixed rigid barrier: no mass, yaw inertia,
/// heading or impact centre are given (after loading, mass and yaw inertia are infinite and the
/// rest 0), and its velocities are 0 (they may be left out of `[initial]` / `[final]`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSection {
    /// Free text (make, model).
    #[serde(default)]
    pub description: Option<String>,
    /// A fixed rigid barrier (vehicle 2 only).
    #[serde(default)]
    pub barrier: bool,
    /// Mass (mass unit; kg after loading; infinite for a barrier).
    #[serde(default = "unset")]
    pub mass: f64,
    /// Yaw moment of inertia (kg m^2 after loading; infinite for a barrier).
    #[serde(default = "unset")]
    pub yaw_inertia: f64,
    /// Heading, degrees counter-clockwise from +x: where the nose points (natural convention),
    /// or the papers' theta (`convention = "brach"`: vehicle 1's tail).
    #[serde(default = "unset")]
    pub heading: f64,
    /// CG to impact centre (polar form; m after loading).
    #[serde(default)]
    pub d: Option<f64>,
    /// Angle from the nose to the CG-to-C line, degrees counter-clockwise (polar form).
    #[serde(default)]
    pub phi: Option<f64>,
    /// The impact centre in the vehicle's frame (x forward, y left), instead of `d`, `phi`.
    #[serde(default)]
    pub impact_point: Option<PointSection>,
    /// The CG's position in the case's fixed frame (length unit), with `[impact] centre`:
    /// the impact centre in the vehicle's frame follows from both and the heading.
    #[serde(default)]
    pub position: Option<PointSection>,
    /// Overall length, for drawings (m after loading).
    #[serde(default)]
    pub length: Option<f64>,
    /// Overall width, for drawings (m after loading).
    #[serde(default)]
    pub width: Option<f64>,
    /// CG to the front face, for drawings (default half the length; m after loading).
    #[serde(default)]
    pub cg_to_front: Option<f64>,
    /// Where `yaw_inertia` came from: written, or estimated from `length` and `width` when
    /// not (set on loading, never read from the file; the estimate is pim_case's `inertia`).
    #[serde(skip)]
    pub yaw_inertia_source: InertiaSource,
}

/// Where a vehicle's yaw inertia came from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum InertiaSource {
    /// Written in the case (`yaw_inertia`), or a barrier's (infinite).
    #[default]
    Stated,
    /// Estimated from the mass, `length` and `width` (pim_case's `inertia::from_outline`).
    Outline,
}

/// A required number the file did not give (checked after parsing, so that a barrier can
/// leave it out).
fn unset() -> f64 {
    f64::NAN
}

impl VehicleSection {
    /// CG to impact centre, m (set after loading).
    pub fn d(&self) -> f64 {
        self.d.unwrap_or(0.0)
    }

    /// Angle phi, degrees (set after loading).
    pub fn phi(&self) -> f64 {
        self.phi.unwrap_or(0.0)
    }

    /// Checks the drawing dimensions (in SI): finite, positive and of a road vehicle's size,
    /// with the CG inside the length, so that no drawing is made of an outline that cannot be.
    /// The error is the field (`length`, `width`, `cg_to_front`) and what is wrong with it.
    pub fn check_outline(&self) -> std::result::Result<(), (&'static str, String)> {
        for (field, value, max) in [
            ("length", self.length, MAX_VEHICLE_LENGTH),
            ("width", self.width, MAX_VEHICLE_WIDTH),
            ("cg_to_front", self.cg_to_front, MAX_VEHICLE_LENGTH),
        ] {
            let Some(x) = value else { continue };
            if !(x.is_finite() && x > 0.0 && x <= max) {
                return Err((
                    field,
                    format!(
                        "{} m (in SI): must be a number above 0 and at most {max} m",
                        crate::ranges::short(x)
                    ),
                ));
            }
        }
        if let (Some(l), Some(f)) = (self.length, self.cg_to_front) {
            if f > l {
                return Err((
                    "cg_to_front",
                    format!(
                        "{f} m is longer than length = {l} m: the centre of gravity must lie \
                         within the vehicle"
                    ),
                ));
            }
        }
        Ok(())
    }
}

/// `[impact]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactSection {
    /// Gamma, degrees in the case's fixed frame.
    #[serde(default = "unset")]
    pub crush_angle: f64,
    /// The same angle measured from vehicle 1's nose instead of the fixed x axis, degrees
    /// (instead of `crush_angle`).
    #[serde(default)]
    pub crush_angle_from_vehicle1: Option<f64>,
    /// The impact centre in the case's fixed frame (length unit), with each vehicle's
    /// `position`, instead of each vehicle's `impact_point` or `d` and `phi`.
    #[serde(default)]
    pub centre: Option<CentreSection>,
    /// Which side of the crush surface vehicle 1 lies on, `"+n"` or `"-n"` (n at
    /// `crush_angle`), when the case knows it: otherwise it is read from the two CGs' heights
    /// above the crush plane (weighted by mobility when both lie on one side).
    #[serde(default)]
    pub vehicle1_side: Option<String>,
}

/// `[coefficients]`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoefficientsSection {
    /// The model by name, optional: `"pim"` (e, mu, em), `"tangential"` (e, et, friction) or
    /// `"impc"` (e, friction: the Carpenter-Welcher model, the tangential model with
    /// `et = -e`). Without it the coefficients given select PIM or the tangential model.
    pub model: Option<ModelName>,
    /// Restitution (both models).
    pub e: f64,
    /// PIM: friction (impulse ratio).
    pub mu: Option<f64>,
    /// PIM: moment restitution.
    pub em: Option<f64>,
    /// Tangential-restitution model: tangential restitution, in [-1, 1].
    pub et: Option<f64>,
    /// Tangential-restitution model: friction limit of the impulse ratio.
    pub friction: Option<f64>,
}

/// A model named in `[coefficients] model = "..."`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ModelName {
    /// Planar Impact Mechanics: e, mu, em.
    Pim,
    /// Normal and tangential restitution with a friction limit: e, et, friction.
    Tangential,
    /// The Carpenter-Welcher impulse-momentum model: e, friction (et = -e).
    Impc,
}

/// The impact model a case selects by its coefficients.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum CaseModel {
    /// PIM: `e`, `mu`, `em`.
    Pim(Coefficients),
    /// The tangential-restitution model: `e`, `et`, `friction`.
    Tangential(pim_core::TangentialCoefficients),
    /// The Carpenter-Welcher model: `model = "impc"`, `e`, `friction`.
    Impc(pim_core::Impc),
}

impl CaseModel {
    /// The model as a type, with the solve options a PIM case is solved with.
    pub fn impact_model(self, options: &pim_core::SolveOptions) -> Box<dyn pim_core::ImpactModel> {
        match self {
            CaseModel::Pim(coefficients) => Box::new(pim_core::PimModel {
                coefficients,
                options: *options,
            }),
            CaseModel::Tangential(c) => Box::new(c),
            CaseModel::Impc(c) => Box::new(c),
        }
    }
}

/// One vehicle's velocity: `{ vx, vy, omega }` in the case's fixed frame, or `{ speed,
/// direction, omega }` (direction in degrees in the case's frame), or `{ forward, lateral,
/// omega }` in the vehicle's own frame (lateral to the left; to the right under
/// `convention = "sae"`). After loading only `vx`, `vy`, `omega` are set (SI, natural frame).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocitySection {
    /// m/s.
    #[serde(default = "unset")]
    pub vx: f64,
    /// m/s.
    #[serde(default = "unset")]
    pub vy: f64,
    /// rad/s.
    pub omega: f64,
    /// Speed of the CG (speed unit), with `direction`.
    #[serde(default)]
    pub speed: Option<f64>,
    /// Direction of travel of the CG, degrees in the case's frame, with `speed`.
    #[serde(default)]
    pub direction: Option<f64>,
    /// Velocity along the vehicle's nose (speed unit), with `lateral`.
    #[serde(default)]
    pub forward: Option<f64>,
    /// Velocity across the vehicle (speed unit), with `forward`.
    #[serde(default)]
    pub lateral: Option<f64>,
}

/// `[initial]` or `[final]`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateSection {
    /// Vehicle 1.
    pub vehicle1: VelocitySection,
    /// Vehicle 2 (may be left out for a barrier, which is at rest; always set after loading).
    #[serde(default)]
    pub vehicle2: Option<VelocitySection>,
}

/// A barrier's velocity: at rest.
pub(crate) const AT_REST: VelocitySection = VelocitySection {
    vx: 0.0,
    vy: 0.0,
    omega: 0.0,
    speed: None,
    direction: None,
    forward: None,
    lateral: None,
};

impl StateSection {
    /// As a pim-core state.
    pub fn to_velocities(self) -> Velocities {
        let v = |s: VelocitySection| VehicleVelocity {
            vx: s.vx,
            vy: s.vy,
            omega: s.omega,
        };
        Velocities {
            vehicle1: v(self.vehicle1),
            vehicle2: v(self.vehicle2.unwrap_or(AT_REST)),
        }
    }
}

/// A vehicle's velocity where every component is optional. Estimates and known components may
/// also be given as `speed` and `direction` or `forward` and `lateral` (both of a pair, as for
/// [`VelocitySection`]); weights and standard deviations only as `vx`, `vy`, `omega`.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartialVelocity {
    /// m/s.
    pub vx: Option<f64>,
    /// m/s.
    pub vy: Option<f64>,
    /// rad/s.
    pub omega: Option<f64>,
    /// Speed (with `direction`).
    #[serde(default)]
    pub speed: Option<f64>,
    /// Direction of travel, degrees (with `speed`).
    #[serde(default)]
    pub direction: Option<f64>,
    /// Along the nose (with `lateral`).
    #[serde(default)]
    pub forward: Option<f64>,
    /// Across the vehicle (with `forward`).
    #[serde(default)]
    pub lateral: Option<f64>,
}

/// Both vehicles, optional components.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartialState {
    /// Vehicle 1.
    #[serde(default)]
    pub vehicle1: PartialVelocity,
    /// Vehicle 2.
    #[serde(default)]
    pub vehicle2: PartialVelocity,
}

impl PartialState {
    /// The six components (v1x, v1y, w1, v2x, v2y, w2), `None` where absent.
    pub fn components(&self) -> [Option<f64>; 6] {
        let a = &self.vehicle1;
        let b = &self.vehicle2;
        [a.vx, a.vy, a.omega, b.vx, b.vy, b.omega]
    }
}

/// `initial` and `final`, each optional.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartialStates {
    /// Contact state.
    #[serde(default)]
    pub initial: Option<PartialState>,
    /// Separation state.
    #[serde(default, rename = "final")]
    pub final_: Option<PartialState>,
}

impl PartialStates {
    /// The twelve components of U, `None` where absent.
    pub fn components(&self) -> [Option<f64>; 12] {
        let mut out = [None; 12];
        if let Some(i) = &self.initial {
            out[..6].copy_from_slice(&i.components());
        }
        if let Some(f) = &self.final_ {
            out[6..].copy_from_slice(&f.components());
        }
        out
    }

    /// Multiplies the speeds by `speed` and the yaw rates by `rate` (unit conversion).
    pub fn scale(&mut self, speed: f64, rate: f64) {
        for s in [&mut self.initial, &mut self.final_].into_iter().flatten() {
            for v in [&mut s.vehicle1, &mut s.vehicle2] {
                for x in [&mut v.vx, &mut v.vy].into_iter().flatten() {
                    *x *= speed;
                }
                if let Some(w) = &mut v.omega {
                    *w *= rate;
                }
            }
        }
    }
}

/// `[bounds]` of a fit.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundsSection {
    /// [low, high] of e (default [0, 0.2]).
    #[serde(default, deserialize_with = "pair")]
    pub e: Option<[f64; 2]>,
    /// [low, high] of mu (default [-1.2, 1.2]); mu is always also between 0 and mu_max.
    #[serde(default, deserialize_with = "pair")]
    pub mu: Option<[f64; 2]>,
    /// [low, high] of the tangential model's et (default [-1, 1]; `pim fit --model tangential`).
    #[serde(default, deserialize_with = "pair")]
    pub et: Option<[f64; 2]>,
    /// [low, high] of the tangential model's friction limit (default [0, 1.2]).
    #[serde(default, deserialize_with = "pair")]
    pub friction: Option<[f64; 2]>,
    /// Bound on each linear velocity component, m/s (default 20).
    pub velocity: Option<f64>,
    /// Bound on each yaw rate, rad/s (default 5).
    pub yaw_rate: Option<f64>,
    /// Vehicle 1's impact centre, estimated within these bounds (the case's value is the start).
    pub vehicle1: Option<CentreBounds>,
    /// Vehicle 2's impact centre, likewise.
    pub vehicle2: Option<CentreBounds>,
    /// The crush-surface angle, estimated within `[low, high]` degrees.
    #[serde(default, deserialize_with = "pair")]
    pub crush_angle: Option<[f64; 2]>,
}

/// Bounds of one vehicle's impact centre in `[bounds]`: `d` and / or `phi`, or `impact_point`
/// `x` and / or `y` (length unit; degrees).
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CentreBounds {
    /// `[low, high]` of the CG-to-impact-centre distance.
    #[serde(default, deserialize_with = "pair")]
    pub d: Option<[f64; 2]>,
    /// `[low, high]` of the angle from the nose, degrees.
    #[serde(default, deserialize_with = "pair")]
    pub phi: Option<[f64; 2]>,
    /// Bounds of the impact point's coordinates in the vehicle frame.
    pub impact_point: Option<PointBounds>,
}

/// `impact_point = { x = [lo, hi], y = [lo, hi] }` in `[bounds]`.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PointBounds {
    /// `[low, high]` along the forward axis.
    #[serde(default, deserialize_with = "pair")]
    pub x: Option<[f64; 2]>,
    /// `[low, high]` along the left axis.
    #[serde(default, deserialize_with = "pair")]
    pub y: Option<[f64; 2]>,
}

/// One `[[observations]]` entry.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObservationSection {
    /// A name for messages, tables and figures (e.g. "EDR front"); without it the entry is
    /// `observation N`, its 1-based position.
    #[serde(default)]
    pub name: Option<String>,
    /// `delta_v_longitudinal`, `delta_v_lateral`, `speed_along_heading` or `lateral_velocity`.
    pub kind: pim_fit::ObservationKind,
    /// 1 or 2.
    pub vehicle: u8,
    /// m/s.
    pub value: f64,
    /// In (0, 1], default 1.
    #[serde(default = "one")]
    pub weight: f64,
    /// Standard deviation of the value (speed unit), instead of `weight`.
    #[serde(default)]
    pub sigma: Option<f64>,
}

fn one() -> f64 {
    1.0
}

/// Largest drawing length (and CG-to-front distance) accepted, m: a tractor with two trailers.
pub const MAX_VEHICLE_LENGTH: f64 = 50.0;

/// Largest drawing width accepted, m.
pub const MAX_VEHICLE_WIDTH: f64 = 10.0;

/// `[low, high]` in `[bounds]`: exactly two numbers (a third is a mistake, not ignored).
fn pair<'de, D: serde::Deserializer<'de>>(d: D) -> std::result::Result<Option<[f64; 2]>, D::Error> {
    let v: Option<Vec<f64>> = Option::deserialize(d)?;
    match v {
        None => Ok(None),
        Some(v) if v.len() == 2 => Ok(Some([v[0], v[1]])),
        Some(v) => Err(serde::de::Error::custom(format!(
            "expected [low, high], two numbers; got {} values",
            v.len()
        ))),
    }
}

impl BoundsSection {
    /// Checks the geometry bounds and velocity limits: finite, low <= high, angles within one
    /// turn, limits above 0 (the coefficient boxes are checked with the fit's settings).
    pub fn check(&self) -> std::result::Result<(), (String, String)> {
        // The coefficient boxes (e, mu, et, friction) are checked with the fit's settings,
        // against the coefficient domains (pim-fit's `FitSettings::check`).
        let angle = [crate::ranges::ANGLE.lo, crate::ranges::ANGLE.hi];
        let length = [-pim_core::MAX_DISTANCE, pim_core::MAX_DISTANCE];
        let vehicles = [("vehicle1", self.vehicle1), ("vehicle2", self.vehicle2)]
            .map(|(name, v)| (name, v.unwrap_or_default()));
        type Field = fn(&CentreBounds) -> Option<[f64; 2]>;
        let fields: [(&str, Field, [f64; 2]); 4] = [
            ("phi", |v| v.phi, angle),
            ("d", |v| v.d, length),
            (
                "impact_point.x",
                |v| v.impact_point.and_then(|p| p.x),
                length,
            ),
            (
                "impact_point.y",
                |v| v.impact_point.and_then(|p| p.y),
                length,
            ),
        ];
        let mut all = vec![("crush_angle".to_string(), self.crush_angle, angle)];
        for (field, get, range) in fields {
            for (name, v) in &vehicles {
                all.push((format!("{name}.{field}"), get(v), range));
            }
        }
        for (name, value, [lo, hi]) in all {
            let Some([a, b]) = value else { continue };
            if !(a.is_finite() && b.is_finite() && lo <= a && a <= b && b <= hi) {
                return Err((
                    format!("bounds.{name}"),
                    format!(
                        "[{}, {}]: give [low, high] with {lo} <= low <= high <= {hi}",
                        crate::ranges::short(a),
                        crate::ranges::short(b)
                    ),
                ));
            }
        }
        for (name, value) in [("velocity", self.velocity), ("yaw_rate", self.yaw_rate)] {
            if let Some(x) = value {
                if !(x.is_finite() && x > 0.0) {
                    return Err((
                        format!("bounds.{name}"),
                        format!("{x}: must be a number above 0"),
                    ));
                }
            }
        }
        Ok(())
    }
}

/// `[damage]` as written.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DamageSection {
    /// What the crush energy is compared with (default `energy_loss`).
    #[serde(default)]
    pub relation: pim_crush::EnergyRelation,
    /// Whether a fit takes the crush energy as evidence (default: when its standard deviation
    /// is above 0).
    #[serde(default)]
    pub evidence: Option<bool>,
    /// Vehicle 1's damage.
    #[serde(default)]
    pub vehicle1: Option<DamageVehicleSection>,
    /// Vehicle 2's damage.
    #[serde(default)]
    pub vehicle2: Option<DamageVehicleSection>,
}

/// `[damage.vehicleN]` as written.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DamageVehicleSection {
    /// `front`, `rear`, `left` or `right`.
    pub side: Option<String>,
    /// Damage width (crush unit).
    #[serde(default)]
    pub width: Option<f64>,
    /// Crush depths, equally spaced across the width (crush unit).
    #[serde(default)]
    pub depths: Option<Vec<f64>>,
    /// Centre of the damage (crush unit; see the module's text).
    #[serde(default)]
    pub offset: Option<f64>,
    /// Stiffness A (stiffness unit).
    #[serde(default)]
    pub a: Option<f64>,
    /// Stiffness B (stiffness unit per length).
    #[serde(default)]
    pub b: Option<f64>,
    /// Direction of the principal force, degrees clockwise from the nose (where it comes
    /// from: 0 frontal, 90 from the right); default: that of the impulse.
    #[serde(default)]
    pub pdof: Option<f64>,
    /// Standard deviation of A.
    #[serde(default)]
    pub a_sigma: Option<f64>,
    /// Standard deviation of B.
    #[serde(default)]
    pub b_sigma: Option<f64>,
    /// Standard deviation of each depth.
    #[serde(default)]
    pub depth_sigma: Option<f64>,
    /// Standard deviation of the width.
    #[serde(default)]
    pub width_sigma: Option<f64>,
}
