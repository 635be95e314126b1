//! The evidence against one separation state, to first order: what a fit that also holds other
//! evidence (the impact) needs of the run-out.

use super::evidence::{Evidence, Residual};
use super::problem::Problem;
use super::search::jacobian;
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
    let relative =
        problem(chassis, separation, evidence, turns, settings).difference_step(&lin.runout);
    let mut h = relative * (1.0 + chassis.friction);
    if chassis.friction + h > crate::chassis::MAX_FRICTION {
        h = -h;
    }
    let mut stepped = chassis.clone();
    stepped.friction += h;
    stepped.rolling_resistance = stepped.rolling_resistance.min(0.5 * stepped.friction);
    let p = problem(&stepped, separation, evidence, turns, settings);
    let other = p.stepped(&theta, &lin.runout)?;
    lin.evaluations += p.work.load(std::sync::atomic::Ordering::Relaxed);
    lin.runouts += 1;
    lin.friction = Some((&other - &lin.weighted) / h);
    Ok(lin)
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
