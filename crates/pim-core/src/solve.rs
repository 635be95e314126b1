//! Forward and backward solution of the six equations.

use crate::coefficients::{Coefficients, SolveOptions, TangentialCondition};
use crate::equations::{assemble, impulse_of, tangential_velocity_row, LinearSystem};
use crate::error::{Equation, PimError, Result};
use crate::friction::{friction_direction, CriticalImpulse, FrictionBasis, FrictionSign};
use crate::model::{Impact, Velocities};
use crate::report::{build_report, ImpactReport};
use nalgebra::{Matrix6, Vector6, LU, U6};

/// Relative pivot below which a row-equilibrated 6x6 system is treated as singular.
const SINGULAR_PIVOT: f64 = 1e-11;

/// A factorised, row-equilibrated 6x6 matrix.
struct Factor {
    lu: LU<f64, U6, U6>,
    scale: Vector6<f64>,
}

impl Factor {
    /// Scales every row to unit max-norm, factorises, and rejects a (near) singular matrix.
    /// `Err(row)` gives the index of the equation that carries the dependency.
    fn new(m: &Matrix6<f64>) -> std::result::Result<Self, usize> {
        let mut scale = Vector6::zeros();
        let mut scaled = *m;
        for i in 0..6 {
            let s = m.row(i).amax();
            if s == 0.0 || !s.is_finite() {
                return Err(i);
            }
            scale[i] = 1.0 / s;
            scaled.row_mut(i).scale_mut(1.0 / s);
        }
        let lu = scaled.lu();
        let u = lu.u();
        let min_pivot = (0..6)
            .map(|i| u[(i, i)].abs())
            .fold(f64::INFINITY, f64::min);
        if min_pivot.is_nan() || min_pivot <= SINGULAR_PIVOT {
            return Err(dependent_row(&scaled));
        }
        Ok(Factor { lu, scale })
    }

    /// Solves `m y = rhs`.
    fn solve(&self, rhs: &Vector6<f64>) -> Vector6<f64> {
        let b = rhs.component_mul(&self.scale);
        self.lu
            .solve(&b)
            .unwrap_or_else(|| Vector6::repeat(f64::NAN))
    }

    /// Solves `m y = e_i` (unit vector of row i).
    fn solve_unit(&self, i: usize) -> Vector6<f64> {
        let mut b = Vector6::zeros();
        b[i] = self.scale[i];
        self.lu
            .solve(&b)
            .unwrap_or_else(|| Vector6::repeat(f64::NAN))
    }
}

/// The row with the largest weight in the left null vector of a singular matrix.
fn dependent_row(m: &Matrix6<f64>) -> usize {
    // Bounded iterations: nalgebra's plain `svd` never stops on NaN.
    let Some(svd) = m.try_svd(true, false, f64::EPSILON, 500) else {
        return 0;
    };
    let Some(u) = svd.u else { return 0 };
    let k = svd.singular_values.imin();
    u.column(k).iamax()
}

fn singular_error(system: &LinearSystem, row: usize, backward: bool, c: &Coefficients) -> PimError {
    let equation = system.equations[row];
    let hint = match (backward, equation) {
        (true, Equation::Restitution) if c.e == 0.0 => {
            "with e = 0 the separation velocities say nothing about the normal approach velocity, \
             so they do not determine the contact velocities; solve forwards or use e > 0"
                .to_string()
        }
        (true, Equation::MomentRestitution) if c.em == 0.0 => {
            "with em = 0 the separation yaw rates say nothing about the relative yaw rate at \
             contact, so they do not determine the contact velocities; use em != 0"
                .to_string()
        }
        (true, Equation::NoSlip) => "the no-slip condition involves only separation velocities, \
             so solving backwards it gives no information on the contact velocities; use the \
             sliding form with mu"
            .to_string(),
        _ => format!(
            "it is a linear combination of the other equations for this geometry and these \
             coefficients (e = {}, mu = {}, em = {})",
            c.e, c.mu, c.em
        ),
    };
    PimError::Singular { equation, hint }
}

/// Separation state and, under the sliding form, the signed critical friction ratio mu_max.
struct ForwardSolution {
    separation: Vector6<f64>,
    mu_max: Option<f64>,
}

