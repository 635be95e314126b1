//! The energy of a damage profile under the linear stiffness model.

use serde::{Deserialize, Serialize};

/// What a damage profile or stiffness cannot be.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CrushError {
    /// A value outside its physical range.
    #[error("{field}: {reason}")]
    Input {
        /// The field (`width`, `depths`, `a`, `b`, `mass`, ...).
        field: &'static str,
        /// What is wrong and what is accepted.
        reason: String,
    },
}

pub(crate) fn input(field: &'static str, reason: impl Into<String>) -> CrushError {
    CrushError::Input {
        field,
        reason: reason.into(),
    }
}

/// Linear stiffness per unit of damage width: `F / w = A + B C`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Stiffness {
    /// A, N/m (force per unit width at the onset of residual crush).
    pub a: f64,
    /// B, N/m^2 (its growth per unit crush); above 0.
    pub b: f64,
}

impl Stiffness {
    /// `G = A^2 / (2 B)`, J/m: the energy per unit width absorbed without residual crush.
    pub fn g(&self) -> f64 {
        self.a * self.a / (2.0 * self.b)
    }

    /// Checks A >= 0 and B > 0, both finite.
    ///
    /// # Errors
    /// [`CrushError::Input`] naming `a` or `b`.
    pub fn check(&self) -> Result<(), CrushError> {
        if !(self.a.is_finite() && self.a >= 0.0) {
            return Err(input(
                "a",
                format!("{}: A must be a number of at least 0 N/m", self.a),
            ));
        }
        if !(self.b.is_finite() && self.b > 0.0) {
            return Err(input(
                "b",
                format!("{}: B must be a number above 0 N/m^2", self.b),
            ));
        }
        Ok(())
    }

    /// The stiffness of a full-width rigid-barrier test: a vehicle of `mass` (kg) and damage
    /// `width` (m) at `speed` (m/s) leaves a uniform residual crush `crush` (m); below
    /// `no_damage_speed` (m/s) it leaves none. With `V = b0 + b1 C`: `A = m b0 b1 / w`,
    /// `B = m b1^2 / w`.
    ///
    /// # Errors
    /// [`CrushError::Input`] for values outside their ranges or a test speed not above the
    /// no-damage speed.
    pub fn from_barrier_test(
        mass: f64,
        width: f64,
        speed: f64,
        crush: f64,
        no_damage_speed: f64,
    ) -> Result<Stiffness, CrushError> {
        for (field, x) in [
            ("mass", mass),
            ("width", width),
            ("speed", speed),
            ("crush", crush),
        ] {
            if !(x.is_finite() && x > 0.0) {
                return Err(input(field, format!("{x}: must be a number above 0")));
            }
        }
        if !(no_damage_speed.is_finite() && no_damage_speed >= 0.0 && no_damage_speed < speed) {
            return Err(input(
                "no_damage_speed",
                format!("{no_damage_speed}: must lie from 0 up to the test speed {speed}"),
            ));
        }
        let b1 = (speed - no_damage_speed) / crush;
        Ok(Stiffness {
            a: mass * no_damage_speed * b1 / width,
            b: mass * b1 * b1 / width,
        })
    }
}

/// A damage profile: its width and the residual crush depths measured at equally spaced
/// points across it, from one end to the other.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Profile {
    /// Damage width L, m.
    pub width: f64,
    /// Crush depths C1..Cn, m (n >= 2, each at least 0).
    pub depths: Vec<f64>,
}

impl Profile {
    /// Checks the width and the depths.
    ///
    /// # Errors
    /// [`CrushError::Input`] naming `width` or `depths`.
    pub fn check(&self) -> Result<(), CrushError> {
        if !(self.width.is_finite() && self.width > 0.0) {
            return Err(input(
                "width",
                format!("{}: must be a number above 0 m", self.width),
            ));
        }
        if self.depths.len() < 2 {
            return Err(input(
                "depths",
                format!(
                    "{} given: at least two crush depths, at the two ends of the damage",
                    self.depths.len()
                ),
            ));
        }
        if let Some((i, c)) = self
            .depths
            .iter()
            .enumerate()
            .find(|(_, c)| !(c.is_finite() && **c >= 0.0))
        {
            return Err(input(
                "depths",
                format!(
                    "C{} = {c}: a crush depth is a number of at least 0 m",
                    i + 1
                ),
            ));
        }
        Ok(())
    }
}

