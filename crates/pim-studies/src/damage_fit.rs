//! The damage in a fit: the crush at the fit's answer, and the fit with the crush energy as
//! evidence.

use crate::damage_assess::{assess, Assessment, EnergyTerm};
use pim_case::case::Case;
use pim_case::damage::Damage;
use pim_case::Result;
pub use pim_documents::damage_fit::{EnergyFit, FitDamage};
use pim_fit::{FitProblem, FitReport, NonlinearTerm, ValidSettings};

/// The damage of a fit of `case` (`None` without `[damage]`): the crush at the report's best
/// answer and, when the energy is evidence, the fit with it.
pub fn fit_damage(
    case: &Case,
    problem: &FitProblem,
    report: &FitReport,
    settings: &ValidSettings,
    unit: Option<f64>,
) -> Result<Option<FitDamage>> {
    let Some(damage) = Damage::of(case)? else {
        return Ok(None);
    };
    let needs_sigma = |at_fit: &Option<Assessment>| {
        damage.evidence == Some(true)
            && at_fit
                .as_ref()
                .is_some_and(|a| a.expected_loss_sigma <= 0.0)
    };
    let no_sigma = || {
        case.error_at(
            "damage.evidence",
            "the crush energy as evidence needs its standard deviation: give a_sigma, b_sigma, \
             depth_sigma or width_sigma in [damage.vehicleN]",
        )
    };
    if !crate::fitcase::geometry(case)?.is_empty() {
        // At the best branch's own geometry.
        let best = report.best_branch();
        let at_fit = match best.and_then(|b| b.geometry.as_ref().zip(b.solution.as_ref())) {
            Some((g, s)) => {
                let impact = g
                    .impact(&problem.impact)
                    .map_err(|e| pim_case::InputError::new(&case.file, e))?;
                assess(
                    &damage,
                    &impact,
                    &pim_fit::state_vector(&s.initial, &s.separation),
                )
            }
            None => None,
        };
        if needs_sigma(&at_fit) {
            return Err(no_sigma());
        }
        return Ok(Some(FitDamage {
            at_fit,
            evidence: false,
            not_evidence: Some(
                "the case estimates its geometry ([bounds] of the impact centre or crush angle): \
                 the crush energy is compared at the fitted geometry, not fitted with it"
                    .into(),
            ),
            with_energy: None,
        }));
    }
    let fitted = fit_damage_of(&damage, problem, report, settings, unit)
        .map_err(|e| pim_case::InputError::new(&case.file, e))?;
    if needs_sigma(&fitted.at_fit) {
        return Err(no_sigma());
    }
    Ok(Some(fitted))
}

