//! The friction direction of equation 5 and the exact friction condition "mu between 0 and
//! mu_max".
//!
//! `mu_max` is the impulse ratio of the no-slip solution (equation 5a instead of 5): the
//! tangential over the normal impulse that ends the sliding exactly at separation, put in the
//! sign convention of equation 5. Both impulses of the no-slip solution are linear in the
//! contact state, so `mu_max` is a ratio of two linear forms; [`classify_friction`] is the one
//! place that decides, from `mu` and `mu_max`, whether friction is admissible. The solver's
//! reports and the fit both call it.

use crate::report::{TangentialOutcome, REPORT_TOL};
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// The sign factor `sgn(vn) sgn(vt)` of equation 5: friction opposes the initial sliding
/// direction, `mu' = mu * sign`. Serialised as the number `1`, `-1` or `0`.
///
/// When the vehicles do not slide along the crush surface at contact (`vt = 0`), friction has
/// no direction to oppose: the sign is [`FrictionSign::NoSliding`], `mu' = 0` and the
/// tangential impulse is zero whatever mu is (a perpendicular central hit gets no sideways
/// impulse and no yaw).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FrictionSign {
    /// `sgn(vn) sgn(vt) = +1`.
    Positive,
    /// `sgn(vn) sgn(vt) = -1`.
    Negative,
    /// `vt = 0` at contact: no sliding, no tangential impulse (`mu' = 0`).
    NoSliding,
}

impl FrictionSign {
    /// Both signs, positive first.
    pub const BOTH: [FrictionSign; 2] = [FrictionSign::Positive, FrictionSign::Negative];

    /// `+1.0`, `-1.0` or `0.0`.
    pub fn value(self) -> f64 {
        match self {
            FrictionSign::Positive => 1.0,
            FrictionSign::Negative => -1.0,
            FrictionSign::NoSliding => 0.0,
        }
    }

    /// The sign of a number (`Negative` for x < 0, else `Positive`).
    pub fn of_value(x: f64) -> Self {
        if x < 0.0 {
            FrictionSign::Negative
        } else {
            FrictionSign::Positive
        }
    }

    /// `sgn(vn) sgn(vt)` of a contact state's relative velocity at C; [`FrictionSign::NoSliding`]
    /// when `vt` is zero (callers decide what counts as zero: [`crate::Impact::friction_sign`]
    /// uses a round-off tolerance).
    pub fn of(vn: f64, vt: f64) -> Self {
        if vt == 0.0 {
            return FrictionSign::NoSliding;
        }
        Self::of_value(Self::of_value(vn).value() * Self::of_value(vt).value())
    }

    /// The other sign (`NoSliding` stays as it is).
    pub fn flipped(self) -> Self {
        match self {
            FrictionSign::Positive => FrictionSign::Negative,
            FrictionSign::Negative => FrictionSign::Positive,
            FrictionSign::NoSliding => FrictionSign::NoSliding,
        }
    }
}

impl Serialize for FrictionSign {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_f64(self.value())
    }
}

impl<'de> Deserialize<'de> for FrictionSign {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let x = f64::deserialize(d)?;
        Ok(if x == 0.0 {
            FrictionSign::NoSliding
        } else {
            FrictionSign::of_value(x)
        })
    }
}

/// The impulse on vehicle 1 of the no-slip solution (sliding ends exactly at separation), N s.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CriticalImpulse {
    /// Normal impulse `Pn = P . n`.
    pub normal: f64,
    /// Tangential impulse `Pt = P . t`.
    pub tangential: f64,
}

impl CriticalImpulse {
    /// The signed critical impulse ratio `mu_max = (Pt / Pn) sign`; `None` when the normal
    /// impulse vanishes (relative to the whole impulse), the ratio is not finite, or there is
    /// no sliding at contact (no sign convention, no friction limit).
    pub fn mu_max(&self, sign: FrictionSign) -> Option<f64> {
        if sign == FrictionSign::NoSliding {
            return None;
        }
        let (pn, pt) = (self.normal, self.tangential);
        let scale = pn.hypot(pt);
        if pn.is_nan() || pn.abs() <= 1e-12 * scale {
            return None;
        }
        let r = pt / pn * sign.value();
        r.is_finite().then_some(r)
    }
}

