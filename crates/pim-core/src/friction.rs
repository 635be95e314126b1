//! The one friction rule of every model, and the exact friction condition.
//!
//! ## The rule
//! The tangential impulse lies between zero and the impulse that sticking needs. In the
//! impulse ratio `rho = Pt / Pn` (impulse on vehicle 1, crush-surface components):
//!
//! ```text
//! rho between 0 and rho_s,      rho_s = Pt_s / Pn_s of the sticking impulse
//! ```
//!
//! where the sticking impulse is the model's own: PIM's no-slip impulse (equation 5a, `Vt = 0`
//! at separation), the tangential model's impulse of `vt' = et vt` (for IMPC, `et = -e`).
//!
//! Why: along the impulse the tangential velocity at C is an affine function of the tangential
//! impulse at a fixed normal impulse (the six equations are linear), `Vt = k Pt + c`, and the
//! sticking impulse is where it reaches its sticking value. Friction takes out sliding; a ratio
//! of the other sign than `rho_s` adds sliding to what the normal impulse leaves, and one beyond
//! `rho_s` overshoots the sticking value and needs more tangential impulse than sticking does,
//! which in PIM creates energy (Brach 1984, section 5). So the direction of friction is the
//! direction of the sticking impulse, not that of the initial sliding. The two agree unless
//! the coupling of the collision (the off-diagonal terms of the collision matrix, from the
//! eccentricity of C) reverses the sliding by itself.
//!
//! ## PIM's form of it
//! PIM's equation 5 writes `rho = mu sgn(vn) sgn(vt)`, so that a positive mu opposes the
//! initial sliding. With `mu_max = rho_s sgn(vn) sgn(vt)` (signed) the rule reads "mu between 0
//! and mu_max" ([`classify_friction`]); `mu_max < 0` where the coupling reverses the sliding
//! (Brach 1984 Table 1B, tests 3 and 4). Where the contact point does **not** slide at contact
//! (`vt = 0`, or round-off of it, [`crate::NO_SLIDING_TOL`]) there is no sliding direction, but
//! an eccentric normal impulse still makes C slide and the no-slip impulse still has a
//! direction: the sign factor is then taken from it, `s = sgn(Pt_s Pn_s)`
//! ([`friction_direction`], [`FrictionBasis::NoSlipImpulse`]), so that mu >= 0 and
//! `mu_max = |rho_s|`. A central hit with no coupling (`rho_s = 0`) then admits only mu = 0.
//! Where the contact point slides this is the former rule, unchanged; at `vt = 0` it replaces
//! "no tangential impulse whatever mu is", which ignored the sliding the normal impulse causes.
//! The answer is continuous as vt passes through 0 at a fixed fraction `mu / mu_max`: the
//! closure of each sliding direction's set of admissible answers meets the other's at `vt = 0`.
//!
//! The no-slip impulse, and so mu_max, is a ratio of two linear forms of the contact state
//! ([`crate::reduction::Reduction::critical_rows`]); [`classify_friction`] is the one place
//! that decides whether a ratio is admissible. The solver's reports, the second model's report
//! and the fit all call it.

use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// Relative tolerance used to decide "mu equals mu_max" and "no energy created".
pub const REPORT_TOL: f64 = 1e-9;

/// What happens along the crush surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum TangentialOutcome {
    /// The vehicles still slide at separation, in the initial direction (|mu| < |mu_max|).
    Sliding,
    /// Sliding ends at or before separation (mu = mu_max, or the no-slip form).
    Sticking,
    /// The tangential impulse overshoots and reverses the sliding (mu beyond mu_max): not physical.
    Reversed,
}

/// The sign factor `s` of equation 5, `mu' = mu s`: `sgn(vn) sgn(vt)` where the contact point
/// slides at contact (friction opposes the initial sliding), the sign of the no-slip impulse
/// ratio where it does not ([`friction_direction`]). Serialised as the number `1` or `-1`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum FrictionSign {
    /// `s = +1`.
    Positive,
    /// `s = -1`.
    Negative,
}

/// Where the sign factor of equation 5 comes from.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum FrictionBasis {
    /// The contact point slides at contact: `s = sgn(vn) sgn(vt)`.
    #[default]
    Sliding,
    /// It does not (`vt = 0`): `s` is the sign of the no-slip impulse ratio `Pt_s / Pn_s`, the
    /// sliding that the normal impulse itself causes (+1 when that impulse has no tangential
    /// part: then only mu = 0 is admissible).
    NoSlipImpulse,
}

impl FrictionSign {
    /// Both signs, positive first.
    pub const BOTH: [FrictionSign; 2] = [FrictionSign::Positive, FrictionSign::Negative];

