//! A vehicle's rest placed on the plan: by its CG (the Rest tool), where it was clicked or on
//! a survey point, with its heading and standard deviation, written as `[scene.vehicleN]
//! rest` and `rest_sigma`; or as it was measured (the Tyres tool), two or more tyre contact
//! points or outline corners, written as `rest_tyres`. On a case being built too.

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
    let xy = written_point(file, &sketch, (at, point.as_deref()), units)?;
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
    let mut edit = scene_section(file, text, &key)?;
    // Placed as a CG, the rest is no longer given by its tyre points.
    edit.remove(&format!("{key}.rest_tyres"));
    edit.set(&format!("{key}.rest"), NewValue::Fields(fields))
        .map_err(|e| input(&e))?;
    edit.set(&format!("{key}.rest_sigma"), NewValue::Fields(sigmas))
        .map_err(|e| input(&e))?;
    let out = edit.text();
    crate::plan::Sketch::check_edited(file, &out, was_case)?;
    Ok(out)
}

/// A point placed on the page at `at` (display length unit of `units`) in the file's frame and
/// length unit, to a hundredth; or, placed on the survey point `point`, that point's own
/// coordinates.
fn written_point(
    file: &str,
    sketch: &crate::plan::Sketch,
    (at, point): ([f64; 2], Option<&str>),
    units: pim_case::units::UnitSystem,
) -> Result<[f64; 2], AnswerError> {
    if let Some(id) = point {
        return crate::survey::survey_point(file, sketch.survey.as_ref(), id);
    }
    let (x, y) = crate::edits::written_frame((sketch.convention, &sketch.units), at, Some(units));
    let metres = sketch.units.length.to_si();
    Ok([
        crate::edits::hundredth(x / metres),
        crate::edits::hundredth(y / metres),
    ])
}

/// The case text open for editing with its section `[key]` (`scene.vehicleN`), added at the
/// end after a blank line, as the file's others are, when it has none.
fn scene_section(file: &str, text: &str, key: &str) -> Result<CaseEdit, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let edit = CaseEdit::new(file, text).map_err(|e| input(&e))?;
    if edit.has(key) {
        return Ok(edit);
    }
    let mut out = text.to_string();
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    out.push_str(&format!("\n[{key}]\n"));
    CaseEdit::new(file, &out).map_err(|e| input(&e))
}

/// One point of a vehicle measured at rest, placed on the page.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct NewTyre {
    /// Where it is, on the page (display length unit).
    pub at: [f64; 2],
    /// Which tyre's contact point (`front_left`, `front_right`, `rear_left`, `rear_right`),
    /// or, with `corner`, which corner of the outline.
    pub name: String,
    /// A corner of the outline, not a tyre.
    #[serde(default)]
    pub corner: bool,
    /// The survey point it was placed on, if any.
    #[serde(default)]
    pub point: Option<String>,
}

/// A vehicle's rest placed on the page as it was measured (the Tyres tool): two or more tyre
/// contact points or outline corners.
#[derive(Debug, Clone, PartialEq, Deserialize)]
pub struct NewRestTyres {
    /// Whose rest: 1 or 2.
    pub vehicle: u8,
    /// The points, in the order clicked.
    pub points: Vec<NewTyre>,
    /// The standard deviation of each coordinate (display length unit).
    pub sigma: f64,
}

/// The case text with vehicle `rest.vehicle`'s rest given by the points placed:
/// `[scene.vehicleN] rest_tyres` written in the file's unit and frame (a point on a survey
/// point at the point's own coordinates, with its id), replacing its `rest` and `rest_sigma`
/// (a rest is given one way). The case is checked: two points of one tyre, a name that is no
/// tyre or corner, or a vehicle without the geometry they need is refused at the field.
///
/// # Errors
/// A vehicle other than 1 or 2, fewer than two points, a point or sigma that is not a finite
/// number (the sigma above 0), a survey point the case lacks, or a case the points make
/// invalid.
pub fn place_rest_tyres(
    file: &str,
    text: &str,
    rest: &NewRestTyres,
    units: Option<pim_case::units::UnitSystem>,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let NewRestTyres {
        vehicle,
        ref points,
        sigma,
    } = *rest;
    if !(vehicle == 1 || vehicle == 2)
        || points.len() < 2
        || !points.iter().flat_map(|p| p.at).all(f64::is_finite)
        || !(sigma.is_finite() && sigma > 0.0)
    {
        return Err(AnswerError::Input(format!(
            "{file}: a rest of vehicle {vehicle} by {} points (sigma {sigma}) cannot be \
             written: give two or more points and a sigma above 0",
            points.len()
        )));
    }
    let (sketch, was_case) = crate::plan::Sketch::read(file, text)?;
    let units = units.unwrap_or_else(|| sketch.system());
    let metres = sketch.units.length.to_si();
    let per_unit = units.length(1.0).recip() / metres;
    let mut rows = Vec::new();
    for p in points {
        let xy = written_point(file, &sketch, (p.at, p.point.as_deref()), units)?;
        let mut row = vec![
            (
                if p.corner { "corner" } else { "wheel" }.to_string(),
                NewValue::Text(p.name.clone()),
            ),
            ("x".to_string(), NewValue::Written(xy[0])),
            ("y".to_string(), NewValue::Written(xy[1])),
            (
                "sigma".to_string(),
                NewValue::Written(crate::edits::hundredth(sigma * per_unit)),
            ),
        ];
        if let Some(id) = &p.point {
            row.push(("point".to_string(), NewValue::Text(id.clone())));
        }
        rows.push(row);
    }
    let key = format!("scene.vehicle{vehicle}");
    let mut edit = scene_section(file, text, &key)?;
    edit.remove(&format!("{key}.rest"));
    edit.remove(&format!("{key}.rest_sigma"));
    edit.set(&format!("{key}.rest_tyres"), NewValue::Rows(rows))
        .map_err(|e| input(&e))?;
    let out = edit.text();
    crate::plan::Sketch::check_edited(file, &out, was_case)?;
    Ok(out)
}