fn forward(
    impact: &Impact,
    coefficients: &Coefficients,
    x: &Vector6<f64>,
    sign: FrictionSign,
    options: &SolveOptions,
) -> Result<ForwardSolution> {
    let system = assemble(impact, coefficients, sign, options);
    let factor =
        Factor::new(&system.f).map_err(|row| singular_error(&system, row, false, coefficients))?;
    let rhs = -(system.g * x);
    let sep = factor.solve(&rhs);
    let mu_max = match options.tangential {
        TangentialCondition::NoSlip => critical_ratio(impact, x, &sep, sign),
        TangentialCondition::Sliding => {
            // The no-slip system differs from this one in row 5 only: X(l) = sep + l z satisfies
            // every other row; choose l so that Vt = 0.
            let z = factor.solve_unit(4);
            let tv = tangential_velocity_row(impact);
            let denom = (tv * z)[0];
            let z_scale = (tv.abs() * z.abs())[0];
            if denom.is_nan() || denom.abs() <= 1e-12 * z_scale {
                None
            } else {
                let lambda = -(tv * sep)[0] / denom;
                critical_ratio(impact, x, &(sep + z * lambda), sign)
            }
        }
    };
    Ok(ForwardSolution {
        separation: sep,
        mu_max,
    })
}

/// mu_max = (Pt / Pn) * sgn(vn) sgn(vt), from a no-slip separation state.
fn critical_ratio(
    impact: &Impact,
    x: &Vector6<f64>,
    no_slip_sep: &Vector6<f64>,
    sign: FrictionSign,
) -> Option<f64> {
    impulse_of(impact, &(no_slip_sep - x)).mu_max(sign)
}

/// The no-slip impulse on vehicle 1 of a contact state (equation 5a instead of 5; the friction
/// sign does not enter that system), `None` when the no-slip system is singular.
fn no_slip_impulse(
    impact: &Impact,
    coefficients: &Coefficients,
    x: &Vector6<f64>,
    options: &SolveOptions,
) -> Option<CriticalImpulse> {
    let opts = SolveOptions {
        tangential: TangentialCondition::NoSlip,
        ..*options
    };
    let system = assemble(impact, coefficients, FrictionSign::Positive, &opts);
    let factor = Factor::new(&system.f).ok()?;
    let sep = factor.solve(&-(system.g * x));
    Some(impulse_of(impact, &(sep - x)))
}

/// The sign factor of equation 5 for a contact state, by the one friction rule
/// ([`crate::friction_direction`]): the sliding direction `sgn(vn) sgn(vt)` where the contact
/// point slides, else the direction of the no-slip impulse at these coefficients (which depends
/// on e, e_m and the moment form, not on mu).
pub fn contact_friction(
    impact: &Impact,
    coefficients: &Coefficients,
    initial: &Velocities,
    options: &SolveOptions,
) -> (FrictionSign, FrictionBasis) {
    friction_direction(impact.sliding_sign(initial), || {
        no_slip_impulse(impact, coefficients, &initial.to_vector(), options)
    })
}

/// The separation velocities for given contact velocities, without the derived quantities.
///
/// This is the bare solve of `F X = -G x` (one 6x6 LU).
pub fn separation_velocities(
    impact: &Impact,
    coefficients: &Coefficients,
    initial: &Velocities,
    options: &SolveOptions,
) -> Result<Velocities> {
    coefficients.validate()?;
    initial.validate()?;
    impact.check_approach(initial)?;
    let (sign, _) = contact_friction(impact, coefficients, initial, options);
    let system = assemble(impact, coefficients, sign, options);
    let factor =
        Factor::new(&system.f).map_err(|row| singular_error(&system, row, false, coefficients))?;
    let x = initial.to_vector();
    Ok(Velocities::from_vector(&factor.solve(&-(system.g * x))))
}

