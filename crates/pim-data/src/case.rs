//! The TOML case file of a solve, a sensitivity study and a fit.

use crate::error::{InputError, Result};
use pim_core::{Coefficients, Collision, Vehicle, VehicleVelocity, Velocities};
use serde::Deserialize;

/// Largest case file accepted, bytes (a case is a few hundred bytes).
pub const MAX_CASE_BYTES: u64 = 1 << 20;

/// One vehicle as written in the case file.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VehicleSection {
    /// Free text (make, model).
    #[serde(default)]
    pub description: Option<String>,
    /// kg.
    pub mass: f64,
    /// kg m^2.
    pub yaw_inertia: f64,
    /// Heading theta, degrees.
    pub heading: f64,
    /// CG to impact centre, m.
    pub d: f64,
    /// Angle phi, degrees.
    pub phi: f64,
}

/// `[impact]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImpactSection {
    /// Gamma, degrees.
    pub crush_angle: f64,
}

/// `[coefficients]`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CoefficientsSection {
    /// Restitution.
    pub e: f64,
    /// Friction.
    pub mu: f64,
    /// Moment restitution.
    pub em: f64,
}

/// One vehicle's velocity, `{ vx, vy, omega }`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct VelocitySection {
    /// m/s.
    pub vx: f64,
    /// m/s.
    pub vy: f64,
    /// rad/s.
    pub omega: f64,
}

/// `[initial]` or `[final]`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StateSection {
    /// Vehicle 1.
    pub vehicle1: VelocitySection,
    /// Vehicle 2.
    pub vehicle2: VelocitySection,
}

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
            vehicle2: v(self.vehicle2),
        }
    }
}

/// The whole case file. Unknown keys are rejected so that a typo cannot be silently ignored.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CaseFile {
    /// Free text.
    #[serde(default)]
    pub title: Option<String>,
    /// Vehicle 1.
    pub vehicle1: VehicleSection,
    /// Vehicle 2.
    pub vehicle2: VehicleSection,
    /// Crush surface.
    pub impact: ImpactSection,
    /// Coefficients (solve, sensitivity).
    #[serde(default)]
    pub coefficients: Option<CoefficientsSection>,
    /// Velocities at contact.
    #[serde(default)]
    pub initial: Option<StateSection>,
    /// Velocities at separation.
    #[serde(default, rename = "final")]
    pub final_: Option<StateSection>,
    /// Estimates (fit): `[estimates.initial]`, `[estimates.final]`.
    #[serde(default)]
    pub estimates: Option<PartialStates>,
    /// Weights of the estimates in (0, 1] (fit), same shape; default 1.
    #[serde(default)]
    pub weights: Option<PartialStates>,
    /// Components known exactly (fit without `--cost`), same shape.
    #[serde(default)]
    pub known: Option<PartialStates>,
    /// Bounds of the fit.
    #[serde(default)]
    pub bounds: Option<BoundsSection>,
    /// Extra observations (fit), e.g. what an EDR recorded.
    #[serde(default)]
    pub observations: Vec<ObservationSection>,
}

/// A vehicle's velocity where every component is optional.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PartialVelocity {
    /// m/s.
    pub vx: Option<f64>,
    /// m/s.
    pub vy: Option<f64>,
    /// rad/s.
    pub omega: Option<f64>,
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
}

/// `[bounds]` of a fit.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoundsSection {
    /// [low, high] of e (default [0, 0.2]).
    pub e: Option<[f64; 2]>,
    /// [low, high] of mu (default [-1.2, 1.2]); mu is always also between 0 and mu_max.
    pub mu: Option<[f64; 2]>,
    /// Bound on each linear velocity component, m/s (default 20).
    pub velocity: Option<f64>,
    /// Bound on each yaw rate, rad/s (default 5).
    pub yaw_rate: Option<f64>,
}

/// One `[[observations]]` entry.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ObservationSection {
    /// `delta_v_longitudinal`, `delta_v_lateral`, `speed_along_heading` or `lateral_velocity`.
    pub kind: pim_fit::ObservationKind,
    /// 1 or 2.
    pub vehicle: u8,
    /// m/s.
    pub value: f64,
    /// In (0, 1], default 1.
    #[serde(default = "one")]
    pub weight: f64,
}

fn one() -> f64 {
    1.0
}

/// A loaded case: the file name (for messages) and its content.
#[derive(Debug, Clone)]
pub struct Case {
    /// The path as given on the command line.
    pub file: String,
    /// The parsed content.
    pub content: CaseFile,
}

