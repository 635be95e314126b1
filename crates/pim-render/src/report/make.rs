//! Making a crash's report from its case alone, as `pim report` and the Python package do: the
//! fit (or solve) it asks for, the uncertainty study when it says what is uncertain, and the
//! document.

use super::doc::Document;
use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_studies::documents::{self, DocumentError, Fitted, Solved};
use pim_studies::fitcase::CostChoice;
use pim_studies::reconstruct::Reconstructed;
use pim_studies::reconstruct_study::ReconstructionStudy;
use pim_studies::uncertainty::Study;

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

/// What a report was made from: a fit, a solve or a reconstruction.
#[derive(Debug, Clone)]
pub enum Basis {
    /// The fit of a fit case.
    Fit(Box<Fitted>),
    /// The solve of a solve case.
    Solve(Box<Solved>),
    /// The whole reconstruction of a case with scene evidence (what `pim fit` answers it with).
    Reconstruction(Box<Reconstructed>),
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
    /// The study of a reconstruction, when one ran and had admissible draws.
    pub scene_study: Option<ReconstructionStudy>,
}

impl Made {
    /// True when the report has an answer (a solve, or a fit with an admissible branch).
    pub fn answered(&self) -> bool {
        match &self.basis {
            Basis::Fit(f) => f.report.best.is_some(),
            Basis::Solve(_) => true,
            Basis::Reconstruction(r) => r.document.status == pim_reconstruct::Status::Found,
        }
    }
}

/// Makes the report of `case` (the study runs on the current rayon pool).
pub fn make(case: &Case, o: &Options) -> Result<Made, DocumentError> {
    let units = o
        .units
        .unwrap_or_else(|| UnitSystem::of(&case.written_units));
    let asked = pim_studies::question::Question::of(case, o.cost);
    if !o.solve && asked.question == pim_studies::question::Question::Reconstruction {
        return reconstruction(case, o, units);
    }
    let is_fit = !o.solve && pim_studies::fitcase::is_fit_case(case);
    let cannot = |e: crate::RenderError| DocumentError::Input(e.in_file(&case.file));
    if !is_fit {
        let solved = documents::solve(case, &pim_core::SolveOptions::default())?;
        let document = super::build::solve(case, &solved, units).map_err(cannot)?;
        return Ok(Made {
            document,
            basis: Basis::Solve(Box::new(solved)),
            study: None,
            scene_study: None,
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
    let uncertain = case.is_uncertain();
    let draws = o.draws.unwrap_or(if uncertain { DEFAULT_DRAWS } else { 0 });
    let study = if draws > 0 && fitted.report.best.is_some() {
        let s = pim_studies::uncertainty::run(
            case,
            &case.spreads(),
            o.cost.map_or(CostChoice::Custom, CostChoice::Preset),
            pim_fit::FitSettings {
                model: o.model,
                ..Default::default()
            },
            draws,
            o.seed,
            &pim_studies::watch::Unwatched,
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
        scene_study: None,
    })
}

/// The report of a case with scene evidence: its whole reconstruction (as `pim fit` answers
/// it), with the evidence consistency table when the evidence conflicts and, unless `draws` is
/// 0, the study through all three phases ([`DEFAULT_DRAWS`] refits by default: the scene's
/// evidence always has standard deviations).
fn reconstruction(case: &Case, o: &Options, units: UnitSystem) -> Result<Made, DocumentError> {
    let branches = o.model.branches(&pim_fit::MomentBranch::ALL);
    let done = pim_studies::consistency::answer(
        case,
        o.model,
        pim_core::MomentForm::Corrected,
        branches,
        &pim_studies::watch::Unwatched,
    )?;
    let draws = o.draws.unwrap_or(DEFAULT_DRAWS);
    let study = if draws > 0 && done.document.status == pim_reconstruct::Status::Found {
        // Around the reconstruction just made, not a second one.
        let s = pim_studies::reconstruct_study::run_around(
            case,
            &done,
            draws,
            o.seed,
            &pim_studies::watch::Unwatched,
        )?;
        (s.feasible_draws > 0).then_some(s)
    } else {
        None
    };
    let document = super::scene::reconstruction(case, &done, study.as_ref(), units)
        .map_err(|e| DocumentError::Input(e.in_file(&case.file)))?;
    Ok(Made {
        document,
        basis: Basis::Reconstruction(Box::new(done)),
        study: None,
        scene_study: study,
    })
}
