//! The RICSAC tests with their crush: the EDCRASH profiles and stiffness of each car
//! (`data/ricsac_vehicles.csv`, Neades 2011 Appendix D) set beside the Q2 fit of each test
//! (Brach's fit of the separation velocities), CRASH3's delta-V beside PIM's and the measured
//! ones (Neades 2011 Table 5.3), and the Q2 fit with the crush energy as evidence.
//!
//! The damaged face of each car is the face of its outline (CG to front, to rear, width of the
//! same file) that the ray from its CG at the test's phi leaves through
//! ([`pim_core::outline::damaged_face`]), as for the derived impact-centre distances. No
//! standard deviation of the crush or the stiffness is published; the energy as evidence
//! assumes [`ASSUMED_STIFFNESS_SIGMA`] of A and B and [`ASSUMED_DEPTH_SIGMA`] of each depth.

use crate::damage_fit::fit_damage_of;
use pim_case::damage::{Damage, Side, VehicleDamage};
use pim_case::ricsac::RicsacTest;
use pim_core::outline::{damaged_face, Face, Outline};
use pim_crush::{EnergyRelation, Profile, ProfileSigmas, Stiffness};
pub use pim_documents::ricsac_damage::{DamageRecord, MeasuredDeltaV};
use pim_fit::{CostPreset, FitProblem, FitSettings};
use rayon::prelude::*;
use serde::Deserialize;

/// Assumed relative standard deviation of A and B (none is published for the RICSAC cars).
pub const ASSUMED_STIFFNESS_SIGMA: f64 = 0.10;
/// Assumed standard deviation of each crush depth, m.
pub const ASSUMED_DEPTH_SIGMA: f64 = 0.02;

/// One row of `data/ricsac_vehicles.csv` (cm, N/cm, N/cm^2, kg, kg m^2).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct CrushRow {
    /// RICSAC test.
    pub test: u32,
    /// 1 or 2.
    pub vehicle: u32,
    /// Damage length L, cm.
    pub damage_length_cm: f64,
    /// Damage offset D, cm.
    pub damage_offset_cm: f64,
    /// C1, cm.
    pub c1_cm: f64,
    /// C2, cm.
    pub c2_cm: f64,
    /// C3, cm.
    pub c3_cm: f64,
    /// C4, cm.
    pub c4_cm: f64,
    /// C5, cm.
    pub c5_cm: f64,
    /// C6, cm.
    pub c6_cm: f64,
    /// A, N/cm.
    pub a_n_per_cm: f64,
    /// B, N/cm^2.
    pub b_n_per_cm2: f64,
    /// CG to front, cm.
    pub cg_to_front_cm: f64,
    /// CG to rear, cm.
    pub cg_to_rear_cm: f64,
    /// Length, cm.
    pub length_cm: f64,
    /// Width, cm.
    pub width_cm: f64,
    /// Mass, kg (not used: the masses of `data/ricsac.csv` are; row 7.2's 771 kg is not a
    /// test car's).
    pub mass_kg: f64,
    /// Yaw inertia, kg m^2 (not used, as the mass).
    pub yaw_inertia_kgm2: f64,
}

/// A row of the RICSAC damage data that cannot be read or used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DataError {
    /// A row that is not one of the table's (the CSV reader's message).
    #[error("row {row}: {message}")]
    Row {
        /// The row, from 1 after the header.
        row: usize,
        /// What is wrong with it.
        message: String,
    },
    /// A vehicle's crush profile or stiffness out of its range.
    #[error("test {test} vehicle {vehicle}: crush depths must be at least 0, L and B above 0")]
    Crush {
        /// The RICSAC test.
        test: u32,
        /// 1 or 2.
        vehicle: u32,
    },
}

fn parse<T: for<'de> Deserialize<'de>>(text: &str) -> Result<Vec<T>, DataError> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    rdr.deserialize()
        .enumerate()
        .map(|(i, r)| {
            r.map_err(|e| DataError::Row {
                row: i + 1,
                message: e.to_string(),
            })
        })
        .collect()
}

