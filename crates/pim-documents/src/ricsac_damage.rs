//! The document types of `ricsac_damage` (what the study of the same name in pim-studies writes).

use crate::damage_fit::FitDamage;
use pim_case::damage::Side;
use serde::{Deserialize, Serialize};

/// One row of `data/reference/neades2011_table5_3.csv`: corrected delta-V, m/s.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize, schemars::JsonSchema)]
pub struct MeasuredDeltaV {
    /// RICSAC test.
    pub test: u32,
    /// Jones & Baum, vehicle 1.
    pub jb_dv1: f64,
    /// Jones & Baum, vehicle 2.
    pub jb_dv2: f64,
    /// Brach & Smith 2002, vehicle 1.
    pub brach_smith_dv1: f64,
    /// Brach & Smith 2002, vehicle 2.
    pub brach_smith_dv2: f64,
    /// McHenry & McHenry 1997, vehicle 1.
    pub mchenry_dv1: f64,
    /// McHenry & McHenry 1997, vehicle 2.
    pub mchenry_dv2: f64,
}

/// One test's crush against its fit.
#[derive(Debug, Clone, Serialize, schemars::JsonSchema)]
pub struct DamageRecord {
    /// RICSAC test.
    pub test: u32,
    /// The damaged face of each car (from phi and the outline).
    pub sides: [Side; 2],
    /// The crush at the Q2 fit, and the Q2 fit with the crush energy as evidence.
    pub damage: Option<FitDamage>,
    /// Neades' Table 5.3 row.
    pub measured: Option<MeasuredDeltaV>,
    /// Why the test has no record.
    pub error: Option<String>,
}
