//! A point of the search: each scene linearised at a separation state, and an admissible
//! impact with the true cost of its scene.

use crate::error::Result;
use crate::problem::{Reconstruction, SceneVehicle, Settings};
use pim_core::Velocities;
use pim_fit::{MomentBranch, Solution};
use pim_runout::{differentiate, differentiate_zones, linearise, Chassis, Linearised, Motion};

/// The scene of one vehicle linearised at one separation state.
#[derive(Debug, Clone)]
pub(crate) struct Lin {
    /// Index of the vehicle in [`Reconstruction::scene`].
    pub(crate) vehicle: usize,
    /// Its count of turns (0 when the rest heading is not given).
    pub(crate) turns: i64,
    /// The separation velocity `(vx, vy, yaw_rate)` linearised at.
    pub(crate) at: [f64; 3],
    /// The road friction of its run-out.
    pub(crate) mu: f64,
    /// The friction of each zone under its run-out (the chassis's order).
    pub(crate) zone_mus: Vec<f64>,
    /// The rolling resistance of its run-out.
    pub(crate) rolling_resistance: f64,
    pub(crate) lin: Linearised,
}

impl Lin {
    /// The derivatives of the weighted residuals (a `Lin` of the search is linearised with
    /// them, except the trial points [`Point::scene`] holds).
    pub(crate) fn jacobian(&self) -> &nalgebra::DMatrix<f64> {
        self.lin
            .jacobian
            .as_ref()
            .expect("linearised with its Jacobian")
    }
}

/// A point of the search: an admissible impact and its scene.
#[derive(Debug, Clone)]
pub(crate) struct Point {
    pub(crate) branch: MomentBranch,
    pub(crate) solution: Solution,
    pub(crate) certificate: pim_fit::Certificate,
    pub(crate) contact: f64,
    pub(crate) scene: Vec<Lin>,
    /// The fitted road frictions ([`Reconstruction::frictions`]).
    pub(crate) mus: Vec<f64>,
    pub(crate) total: f64,
}

/// The friction scene vehicle `vehicle` runs out on with the fitted frictions `mus` (its
/// chassis's own when not fitted).
pub(crate) fn friction_for(r: &Reconstruction, vehicle: usize, mus: &[f64]) -> f64 {
    r.friction_of(vehicle)
        .and_then(|g| mus.get(g).copied())
        .unwrap_or(r.scene[vehicle].chassis.friction)
}

/// The stated frictions: where every search starts.
pub(crate) fn stated_frictions(r: &Reconstruction) -> Vec<f64> {
    r.frictions.iter().map(|f| f.value).collect()
}

/// The separation velocity of scene vehicle `v` in a state.
pub(crate) fn velocity_of(state: &Velocities, s: &SceneVehicle) -> [f64; 3] {
    let v = if s.id.index() == 0 {
        state.vehicle1
    } else {
        state.vehicle2
    };
    [v.vx, v.vy, v.omega]
}

pub(crate) fn linearised(
    r: &Reconstruction,
    settings: &Settings,
    vehicle: usize,
    turns: i64,
    at: [f64; 3],
    jacobian: bool,
    mus: &[f64],
) -> Result<Lin> {
    let (chassis, start) = runout_of(r, vehicle, at, mus);
    let s = &r.scene[vehicle];
    let lin = linearise(
        &chassis,
        &start,
        &s.evidence,
        turns,
        &settings.runout,
        false,
    )?;
    let lin = Lin {
        vehicle,
        turns,
        at,
        mu: chassis.friction,
        zone_mus: chassis.zones.iter().map(|z| z.friction).collect(),
        rolling_resistance: chassis.rolling_resistance,
        lin,
    };
    if jacobian {
        differentiated(r, settings, lin, mus)
    } else {
        Ok(lin)
    }
}

/// `lin` (linearised with the frictions `mus`) with its derivatives: those with respect to
/// the separation velocity, and the road friction's where it is fitted; its run-out is not
/// simulated again.
pub(crate) fn differentiated(
    r: &Reconstruction,
    settings: &Settings,
    lin: Lin,
    mus: &[f64],
) -> Result<Lin> {
    let (chassis, start) = runout_of(r, lin.vehicle, lin.at, mus);
    let s = &r.scene[lin.vehicle];
    let friction_too = r.friction_of(lin.vehicle).is_some();
    let mut d = differentiate(
        lin.lin,
        &chassis,
        &start,
        &s.evidence,
        lin.turns,
        &settings.runout,
        friction_too,
    )?;
    if r.zone_frictions_of(lin.vehicle).next().is_some() {
        d = differentiate_zones(
            d,
            &chassis,
            &start,
            &s.evidence,
            lin.turns,
            &settings.runout,
        )?;
    }
    Ok(Lin { lin: d, ..lin })
}

/// The chassis scene vehicle `vehicle` runs out with (the fitted frictions `mus` where they
/// are fitted, the road's and each zone's, the rolling resistance at most half of each) and
/// its separation state at velocity `at`.
fn runout_of(r: &Reconstruction, vehicle: usize, at: [f64; 3], mus: &[f64]) -> (Chassis, Motion) {
    let s = &r.scene[vehicle];
    let start = Motion {
        vx: at[0],
        vy: at[1],
        yaw_rate: at[2],
        ..s.pose
    };
    let mut chassis = s.chassis.clone();
    let mut lowest = f64::INFINITY;
    if r.friction_of(vehicle).is_some() {
        chassis.friction = friction_for(r, vehicle, mus);
        lowest = chassis.friction;
    }
    for (g, k) in r.zone_frictions_of(vehicle) {
        let mu = mus.get(g).copied().unwrap_or(r.frictions[g].value);
        chassis.zones[k].friction = mu;
        lowest = lowest.min(mu);
    }
    chassis.rolling_resistance = chassis.rolling_resistance.min(0.5 * lowest);
    (chassis, start)
}
