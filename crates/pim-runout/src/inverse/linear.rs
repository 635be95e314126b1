//! The evidence against one separation state, to first order: what a fit that also holds other
//! evidence (the impact) needs of the run-out.

use super::evidence::{Evidence, Residual};
use super::levenberg::jacobian;
use super::problem::Problem;
use crate::chassis::{Chassis, Motion};
use crate::error::Result;
use crate::simulate::{Runout, Settings};
use nalgebra::{DMatrix, DVector};
use std::f64::consts::TAU;

/// The scene's residuals at one separation state and their derivatives.
#[derive(Debug, Clone)]
pub struct Linearised {
    /// Every piece of evidence against the run-out from the state (fitted minus given).
    pub residuals: Vec<Residual>,
    /// The residuals in units of their standard deviations.
    pub weighted: DVector<f64>,
    /// Derivatives of [`Linearised::weighted`] with respect to the separation velocity
    /// `(vx, vy, yaw_rate)` (rows: residuals; columns: m/s, m/s, rad/s), by forward differences
    /// of run-outs integrated through this run-out's steps (internal numerical
    /// differentiation, see the [module docs](super)); `None` when not asked for.
    pub jacobian: Option<DMatrix<f64>>,
    /// The sum of the squared weighted residuals.
    pub cost: f64,
    /// The run-out from the state.
    pub runout: Runout,
    /// Run-outs simulated.
    pub runouts: usize,
    /// Right-hand side evaluations of those run-outs: the work of the linearisation.
    pub evaluations: u64,
    /// Derivatives of [`Linearised::weighted`] with respect to the road friction, by a forward
    /// difference (one more run-out), when asked for ([`linearise_with_friction`]).
    pub friction: Option<DVector<f64>>,
    /// Derivatives of [`Linearised::weighted`] with respect to each friction zone's friction,
    /// in the order of the chassis's [`zones`](crate::Chassis::zones), when asked for
    /// ([`differentiate_zones`]); empty otherwise.
    pub zones: Vec<DVector<f64>>,
}

/// The residuals of `evidence` against the run-out from `separation` (its position, heading and
/// velocities), the rest heading compared with the heading at separation turned to the nearest
/// rest heading plus `turns` full turns (as candidate `turns` of
/// [`estimate`](super::estimate) compares it), and with `jacobian` their derivatives. The road
/// friction is the chassis's: [`Evidence::friction_sigma`] is not read here.
///
/// # Errors
/// [`RunoutError::Input`](crate::RunoutError::Input) for a state beyond the searched range or
/// input the model cannot use.
pub fn linearise(
    chassis: &Chassis,
    separation: &Motion,
    evidence: &Evidence,
    turns: i64,
    settings: &Settings,
    jacobian_too: bool,
) -> Result<Linearised> {
    let p = problem(chassis, separation, evidence, turns, settings);
    let theta = [separation.vx, separation.vy, separation.yaw_rate];
    let runout = p.runout(&theta)?;
    let residuals = p.residuals(&theta, &runout);
    let weighted =
        DVector::from_iterator(residuals.len(), residuals.iter().map(|x| x.value / x.sigma));
    let lin = Linearised {
        cost: weighted.norm_squared(),
        residuals,
        weighted,
        jacobian: None,
        runout,
        runouts: 1,
        evaluations: p.work.load(std::sync::atomic::Ordering::Relaxed),
        friction: None,
        zones: Vec::new(),
    };
    if jacobian_too {
        differentiate(lin, chassis, separation, evidence, turns, settings, false)
    } else {
        Ok(lin)
    }
}

/// The derivatives of `lin`, a linearisation from the same chassis, state, evidence, turns
/// and settings (made by [`linearise`] without them, say, when it was only a trial point),
/// added without simulating its run-out again: [`Linearised::jacobian`] and, with
/// `friction_too`, [`Linearised::friction`] as [`linearise_with_friction`] computes them.
/// Derivatives `lin` already has are kept; [`Linearised::runouts`] and
/// [`Linearised::evaluations`] grow by the run-outs the new ones took.
///
/// # Errors
/// As [`linearise`].
pub fn differentiate(
    mut lin: Linearised,
    chassis: &Chassis,
    separation: &Motion,
    evidence: &Evidence,
    turns: i64,
    settings: &Settings,
    friction_too: bool,
) -> Result<Linearised> {
    let theta = [separation.vx, separation.vy, separation.yaw_rate];
    if lin.jacobian.is_none() {
        let p = problem(chassis, separation, evidence, turns, settings);
        let mut runouts = 0;
        lin.jacobian = Some(jacobian(
            &p,
            &theta,
            &lin.weighted,
            &lin.runout,
            &mut runouts,
        )?);
        lin.runouts += runouts;
        lin.evaluations += p.work.load(std::sync::atomic::Ordering::Relaxed);
    }
    if !friction_too || lin.friction.is_some() {
        return Ok(lin);
    }
    let d = friction_derivative(
        &mut lin, chassis, separation, evidence, turns, settings, None,
    )?;
    lin.friction = Some(d);
    Ok(lin)
}

