//! What every write of a case file is checked with: what `pim fit` refuses before it computes.

use pim_case::case::Case;

/// Refuses what `pim fit FILE` refuses before it computes, with its message: the case as read
/// ([`Case::from_text`], or a motion case's [`Case::motion_from_text`]), its crush, its
/// collision, and the inputs of the question it asks (the reconstruction's every piece of
/// evidence, or the impact fit's problem and bounds, or the run-out's inputs), built as the
/// study builds them and then dropped. This is the one check of every write of a case file
/// (`pim set`, the editor's Save, Python's `edit_case`): what it accepts, `pim fit` reads.
///
/// # Errors
/// A located [`DocumentError::Input`] naming the file, line and field.
pub fn check_text(file: &str, text: &str) -> Result<Case, crate::documents::DocumentError> {
    if pim_case::scene_sections::is_motion(text) {
        let case = Case::motion_from_text(file, text)?;
        case.scene_inputs()?;
        return Ok(case);
    }
    let case = Case::from_text(file, text)?;
    pim_case::damage::Damage::of(&case)?;
    case.impact()?;
    match crate::question::Question::of(&case, None).question {
        crate::question::Question::Reconstruction => {
            crate::reconstruct::case_reconstruction(
                &case,
                pim_fit::FitModel::Pim,
                pim_core::MomentForm::Corrected,
                pim_fit::MomentBranch::ALL.to_vec(),
            )?;
        }
        crate::question::Question::Impact | crate::question::Question::Solve => {
            if crate::fitcase::is_fit_case(&case) {
                crate::fitcase::problem(&case, crate::fitcase::CostChoice::Custom)?;
                crate::fitcase::settings(
                    &case,
                    pim_fit::FitModel::Pim,
                    pim_core::MomentForm::Corrected,
                    pim_fit::MomentBranch::ALL.to_vec(),
                )?;
            }
            if case.has_runout() {
                case.scene_inputs()?;
            }
        }
    }
    Ok(case)
}
