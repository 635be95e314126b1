//! The crush energies at a pair of states: set beside PIM's energy loss and delta-V, and as a
//! residual of a fit.

use pim_case::damage::{Damage, Side};
use pim_core::{Impact, VehicleId, Velocities};
use pim_crush::{EnergyRelation, MAX_PDOF_CORRECTION_ANGLE};
pub use pim_documents::damage_assess::{Assessment, VehicleAssessment};
use pim_fit::Vector12;

fn wrap(a: f64) -> f64 {
    pim_core::wrap_degrees(a)
}

/// The crush of `damage` at the states `u` of `impact`. `None` when a state has no impulse
/// on a damaged vehicle and the case gives no PDOF for it.
pub fn assess(damage: &Damage, impact: &Impact, u: &Vector12) -> Option<Assessment> {
    let x = Velocities::from_vector(&u.fixed_rows::<6>(0).into_owned());
    let y = Velocities::from_vector(&u.fixed_rows::<6>(6).into_owned());
    let masses = impact.masses();
    let inertias = impact.inertias();
    let arms = impact.lever_arms();
    let mut warnings = Vec::new();
    let mut parts: Vec<(usize, VehicleAssessment)> = Vec::new();
    let mut factors = [1.0, 1.0];
    for k in 0..2 {
        let id = VehicleId::from_index(k);
        let (a, b) = (x.vehicle(id), y.vehicle(id));
        let d = [b.vx - a.vx, b.vy - a.vy];
        let size = d[0].hypot(d[1]);
        let h = if size > 0.0 {
            (arms[k][0] * d[1] - arms[k][1] * d[0]).abs() / size
        } else {
            0.0
        };
        factors[k] = pim_crush::effective_mass_factor(masses[k], inertias[k], h);
        let Some(v) = &damage.vehicles[k] else {
            continue;
        };
        let (pdof, from) = match v.pdof {
            Some(p) => (wrap(p), "case"),
            None if size > 0.0 => (pim_core::pdof(impact.to_body(id, d)).0, "impulse"),
            None => return None,
        };
        let alpha = wrap(pdof - v.side.normal_pdof());
        let factor = pim_crush::pdof_factor(alpha.to_radians());
        warnings.extend(pdof_warning(k, v.side, pdof, alpha));
        let e0 = pim_crush::crush_energy(&v.profile, &v.stiffness).ok()?;
        let s0 = pim_crush::crush_energy_sigma(&v.profile, &v.stiffness, &v.sigmas).ok()?;
        let energy = e0 * factor;
        parts.push((
            k,
            VehicleAssessment {
                side: v.side,
                measured: v.measured,
                depths: v.profile.depths.clone(),
                width: v.profile.width,
                crush_energy: e0,
                pdof,
                pdof_from: from,
                alpha,
                pdof_factor: factor,
                energy,
                energy_sigma: s0 * factor,
                barrier_equivalent_speed: pim_crush::barrier_equivalent_speed(energy, masses[k])
                    .ok()?,
                moment_arm: h,
                effective_mass_factor: factors[k],
                crash3_delta_v: 0.0,
                pim_delta_v: size,
            },
        ));
    }
    if !impact.is_barrier() && damage.vehicles.iter().any(Option::is_none) {
        let k = damage
            .vehicles
            .iter()
            .position(Option::is_none)
            .unwrap_or(1);
        warnings.push(format!(
            "vehicle {} has no [damage.vehicle{}]: the crush energy holds the other vehicle's \
             only (give its side, a and b to take its crush from the force balance)",
            k + 1,
            k + 1
        ));
    }
    let total: f64 = parts.iter().map(|(_, p)| p.energy).sum();
    let sigma = parts
        .iter()
        .map(|(_, p)| p.energy_sigma.powi(2))
        .sum::<f64>()
        .sqrt();
    let crash3 = pim_crush::crash3_delta_v(total, masses, factors).ok()?;
    let mut vehicles: [Option<VehicleAssessment>; 2] = [None, None];
    for (k, mut p) in parts {
        p.crash3_delta_v = crash3[k];
        vehicles[k] = Some(p);
    }
    let (vn, _) = impact.relative_velocity(&x);
    let (vn_after, _) = impact.relative_velocity(&y);
    let e = if vn != 0.0 { -vn_after / vn } else { 0.0 };
    let expected = damage.relation.expected_loss(total, e);
    let expected_sigma = damage.relation.expected_loss(sigma, e);
    let energy_loss = x.kinetic_energy(impact) - y.kinetic_energy(impact);
    let difference = energy_loss - expected;
    let relation_note = relation_note(damage.relation, e);
    Some(Assessment {
        relation: damage.relation,
        vehicles,
        crush_energy: total,
        crush_energy_sigma: sigma,
        e,
        expected_loss: expected,
        expected_loss_sigma: expected_sigma,
        energy_loss,
        difference,
        z: (expected_sigma > 0.0).then(|| difference / expected_sigma),
        relation_note,
        warnings,
    })
}

