//! `[contact_sigma]` as written (see [`crate::contact_pose`]).

use serde::Deserialize;

/// `[contact_sigma]` as written: standard deviations in the case's length unit and degrees.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactSigmaSection {
    /// Vehicle 1's pose.
    #[serde(default)]
    pub vehicle1: Option<PoseSigma>,
    /// Vehicle 2's pose.
    #[serde(default)]
    pub vehicle2: Option<PoseSigma>,
    /// The impact centre in the scene (the case's axes).
    #[serde(default)]
    pub centre: Option<AxesSigma>,
    /// The crush surface's angle, degrees.
    #[serde(default)]
    pub crush_angle: Option<f64>,
    /// Not read from the file: the unknowns (bit `i` for the `i`-th of
    /// [`Case::contact_unknowns`](crate::case::Case::contact_unknowns)) whose prior is left out,
    /// as [`Case::without_contact_prior`](crate::case::Case::without_contact_prior) leaves one
    /// out.
    #[serde(skip)]
    pub priors_left_out: u32,
}

/// One vehicle's pose at contact: standard deviations.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSigma {
    /// Its heading, degrees.
    #[serde(default)]
    pub heading: Option<f64>,
    /// Its CG in the scene (the case's axes).
    #[serde(default)]
    pub position: Option<AxesSigma>,
    /// The impact centre on the vehicle (x forward, y to the left as written).
    #[serde(default)]
    pub impact_point: Option<AxesSigma>,
}

/// Standard deviations along two axes, either optional.
#[derive(Debug, Clone, Copy, Default, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AxesSigma {
    /// Along x.
    #[serde(default)]
    pub x: Option<f64>,
    /// Along y.
    #[serde(default)]
    pub y: Option<f64>,
}
