//! Evidence that is not linear in the velocities (the crush energy) in the whole
//! reconstruction: a measured energy loss fitted with the scenes, on simulated crashes with a
//! known truth.
use crate::common;

use common::crash::{crashes, settings, Crash};
use pim_fit::Vector12;
use pim_reconstruct::{reconstruct, ContactTerm, StateEvidence, Status};
use std::sync::Arc;

/// The kinetic energy the impact takes out, `sum m v^2 / 2 + I w^2 / 2` at contact minus at
/// separation, measured as `measured` with a standard deviation `sigma` (J).
#[derive(Debug)]
struct EnergyLoss {
    masses: [f64; 2],
    inertias: [f64; 2],
    measured: f64,
    sigma: f64,
}

impl EnergyLoss {
    fn of(&self, u: &Vector12) -> f64 {
        let ke = |base: usize| -> f64 {
            (0..2)
                .map(|k| {
                    let (vx, vy, w) = (u[base + 3 * k], u[base + 3 * k + 1], u[base + 3 * k + 2]);
                    0.5 * self.masses[k] * (vx * vx + vy * vy) + 0.5 * self.inertias[k] * w * w
                })
                .sum()
        };
        ke(0) - ke(6)
    }
}

impl StateEvidence for EnergyLoss {
    fn name(&self) -> String {
        "energy loss".into()
    }
    fn quantity(&self) -> &'static str {
        "energy"
    }
    fn residual(&self, u: &Vector12) -> Option<(f64, f64)> {
        Some((self.of(u) - self.measured, self.sigma))
    }
}

fn with_energy(c: &mut Crash, offset_sigmas: f64, sigma: f64) -> Arc<EnergyLoss> {
    let col = *c.recon.contact.impact.collision();
    let mut term = EnergyLoss {
        masses: [col.vehicle1.mass, col.vehicle2.mass],
        inertias: [col.vehicle1.yaw_inertia, col.vehicle2.yaw_inertia],
        measured: 0.0,
        sigma,
    };
    let truth = pim_fit::state_vector(&c.contact, &c.separation);
    term.measured = term.of(&truth) + offset_sigmas * sigma;
    let term = Arc::new(term);
    c.recon.nonlinear.0.push(term.clone());
    term
}

/// Noise-free scenes and the exact energy loss: the answer is the truth, the energy's
/// residual is zero, and the chi-square counts it as one datum more.
#[test]
fn the_exact_energy_loss_keeps_the_truth() {
    for (seed, mut c) in crashes(0.0).take(4) {
        let plain = reconstruct(&c.recon, &settings()).unwrap();
        let term = with_energy(&mut c, 0.0, 2000.0);
        let out = reconstruct(&c.recon, &settings()).unwrap();
        assert_eq!(out.status, Status::Found, "seed {seed}: {:?}", out.reason);
        let b = out.best.as_ref().unwrap();
        let s = &b.solution;
        let err = c.speed_error(b);
        assert!(err < 1e-3, "seed {seed}: impact speed off by {err}");
        let u = pim_fit::state_vector(&s.initial, &s.separation);
        let z = (term.of(&u) - term.measured) / term.sigma;
        assert!(z.abs() < 1e-3, "seed {seed}: energy residual {z} sigma");
        let p = plain.best.unwrap();
        assert_eq!(
            b.degrees_of_freedom,
            p.degrees_of_freedom + 1,
            "seed {seed}"
        );
        // The energy is one of the contact problem's residuals, by its name.
        assert!(c
            .recon
            .contact_residuals(&u)
            .iter()
            .any(|r| r.term == ContactTerm::Nonlinear(0)));
    }
}

/// A measured energy two standard deviations off the truth (the rest noise-free): the truth
/// costs exactly 4, so the answer costs at most that, its energy residual lies between the
/// truth's -2 sigma and 0 (the fit moves the speeds toward the measured energy as far as the
/// other evidence lets it), and its chi-square is the sum of every residual squared, the
/// energy's included.
#[test]
fn an_energy_off_the_truth_is_a_residual_of_the_chi_square() {
    for (seed, mut c) in crashes(0.0).take(3) {
        let term = with_energy(&mut c, 2.0, 500.0);
        let out = reconstruct(&c.recon, &settings()).unwrap();
        let Some(b) = out.best.as_ref() else {
            panic!("seed {seed}: {:?}", out.reason)
        };
        let s = &b.solution;
        let u = pim_fit::state_vector(&s.initial, &s.separation);
        let z = (term.of(&u) - term.measured) / term.sigma;
        assert!(
            z > -2.0 - 1e-6 && z < 1e-6,
            "seed {seed}: energy residual {z}"
        );
        assert!(
            b.chi_square <= 4.0 + 1e-6,
            "seed {seed}: chi-square {}",
            b.chi_square
        );
        let sum: f64 = c
            .recon
            .contact_residuals(&u)
            .iter()
            .map(|r| r.weight * r.residual * r.residual / c.recon.unit.unwrap_or(1.0))
            .sum::<f64>()
            + b.scene
                .iter()
                .flat_map(|f| f.residuals.iter())
                .map(|r| (r.value / r.sigma).powi(2))
                .sum::<f64>();
        assert!(
            (sum - b.chi_square).abs() <= 1e-6 * (1.0 + sum),
            "seed {seed}: chi-square {} against the sum {sum}",
            b.chi_square
        );
    }
}