/// The damage of a fit: the crush at the report's best answer and, when the energy is
/// evidence (as `damage` says, or when its standard deviation is above 0), the fit with it.
/// `unit` is the unit of the problem's inverse-variance weights (`None` without standard
/// deviations: the velocity residuals then count as if their sigma were 1 m/s).
///
/// # Errors
/// The nonlinear fit's error.
pub fn fit_damage_of(
    damage: &Damage,
    problem: &FitProblem,
    report: &FitReport,
    settings: &ValidSettings,
    unit: Option<f64>,
) -> std::result::Result<FitDamage, pim_fit::FitError> {
    let at_fit = report
        .best_branch()
        .and_then(|b| b.solution.as_ref())
        .and_then(|s| {
            assess(
                damage,
                &problem.impact,
                &pim_fit::state_vector(&s.initial, &s.separation),
            )
        });
    let sigma = at_fit.as_ref().map_or(0.0, |a| a.expected_loss_sigma);
    let wanted = damage.evidence.unwrap_or(sigma > 0.0) && sigma > 0.0;
    let mut out = FitDamage {
        at_fit,
        evidence: false,
        not_evidence: None,
        with_energy: None,
    };
    if !wanted {
        out.not_evidence = Some(if damage.evidence == Some(false) {
            "[damage] evidence = false: compared, not fitted".into()
        } else if out.at_fit.is_none() {
            "no admissible answer to compare with".into()
        } else {
            "the crush energy has no standard deviation (give a_sigma, b_sigma, depth_sigma or \
             width_sigma): compared, not fitted"
                .into()
        });
        return Ok(out);
    }
    let term = EnergyTerm {
        damage,
        impact: &problem.impact,
    };
    let terms: [&dyn NonlinearTerm; 1] = [&term];
    let u = unit.unwrap_or(1.0);
    let fitted = pim_fit::fit_nonlinear(problem, report, u, &terms, settings)?;
    let Some(f) = fitted else {
        out.not_evidence = Some("no admissible answer to start from".into());
        return Ok(out);
    };
    let s = &f.solution;
    let at = pim_fit::state_vector(&s.initial, &s.separation);
    let chi_square = unit.map(|u| {
        let mut c = pim_fit::ChiSquare::new(problem, f.moment, f.cost, u);
        c.degrees_of_freedom += 1;
        c.p_value = pim_fit::ChiSquare::p_value_of(c.degrees_of_freedom, c.value);
        c
    });
    out.evidence = true;
    out.with_energy = Some(EnergyFit {
        moment: f.moment,
        e: s.e,
        mu: s.mu,
        em: s.em,
        initial: s.initial,
        final_: s.separation,
        cost: f.cost,
        cost_without_energy: f.linear_cost,
        energy_z: -f.residuals.first().copied().unwrap_or(0.0),
        chi_square,
        velocity_sigma_assumed: unit.is_none(),
        lower_bound: f.lower_bound,
        proven: f.proven,
        fits: f.fits,
        damage: assess(damage, &problem.impact, &at),
        delta_v: [s.delta_v[0].magnitude, s.delta_v[1].magnitude],
        energy_loss: s.energy_loss,
        solution: s.clone(),
    });
    Ok(out)
}

/// The crush energy of a case's damage as evidence of the whole reconstruction: at the
/// velocities `U`, the energy PIM's impact takes out minus the crush energy (with the PDOF
/// factors and the relation at those states), and its standard deviation.
#[derive(Debug)]
pub struct CrushEnergy {
    /// The damage.
    pub damage: Damage,
    /// The collision.
    pub impact: pim_core::Impact,
}

impl pim_reconstruct::StateEvidence for CrushEnergy {
    fn name(&self) -> String {
        "crush energy".into()
    }

    fn quantity(&self) -> &'static str {
        "energy"
    }

    fn residual(&self, u: &pim_fit::Vector12) -> Option<(f64, f64)> {
        let a = assess(&self.damage, &self.impact, u)?;
        (a.expected_loss_sigma > 0.0).then_some((a.difference, a.expected_loss_sigma))
    }
}

impl CrushEnergy {
    /// The crush energy of `case` as evidence of its reconstruction: `None` without
    /// `[damage]`, with `evidence = false`, or without a standard deviation of the crush (then
    /// the reason, to note).
    ///
    /// # Errors
    /// `evidence = true` without a standard deviation (located), or a damage section the crush
    /// model cannot read.
    pub fn of_case(
        case: &Case,
        impact: &pim_core::Impact,
    ) -> Result<(Option<CrushEnergy>, Option<String>)> {
        let Some(damage) = Damage::of(case)? else {
            return Ok((None, None));
        };
        let has_sigma = damage.vehicles.iter().flatten().any(|v| {
            let s = &v.sigmas;
            s.a > 0.0 || s.b > 0.0 || s.depth > 0.0 || s.width > 0.0
        });
        match (damage.evidence, has_sigma) {
            (Some(false), _) => Ok((
                None,
                Some(format!(
                    "{}: [damage] evidence = false: the crush is not fitted with the scene",
                    case.file
                )),
            )),
            (Some(true), false) => Err(case.error_at(
                "damage.evidence",
                "the crush energy as evidence needs its standard deviation: give a_sigma, \
                 b_sigma, depth_sigma or width_sigma in [damage.vehicleN]",
            )),
            (None, false) => Ok((
                None,
                Some(format!(
                    "{}: the crush energy has no standard deviation (give a_sigma, b_sigma, \
                     depth_sigma or width_sigma in [damage.vehicleN]): not fitted with the scene",
                    case.file
                )),
            )),
            (_, true) => Ok((
                Some(CrushEnergy {
                    damage,
                    impact: *impact,
                }),
                None,
            )),
        }
    }
}
