//! A survey's CSV imported into the case (`[survey]`, see [`pim_case::survey`]), and evidence
//! placed on one of its points: a rest, a mark or the impact centre written at the point's own
//! coordinates with the point's id kept beside them.

use crate::AnswerError;
use pim_case::case::Case;
use pim_case::edit::{CaseEdit, NewValue};
use pim_case::survey::{read_csv, with_survey, Placing};
use pim_case::units::LengthUnit;
use serde::Deserialize;

/// A survey the page imports.
#[derive(Debug, Clone, Deserialize)]
pub struct SurveyImport {
    /// The CSV's text: `id, x, y[, code[, description]]` a line, with or without a header.
    pub csv: String,
    /// Its file name, kept as `[survey] source`.
    #[serde(default)]
    pub source: Option<String>,
    /// The survey's length unit (`m` or `ft`; default the case's own).
    #[serde(default)]
    pub unit: Option<LengthUnit>,
    /// The survey point made the case's origin (default: the survey's own origin).
    #[serde(default)]
    pub origin: Option<String>,
    /// Degrees the survey is turned, counter-clockwise as seen on the plan (default 0).
    #[serde(default)]
    pub rotation: f64,
}

/// The case text with its `[survey]` replaced by the survey `import` reads (placed by its unit,
/// origin and turn), every other byte kept; checked as a case after the edit (evidence that
/// names a point the new survey moved or dropped is refused, named at its line).
///
/// # Errors
/// Text that is not a valid case (the CSV's faults name its source, line and column), a turn
/// that is not a finite number, or a case the survey makes invalid.
pub fn import_survey(file: &str, text: &str, import: &SurveyImport) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    if !import.rotation.is_finite() {
        return Err(AnswerError::Input(format!(
            "{file}: survey rotation {}: give a finite angle, degrees",
            import.rotation
        )));
    }
    let (case, was_case) = crate::plan::Sketch::read(file, text)?;
    let unit = case.units.length;
    let placing = Placing {
        scale: import.unit.unwrap_or(unit).to_si() / unit.to_si(),
        origin: import
            .origin
            .as_deref()
            .map(str::trim)
            .filter(|o| !o.is_empty())
            .map(str::to_string),
        rotation: import.rotation,
        convention: case.convention,
    };
    let source = import.source.as_deref().filter(|s| !s.trim().is_empty());
    let points =
        read_csv(source.unwrap_or("survey"), &import.csv, &placing).map_err(|e| input(&e))?;
    let out = with_survey(file, text, source, &points).map_err(|e| input(&e))?;
    crate::plan::Sketch::check_edited(file, &out, was_case)?;
    Ok(out)
}

/// The written coordinates of the survey point `id` of `case`.
pub(crate) fn survey_point(case: &Case, id: &str) -> Result<[f64; 2], AnswerError> {
    case.content
        .survey
        .as_ref()
        .and_then(|s| s.points.iter().find(|p| p.id == id))
        .map(|p| [p.x, p.y])
        .ok_or_else(|| AnswerError::Input(format!("{}: the survey has no point {id:?}", case.file)))
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
    let p = survey_point(case, id)?;
    for (axis, value) in [("x", p[0]), ("y", p[1])] {
        edit.set(&format!("{key}.{axis}"), NewValue::Written(value))
            .map_err(|e| input(&e))?;
    }
    edit.set(&format!("{key}.point"), NewValue::Text(id.to_string()))
        .map_err(|e| input(&e))?;
    Ok(Some(p))
}
