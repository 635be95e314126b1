//! Derived results of a solve: impulses, delta-V, energy, mu_max, sliding and admissibility.

use crate::coefficients::{Coefficients, SolveOptions, TangentialCondition};
use crate::equations::{assemble, impulse_of, LinearSystem};
use crate::error::{Equation, VehicleId};
use crate::friction::{
    classify_friction, creates_energy, FrictionBasis, FrictionSign, TangentialOutcome, REPORT_TOL,
};
use crate::model::{Impact, Velocities};
use serde::{Deserialize, Serialize};

/// Velocity of each vehicle's material point at the impact centre C, m/s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ContactPoints {
    /// `[x, y]` of vehicle 1's point at C, at contact.
    pub vehicle1_initial: [f64; 2],
    /// `[x, y]` of vehicle 2's point at C, at contact.
    pub vehicle2_initial: [f64; 2],
    /// `[x, y]` of vehicle 1's point at C, at separation.
    pub vehicle1_final: [f64; 2],
    /// `[x, y]` of vehicle 2's point at C, at separation.
    pub vehicle2_final: [f64; 2],
}

/// Relative velocity at C (vehicle 1 minus vehicle 2) along the crush-surface normal n and tangent t, m/s.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RelativeVelocity {
    /// vn at contact.
    pub normal_initial: f64,
    /// vt at contact.
    pub tangential_initial: f64,
    /// Vn at separation.
    pub normal_final: f64,
    /// Vt at separation.
    pub tangential_final: f64,
}

/// The impulses acting on vehicle 1 (vehicle 2 receives the opposite).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Impulse {
    /// Px = m1 (V1x - v1x), N s.
    pub px: f64,
    /// Py = m1 (V1y - v1y), N s.
    pub py: f64,
    /// Pn = P . n, N s.
    pub normal: f64,
    /// Pt = P . t, N s.
    pub tangential: f64,
    /// Moment impulse on vehicle 1 at C, M = I1 (W1 - w1) - r1 x P, N m s.
    pub moment: f64,
}

/// Velocity change of one vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct DeltaV {
    /// V x - v x, m/s.
    pub dvx: f64,
    /// V y - v y, m/s.
    pub dvy: f64,
    /// W - w, rad/s.
    pub domega: f64,
    /// |V - v|, m/s.
    pub magnitude: f64,
    /// Direction of V - v (the principal direction of force) to the fixed x axis, degrees in (-180, 180].
    pub direction: f64,
}

/// What a reconstructionist reads for one vehicle: speeds, delta-V in the vehicle's own axes,
/// the principal direction of force and the yaw-rate change.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct VehicleResult {
    /// Direction the nose points, degrees counter-clockwise from the fixed x axis, (-180, 180].
    pub heading: f64,
    /// CG speed at contact, m/s.
    pub speed_initial: f64,
    /// CG speed at separation, m/s.
    pub speed_final: f64,
    /// |V - v|, m/s.
    pub delta_v: f64,
    /// Delta-V along the vehicle's forward axis (what an EDR's longitudinal channel records),
    /// m/s; negative when the vehicle is slowed, as in a frontal impact.
    pub delta_v_longitudinal: f64,
    /// Delta-V along the vehicle's left axis, m/s (positive to the left; an EDR's lateral
    /// channel in SAE J211 axes, positive to the right, reads the opposite sign).
    pub delta_v_lateral: f64,
    /// Principal direction of force: where the impulse on the vehicle comes from, degrees
    /// clockwise from the nose (SAE), in (-180, 180]: 0 frontal, 90 from the right, -90 from the
    /// left, 180 from behind. Opposite to the delta-V direction.
    pub pdof: f64,
    /// The PDOF as a clock direction, 1..=12 (12 frontal, 3 right side, 9 left side).
    pub clock: u8,
    /// W - w, rad/s (counter-clockwise positive).
    pub yaw_rate_change: f64,
}

/// The principal direction of force (degrees clockwise from the nose) of a delta-V given in
/// the vehicle's own axes `(forward, left)`, and its clock direction.
pub fn pdof(delta_v_body: [f64; 2]) -> (f64, u8) {
    let [fwd, left] = delta_v_body;
    if fwd == 0.0 && left == 0.0 {
        return (0.0, 12);
    }
    pdof_of_direction(0.0, left.atan2(fwd).to_degrees())
}

