//! The TOML case file of `pim solve`, `pim sensitivity` and `pim fit`.

pub use crate::error::Failure;
use pim_core::{Coefficients, Collision, Vehicle, VehicleVelocity, Velocities};
use serde::Deserialize;
use std::path::Path;

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

/// Reads a file that must be a small regular text file, with messages naming it.
pub fn read_text_file(path: &Path, max_bytes: u64) -> Result<String, Failure> {
    let name = path.display();
    let meta = std::fs::metadata(path)
        .map_err(|e| Failure::Input(format!("{name}: cannot read: {}", io_reason(&e))))?;
    if meta.is_dir() {
        return Err(Failure::Input(format!(
            "{name}: is a directory, expected a file"
        )));
    }
    if meta.len() > max_bytes {
        return Err(Failure::Input(format!(
            "{name}: is {} bytes, larger than the {} bytes accepted for this kind of file",
            meta.len(),
            max_bytes
        )));
    }
    let bytes = std::fs::read(path)
        .map_err(|e| Failure::Input(format!("{name}: cannot read: {}", io_reason(&e))))?;
    String::from_utf8(bytes).map_err(|e| {
        Failure::Input(format!(
            "{name}: is not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        ))
    })
}

/// A short reason for an I/O error.
pub fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file".to_string(),
        std::io::ErrorKind::PermissionDenied => "permission denied".to_string(),
        _ => e.to_string(),
    }
}

/// Line and column (1-based) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let upto = &text[..offset.min(text.len())];
    let line = upto.matches('\n').count() + 1;
    let col = upto.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// Parses TOML into `T`, with errors as `file:line:col: message`.
pub fn parse_toml<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T, Failure> {
    if text.trim().is_empty() {
        return Err(Failure::Input(format!("{file}: the file is empty")));
    }
    toml::from_str(text).map_err(|e| {
        let msg = e.message().trim().to_string();
        match e.span() {
            Some(span) => {
                let (line, col) = line_col(text, span.start);
                Failure::Input(format!("{file}:{line}:{col}: {msg}"))
            }
            None => Failure::Input(format!("{file}: {msg}")),
        }
    })
}

fn finite(file: &str, path: &str, value: f64) -> Result<(), Failure> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(Failure::Input(format!(
            "{file}: {path} must be a finite number, got {value}"
        )))
    }
}

impl Case {
    /// Loads and parses a case file.
    pub fn load(path: &Path) -> Result<Self, Failure> {
        let text = read_text_file(path, MAX_CASE_BYTES)?;
        Self::from_text(&path.display().to_string(), &text)
    }

    /// Parses case-file text; `file` names it in messages.
    pub fn from_text(file: &str, text: &str) -> Result<Self, Failure> {
        let content: CaseFile = parse_toml(file, text)?;
        let case = Case {
            file: file.to_string(),
            content,
        };
        case.check_states()?;
        Ok(case)
    }

    fn check_states(&self) -> Result<(), Failure> {
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
    pub fn impact(&self) -> Result<pim_core::Impact, Failure> {
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
        .map_err(|e| Failure::Input(format!("{}: {e}", self.file)))
    }

    /// The `[coefficients]` section, required and checked.
    pub fn coefficients(&self) -> Result<Coefficients, Failure> {
        let c = self.content.coefficients.ok_or_else(|| {
            Failure::Input(format!(
                "{}: missing section [coefficients] (e, mu, em)",
                self.file
            ))
        })?;
        let c = Coefficients {
            e: c.e,
            mu: c.mu,
            em: c.em,
        };
        c.validate()
            .map_err(|e| Failure::Input(format!("{}: [coefficients] {e}", self.file)))?;
        Ok(c)
    }

    /// Exactly one of `[initial]` / `[final]`: `(state, true)` for initial.
    pub fn known_state(&self) -> Result<(Velocities, bool), Failure> {
        match (&self.content.initial, &self.content.final_) {
            (Some(i), None) => Ok((i.to_velocities(), true)),
            (None, Some(f)) => Ok((f.to_velocities(), false)),
            (Some(_), Some(_)) => Err(Failure::Input(format!(
                "{}: give either [initial] (solve forwards) or [final] (solve backwards), not both",
                self.file
            ))),
            (None, None) => Err(Failure::Input(format!(
                "{}: missing section [initial] (velocities at contact) or [final] (at separation)",
                self.file
            ))),
        }
    }
}