/// A force that points out of the damaged face, or so far off its normal that CRASH3's
/// direction-of-force factor is held: said of vehicle `k`.
fn pdof_warning(k: usize, side: Side, pdof: f64, alpha: f64) -> Option<String> {
    let name = if k == 0 { "vehicle 1" } else { "vehicle 2" };
    if alpha.abs() > 90.0 {
        Some(format!(
            "{name}: the force (PDOF {pdof:.0} deg) points out of its damaged {} face \
             ({alpha:.0} deg from the face's normal): check [damage.vehicle{}] side",
            side.name(),
            k + 1
        ))
    } else if alpha.abs().to_radians() > MAX_PDOF_CORRECTION_ANGLE {
        Some(format!(
            "{name}: the force is {:.0} deg from the {} face's normal; the direction-of-force \
             factor is held at its 45 deg value (2), as CRASH3 does",
            alpha.abs(),
            side.name()
        ))
    } else {
        None
    }
}

/// What the crush energy is compared with, in words, at restitution `e`.
fn relation_note(relation: EnergyRelation, e: f64) -> String {
    // Shown to three decimals: a restitution of -1e-12 reads 0.000, not -0.000.
    let e_shown = if e.abs() < 5e-4 { 0.0 } else { e };
    match relation {
        EnergyRelation::EnergyLoss => format!(
            "crush energy taken as the energy loss (CRASH3's convention); a barrier-calibrated \
             stiffness measures the energy up to maximum crush, of which a collision with e = \
             {e_shown:.3} loses (1 - e^2) = {:.3} in a central impact: read that way the crush asks \
             for {:.1} % less loss",
            1.0 - e_shown * e_shown,
            100.0 * e_shown * e_shown
        ),
        EnergyRelation::Compression => format!(
            "crush energy taken as the energy absorbed up to maximum crush: the expected loss is \
             (1 - e^2) = {:.3} of it at e = {e_shown:.3} (CRASH3's convention would expect {:.1} % \
             more)",
            1.0 - e_shown * e_shown,
            if e * e < 1.0 {
                100.0 * (1.0 / (1.0 - e * e) - 1.0)
            } else {
                f64::INFINITY
            }
        ),
    }
}

/// The crush energy as a residual of a fit: `(expected loss - PIM's loss) / sigma`, with the
/// PDOF factors, the restitution of the relation and the sigma all evaluated at the states
/// being fitted.
pub struct EnergyTerm<'a> {
    /// The damage.
    pub damage: &'a Damage,
    /// The collision.
    pub impact: &'a Impact,
}

impl pim_fit::NonlinearTerm for EnergyTerm<'_> {
    fn residual(&self, u: &Vector12) -> Option<f64> {
        let a = assess(self.damage, self.impact, u)?;
        (a.expected_loss_sigma > 0.0).then(|| -a.difference / a.expected_loss_sigma)
    }
}