/// The PDOF and clock direction of a (non-zero) delta-V whose direction is `direction`, for a
/// vehicle whose nose points along `heading` (both degrees counter-clockwise from the same
/// axis). The force comes from -delta-V: clockwise from the nose, `heading - direction - 180`.
fn pdof_of_direction(heading: f64, direction: f64) -> (f64, u8) {
    let angle = crate::model::wrap_degrees(heading - direction - 180.0);
    let hours = (angle / 30.0).round().rem_euclid(12.0) as u8;
    (angle, if hours == 0 { 12 } else { hours })
}

/// The reconstructionist's results of both vehicles for a pair of states.
pub fn vehicle_results(
    impact: &Impact,
    initial: &Velocities,
    separation: &Velocities,
) -> [VehicleResult; 2] {
    [
        vehicle_result(
            impact,
            crate::error::VehicleId::One,
            &delta_v(&initial.vehicle1, &separation.vehicle1),
            initial,
            separation,
        ),
        vehicle_result(
            impact,
            crate::error::VehicleId::Two,
            &delta_v(&initial.vehicle2, &separation.vehicle2),
            initial,
            separation,
        ),
    ]
}

/// One vehicle's results from its delta-V (already computed by the report).
fn vehicle_result(
    impact: &Impact,
    id: crate::error::VehicleId,
    dv: &DeltaV,
    initial: &Velocities,
    separation: &Velocities,
) -> VehicleResult {
    let body = impact.to_body(id, [dv.dvx, dv.dvy]);
    let heading = impact.nose_heading(id);
    let (angle, clock) = if dv.magnitude > 0.0 {
        pdof_of_direction(heading, dv.direction)
    } else {
        (0.0, 12)
    };
    VehicleResult {
        heading,
        speed_initial: initial.vehicle(id).speed(),
        speed_final: separation.vehicle(id).speed(),
        delta_v: dv.magnitude,
        delta_v_longitudinal: body[0],
        delta_v_lateral: body[1],
        pdof: angle,
        clock,
        yaw_rate_change: dv.domega,
    }
}

/// Kinetic energy balance of the impact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Energy {
    /// Total kinetic energy at contact, J.
    pub initial: f64,
    /// Total kinetic energy at separation, J.
    #[serde(rename = "final")]
    pub final_: f64,
    /// initial - final, J (negative when the solution creates energy).
    pub loss: f64,
    /// 100 (initial - final) / initial, percent.
    pub loss_percent: f64,
}

/// Whether a solution is physically admissible.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Admissibility {
    /// True when every condition below holds.
    pub admissible: bool,
    /// mu lies between 0 and mu_max (always true under the no-slip form).
    pub friction_ok: bool,
    /// The kinetic energy at separation does not exceed that at contact.
    pub energy_ok: bool,
}

/// Residual of each of the six equations, in the equation's own units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Residuals {
    /// Which equation each value belongs to.
    pub equations: [Equation; 6],
    /// `F X + G x`, row by row.
    pub values: [f64; 6],
    /// Each residual divided by the size of its terms (`|F||X| + |G||x|`), at least a millionth
    /// of the largest equation's size; dimensionless.
    pub relative: [f64; 6],
}

impl Residuals {
    /// The largest relative residual.
    pub fn max_relative(&self) -> f64 {
        self.relative.iter().fold(0.0, |a, &b| a.max(b.abs()))
    }
}

/// Everything a solve produces.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ImpactReport {
    /// The coefficients used.
    pub coefficients: Coefficients,
    /// The options used.
    pub options: SolveOptions,
    /// Velocities at contact.
    pub initial: Velocities,
    /// Velocities at separation.
    #[serde(rename = "final")]
    pub separation: Velocities,
    /// Velocities of the material points at C.
    pub contact_points: ContactPoints,
    /// Normal and tangential relative velocities at C.
    pub relative: RelativeVelocity,
    /// Impulses on vehicle 1.
    pub impulse: Impulse,
    /// Velocity change of vehicle 1 and vehicle 2.
    pub delta_v: [DeltaV; 2],
    /// Speeds, delta-V in each vehicle's axes, PDOF and yaw-rate change, per vehicle.
    pub vehicles: [VehicleResult; 2],
    /// Kinetic energy balance.
    pub energy: Energy,
    /// The sign factor of equation 5, mu' = mu times this (`1` or `-1` in JSON):
    /// `sgn(vn) sgn(vt)` at contact, or the direction of the no-slip impulse where the contact
    /// point does not slide at contact (see `friction_basis`).
    pub friction_sign: FrictionSign,
    /// Where `friction_sign` comes from: the sliding at contact, or (`vt = 0`) the no-slip
    /// impulse.
    pub friction_basis: FrictionBasis,
    /// Signed critical impulse ratio: the mu at which Vt = 0 (None if the normal impulse vanishes).
    pub mu_max: Option<f64>,
    /// mu / mu_max (the effective ratio is 1 under the no-slip form).
    pub mu_ratio: Option<f64>,
    /// Sliding, sticking or reversed.
    pub tangential: TangentialOutcome,
    /// True when the vehicles still slide at separation.
    pub sliding: bool,
    /// Physical admissibility.
    pub admissibility: Admissibility,
}

