//! The tolerances file of `pim batch DATA.csv --draws N --tolerances FILE`: the standard
//! deviations applied to every test of a data file, checked before the batch runs.

use crate::case::Case;
use crate::fit_sections as fitcase;
use crate::spread::{Spread, UncertaintySection};
use crate::{InputError, Result};
use serde::Deserialize;

/// A tolerances file: the standard deviations that `pim batch DATA.csv --draws N --tolerances
/// FILE` applies to every test of a data file. The same sections as a case file: `[units]`,
/// `[sigma.initial]` / `[sigma.final]` (the measured velocities' standard deviations) and
/// `[uncertainty]` (the geometry's and the vehicles'), each a standard deviation: a uniform
/// range is a pair of absolute values, which one file cannot give for every test.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Tolerances {
    /// Units of the file's numbers (default SI).
    #[serde(default)]
    pub units: crate::units::UnitsSection,
    /// Standard deviations of the measured velocities.
    #[serde(default)]
    pub sigma: Option<crate::case::PartialStates>,
    /// Standard deviations of the inputs the fit takes as exact.
    #[serde(default)]
    pub uncertainty: Option<UncertaintySection>,
}

impl Tolerances {
    /// Parses and checks a tolerances file; the result is in SI.
    pub fn from_text(file: &str, text: &str) -> Result<Self> {
        let mut t: Tolerances = crate::case::parse_toml(file, text)?;
        if t.sigma.is_none() && t.uncertainty.is_none() {
            return Err(InputError::new(
                file,
                "nothing is uncertain: give [sigma.initial] / [sigma.final] and/or [uncertainty]",
            ));
        }
        if let Some(u) = &t.uncertainty {
            let mut all = vec![("impact.crush_angle".to_string(), u.impact.crush_angle)];
            for (name, v) in [("vehicle1", u.vehicle1), ("vehicle2", u.vehicle2)] {
                all.extend([
                    (format!("{name}.mass"), v.mass),
                    (format!("{name}.yaw_inertia"), v.yaw_inertia),
                    (format!("{name}.heading"), v.heading),
                    (format!("{name}.d"), v.d),
                    (format!("{name}.phi"), v.phi),
                ]);
            }
            for (what, sp) in all {
                match sp {
                    Some(Spread::Uniform { .. }) => {
                        return Err(crate::case::error_at(
                            file,
                            text,
                            &format!("uncertainty.{what}"),
                            "a tolerances file applies to every test, so give a standard \
                             deviation; a uniform range holds absolute values and belongs in a \
                             case file",
                        ))
                    }
                    Some(sp) => sp.check_own().map_err(|why| {
                        crate::case::error_at(file, text, &format!("uncertainty.{what}"), why)
                    })?,
                    None => {}
                }
            }
        }
        let u = t.units;
        if let Some(s) = &mut t.sigma {
            let written = s.components();
            s.scale(u.speed.to_si(), u.yaw_rate.to_si());
            // Checked here, against this file, before any test uses them.
            for (k, si) in s.components().iter().enumerate() {
                let (Some(si), Some(w)) = (si, written[k]) else {
                    continue;
                };
                if !(si.is_finite() && *si >= fitcase::SIGMA_MIN) {
                    return Err(crate::case::error_at(
                        file,
                        text,
                        &format!("sigma.{}", pim_fit::COMPONENT_NAMES[k]),
                        format!(
                            "{}: a standard deviation must be a number of at least {} (m/s or \
                             rad/s, in SI)",
                            crate::ranges::short(w),
                            fitcase::SIGMA_MIN
                        ),
                    ));
                }
            }
        }
        t.uncertainty = t
            .uncertainty
            .map(|x| x.to_si(u.mass.to_si(), u.yaw_inertia.to_si(), u.length.to_si()));
        t.units = Default::default();
        Ok(t)
    }

    /// Gives `case` these standard deviations (the case must be SI, as a loaded case is).
    pub fn apply(&self, case: &mut Case) {
        case.content.sigma = self.sigma;
        case.content.uncertainty = self.uncertainty;
    }
}
