//! Coefficient sensitivity study (Brach 1983, Tables 4-6).
//!
//! Each coefficient is set to its value times `(1 - p)` and `(1 + p)`; every combination is
//! solved; then, for each coefficient and level, the results are averaged over the combinations
//! at that level. `em = 1` is not varied (values above 1 have no meaning), so a study with
//! `em = 1` has four combinations, otherwise eight. Levels are ordered low (numerically smaller)
//! then high, and combinations run with e slowest and em fastest, as in the 1983 tables.

use crate::coefficients::{Coefficients, SolveOptions, EM_ONE_TOL};
use crate::error::{PimError, Result};
use crate::model::{Impact, Velocities};
use crate::report::ImpactReport;
use crate::solve::solve_forward;
use serde::{Deserialize, Serialize};

/// One of the three coefficients.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum CoefficientName {
    /// Restitution e.
    E,
    /// Friction mu.
    Mu,
    /// Moment restitution e_m.
    Em,
}

/// Level of a coefficient in the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Level {
    /// The numerically smaller of value x (1 - p) and value x (1 + p).
    Low,
    /// The numerically larger.
    High,
    /// Not varied (em = 1).
    Nominal,
}

/// One combination of levels and its solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SensitivityCase {
    /// Levels of e, mu and em.
    pub levels: [Level; 3],
    /// The coefficients of this combination.
    pub coefficients: Coefficients,
    /// The forward solution.
    pub report: ImpactReport,
}

/// Averages over all combinations with one coefficient at one level (1983 Table 6).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct LevelAverage {
    /// The coefficient held at this level.
    pub coefficient: CoefficientName,
    /// The level.
    pub level: Level,
    /// The coefficient's value at this level.
    pub value: f64,
    /// Mean |delta-V| of vehicle 1, m/s.
    pub delta_v1: f64,
    /// Mean |delta-V| of vehicle 2, m/s.
    pub delta_v2: f64,
    /// Mean |delta-omega| of vehicle 1, rad/s.
    pub delta_omega1: f64,
    /// Mean |delta-omega| of vehicle 2, rad/s.
    pub delta_omega2: f64,
    /// Mean energy loss, percent.
    pub energy_loss_percent: f64,
}

/// The complete study.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SensitivityStudy {
    /// The variation p in percent.
    pub percent: f64,
    /// The solution at the nominal coefficients.
    pub nominal: ImpactReport,
    /// Every combination.
    pub cases: Vec<SensitivityCase>,
    /// Averages per coefficient and level.
    pub averages: Vec<LevelAverage>,
}

fn levels(
    name: &'static str,
    value: f64,
    p: f64,
    domain: &'static str,
    ok: impl Fn(f64) -> bool,
) -> Result<Vec<(Level, f64)>> {
    let mut out = Vec::with_capacity(2);
    for factor in [1.0 - p, 1.0 + p] {
        let v = value * factor;
        if !ok(v) {
            return Err(PimError::SensitivityLevelOutOfRange {
                name,
                factor,
                value: v,
                domain,
            });
        }
        out.push(v);
    }
    out.sort_by(f64::total_cmp);
    Ok(vec![(Level::Low, out[0]), (Level::High, out[1])])
}

/// Runs the study for `percent` (for example 10 for +/-10 %).
pub fn sensitivity(
    impact: &Impact,
    coefficients: &Coefficients,
    initial: &Velocities,
    options: &SolveOptions,
    percent: f64,
) -> Result<SensitivityStudy> {
    if !(percent.is_finite() && (0.0..100.0).contains(&percent)) {
        return Err(PimError::BadPercentage(percent));
    }
    let nominal = solve_forward(impact, coefficients, initial, options)?;
    let p = percent / 100.0;
    let es = levels("e", coefficients.e, p, "[0, 1]", |v| {
        (0.0..=1.0).contains(&v)
    })?;
    let mus = levels("mu", coefficients.mu, p, "any finite value", f64::is_finite)?;
    let ems = if (coefficients.em - 1.0).abs() <= EM_ONE_TOL {
        vec![(Level::Nominal, 1.0)]
    } else {
        levels("em", coefficients.em, p, "[-1, 0]", |v| {
            (-1.0..=0.0).contains(&v)
        })?
    };
    let mut cases = Vec::with_capacity(es.len() * mus.len() * ems.len());
    for &(le, e) in &es {
        for &(lmu, mu) in &mus {
            for &(lem, em) in &ems {
                let c = Coefficients { e, mu, em };
                let report = solve_forward(impact, &c, initial, options)?;
                cases.push(SensitivityCase {
                    levels: [le, lmu, lem],
                    coefficients: c,
                    report,
                });
            }
        }
    }
    let mut averages = Vec::new();
    for (k, name, list) in [
        (0, CoefficientName::E, &es),
        (1, CoefficientName::Mu, &mus),
        (2, CoefficientName::Em, &ems),
    ] {
        if list.len() < 2 {
            continue;
        }
        for &(level, value) in list.iter() {
            let sel: Vec<&ImpactReport> = cases
                .iter()
                .filter(|c| c.levels[k] == level)
                .map(|c| &c.report)
                .collect();
            let mean = |f: &dyn Fn(&ImpactReport) -> f64| {
                sel.iter().map(|r| f(r)).sum::<f64>() / sel.len() as f64
            };
            averages.push(LevelAverage {
                coefficient: name,
                level,
                value,
                delta_v1: mean(&|r| r.delta_v[0].magnitude),
                delta_v2: mean(&|r| r.delta_v[1].magnitude),
                delta_omega1: mean(&|r| r.delta_v[0].domega.abs()),
                delta_omega2: mean(&|r| r.delta_v[1].domega.abs()),
                energy_loss_percent: mean(&|r| r.energy.loss_percent),
            });
        }
    }
    Ok(SensitivityStudy {
        percent,
        nominal,
        cases,
        averages,
    })
}