/// Parses `data/ricsac_vehicles.csv`.
///
/// # Errors
/// The row and what is wrong with it.
pub fn parse_crush(text: &str) -> Result<Vec<CrushRow>, DataError> {
    let rows: Vec<CrushRow> = parse(text)?;
    for r in &rows {
        let c = [r.c1_cm, r.c2_cm, r.c3_cm, r.c4_cm, r.c5_cm, r.c6_cm];
        if c.iter().any(|x| !(x.is_finite() && *x >= 0.0))
            || !(r.damage_length_cm > 0.0 && r.a_n_per_cm >= 0.0 && r.b_n_per_cm2 > 0.0)
        {
            return Err(DataError::Crush {
                test: r.test,
                vehicle: r.vehicle,
            });
        }
    }
    Ok(rows)
}

/// Parses `data/reference/neades2011_table5_3.csv`.
///
/// # Errors
/// The row and what is wrong with it.
pub fn parse_measured(text: &str) -> Result<Vec<MeasuredDeltaV>, DataError> {
    parse(text)
}

fn side_of(face: Face) -> Side {
    match face {
        Face::Front => Side::Front,
        Face::Rear => Side::Rear,
        Face::Left => Side::Left,
        Face::Right => Side::Right,
    }
}

/// A car's damage from its row, on the face its phi points to.
pub fn vehicle_damage(row: &CrushRow, phi_deg: f64) -> (Side, VehicleDamage) {
    let outline = Outline {
        cg_to_front: row.cg_to_front_cm / 100.0,
        cg_to_rear: row.cg_to_rear_cm / 100.0,
        width: row.width_cm / 100.0,
    };
    let side = side_of(damaged_face(&outline, phi_deg));
    let depths = [
        row.c1_cm, row.c2_cm, row.c3_cm, row.c4_cm, row.c5_cm, row.c6_cm,
    ]
    .iter()
    .map(|c| c / 100.0)
    .collect();
    let stiffness = Stiffness {
        a: row.a_n_per_cm * 100.0,
        b: row.b_n_per_cm2 * 1e4,
    };
    (
        side,
        VehicleDamage {
            side,
            profile: Profile {
                width: row.damage_length_cm / 100.0,
                depths,
            },
            offset: row.damage_offset_cm / 100.0,
            stiffness,
            sigmas: ProfileSigmas {
                a: ASSUMED_STIFFNESS_SIGMA * stiffness.a,
                b: ASSUMED_STIFFNESS_SIGMA * stiffness.b,
                depth: ASSUMED_DEPTH_SIGMA,
                width: 0.0,
            },
            measured: true,
            pdof: None,
        },
    )
}

/// The crush of every test of `tests` against its Q2 fit under `settings` (the batch's),
/// in test order.
pub fn damage_records(
    tests: &[RicsacTest],
    crush: &[CrushRow],
    measured: &[MeasuredDeltaV],
    settings: &FitSettings,
) -> Vec<DamageRecord> {
    tests
        .par_iter()
        .map(|t| {
            let row = |k: u32| crush.iter().find(|r| r.test == t.test && r.vehicle == k);
            let measured = measured.iter().find(|m| m.test == t.test).copied();
            let failed = |why: String| DamageRecord {
                test: t.test,
                sides: [Side::Front, Side::Front],
                damage: None,
                measured,
                error: Some(why),
            };
            let (Some(r1), Some(r2)) = (row(1), row(2)) else {
                return failed(format!("test {}: no crush rows for both cars", t.test));
            };
            let (s1, d1) = vehicle_damage(r1, t.phi1_deg);
            let (s2, d2) = vehicle_damage(r2, t.phi2_deg);
            let damage = Damage {
                relation: EnergyRelation::EnergyLoss,
                evidence: Some(true),
                vehicles: [Some(d1), Some(d2)],
            };
            let impact = match t.impact() {
                Ok(i) => i,
                Err(e) => return failed(e.to_string()),
            };
            let problem = FitProblem::from_preset(
                impact,
                CostPreset::Q2,
                &t.initial(),
                &t.separation(),
                None,
            );
            let settings = match settings.clone().check() {
                Ok(s) => s,
                Err(e) => return failed(e.to_string()),
            };
            let report = match pim_fit::fit(&problem, &settings) {
                Ok(r) => r,
                Err(e) => return failed(e.to_string()),
            };
            match fit_damage_of(&damage, &problem, &report, &settings, None) {
                Ok(d) => DamageRecord {
                    test: t.test,
                    sides: [s1, s2],
                    damage: Some(d),
                    measured,
                    error: None,
                },
                Err(e) => failed(e.to_string()),
            }
        })
        .collect()
}
