//! `pim predict-dv`: Brach 1984 section 6 applied to every test of a data file (see
//! [`pim_core::prediction`] for the equations).

use pim_case::ricsac::RicsacTest;
use pim_core::point_mass::PointMassImpact;
use pim_core::prediction::{delta_v_eq14, l_factor, point_mass_eq17};
pub use pim_documents::predict::{DeltaVPrediction, TestPrediction};

/// The predictions of every test of a data file (`file` names it in messages), with restitution
/// `e` in eq. 17, which must be in [0, 1].
pub fn predict_all(
    file: &str,
    tests: &[RicsacTest],
    e: f64,
) -> std::result::Result<Vec<TestPrediction>, pim_case::InputError> {
    if !(e.is_finite() && (0.0..=1.0).contains(&e)) {
        return Err(pim_case::InputError::new(
            file,
            format!("e = {e}: must be in [0, 1]"),
        ));
    }
    tests
        .iter()
        .map(|t| {
            predict(t, e).map_err(|err| {
                pim_case::InputError::new(file, format!("test {} (line {}): {err}", t.test, t.line))
            })
        })
        .collect()
}

/// The predictions of one test, with restitution `e` in eq. 17 (Brach: 0 unless known).
pub fn predict(t: &RicsacTest, e: f64) -> Result<TestPrediction, pim_core::PimError> {
    let impact = t.impact()?;
    let x = t.initial();
    let xf = t.separation();
    let t0 = x.kinetic_energy(&impact);
    let t1 = xf.kinetic_energy(&impact);
    let fraction = if t0 > 0.0 { (t0 - t1) / t0 } else { 0.0 };
    let masses = impact.masses();
    let speeds = [x.vehicle1.speed(), x.vehicle2.speed()];
    let l = l_factor(masses[0] / masses[1], speeds[1] / speeds[0]);
    let eq14 = delta_v_eq14(l, masses, speeds, fraction);
    let two_thirds = delta_v_eq14(2.0 / 3.0, masses, speeds, fraction);
    let pm = point_mass_eq17(
        &PointMassImpact {
            masses,
            crush_angle: t.crush_angle_deg,
            initial: [
                [x.vehicle1.vx, x.vehicle1.vy],
                [x.vehicle2.vx, x.vehicle2.vy],
            ],
        },
        e,
    )?;
    let one = |k: usize, measured: f64| DeltaVPrediction {
        measured,
        eq14: eq14[k],
        eq14_two_thirds: two_thirds[k],
        eq17: pm.delta_v[k],
    };
    Ok(TestPrediction {
        test: t.test,
        l,
        mass_ratio: masses[0] / masses[1],
        speed_ratio: speeds[1] / speeds[0],
        energy_loss_fraction: fraction,
        mu_m_point_mass: pm.mu_m,
        delta_v1: one(0, t.dv1_measured_mps),
        delta_v2: one(1, t.dv2_measured_mps),
    })
}