fn delta_v(before: &crate::VehicleVelocity, after: &crate::VehicleVelocity) -> DeltaV {
    let dvx = after.vx - before.vx;
    let dvy = after.vy - before.vy;
    DeltaV {
        dvx,
        dvy,
        domega: after.omega - before.omega,
        magnitude: (dvx * dvx + dvy * dvy).sqrt(),
        direction: dvy.atan2(dvx).to_degrees(),
    }
}

/// Residuals of the six equations for a pair of states.
pub fn residuals(
    impact: &Impact,
    coefficients: &Coefficients,
    sign: FrictionSign,
    options: &SolveOptions,
    initial: &Velocities,
    separation: &Velocities,
) -> Residuals {
    residuals_of(
        &assemble(impact, coefficients, sign, options),
        initial,
        separation,
    )
}

/// Residuals of an assembled system for a pair of states.
fn residuals_of(system: &LinearSystem, initial: &Velocities, separation: &Velocities) -> Residuals {
    let x = initial.to_vector();
    let xf = separation.to_vector();
    let r = system.f * xf + system.g * x;
    let size = system.f.abs() * xf.abs() + system.g.abs() * x.abs();
    let mut values = [0.0; 6];
    let mut relative = [0.0; 6];
    // Each residual relative to the size of its own terms, but never to less than a millionth
    // of the largest equation's: an equation whose terms are all round-off (no tangential
    // impulse and no tangential velocity, say) would otherwise call its round-off 100 %.
    let floor = 1e-6 * size.max();
    for i in 0..6 {
        values[i] = r[i];
        let scale = size[i].max(floor);
        relative[i] = if scale > 0.0 { r[i] / scale } else { r[i] };
    }
    Residuals {
        equations: system.equations,
        values,
        relative,
    }
}

impl ImpactReport {
    /// Residuals of the six equations for this solution (computed on demand: a forward or
    /// backward solve satisfies them to round-off by construction).
    pub fn residuals(&self, impact: &Impact) -> Residuals {
        residuals(
            impact,
            &self.coefficients,
            self.friction_sign,
            &self.options,
            &self.initial,
            &self.separation,
        )
    }

    /// The failed admissibility conditions, in words (empty when admissible): the friction
    /// condition's ([`ImpactReport::friction_reason`]), then the energy condition's.
    pub fn inadmissibility_reasons(&self) -> Vec<String> {
        self.friction_reason()
            .into_iter()
            .chain(self.energy_reason())
            .collect()
    }

    /// Why mu is not admissible (not between 0 and mu_max), in words; `None` when it is.
    pub fn friction_reason(&self) -> Option<String> {
        if self.admissibility.friction_ok {
            return None;
        }
        let mu = self.coefficients.mu;
        let not_sliding = self.friction_basis == FrictionBasis::NoSlipImpulse;
        Some(match self.mu_max {
            Some(m) if not_sliding && m.abs() <= REPORT_TOL => format!(
                "mu = {mu} but the vehicles do not slide at contact and the normal impulse does \
                 not make them slide (mu_max = 0): any tangential impulse is more than sticking \
                 needs; only mu = 0 (or the no-slip form) is admissible"
            ),
            Some(m) => format!(
                "mu = {mu} is not between 0 and mu_max = {m:.6}: the tangential impulse {}",
                if mu * m < 0.0 {
                    "pushes the vehicles along their sliding direction instead of against it"
                } else {
                    "is larger than sticking needs and reverses the sliding"
                }
            ),
            None => format!("mu = {mu} but the normal impulse vanishes, so mu_max is undefined"),
        })
    }