/// The energy absorbed by the profile, J: the exact integral of `A C + B C^2 / 2 + G` over the
/// width with the crush linear between the measured points.
///
/// # Errors
/// [`CrushError::Input`] for a profile or stiffness outside its ranges.
pub fn crush_energy(profile: &Profile, stiffness: &Stiffness) -> Result<f64, CrushError> {
    profile.check()?;
    stiffness.check()?;
    let n = profile.depths.len();
    let step = profile.width / (n - 1) as f64;
    let (a, b) = (stiffness.a, stiffness.b);
    let mut e = stiffness.g() * profile.width;
    for w in profile.depths.windows(2) {
        let (c0, c1) = (w[0], w[1]);
        // Over one interval C is linear: its mean is (c0 + c1)/2, the mean of C^2 is
        // (c0^2 + c0 c1 + c1^2)/3.
        e += step * (a * 0.5 * (c0 + c1) + 0.5 * b * (c0 * c0 + c0 * c1 + c1 * c1) / 3.0);
    }
    Ok(e)
}

/// CRASH3's published closed forms for 2, 4 and 6 equally spaced crush depths, J (`None` for
/// another count). They equal [`crush_energy`]; they are kept as written for the comparison.
pub fn crash3_energy(profile: &Profile, stiffness: &Stiffness) -> Option<f64> {
    let (a, b, g, l) = (stiffness.a, stiffness.b, stiffness.g(), profile.width);
    let c = &profile.depths;
    match c.len() {
        2 => Some(
            l * (a / 2.0 * (c[0] + c[1]) + b / 6.0 * (c[0] * c[0] + c[0] * c[1] + c[1] * c[1]) + g),
        ),
        4 => Some(
            l / 3.0
                * (a / 2.0 * (c[0] + 2.0 * c[1] + 2.0 * c[2] + c[3])
                    + b / 6.0
                        * (c[0] * c[0]
                            + 2.0 * c[1] * c[1]
                            + 2.0 * c[2] * c[2]
                            + c[3] * c[3]
                            + c[0] * c[1]
                            + c[1] * c[2]
                            + c[2] * c[3])
                    + 3.0 * g),
        ),
        6 => Some(
            l / 5.0
                * (a / 2.0 * (c[0] + 2.0 * c[1] + 2.0 * c[2] + 2.0 * c[3] + 2.0 * c[4] + c[5])
                    + b / 6.0
                        * (c[0] * c[0]
                            + 2.0 * c[1] * c[1]
                            + 2.0 * c[2] * c[2]
                            + 2.0 * c[3] * c[3]
                            + 2.0 * c[4] * c[4]
                            + c[5] * c[5]
                            + c[0] * c[1]
                            + c[1] * c[2]
                            + c[2] * c[3]
                            + c[3] * c[4]
                            + c[4] * c[5])
                    + 5.0 * g),
        ),
        _ => None,
    }
}

/// The angle beyond which CRASH3 holds its direction-of-force correction, rad (45 deg).
pub const MAX_PDOF_CORRECTION_ANGLE: f64 = std::f64::consts::FRAC_PI_4;

/// CRASH3's correction of the energy for a force at `alpha` (rad) from the face's normal:
/// `1 + tan^2(alpha)`, with |alpha| held at 45 deg beyond it (so 1 to 2).
pub fn pdof_factor(alpha: f64) -> f64 {
    let t = alpha.abs().min(MAX_PDOF_CORRECTION_ANGLE).tan();
    1.0 + t * t
}

/// The speed at which the vehicle would absorb `energy` (J) against a rigid barrier, m/s:
/// `sqrt(2 E / m)`.
///
/// # Errors
/// [`CrushError::Input`] for a mass not above 0 or an energy below 0.
pub fn barrier_equivalent_speed(energy: f64, mass: f64) -> Result<f64, CrushError> {
    if !(mass.is_finite() && mass > 0.0) {
        return Err(input(
            "mass",
            format!("{mass}: must be a number above 0 kg"),
        ));
    }
    if !(energy.is_finite() && energy >= 0.0) {
        return Err(input(
            "energy",
            format!("{energy}: must be a number of at least 0 J"),
        ));
    }
    Ok((2.0 * energy / mass).sqrt())
}