/// The verdict on a friction ratio under equation 5 (sliding).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionVerdict {
    /// Sliding, sticking (mu = mu_max) or reversed (mu beyond mu_max).
    pub outcome: TangentialOutcome,
    /// `mu / mu_max`, when mu_max is defined and not zero.
    pub ratio: Option<f64>,
    /// mu lies between 0 and mu_max (within [`REPORT_TOL`]).
    pub admissible: bool,
}

/// The exact friction condition: is `mu` between 0 and `mu_max` (signed)?
///
/// `mu = 0` (to `REPORT_TOL`) is always admissible; otherwise mu and mu_max must have the same
/// sign and `|mu| <= |mu_max|` (to a relative `10 REPORT_TOL`). A tolerance on the ratio
/// `mu / mu_max` at its zero end would let through a mu of the wrong sign whenever mu_max is
/// huge (near a vanishing no-slip normal impulse, where mu_max jumps from +infinity to
/// -infinity); the zero end is therefore a tolerance on mu itself. When mu_max is zero only
/// `mu = 0` is admissible, and the vehicles then stick; when it is undefined (no normal
/// impulse), only `mu = 0`.
pub fn classify_friction(mu: f64, mu_max: Option<f64>) -> FrictionVerdict {
    match mu_max {
        Some(m) if m.abs() > REPORT_TOL => {
            let r = mu / m;
            let outcome = if (r - 1.0).abs() <= REPORT_TOL * 10.0 {
                TangentialOutcome::Sticking
            } else if r > 1.0 {
                TangentialOutcome::Reversed
            } else {
                TangentialOutcome::Sliding
            };
            FrictionVerdict {
                outcome,
                ratio: Some(r),
                admissible: mu.abs() <= REPORT_TOL || (r > 0.0 && r <= 1.0 + 10.0 * REPORT_TOL),
            }
        }
        Some(_) => {
            let ok = mu.abs() <= REPORT_TOL;
            FrictionVerdict {
                outcome: if ok {
                    TangentialOutcome::Sticking
                } else {
                    TangentialOutcome::Reversed
                },
                ratio: None,
                admissible: ok,
            }
        }
        None => FrictionVerdict {
            outcome: TangentialOutcome::Sliding,
            ratio: None,
            admissible: mu.abs() <= REPORT_TOL,
        },
    }
}

/// True when the kinetic energy at separation `t1` exceeds that at contact `t0` (J), beyond a
/// relative [`REPORT_TOL`]: the one test of "no energy created".
pub fn creates_energy(t0: f64, t1: f64) -> bool {
    t1 > t0 * (1.0 + REPORT_TOL)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_classification() {
        let v = classify_friction(0.3, Some(0.6));
        assert!(v.admissible && v.outcome == TangentialOutcome::Sliding);
        assert!(!classify_friction(0.3, Some(-0.6)).admissible);
        assert!(classify_friction(-0.3, Some(-0.6)).admissible);
        assert!(!classify_friction(0.7, Some(0.6)).admissible);
        let at = classify_friction(0.6, Some(0.6));
        assert!(at.admissible && at.outcome == TangentialOutcome::Sticking);
        assert!(classify_friction(0.0, None).admissible);
        // A huge mu_max of the other sign is not "between 0 and mu_max".
        assert!(!classify_friction(0.4, Some(-4.1e8)).admissible);
        assert!(classify_friction(-1e-12, Some(0.5)).admissible);
        assert!(!classify_friction(0.1, None).admissible);
    }

    #[test]
    fn sign_of_relative_velocity() {
        assert_eq!(FrictionSign::of(-1.0, 2.0), FrictionSign::Negative);
        assert_eq!(FrictionSign::of(-1.0, -2.0), FrictionSign::Positive);
        assert_eq!(FrictionSign::of(0.0, 0.0), FrictionSign::NoSliding);
        assert_eq!(FrictionSign::of(-3.0, 0.0), FrictionSign::NoSliding);
        assert!(FrictionSign::NoSliding.value().abs() < f64::MIN_POSITIVE);
        let m = CriticalImpulse {
            normal: 2.0,
            tangential: -1.0,
        };
        assert_eq!(m.mu_max(FrictionSign::Negative), Some(0.5));
    }
}