/// Solves forwards: separation velocities from the contact velocities, with every derived result.
///
/// Errors: a bad coefficient or velocity, vehicles that do not approach at C, a singular system.
///
/// ```
/// use pim_core::*;
/// let collision = Collision {
///     vehicle1: Vehicle { mass: 1036.0, yaw_inertia: 1348.0, heading: 0.0, d: 1.4, phi: 0.0 },
///     vehicle2: Vehicle { mass: 2189.0, yaw_inertia: 5287.0, heading: 90.0, d: 1.6, phi: -30.0 },
///     crush_angle: 0.0,
/// };
/// let impact = Impact::new(collision).unwrap();
/// let initial = Velocities {
///     vehicle1: VehicleVelocity { vx: -9.48, vy: 0.0, omega: 0.0 },
///     vehicle2: VehicleVelocity { vx: 0.0, vy: 9.48, omega: 0.0 },
/// };
/// let c = Coefficients { e: 0.467, mu: 0.486, em: 1.0 };
/// let r = solve_forward(&impact, &c, &initial, &SolveOptions::default()).unwrap();
/// // momentum is conserved
/// let p0 = 1036.0 * -9.48;
/// let p1 = 1036.0 * r.separation.vehicle1.vx + 2189.0 * r.separation.vehicle2.vx;
/// assert!((p0 - p1).abs() < 1e-9);
/// assert!(r.energy.loss_percent > 0.0);
/// ```
pub fn solve_forward(
    impact: &Impact,
    coefficients: &Coefficients,
    initial: &Velocities,
    options: &SolveOptions,
) -> Result<ImpactReport> {
    coefficients.validate()?;
    initial.validate()?;
    impact.check_approach(initial)?;
    let (sign, basis) = contact_friction(impact, coefficients, initial, options);
    let x = initial.to_vector();
    let sol = forward(impact, coefficients, &x, sign, options)?;
    Ok(build_report(
        impact,
        coefficients,
        options,
        initial,
        &Velocities::from_vector(&sol.separation),
        (sign, basis),
        sol.mu_max,
    ))
}

/// Solves backwards: contact velocities from the separation velocities (the same six equations
/// solved for the other half of the unknowns), with every derived result.
///
/// Under the sliding form the friction direction depends on the unknown contact state; both
/// directions are tried and a direction is kept when the recovered contact velocities approach at
/// C and slide that way. When both directions pass, the physically admissible one is kept
/// (0 <= mu <= mu_max, no energy created); when both or neither are admissible the problem has two
/// answers and an [`PimError::InconsistentSliding`] error says so (use
/// [`solve_backward_with_sign`] if the direction is known).
/// Errors: as [`solve_forward`], plus a singular backward system (e = 0 or em = 0 leave the
/// contact state undetermined) and data for which no friction direction is consistent.
pub fn solve_backward(
    impact: &Impact,
    coefficients: &Coefficients,
    separation: &Velocities,
    options: &SolveOptions,
) -> Result<ImpactReport> {
    coefficients.validate()?;
    separation.validate()?;
    impact.check_barrier_state(separation)?;
    let signs: &[FrictionSign] = match options.tangential {
        TangentialCondition::Sliding => &FrictionSign::BOTH,
        TangentialCondition::NoSlip => &[FrictionSign::Positive],
    };
    backward(impact, coefficients, separation, options, signs)
}

/// Solves backwards when the sign factor of equation 5 is known: `friction_sign` is
/// `sgn(vn) sgn(vt)` of the contact state (+1 or -1), or where it does not slide the direction
/// of its no-slip impulse. The recovered contact state must give that sign by the friction rule
/// ([`contact_friction`]), or the result is an [`PimError::InconsistentSliding`] error.
pub fn solve_backward_with_sign(
    impact: &Impact,
    coefficients: &Coefficients,
    separation: &Velocities,
    options: &SolveOptions,
    friction_sign: FrictionSign,
) -> Result<ImpactReport> {
    coefficients.validate()?;
    separation.validate()?;
    impact.check_barrier_state(separation)?;
    backward(impact, coefficients, separation, options, &[friction_sign])
}

