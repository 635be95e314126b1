//! A vehicle's rest placed on the plan (the Rest tool): where it was clicked or on a survey
//! point, with its heading and standard deviation, written as `[scene.vehicleN] rest` and
//! `rest_sigma`, on a case being built too.

use crate::AnswerError;
use pim_case::edit::{CaseEdit, NewValue};
use serde::Deserialize;

/// A vehicle's rest placed on the page (the Rest tool).
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct NewRest {
    /// Whose rest: 1 or 2.
    pub vehicle: u8,
    /// Where its CG rests, on the page (display length unit).
    pub at: [f64; 2],
    /// Its heading at rest as the case writes headings (degrees; SAE clockwise), if measured.
    #[serde(default)]
    pub heading: Option<f64>,
    /// The standard deviation of each coordinate (display length unit).
    pub sigma: f64,
    /// The survey point it was placed on (`[survey]`'s id), if any.
    #[serde(default)]
    pub point: Option<String>,
}

/// The case text with vehicle `rest.vehicle`'s rest placed: `[scene.vehicleN] rest` (and
/// `rest_sigma`, 3 degrees for a heading) written where the page put it (display length unit of
/// `units`, `None`: the case's own) in the file's unit and frame, to a hundredth, or at the
/// survey point it was placed on with the point's id; the section added when the case has
/// none. The case may still be being built: it is checked as a case when it was one.
///
/// # Errors
/// A vehicle other than 1 or 2, a point, heading or sigma that is not a finite number (the
/// sigma above 0), a survey point the case lacks, or a case the rest makes invalid.
pub fn place_rest(
    file: &str,
    text: &str,
    rest: &NewRest,
    units: Option<pim_case::units::UnitSystem>,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let NewRest {
        vehicle,
        at,
        heading,
        sigma,
        ref point,
    } = *rest;
    if !(vehicle == 1 || vehicle == 2)
        || !at.iter().chain(&heading).all(|x| x.is_finite())
        || !(sigma.is_finite() && sigma > 0.0)
    {
        return Err(AnswerError::Input(format!(
            "{file}: a rest of vehicle {vehicle} at {at:?} (heading {heading:?}, sigma {sigma}) \
             cannot be written"
        )));
    }
    let (sketch, was_case) = crate::plan::Sketch::read(file, text)?;
    let units = units.unwrap_or_else(|| sketch.system());
    let per_unit = units.length(1.0).recip() / sketch.units.length.to_si();
    let hundredth = |x: f64| crate::edits::hundredth(x * per_unit);
    let xy = match point {
        Some(id) => crate::survey::survey_point(file, sketch.survey.as_ref(), id)?,
        None => {
            let (x, y) =
                crate::edits::written_frame((sketch.convention, &sketch.units), at, Some(units));
            let metres = sketch.units.length.to_si();
            [
                crate::edits::hundredth(x / metres),
                crate::edits::hundredth(y / metres),
            ]
        }
    };
    let mut fields = vec![
        ("x".to_string(), NewValue::Written(xy[0])),
        ("y".to_string(), NewValue::Written(xy[1])),
    ];
    let mut sigmas = vec![
        ("x".to_string(), NewValue::Written(hundredth(sigma))),
        ("y".to_string(), NewValue::Written(hundredth(sigma))),
    ];
    if let Some(h) = heading {
        fields.push((
            "heading".into(),
            NewValue::Written(crate::edits::hundredth(h)),
        ));
        sigmas.push(("heading".into(), NewValue::Written(3.0)));
    }
    if let Some(id) = point {
        fields.push(("point".into(), NewValue::Text(id.clone())));
    }
    let key = format!("scene.vehicle{vehicle}");
    let mut edit = CaseEdit::new(file, text).map_err(|e| input(&e))?;
    if edit.has(&format!("{key}.rest_tyres")) {
        return Err(AnswerError::Input(format!(
            "{file}: vehicle {vehicle}'s rest is given by its tyre points: move them in the TOML"
        )));
    }
    let mut out = text.to_string();
    if !edit.has(&key) {
        // A section of its own at the end, after a blank line, as the file's others are.
        if !out.is_empty() && !out.ends_with('\n') {
            out.push('\n');
        }
        out.push_str(&format!("\n[{key}]\n"));
        edit = CaseEdit::new(file, &out).map_err(|e| input(&e))?;
    }
    edit.set(&format!("{key}.rest"), NewValue::Fields(fields))
        .map_err(|e| input(&e))?;
    edit.set(&format!("{key}.rest_sigma"), NewValue::Fields(sigmas))
        .map_err(|e| input(&e))?;
    let out = edit.text();
    crate::plan::Sketch::check_edited(file, &out, was_case)?;
    Ok(out)
}
