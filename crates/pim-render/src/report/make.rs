//! Making a crash's report from its case alone, as `pim report` and the Python package do: the
//! fit (or solve) it asks for, the uncertainty study when it says what is uncertain, and the
//! document.

use super::doc::Document;
use pim_data::case::Case;
use pim_data::documents::{self, DocumentError, Fitted, Solved};
use pim_data::fitcase::CostChoice;
use pim_data::uncertainty::Study;
use pim_data::units::UnitSystem;

/// The draws of a report's uncertainty study when none are asked for and the case gives
/// `[sigma]` or `[uncertainty]`.
pub const DEFAULT_DRAWS: usize = 200;

/// What a report is made of.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    /// The cost function of a fit (`None`: the case's own known and estimated values).
    pub cost: Option<pim_fit::CostPreset>,
    /// The model fitted (also by every draw of the uncertainty study).
    pub model: pim_fit::FitModel,
    /// Report the solve of a case that also holds a fit.
    pub solve: bool,
    /// Refits of the study (`None`: [`DEFAULT_DRAWS`] when the case says what is uncertain,
    /// else none; `Some(0)`: none).
    pub draws: Option<usize>,
    /// Seed of the study.
    pub seed: u64,
    /// Units of the report (`None`: the case's own).
    pub units: Option<UnitSystem>,
}

impl Default for Options {
    fn default() -> Self {
        Options {
            cost: None,
            model: pim_fit::FitModel::Pim,
            solve: false,
            draws: None,
            seed: 1,
            units: None,
        }
    }
}

/// What a report was made from: a fit or a solve.
#[derive(Debug, Clone)]
pub enum Basis {
    /// The fit of a fit case.
    Fit(Box<Fitted>),
    /// The solve of a solve case.
    Solve(Box<Solved>),
}

/// A made report: the document, and what it was made from.
#[derive(Debug, Clone)]
pub struct Made {
    /// The document.
    pub document: Document,
    /// The fit or solve it reports.
    pub basis: Basis,
    /// The uncertainty study, when one ran and had admissible draws.
    pub study: Option<Study>,
}

impl Made {
    /// True when the report has an answer (a solve, or a fit with an admissible branch).
    pub fn answered(&self) -> bool {
        match &self.basis {
            Basis::Fit(f) => f.report.best.is_some(),
            Basis::Solve(_) => true,
        }
    }
}

/// Makes the report of `case` (the study runs on the current rayon pool).
pub fn make(case: &Case, o: &Options) -> Result<Made, DocumentError> {
    let units = o
        .units
        .unwrap_or_else(|| UnitSystem::of(&case.written_units));
    let c = &case.content;
    let is_fit = !o.solve && pim_data::fitcase::is_fit_case(case);
    let cannot = |e: String| DocumentError::Input(format!("{}: cannot draw: {e}", case.file));
    if !is_fit {
        let solved = documents::solve(case, &pim_core::SolveOptions::default())?;
        let document = super::build::solve(case, &solved, units).map_err(cannot)?;
        return Ok(Made {
            document,
            basis: Basis::Solve(Box::new(solved)),
            study: None,
        });
    }
    let name = o.cost.map_or("custom", |p| p.name());
    let fitted = documents::fit(
        case,
        o.cost,
        o.model,
        pim_core::MomentForm::Corrected,
        o.model.branches(&pim_fit::MomentBranch::ALL),
    )?;
    let uncertain = c.sigma.is_some() || c.uncertainty.is_some();
    let draws = o.draws.unwrap_or(if uncertain { DEFAULT_DRAWS } else { 0 });
    let study = if draws > 0 && fitted.report.best.is_some() {
        let s = pim_data::uncertainty::run(
            case,
            &c.uncertainty.unwrap_or_default(),
            o.cost.map_or(CostChoice::Custom, CostChoice::Preset),
            pim_fit::FitSettings {
                model: o.model,
                ..Default::default()
            },
            draws,
            o.seed,
            &|| {},
        )?;
        (s.feasible_draws > 0).then_some(s)
    } else {
        None
    };
    let document = super::build::fit(case, &fitted, name, study.as_ref(), units).map_err(cannot)?;
    Ok(Made {
        document,
        basis: Basis::Fit(Box::new(fitted)),
        study,
    })
}
