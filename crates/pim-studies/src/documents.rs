//! The documents of the `pim` command's JSON output, made from a loaded case: one function per
//! command, so that every front end (the command line, the Python package) gives the same
//! document for the same input.

use crate::fitcase;
use pim_case::case::Case;
use pim_core::{Impact, ImpactReport, SolveOptions};
use pim_documents::records::{BranchRecord, FitOut, ModelOut, SolveOut};
use pim_fit::{CostPreset, FitProblem, FitReport, MomentBranch};

/// Why a document could not be made.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DocumentError {
    /// Bad input: the message names the file and field.
    #[error("{0}")]
    Input(String),
    /// Valid input for which the model has no answer (singular or inconsistent equations).
    #[error("{0}")]
    NoAnswer(String),
}

impl From<pim_case::InputError> for DocumentError {
    fn from(e: pim_case::InputError) -> Self {
        DocumentError::Input(e.message)
    }
}

impl DocumentError {
    /// Classifies a pim-core error raised while solving the case in `file`: singular or
    /// inconsistent equations are "no answer", anything else bad input.
    pub fn from_core(file: &str, e: pim_core::PimError) -> Self {
        use pim_core::PimError as E;
        match e {
            E::Singular { .. } | E::InconsistentSliding(_) => {
                DocumentError::NoAnswer(format!("{file}: {e}"))
            }
            _ => DocumentError::Input(format!("{file}: {e}")),
        }
    }
}

/// A solved case: the impact, pim-core's report, the direction and the document.
#[derive(Debug, Clone)]
pub struct Solved {
    /// The checked impact.
    pub impact: Impact,
    /// pim-core's report.
    pub report: ImpactReport,
    /// True when the case gave the contact state (`[initial]`).
    pub forward: bool,
    /// The document of `pim solve --format json`.
    pub document: SolveOut,
}

/// `pim solve`: the case's known state carried through the impact with its coefficients.
pub fn solve(case: &Case, options: &SolveOptions) -> Result<Solved, DocumentError> {
    let impact = case.impact()?;
    let (state, forward) = case.known_state()?;
    // The model is picked once, here; everything below asks it, whichever it is.
    let model = case.model()?.impact_model(options);
    let solution = if forward {
        model.solve(&impact, &state)
    } else {
        model.solve_backward(&impact, &state)
    }
    .map_err(|e| match (forward, e) {
        (true, e) => not_approaching(case, &state, e),
        (false, pim_core::PimError::Unsupported(why)) => {
            DocumentError::Input(format!("{}: {why}: give [initial]", case.file))
        }
        (false, e) => DocumentError::from_core(&case.file, e),
    })?;
    let mut document = SolveOut::new(&impact, &solution.report, forward);
    if let Some(c) = solution.contact {
        document.model = Some(ModelOut {
            name: model.name(),
            description: model.description(),
            coefficients: model.coefficients().into_iter().collect(),
            mode: c.mode,
            impulse_ratio: c.impulse_ratio,
            stick_ratio: c.stick_ratio,
        });
    }
    if let Some(damage) = pim_case::damage::Damage::of(case)? {
        let r = &solution.report;
        let u = pim_fit::state_vector(&r.initial, &r.separation);
        document.damage = crate::damage_assess::assess(&damage, &impact, &u);
    }
    Ok(Solved {
        impact,
        report: solution.report,
        forward,
        document,
    })
}

/// A forward solve's error, explained when the vehicles do not approach.
fn not_approaching(
    case: &Case,
    state: &pim_core::Velocities,
    e: pim_core::PimError,
) -> DocumentError {
    match (&e, case.explain_not_approaching(state)) {
        (pim_core::PimError::NotApproaching { .. }, Some(why)) => {
            DocumentError::Input(format!("{}: {e}; {why}", case.file))
        }
        _ => DocumentError::from_core(&case.file, e),
    }
}

/// A fitted case: the problem, pim-fit's report and the document.
#[derive(Debug, Clone)]
pub struct Fitted {
    /// The fit problem (at the case's geometry).
    pub problem: FitProblem,
    /// pim-fit's report (each branch at its own geometry when `[bounds]` estimates it).
    pub report: FitReport,
    /// The document of `pim fit --format json`.
    pub document: FitOut,
}

/// `pim fit`: `cost` a preset, or `None` for the case's own `[known]` and `[estimates]`.
pub fn fit(
    case: &Case,
    cost: Option<CostPreset>,
    model: pim_fit::FitModel,
    moment_form: pim_core::MomentForm,
    branches: Vec<MomentBranch>,
) -> Result<Fitted, DocumentError> {
    fitcase::check_fit_sections(case)?;
    let (choice, name) = match cost {
        Some(p) => (fitcase::CostChoice::Preset(p), p.name()),
        None => (fitcase::CostChoice::Custom, "custom"),
    };
    let side = pim_documents::records::SideOut::of(&case.impact()?);
    let problem = fitcase::problem(case, choice)?;
    let branches = model.branches(&branches);
    let settings = fitcase::settings(case, model, moment_form, branches)?;
    let mut report = fitcase::fit(case, &problem, &settings)?;
    let unit = fitcase::sigma_unit(case)?;
    if let Some(preset) = cost {
        report.notes.extend(fitcase::ignored_weights(case, preset));
    }
    let damage = crate::damage_fit::fit_damage(case, &problem, &report, &settings, unit)?;
    let notes = report.notes.clone();
    let document = FitOut {
        units: pim_documents::records::SiUnits,
        model: model.name(),
        cost_function: name.to_string(),
        branches: report
            .branches
            .iter()
            .map(|b| {
                let mut r = BranchRecord::new(b)
                    .with_chi_square(&problem, unit)
                    .with_bounds(b, settings.get(), &|bound| fitcase::sets_bound(case, bound));
                if let Some(sol) = &b.solution {
                    r.residuals = crate::residuals::residuals(case, &problem, sol, unit);
                }
                r
            })
            .collect(),
        best: report.best,
        notes,
        side,
        damage,
    };
    Ok(Fitted {
        problem,
        report,
        document,
    })
}
