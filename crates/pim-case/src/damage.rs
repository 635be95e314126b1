//! The damage of a case (`[damage]`): each vehicle's crush profile and stiffness read into
//! pim-crush's inputs, the crush energies set beside PIM's energy loss and CRASH3's delta-V
//! beside PIM's, and the energy as evidence of a fit.
//!
//! ```toml
//! [units]
//! stiffness = "N/cm"       # A in N/cm and B in N/cm^2 ("N/m": N/m, N/m^2; "lbf/in": lbf/in, lbf/in^2)
//! crush = "cm"             # depths, damage width, offset ("m", "cm", "mm", "in", "ft"; default: length)
//!
//! [damage]
//! relation = "energy_loss" # or "compression": what the crush energy is compared with
//!
//! [damage.vehicle1]
//! side = "front"           # front, rear, left, right
//! width = 117              # damage width
//! depths = [10, 14, 18, 26, 31, 38]   # 2 or more, equally spaced across the width
//! offset = 36              # centre of damage: front/rear from the centreline (+ left; SAE: + right),
//!                          # left/right along the length from the CG (+ forward)
//! a = 624                  # stiffness A, B
//! b = 23
//! depth_sigma = 2          # standard deviations (optional): a_sigma, b_sigma, depth_sigma, width_sigma
//! ```
//!
//! A vehicle with `a`, `b` and `side` but no `depths` takes its crush from the other vehicle's
//! by the force balance at the interface (CRASH3's rule, [`pim_crush::balanced_profile`]).

use crate::case::Case;
use crate::error::Result;
use crate::units::{CrushUnit, StiffnessUnit};
use pim_crush::{EnergyRelation, Profile, ProfileSigmas, Stiffness};
use serde::{Deserialize, Serialize};

/// The damaged face of a vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// The front.
    Front,
    /// The rear.
    Rear,
    /// The left side.
    Left,
    /// The right side.
    Right,
}

impl Side {
    /// The direction a force normal to this face comes from, degrees clockwise from the nose.
    pub fn normal_pdof(self) -> f64 {
        match self {
            Side::Front => 0.0,
            Side::Right => 90.0,
            Side::Rear => 180.0,
            Side::Left => -90.0,
        }
    }

    /// The name in case files.
    pub fn name(self) -> &'static str {
        match self {
            Side::Front => "front",
            Side::Rear => "rear",
            Side::Left => "left",
            Side::Right => "right",
        }
    }

    fn parse(s: &str) -> Option<Side> {
        Some(match s.trim() {
            "front" => Side::Front,
            "rear" | "back" => Side::Rear,
            "left" => Side::Left,
            "right" => Side::Right,
            _ => return None,
        })
    }
}

/// One vehicle's damage, checked, in SI and the natural frame.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct VehicleDamage {
    /// The damaged face.
    pub side: Side,
    /// The profile (measured, or from the force balance).
    pub profile: Profile,
    /// Centre of damage, m (front/rear: + left of the centreline; sides: + ahead of the CG).
    pub offset: f64,
    /// A, B in SI.
    pub stiffness: Stiffness,
    /// Standard deviations in SI.
    pub sigmas: ProfileSigmas,
    /// False when the profile follows from the other vehicle's by the force balance.
    pub measured: bool,
    /// The PDOF the case gives, degrees clockwise from the nose.
    pub pdof: Option<f64>,
}

/// A case's damage, checked.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Damage {
    /// What the crush energy is compared with.
    pub relation: EnergyRelation,
    /// Whether a fit takes the energy as evidence, as the case says (`None`: by its sigma).
    pub evidence: Option<bool>,
    /// Each vehicle's damage (none for a vehicle without a section, or a barrier).
    pub vehicles: [Option<VehicleDamage>; 2],
}

/// Largest stiffness A accepted, N/m: a hundred times a heavy truck front's.
const MAX_A: f64 = 1e8;
/// Largest stiffness B accepted, N/m^2.
const MAX_B: f64 = 1e10;

/// Largest crush depth or width accepted without vehicle dimensions, m.
const MAX_CRUSH: f64 = 10.0;