/// `lin` (from the same chassis, state, evidence, turns and settings) with the derivatives of
/// its weighted residuals with respect to each friction zone's friction
/// ([`Linearised::zones`]), each by one more run-out stepped as the road friction's is
/// ([`linearise_with_friction`]): a zone the run-out never reaches has derivatives 0. The
/// rolling resistance is held at most half the stepped zone's friction, as a fitted road
/// friction holds it. Derivatives `lin` already has are kept.
///
/// # Errors
/// As [`linearise`].
pub fn differentiate_zones(
    mut lin: Linearised,
    chassis: &Chassis,
    separation: &Motion,
    evidence: &Evidence,
    turns: i64,
    settings: &Settings,
) -> Result<Linearised> {
    if lin.zones.len() == chassis.zones.len() {
        return Ok(lin);
    }
    let mut zones = Vec::with_capacity(chassis.zones.len());
    for k in 0..chassis.zones.len() {
        zones.push(friction_derivative(
            &mut lin,
            chassis,
            separation,
            evidence,
            turns,
            settings,
            Some(k),
        )?);
    }
    lin.zones = zones;
    Ok(lin)
}

/// The derivatives of `lin`'s weighted residuals with respect to the road friction (`zone`
/// `None`) or zone `k`'s, by a forward difference through `lin`'s run-out (backward where the
/// step would pass [`MAX_FRICTION`](crate::MAX_FRICTION)); the run-out it takes is counted in
/// `lin`.
fn friction_derivative(
    lin: &mut Linearised,
    chassis: &Chassis,
    separation: &Motion,
    evidence: &Evidence,
    turns: i64,
    settings: &Settings,
    zone: Option<usize>,
) -> Result<DVector<f64>> {
    let theta = [separation.vx, separation.vy, separation.yaw_rate];
    let relative =
        problem(chassis, separation, evidence, turns, settings).difference_step(&lin.runout);
    let mut stepped = chassis.clone();
    let mu = match zone {
        None => &mut stepped.friction,
        Some(k) => &mut stepped.zones[k].friction,
    };
    let mut h = relative * (1.0 + *mu);
    if *mu + h > crate::chassis::MAX_FRICTION {
        h = -h;
    }
    *mu += h;
    let stepped_mu = *mu;
    stepped.rolling_resistance = stepped.rolling_resistance.min(0.5 * stepped_mu);
    let p = problem(&stepped, separation, evidence, turns, settings);
    let other = p.stepped(&theta, &lin.runout)?;
    lin.evaluations += p.work.load(std::sync::atomic::Ordering::Relaxed);
    lin.runouts += 1;
    Ok((&other - &lin.weighted) / h)
}

/// The problem of candidate `turns` from `separation`, the friction held.
fn problem<'a>(
    chassis: &'a Chassis,
    separation: &Motion,
    evidence: &'a Evidence,
    turns: i64,
    settings: &'a Settings,
) -> Problem<'a> {
    let nearest = evidence
        .rest
        .and_then(|r| r.heading)
        .map(|h| h + TAU * ((separation.heading - h) / TAU).round());
    Problem {
        chassis,
        start: *separation,
        evidence,
        heading: nearest.map(|h| h + TAU * turns as f64),
        settings,
        estimate_friction: false,
        work: Default::default(),
    }
}

/// As [`linearise`] with `jacobian_too`, and the derivatives with respect to the road friction
/// too ([`Linearised::friction`]): the friction stepped by `1e-6 (1 + friction)` and the
/// stepped run-out integrated through the nominal's steps (by `sqrt(rtol) (1 + friction)` on a
/// run-out of its own where that cannot be replayed; back when the step would pass
/// [`MAX_FRICTION`](crate::MAX_FRICTION)), the rolling resistance held at most half the
/// friction as the scene's own search holds it.
///
/// # Errors
/// As [`linearise`].
pub fn linearise_with_friction(
    chassis: &Chassis,
    separation: &Motion,
    evidence: &Evidence,
    turns: i64,
    settings: &Settings,
) -> Result<Linearised> {
    let lin = linearise(chassis, separation, evidence, turns, settings, false)?;
    differentiate(lin, chassis, separation, evidence, turns, settings, true)
}
