//! The tangential model's convex pieces, as data (their rows and candidates are written in
//! `tangential`).

use pim_core::FrictionSign;

/// The line of impulses at a fixed contact state and restitution (`Vn = -e vn`): along it the
/// impulse and the final tangential velocity are affine, `dPn = alpha dVt` and
/// `dPt = beta dVt`, and the normal impulse that pushes the vehicles apart has the sign
/// `sigma` (the sign of the frictionless impulse). All three are constants of the geometry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Line {
    pub alpha: f64,
    pub beta: f64,
    pub sigma: f64,
}

/// A contact mode of the tangential model with the signs that make it linear.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Mode {
    /// Sticking: `Vt = et vt` for an et of the range and `|Pt| <= friction_max |Pn|`; `s_vt`
    /// is the sign of `vt`.
    Stick { s_vt: f64 },
    /// Sliding on the side `s` (`Pt / Pn = s friction`) where sticking at some et of the range
    /// needs more than the friction limit on that side; `far` when that sticking impulse's
    /// normal part has the other sign (beyond the pole of the ratio on the line).
    Slide {
        s: FrictionSign,
        s_vt: f64,
        far: bool,
    },
}

impl Mode {
    /// The sign of `vt` the mode assumes.
    pub fn s_vt(&self) -> f64 {
        match *self {
            Mode::Stick { s_vt } | Mode::Slide { s_vt, .. } => s_vt,
        }
    }
}