impl Damage {
    /// The case's `[damage]`, checked and in SI (`None` without one). Messages name the file,
    /// line and field.
    pub fn of(case: &Case) -> Result<Option<Damage>> {
        let Some(section) = &case.content.damage else {
            return Ok(None);
        };
        let mut read = [None, None];
        for (k, s) in [&section.vehicle1, &section.vehicle2]
            .into_iter()
            .enumerate()
        {
            if let Some(s) = s {
                read[k] = Some(Read::of(case, k, s)?);
            }
        }
        let measured = |r: &Option<Read>| r.as_ref().is_some_and(|r| r.profile.is_some());
        if read.iter().any(Option::is_some) && !read.iter().any(measured) {
            return Err(case.error_at(
                "damage",
                "no vehicle's crush is measured: give depths and width for at least one vehicle \
                 (the other's may follow from the force balance)",
            ));
        }
        let mut vehicles: [Option<VehicleDamage>; 2] = [None, None];
        for k in 0..2 {
            let Some(r) = read[k].clone() else {
                continue;
            };
            let (profile, measured) = match r.profile {
                Some(p) => (p, true),
                None => {
                    let other = read[1 - k].as_ref().expect("the other is measured");
                    let op = other.profile.as_ref().expect("measured");
                    let p = pim_crush::balanced_profile(op, &other.stiffness, &r.stiffness)
                        .map_err(|e| {
                            crush_error(case, "vehicle", &e, case.written_units.stiffness)
                        })?;
                    (p, false)
                }
            };
            vehicles[k] = Some(VehicleDamage {
                side: r.side,
                profile,
                offset: r.offset,
                stiffness: r.stiffness,
                sigmas: r.sigmas,
                measured,
                pdof: r.pdof,
            });
        }
        Ok(Some(Damage {
            relation: section.relation,
            evidence: section.evidence,
            vehicles,
        }))
    }
}

/// One vehicle's `[damage.vehicleN]` checked and in SI, its profile `None` where the case
/// leaves it to the force balance.
#[derive(Clone)]
struct Read {
    side: Side,
    profile: Option<Profile>,
    offset: f64,
    stiffness: Stiffness,
    sigmas: ProfileSigmas,
    pdof: Option<f64>,
}

impl Read {
    /// Vehicle `k`'s section `s`, checked; messages name the file, line and field.
    fn of(case: &Case, k: usize, s: &crate::sections::DamageVehicleSection) -> Result<Read> {
        let name = ["vehicle1", "vehicle2"][k];
        let u = &case.written_units;
        let crush_unit = u.crush.map_or(u.length.to_si(), CrushUnit::to_si);
        let at = |field: &str| format!("damage.{name}.{field}");
        if case.content.vehicle(k).barrier {
            return Err(case.error_at(
                &format!("damage.{name}"),
                "vehicle 2 is a rigid barrier, which takes no crush: leave its damage out",
            ));
        }
        let side = match s.side.as_deref() {
            Some(t) => Side::parse(t).ok_or_else(|| {
                case.error_at(
                    &at("side"),
                    format!("{t:?}: accepted \"front\", \"rear\", \"left\", \"right\""),
                )
            })?,
            None => {
                return Err(case.error_at(
                    &format!("damage.{name}"),
                    "side: missing; give the damaged face: \"front\", \"rear\", \"left\" \
                     or \"right\"",
                ))
            }
        };
        let stiffness = stiffness_of(case, name, s)?;
        let (a_unit, b_unit) = (u.stiffness.a_to_si(), u.stiffness.b_to_si());
        let sigma = |x: Option<f64>, scale: f64, field: &str| -> Result<f64> {
            let v = x.unwrap_or(0.0);
            if !(v.is_finite() && v >= 0.0) {
                return Err(case.error_at(
                    &at(field),
                    format!("{v}: a standard deviation is a number of at least 0"),
                ));
            }
            Ok(v * scale)
        };
        let sigmas = ProfileSigmas {
            a: sigma(s.a_sigma, a_unit, "a_sigma")?,
            b: sigma(s.b_sigma, b_unit, "b_sigma")?,
            depth: sigma(s.depth_sigma, crush_unit, "depth_sigma")?,
            width: sigma(s.width_sigma, crush_unit, "width_sigma")?,
        };
        let offset = s.offset.unwrap_or(0.0) * crush_unit;
        if !offset.is_finite() {
            return Err(case.error_at(&at("offset"), "must be a finite number"));
        }
        // The lateral offset of front and rear damage is a y coordinate of the file's frame.
        let sae = case.written == pim_core::Convention::Sae;
        let offset = if sae && matches!(side, Side::Front | Side::Rear) {
            -offset
        } else {
            offset
        };
        if let Some(p) = s.pdof {
            if !(p.is_finite() && p.abs() <= 360.0) {
                return Err(case.error_at(
                    &at("pdof"),
                    format!("{p}: degrees clockwise from the nose, within +-360"),
                ));
            }
        }
        let profile = profile_of(case, name, s, crush_unit)?;
        if let Some(p) = &profile {
            p.check()
                .map_err(|e| crush_error(case, name, &e, u.stiffness))?;
            check_fits(case, name, k, side, p, offset)?;
        }
        Ok(Read {
            side,
            profile,
            offset,
            stiffness,
            sigmas,
            pdof: s.pdof,
        })
    }
}