fn backward(
    impact: &Impact,
    coefficients: &Coefficients,
    separation: &Velocities,
    options: &SolveOptions,
    signs: &[FrictionSign],
) -> Result<ImpactReport> {
    let xf = separation.to_vector();
    let no_slip = options.tangential == TangentialCondition::NoSlip;
    // For each assumed sliding direction: the contact state, or why it does not fit.
    let mut consistent: Vec<(FrictionSign, Velocities)> = Vec::new();
    let mut rejected: Vec<(FrictionSign, PimError)> = Vec::new();
    for &s in signs {
        let system = assemble(impact, coefficients, s, options);
        let factor = match Factor::new(&system.g) {
            Ok(f) => f,
            Err(row) => {
                rejected.push((s, singular_error(&system, row, true, coefficients)));
                continue;
            }
        };
        let x = Velocities::from_vector(&factor.solve(&-(system.f * xf)));
        if let Err(e) = impact.check_approach(&x) {
            rejected.push((s, e));
        } else if no_slip || contact_friction(impact, coefficients, &x, options).0 == s {
            consistent.push((s, x));
        } else {
            rejected.push((
                s,
                PimError::InconsistentSliding(
                    "the recovered contact velocities slide the other way".to_string(),
                ),
            ));
        }
    }
    if consistent.is_empty() {
        // One assumption only, or the same failure for both: return it as it is.
        if rejected.len() == 1
            || rejected
                .iter()
                .all(|(_, e)| matches!(e, PimError::Singular { .. }))
        {
            return Err(rejected.swap_remove(0).1);
        }
        let parts: Vec<String> = rejected
            .iter()
            .map(|(s, e)| format!("assuming sgn(vn) sgn(vt) = {:+}: {e}", s.value()))
            .collect();
        return Err(PimError::InconsistentSliding(format!(
            "no contact state fits these separation velocities with mu = {}; {}",
            coefficients.mu,
            parts.join("; ")
        )));
    }
    let no_slip_opts = SolveOptions {
        tangential: TangentialCondition::NoSlip,
        ..*options
    };
    let mut reports: Vec<ImpactReport> = consistent
        .iter()
        .map(|(sign, initial)| {
            let mu_max = forward(
                impact,
                coefficients,
                &initial.to_vector(),
                *sign,
                &no_slip_opts,
            )
            .ok()
            .and_then(|s| s.mu_max);
            build_report(
                impact,
                coefficients,
                options,
                initial,
                separation,
                (*sign, basis_of(impact, initial)),
                mu_max,
            )
        })
        .collect();
    if reports.len() == 2 && coefficients.mu != 0.0 {
        // Both directions reproduce the data; a real contact state must also be admissible
        // (0 <= mu <= mu_max, no energy created).
        let admissible: Vec<bool> = reports.iter().map(|r| r.admissibility.admissible).collect();
        match admissible.as_slice() {
            [true, false] => reports.truncate(1),
            [false, true] => {
                reports.swap_remove(0);
            }
            _ => {
                return Err(PimError::InconsistentSliding(format!(
                    "both friction directions fit these separation velocities with mu = {} and \
                     both are {} (contact states differ: vehicle1 vx {:.3} vs {:.3} m/s); the \
                     backward problem has two answers, solve forwards from one of them",
                    coefficients.mu,
                    if admissible[0] {
                        "admissible"
                    } else {
                        "inadmissible"
                    },
                    reports[0].initial.vehicle1.vx,
                    reports[1].initial.vehicle1.vx
                )));
            }
        }
    }
    Ok(reports.swap_remove(0))
}

/// The signed critical impulse ratio mu_max for a contact state: the mu of equation 5 at which
/// the tangential relative velocity at separation is zero (`None` when the normal impulse
/// vanishes or the no-slip system is singular).
pub fn critical_friction(
    impact: &Impact,
    coefficients: &Coefficients,
    initial: &Velocities,
    options: &SolveOptions,
) -> Result<Option<f64>> {
    coefficients.validate()?;
    initial.validate()?;
    impact.check_approach(initial)?;
    let (sign, _) = contact_friction(impact, coefficients, initial, options);
    let opts = SolveOptions {
        tangential: TangentialCondition::NoSlip,
        ..*options
    };
    Ok(forward(impact, coefficients, &initial.to_vector(), sign, &opts)?.mu_max)
}

/// Derived results (impulses, delta-V, energy, mu_max, admissibility) for a given pair of
/// states, for example a fitted one, with the sign factor of equation 5 it was computed with
/// (see [`contact_friction`]). The states are taken as they are; their equation residuals are in
/// [`ImpactReport::residuals`].
pub fn analyse(
    impact: &Impact,
    coefficients: &Coefficients,
    options: &SolveOptions,
    initial: &Velocities,
    separation: &Velocities,
    friction_sign: FrictionSign,
) -> Result<ImpactReport> {
    coefficients.validate()?;
    initial.validate()?;
    separation.validate()?;
    let sign = friction_sign;
    let no_slip = SolveOptions {
        tangential: TangentialCondition::NoSlip,
        ..*options
    };
    let mu_max = forward(impact, coefficients, &initial.to_vector(), sign, &no_slip)
        .ok()
        .and_then(|s| s.mu_max);
    Ok(build_report(
        impact,
        coefficients,
        options,
        initial,
        separation,
        (sign, basis_of(impact, initial)),
        mu_max,
    ))
}

/// Whether a contact state's friction sign comes from its sliding or from its no-slip impulse.
fn basis_of(impact: &Impact, initial: &Velocities) -> FrictionBasis {
    if impact.sliding_sign(initial).is_some() {
        FrictionBasis::Sliding
    } else {
        FrictionBasis::NoSlipImpulse
    }
}