/// Line and column (1-based) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let upto = &text[..offset.min(text.len())];
    let line = upto.matches('\n').count() + 1;
    let col = upto.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Parses TOML into `T`, with errors as `file:line:col: field: message` (the field as its
/// dotted path, e.g. `vehicle1.mass`).
pub fn parse_toml<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T> {
    if text.trim().is_empty() {
        return Err(InputError::new(file, "the file is empty"));
    }
    let located = |e: &toml::de::Error, field: Option<String>| {
        let msg = plain_words(e.message().trim());
        let what = match field {
            Some(f) if !f.is_empty() && f != "." => format!("{f}: {msg}"),
            _ => msg,
        };
        match e.span() {
            Some(span) => {
                let (line, col) = line_col(text, span.start);
                InputError::located(file, format!("{file}:{line}:{col}: {what}"))
            }
            None => InputError::new(file, what),
        }
    };
    let de = toml::Deserializer::parse(text).map_err(|e| located(&e, None))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = e.path().to_string();
        located(e.inner(), Some(field))
    })
}

/// serde's type messages in the words of a case file: `invalid type: string "heavy", expected
/// f64` becomes `expected a number, got the text "heavy"`.
fn plain_words(msg: &str) -> String {
    let Some(rest) = msg.strip_prefix("invalid type: ") else {
        return msg.to_string();
    };
    let Some((got, want)) = rest.split_once(", expected ") else {
        return msg.to_string();
    };
    let got = if let Some(t) = got.strip_prefix("string ") {
        format!("the text {t}")
    } else if let Some(t) = got.strip_prefix("integer ") {
        format!("the whole number {}", t.trim_matches('`'))
    } else if let Some(t) = got.strip_prefix("floating point ") {
        format!("the number {}", t.trim_matches('`'))
    } else if let Some(t) = got.strip_prefix("boolean ") {
        t.trim_matches('`').to_string()
    } else if got == "sequence" {
        "a list".to_string()
    } else if got == "map" {
        "a table".to_string()
    } else {
        got.to_string()
    };
    let want = match want {
        "f64" | "f32" => "a number".to_string(),
        "u8" | "u16" | "u32" | "u64" | "usize" | "i32" | "i64" => "a whole number".to_string(),
        "a string" => "text in quotes".to_string(),
        w => w.to_string(),
    };
    format!("expected {want}, got {got}")
}

fn finite(file: &str, path: &str, value: f64) -> Result<()> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(InputError::new(
            file,
            format!("{path} must be a finite number, got {value}"),
        ))
    }
}

impl Case {
    /// Parses case-file text; `file` names it in messages.
    pub fn from_text(file: &str, text: &str) -> Result<Self> {
        let content: CaseFile = parse_toml(file, text)?;
        let case = Case {
            file: file.to_string(),
            content,
        };
        case.check_states()?;
        Ok(case)
    }

    fn check_states(&self) -> Result<()> {
        for (name, s) in [
            ("initial", &self.content.initial),
            ("final", &self.content.final_),
        ] {
            if let Some(s) = s {
                for (veh, v) in [("vehicle1", s.vehicle1), ("vehicle2", s.vehicle2)] {
                    for (field, x) in [("vx", v.vx), ("vy", v.vy), ("omega", v.omega)] {
                        finite(&self.file, &format!("[{name}] {veh}.{field}"), x)?;
                    }
                }
            }
        }
        Ok(())
    }

    /// The collision, checked by pim-core (messages name the vehicle and field).
    pub fn impact(&self) -> Result<pim_core::Impact> {
        let v = |s: &VehicleSection| Vehicle {
            mass: s.mass,
            yaw_inertia: s.yaw_inertia,
            heading: s.heading,
            d: s.d,
            phi: s.phi,
        };
        pim_core::Impact::new(Collision {
            vehicle1: v(&self.content.vehicle1),
            vehicle2: v(&self.content.vehicle2),
            crush_angle: self.content.impact.crush_angle,
        })
        .map_err(|e| InputError::new(&self.file, e))
    }

    /// The `[coefficients]` section, required and checked.
    pub fn coefficients(&self) -> Result<Coefficients> {
        let c = self.content.coefficients.ok_or_else(|| {
            InputError::new(&self.file, "missing section [coefficients] (e, mu, em)")
        })?;
        let c = Coefficients {
            e: c.e,
            mu: c.mu,
            em: c.em,
        };
        c.validate()
            .map_err(|e| InputError::new(&self.file, format!("[coefficients] {e}")))?;
        Ok(c)
    }

    /// Exactly one of `[initial]` / `[final]`: `(state, true)` for initial.
    pub fn known_state(&self) -> Result<(Velocities, bool)> {
        match (&self.content.initial, &self.content.final_) {
            (Some(i), None) => Ok((i.to_velocities(), true)),
            (None, Some(f)) => Ok((f.to_velocities(), false)),
            (Some(_), Some(_)) => Err(InputError::new(
                &self.file,
                "give either [initial] (solve forwards) or [final] (solve backwards), not both",
            )),
            (None, None) => Err(InputError::new(
                &self.file,
                "missing section [initial] (velocities at contact) or [final] (at separation)",
            )),
        }
    }
}