    /// Why the solution is not admissible by its energy (it creates kinetic energy), in
    /// words; `None` when it is.
    pub fn energy_reason(&self) -> Option<String> {
        (!self.admissibility.energy_ok).then(|| {
            format!(
                "the solution creates kinetic energy: {:.1} J at separation against {:.1} J at \
                 contact ({:.3} % more)",
                self.energy.final_, self.energy.initial, -self.energy.loss_percent
            )
        })
    }
}

/// Computes every derived quantity of a solution `(initial, separation)`.
pub(crate) fn build_report(
    impact: &Impact,
    coefficients: &Coefficients,
    options: &SolveOptions,
    initial: &Velocities,
    separation: &Velocities,
    (sign, basis): (FrictionSign, FrictionBasis),
    mu_max: Option<f64>,
) -> ImpactReport {
    let [p1i, p2i] = impact.contact_point_velocities(initial);
    let [p1f, p2f] = impact.contact_point_velocities(separation);
    let (vn, vt) = impact.relative_velocity(initial);
    let (vn_f, vt_f) = impact.relative_velocity(separation);
    let [m1, _] = impact.masses();
    let [i1, _] = impact.inertias();
    let dv1 = delta_v(&initial.vehicle1, &separation.vehicle1);
    let dv2 = delta_v(&initial.vehicle2, &separation.vehicle2);
    let px = m1 * dv1.dvx;
    let py = m1 * dv1.dvy;
    let p = impulse_of(impact, &(separation.to_vector() - initial.to_vector()));
    let [r1, _] = impact.lever_arms();
    let impulse = Impulse {
        px,
        py,
        normal: p.normal,
        tangential: p.tangential,
        moment: i1 * dv1.domega - (r1[0] * py - r1[1] * px),
    };
    let t0 = initial.kinetic_energy(impact);
    let t1 = separation.kinetic_energy(impact);
    let energy = Energy {
        initial: t0,
        final_: t1,
        loss: t0 - t1,
        loss_percent: if t0 > 0.0 {
            100.0 * (t0 - t1) / t0
        } else {
            0.0
        },
    };

    let (tangential, mu_ratio, friction_ok) = match options.tangential {
        TangentialCondition::NoSlip => (TangentialOutcome::Sticking, Some(1.0), true),
        TangentialCondition::Sliding => {
            let v = classify_friction(coefficients.mu, mu_max);
            (v.outcome, v.ratio, v.admissible)
        }
    };
    let energy_ok = !creates_energy(t0, t1);
    ImpactReport {
        coefficients: *coefficients,
        options: *options,
        initial: *initial,
        separation: *separation,
        contact_points: ContactPoints {
            vehicle1_initial: p1i,
            vehicle2_initial: p2i,
            vehicle1_final: p1f,
            vehicle2_final: p2f,
        },
        relative: RelativeVelocity {
            normal_initial: vn,
            tangential_initial: vt,
            normal_final: vn_f,
            tangential_final: vt_f,
        },
        impulse,
        delta_v: [dv1, dv2],
        vehicles: [
            vehicle_result(impact, VehicleId::One, &dv1, initial, separation),
            vehicle_result(impact, VehicleId::Two, &dv2, initial, separation),
        ],
        energy,
        friction_sign: sign,
        friction_basis: basis,
        mu_max,
        mu_ratio,
        tangential,
        sliding: tangential == TangentialOutcome::Sliding,
        admissibility: Admissibility {
            admissible: friction_ok && energy_ok,
            friction_ok,
            energy_ok,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::pdof;

    #[test]
    fn principal_direction_of_force() {
        // Frontal: slowed along the forward axis.
        assert_eq!(pdof([-5.0, 0.0]), (0.0, 12));
        // Struck on the left side: pushed to the right (negative left component).
        let (a, c) = pdof([0.0, -4.0]);
        assert!((a + 90.0).abs() < 1e-12 && c == 9);
        // Struck on the right side.
        let (a, c) = pdof([0.0, 4.0]);
        assert!((a - 90.0).abs() < 1e-12 && c == 3);
        // Rear impact: pushed forward.
        let (a, c) = pdof([3.0, 0.0]);
        assert!((a - 180.0).abs() < 1e-12 && c == 6);
        // Front right at 30 deg.
        let (a, c) = pdof([-(30f64.to_radians().cos()), 30f64.to_radians().sin()]);
        assert!((a - 30.0).abs() < 1e-9 && c == 1);
    }
}