/// The stiffness A and B of vehicle `name`'s section `s`, checked, in SI.
fn stiffness_of(
    case: &Case,
    name: &str,
    s: &crate::sections::DamageVehicleSection,
) -> Result<Stiffness> {
    let u = &case.written_units;
    let (a, b) = match (s.a, s.b) {
        (Some(a), Some(b)) => (a * u.stiffness.a_to_si(), b * u.stiffness.b_to_si()),
        (a, _) => {
            let missing = if a.is_none() { "a" } else { "b" };
            return Err(case.error_at(
                &format!("damage.{name}"),
                format!(
                    "{missing}: missing; give the stiffness A and B of the damaged face (in \
                     [units] stiffness: N/m, N/cm or lbf/in), e.g. from a crash test of the \
                     same vehicle"
                ),
            ));
        }
    };
    let stiffness = Stiffness { a, b };
    stiffness
        .check()
        .map_err(|e| crush_error(case, name, &e, u.stiffness))?;
    for (field, x, limit, unit) in [("a", a, MAX_A, "N/m"), ("b", b, MAX_B, "N/m^2")] {
        if x > limit {
            return Err(case.error_at(
                &format!("damage.{name}.{field}"),
                format!(
                    "{} {unit} (in SI) is beyond any vehicle's stiffness (at most {} {unit}; \
                     passenger cars' fronts are near 5e4 N/m and 5e5 N/m^2): check the value \
                     and [units] stiffness",
                    crate::ranges::short(x),
                    crate::ranges::short(limit)
                ),
            ));
        }
    }
    Ok(stiffness)
}

/// The measured profile of vehicle `name`'s section `s` in SI (`None`: neither depths nor
/// width, the profile left to the force balance).
fn profile_of(
    case: &Case,
    name: &str,
    s: &crate::sections::DamageVehicleSection,
    crush_unit: f64,
) -> Result<Option<Profile>> {
    match (&s.depths, s.width) {
        (Some(d), Some(w)) => Ok(Some(Profile {
            width: w * crush_unit,
            depths: d.iter().map(|c| c * crush_unit).collect(),
        })),
        (None, None) => Ok(None),
        (Some(_), None) => Err(case.error_at(
            &format!("damage.{name}"),
            "width: missing; give the width of the damage the depths were measured across",
        )),
        (None, Some(_)) => Err(case.error_at(
            &format!("damage.{name}"),
            "depths: missing; give the crush depths measured across the width (2, 4 or 6 \
             equally spaced, as CRASH3 measures them)",
        )),
    }
}

fn crush_error(
    case: &Case,
    name: &str,
    e: &pim_crush::CrushError,
    unit: StiffnessUnit,
) -> crate::InputError {
    let pim_crush::CrushError::Input { field, reason } = e;
    let reason = match *field {
        "a" | "b" => format!(
            "{} (in SI; [units] stiffness = {:?})",
            reason,
            toml::Value::try_from(unit)
                .ok()
                .and_then(|v| v.as_str().map(str::to_string))
                .unwrap_or_default()
        ),
        _ => reason.clone(),
    };
    case.error_at(&format!("damage.{name}.{field}"), reason)
}

/// Checks that the damage lies within the vehicle: its depths not beyond the vehicle's length
/// (front, rear) or width (sides), its width and offset within the face.
fn check_fits(
    case: &Case,
    name: &str,
    k: usize,
    side: Side,
    p: &Profile,
    offset: f64,
) -> Result<()> {
    let v = case.content.vehicle(k);
    let (depth_limit, face, what) = match side {
        Side::Front | Side::Rear => (v.length, v.width, ("length", "width")),
        Side::Left | Side::Right => (v.width, v.length, ("width", "length")),
    };
    let deepest = p.depths.iter().cloned().fold(0.0, f64::max);
    let limit = depth_limit.unwrap_or(MAX_CRUSH);
    if deepest >= limit {
        return Err(case.error_at(
            &format!("damage.{name}.depths"),
            format!(
                "a crush of {} m is not less than the vehicle's {} ({limit:.3} m): check the \
                 depths and [units] crush",
                crate::ranges::short(deepest),
                if depth_limit.is_some() {
                    what.0
                } else {
                    "largest accepted crush"
                }
            ),
        ));
    }
    let face = face.unwrap_or(MAX_CRUSH * 3.0);
    // A few millimetres of rounding are allowed at the corners.
    if p.width > face + 5e-3 {
        return Err(case.error_at(
            &format!("damage.{name}.width"),
            format!(
                "a damage width of {} m is wider than the vehicle's {} ({face:.3} m)",
                crate::ranges::short(p.width),
                what.1
            ),
        ));
    }
    if offset.abs() + p.width / 2.0 > face / 2.0 + 0.01 * face
        && matches!(side, Side::Front | Side::Rear)
    {
        return Err(case.error_at(
            &format!("damage.{name}.offset"),
            format!(
                "the damage ({:.3} m wide, centred {:.3} m from the centreline) reaches beyond \
                 the vehicle's width ({face:.3} m)",
                p.width, offset
            ),
        ));
    }
    Ok(())
}