    /// `+1.0` or `-1.0`.
    pub fn value(self) -> f64 {
        match self {
            FrictionSign::Positive => 1.0,
            FrictionSign::Negative => -1.0,
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

    /// `sgn(vn) sgn(vt)` of a contact state's relative velocity at C; `None` when `vt` is zero
    /// (callers decide what counts as zero: [`crate::Impact::sliding_sign`] uses a round-off
    /// tolerance).
    pub fn of(vn: f64, vt: f64) -> Option<Self> {
        if vt == 0.0 {
            return None;
        }
        Some(Self::of_value(
            Self::of_value(vn).value() * Self::of_value(vt).value(),
        ))
    }

    /// The other sign.
    pub fn flipped(self) -> Self {
        match self {
            FrictionSign::Positive => FrictionSign::Negative,
            FrictionSign::Negative => FrictionSign::Positive,
        }
    }
}

/// The one rule for the sign factor of equation 5: the sliding direction at contact when there
/// is one, else the direction of the no-slip impulse (`no_slip` is evaluated only then; `None`
/// or a zero tangential part gives `Positive`).
pub fn friction_direction(
    sliding: Option<FrictionSign>,
    no_slip: impl FnOnce() -> Option<CriticalImpulse>,
) -> (FrictionSign, FrictionBasis) {
    match sliding {
        Some(s) => (s, FrictionBasis::Sliding),
        None => (
            no_slip().map_or(FrictionSign::Positive, |p| p.direction()),
            FrictionBasis::NoSlipImpulse,
        ),
    }
}

impl schemars::JsonSchema for FrictionSign {
    fn schema_name() -> std::borrow::Cow<'static, str> {
        "FrictionSign".into()
    }

    fn inline_schema() -> bool {
        true
    }

    fn json_schema(_: &mut schemars::SchemaGenerator) -> schemars::Schema {
        schemars::json_schema!({
            "type": "number",
            "description": "The sign of the friction impulse along the crush surface: 1 or -1."
        })
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
        Ok(FrictionSign::of_value(x))
    }
}

/// An impulse on vehicle 1 in crush-surface components, N s: of a solution, or of the no-slip
/// solution (sliding ends exactly at separation), whose ratio gives mu_max.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CriticalImpulse {
    /// Normal impulse `Pn = P . n`.
    pub normal: f64,
    /// Tangential impulse `Pt = P . t`.
    pub tangential: f64,
}

impl CriticalImpulse {
    /// The signed critical impulse ratio `mu_max = (Pt / Pn) sign`; `None` when the normal
    /// impulse vanishes (relative to the whole impulse) or the ratio is not finite.
    pub fn mu_max(&self, sign: FrictionSign) -> Option<f64> {
        let (pn, pt) = (self.normal, self.tangential);
        let scale = pn.hypot(pt);
        if pn.is_nan() || pn.abs() <= 1e-12 * scale {
            return None;
        }
        let r = pt / pn * sign.value();
        r.is_finite().then_some(r)
    }

    /// The sign of the impulse ratio `Pt / Pn` (`Positive` when either part is zero or not a
    /// number): the direction of friction that this impulse stands for.
    pub fn direction(&self) -> FrictionSign {
        let p = self.normal * self.tangential;
        if p < 0.0 {
            FrictionSign::Negative
        } else {
            FrictionSign::Positive
        }
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
        assert_eq!(FrictionSign::of(-1.0, 2.0), Some(FrictionSign::Negative));
        assert_eq!(FrictionSign::of(-1.0, -2.0), Some(FrictionSign::Positive));
        assert_eq!(FrictionSign::of(0.0, 0.0), None);
        assert_eq!(FrictionSign::of(-3.0, 0.0), None);
        let m = CriticalImpulse {
            normal: 2.0,
            tangential: -1.0,
        };
        assert_eq!(m.mu_max(FrictionSign::Negative), Some(0.5));
        assert_eq!(m.direction(), FrictionSign::Negative);
        // Without sliding at contact the sign comes from the no-slip impulse.
        let (s, basis) = friction_direction(None, || Some(m));
        assert_eq!(
            (s, basis),
            (FrictionSign::Negative, FrictionBasis::NoSlipImpulse)
        );
        assert_eq!(m.mu_max(s), Some(0.5));
        let (s, basis) = friction_direction(Some(FrictionSign::Positive), || unreachable!());
        assert_eq!((s, basis), (FrictionSign::Positive, FrictionBasis::Sliding));
        assert_eq!(friction_direction(None, || None).0, FrictionSign::Positive);
    }
}
