//! A survey's CSV imported into the case (`[survey]`, see [`pim_case::survey`]), and evidence
//! placed on one of its points: a rest, a mark or the impact centre written at the point's own
//! coordinates with the point's id kept beside them.

use crate::AnswerError;
use pim_case::case::Case;
use pim_case::edit::{CaseEdit, NewValue};
use pim_case::survey::Import;
use serde::Deserialize;

/// A survey the page imports: its CSV, its file's name and how it is placed.
#[derive(Debug, Clone, Deserialize)]
pub struct SurveyImport {
    /// The CSV's text: `id, x, y[, code[, description]]` a line, with or without a header.
    pub csv: String,
    /// Its file name, kept as `[survey] source`.
    #[serde(default)]
    pub source: Option<String>,
    /// Its unit, origin point and turn.
    #[serde(flatten)]
    pub placing: Import,
}

/// The case text with its `[survey]` replaced by the survey `import` reads
/// ([`pim_case::survey::import`]), every other byte kept; checked as a case after the edit
/// when it was one (evidence that names a point the new survey moved or dropped is refused,
/// named at its line), a case being built otherwise.
///
/// # Errors
/// Text that is not a case or one being built, the CSV's faults (named at its line), or a
/// case the survey makes invalid.
pub fn import_survey(file: &str, text: &str, import: &SurveyImport) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let (_, was_case) = crate::plan::Sketch::read(file, text)?;
    let source = import.source.as_deref().unwrap_or("survey");
    let out = pim_case::survey::import(file, text, (source, &import.csv), &import.placing)
        .map_err(|e| input(&e))?;
    crate::plan::Sketch::check_edited(file, &out, was_case)?;
    Ok(out)
}

/// The written coordinates of the survey point `id` of the `survey` of `file`.
pub(crate) fn survey_point(
    file: &str,
    survey: Option<&pim_case::survey::SurveySection>,
    id: &str,
) -> Result<[f64; 2], AnswerError> {
    survey
        .and_then(|s| s.points.iter().find(|p| p.id == id))
        .map(|p| [p.x, p.y])
        .ok_or_else(|| AnswerError::Input(format!("{file}: the survey has no point {id:?}")))
}

/// `{key}.x`, `{key}.y` set to the survey point `point` (its own coordinates) and
/// `{key}.point` to its id; or, with no point, `{key}.point` removed (the evidence moved off
/// the point it was placed on).
pub(crate) fn placed_on(
    case: &Case,
    edit: &mut CaseEdit,
    key: &str,
    point: Option<&str>,
) -> Result<Option<[f64; 2]>, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let Some(id) = point else {
        edit.remove(&format!("{key}.point"));
        return Ok(None);
    };
    let p = survey_point(&case.file, case.survey(), id)?;
    for (axis, value) in [("x", p[0]), ("y", p[1])] {
        edit.set(&format!("{key}.{axis}"), NewValue::Written(value))
            .map_err(|e| input(&e))?;
    }
    edit.set(&format!("{key}.point"), NewValue::Text(id.to_string()))
        .map_err(|e| input(&e))?;
    Ok(Some(p))
}
