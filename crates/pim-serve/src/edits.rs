//! The case text edited as the page's tools edit it: a rest or a mark dragged, a mark or a
//! traced mark added, a skid set; each value written in the file's length unit and frame, to a hundredth (as a scene
//! diagram gives it), every other byte kept.

use crate::AnswerError;

/// `x` to a hundredth, as a scene diagram gives positions and angles (never `-0`).
pub(crate) fn hundredth(x: f64) -> f64 {
    (x * 100.0).round() / 100.0 + 0.0
}
use pim_case::case::Case;
use pim_case::edit::{CaseEdit, NewValue};
use pim_case::units::UnitSystem;
use pim_core::Convention;

/// The case text with vehicle `vehicle`'s rest position moved to the page point `at` (in the
/// plan's display length unit): `scene.vehicleN.rest.x` and `.y` rewritten in the file's
/// length unit and frame, every other byte kept.
///
/// # Errors
/// Text that is not TOML, or a case whose units cannot be read.
pub fn move_rest(file: &str, text: &str, vehicle: u8, at: [f64; 2]) -> Result<String, AnswerError> {
    move_rest_in(file, text, vehicle, at, None)
}

/// [`move_rest`] with the page point in the length unit of `units` (`None`: the case's own).
///
/// # Errors
/// As [`move_rest`].
pub fn move_rest_in(
    file: &str,
    text: &str,
    vehicle: u8,
    at: [f64; 2],
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    move_onto(file, text, (vehicle, None), (at, None), units)
}

/// Vehicle `vehicle`'s rest (`mark: None`) or its tyre mark `mark` moved to the page point
/// `at` (display length unit of `units`, `None`: the case's own), or placed on the survey point
/// `point` (its coordinates as `[survey]` writes them, and `point = "id"` kept beside them); a
/// move without a point drops the `point` the evidence had.
///
/// # Errors
/// As [`move_rest`], a survey point the case does not have, and a rest given by tyre points
/// placed on one survey point.
pub fn move_onto(
    file: &str,
    text: &str,
    (vehicle, mark): (u8, Option<usize>),
    (at, point): ([f64; 2], Option<&str>),
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    if let Some(i) = mark {
        if !(vehicle == 1 || vehicle == 2) || !at.iter().all(|x| x.is_finite()) {
            return Err(AnswerError::Input(format!(
                "{file}: mark {} of vehicle {vehicle} at {at:?} cannot be written",
                i + 1
            )));
        }
        return move_point(
            file,
            text,
            &format!("scene.vehicle{vehicle}.marks.{i}"),
            (at, point),
            units,
        );
    }
    if !(vehicle == 1 || vehicle == 2) || !at.iter().all(|x| x.is_finite()) {
        return Err(AnswerError::Input(format!(
            "{file}: a rest position of vehicle {vehicle} at {at:?} cannot be written"
        )));
    }
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let case = Case::from_text(file, text).map_err(|e| input(&e))?;
    match case.rest_tyres_written(usize::from(vehicle) - 1) {
        tyres if !tyres.is_empty() => {
            if point.is_some() {
                return Err(AnswerError::Input(format!(
                    "{file}: vehicle {vehicle}'s rest is given by its tyre points: place each \
                     tyre point on its survey point in the TOML (`point = \"id\"`)"
                )));
            }
            move_tyres(&case, text, vehicle, at, units)
        }
        _ => move_point(
            file,
            text,
            &format!("scene.vehicle{vehicle}.rest"),
            (at, point),
            units,
        ),
    }
}

/// A rest given by tyre points, its CG moved to the page point `at`: every point moved by the
/// same offset (the vehicle's measured rest moved whole), in the file's unit and frame.
fn move_tyres(
    case: &Case,
    text: &str,
    vehicle: u8,
    at: [f64; 2],
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let inputs = case.scene_inputs().map_err(|e| input(&e))?;
    let Some(rest) = inputs
        .vehicles
        .iter()
        .find(|v| v.id.index() + 1 == vehicle as usize)
        .and_then(|v| v.evidence.as_ref())
        .and_then(|e| e.rest)
    else {
        return Err(AnswerError::Input(format!(
            "{}: vehicle {vehicle} has no rest to move",
            case.file
        )));
    };
    let flip = case.written.sign();
    let (cx, cy) = rest.cg();
    let (x, y) = written_frame((case.written, &case.written_units), at, units);
    let mut edit = pim_case::edit::CaseEdit::new(&case.file, text).map_err(|e| input(&e))?;
    let per_unit =
        pim_case::edit::Quantity::Length.si_per_unit(&edit.units().map_err(|e| input(&e))?);
    let delta = [(x - cx) / per_unit, (y - flip * cy) / per_unit];
    let tyres = case.rest_tyres_written(usize::from(vehicle) - 1);
    for (i, t) in tyres.iter().enumerate() {
        for (axis, value, d) in [("x", t.0, delta[0]), ("y", t.1, delta[1])] {
            let path = format!("scene.vehicle{vehicle}.rest_tyres.{i}.{axis}");
            let written = hundredth(value + d);
            edit.set(&path, pim_case::edit::NewValue::Written(written))
                .map_err(|e| input(&e))?;
        }
    }
    Ok(edit.text())
}

/// The case text with vehicle `vehicle`'s tyre mark `mark` (from 0, as `marks` lists them)
/// moved to the page point `at` (display length unit of `units`, `None`: the case's own),
/// written as [`move_rest`] writes a rest.
///
/// # Errors
/// As [`move_rest`], and a mark the case does not have.
pub fn move_mark(
    file: &str,
    text: &str,
    (vehicle, mark): (u8, usize),
    at: [f64; 2],
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    move_onto(file, text, (vehicle, Some(mark)), (at, None), units)
}

/// `{key}.x` and `{key}.y` rewritten to the page point `at`, in the file's length unit and
/// frame, to a hundredth (as a scene diagram gives them), every other byte kept; or to the
/// survey point `point` (see [`move_onto`]).
fn move_point(
    file: &str,
    text: &str,
    key: &str,
    (at, point): ([f64; 2], Option<&str>),
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let mut on = OnFile::of(file, text, units)?;
    if crate::survey::placed_on(&on.case, &mut on.edit, key, point)?.is_some() {
        return Ok(on.edit.text());
    }
    let p = on.point(at);
    for (axis, value) in [("x", p[0]), ("y", p[1])] {
        on.edit
            .set(&format!("{key}.{axis}"), NewValue::Written(value))
            .map_err(|e| AnswerError::Input(e.to_string()))?;
    }
    Ok(on.edit.text())
}

/// A page point (display length unit of `units`, `None`: the case's own, `written_units`) in
/// the written frame of a case written in `written`, metres: the page is the written frame
/// turned, natural (h, v) = (x, y), SAE (h, v) = (y, x).
pub(crate) fn written_frame(
    (written, written_units): (Convention, &pim_case::units::UnitsSection),
    at: [f64; 2],
    units: Option<UnitSystem>,
) -> (f64, f64) {
    let units = units.unwrap_or_else(|| UnitSystem::of(written_units));
    let m = units.length(1.0).recip();
    let [x, y] = written.from_page(at);
    (x * m, y * m)
}

/// A tyre mark placed on the page.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
pub struct NewMark {
    /// Whose mark: 1 or 2.
    pub vehicle: u8,
    /// Where, on the page (display length unit).
    pub at: [f64; 2],
    /// Its standard deviation (display length unit).
    pub sigma: f64,
    /// The tyre that left it (`front_left` ... `rear_right`), or `cg` (the default: a point
    /// of the CG's path).
    #[serde(default)]
    pub wheel: Option<String>,
    /// The survey point it lies on (`[survey]`'s id), if placed on one: written at the point's
    /// own coordinates, its id kept beside them.
    #[serde(default)]
    pub point: Option<String>,
}

/// The case text with a tyre mark of vehicle `vehicle` added at the page point `at` with the
/// standard deviation `sigma` (both in the display length unit of `units`, `None`: the
/// case's own): appended to `[scene.vehicleN] marks` in the file's length unit and frame, to a
/// hundredth, every other byte kept. The text is checked as a case after the edit.
///
/// # Errors
/// Text that is not a valid case, a vehicle other than 1 or 2, a point or sigma that is not a
/// finite number (the sigma above 0), or a case the mark makes invalid (with pim's message).
pub fn add_mark(
    file: &str,
    text: &str,
    mark: &NewMark,
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let NewMark {
        vehicle,
        at,
        sigma,
        ref wheel,
        ref point,
    } = *mark;
    if !(vehicle == 1 || vehicle == 2)
        || !at.iter().all(|x| x.is_finite())
        || !(sigma.is_finite() && sigma > 0.0)
    {
        return Err(AnswerError::Input(format!(
            "{file}: a mark of vehicle {vehicle} at {at:?} with sigma {sigma} cannot be written"
        )));
    }
    let mut on = OnFile::of(file, text, units)?;
    let p = match point {
        Some(id) => crate::survey::survey_point(&on.case.file, on.case.survey(), id)?,
        None => on.point(at),
    };
    let mut entries = vec![
        ("x", NewValue::Written(p[0])),
        ("y", NewValue::Written(p[1])),
        ("sigma", NewValue::Written(on.length(sigma))),
    ];
    // The tyre that left it (the CG's path without one); the case's check below refuses a
    // name that is no wheel.
    if let Some(w) = wheel.as_deref().filter(|w| *w != "cg") {
        entries.push(("wheel", NewValue::Text(w.to_string())));
    }
    if let Some(id) = point {
        entries.push(("point", NewValue::Text(id.clone())));
    }
    on.pushed(&format!("scene.vehicle{vehicle}.marks"), &entries)
}

/// A yaw mark traced on the page: points along the mark one tyre left.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
pub struct NewTrace {
    /// Whose mark: 1 or 2.
    pub vehicle: u8,
    /// Its points in order along it, on the page (display length unit): two or more.
    pub points: Vec<[f64; 2]>,
    /// The standard deviation of the tyre path's distance from each point (display length
    /// unit).
    pub sigma: f64,
    /// The tyre that left it (`front_left` ... `rear_right`), or `cg`.
    pub wheel: String,
}

/// The case text with a traced mark of vehicle `vehicle` appended to `[scene.vehicleN]
/// traces`: its points and sigma (display length unit of `units`, `None`: the case's own) in
/// the file's length unit and frame, to a hundredth, and its wheel, every other byte kept. The
/// text is checked as a case after the edit.
///
/// # Errors
/// Text that is not a valid case, a vehicle other than 1 or 2, fewer than two points, a point
/// or sigma that is not a finite number (the sigma above 0), or a case the trace makes invalid
/// (a wheel the vehicle does not have: pim's message).
pub fn add_trace(
    file: &str,
    text: &str,
    trace: &NewTrace,
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let NewTrace {
        vehicle,
        ref points,
        sigma,
        ref wheel,
    } = *trace;
    if !(vehicle == 1 || vehicle == 2)
        || points.len() < 2
        || !points.iter().flatten().all(|x| x.is_finite())
        || !(sigma.is_finite() && sigma > 0.0)
    {
        return Err(AnswerError::Input(format!(
            "{file}: a trace of vehicle {vehicle} through {points:?} with sigma {sigma} cannot \
             be written (two points or more, a sigma above 0)"
        )));
    }
    let mut on = OnFile::of(file, text, units)?;
    let entries = [
        ("wheel", NewValue::Text(wheel.trim().to_string())),
        (
            "points",
            NewValue::Points(points.iter().map(|&p| on.point(p)).collect()),
        ),
        ("sigma", NewValue::Written(on.length(sigma))),
    ];
    on.pushed(&format!("scene.vehicle{vehicle}.traces"), &entries)
}

/// A case's text being edited from the page: its edit, and the page's points and lengths (the
/// display length unit of `units`, `None`: the case's own) as the file writes them, in its
/// length unit and frame, to a hundredth.
struct OnFile {
    case: Case,
    edit: CaseEdit,
    units: Option<UnitSystem>,
    /// Metres per the file's length unit.
    per_unit: f64,
}

impl OnFile {
    fn of(file: &str, text: &str, units: Option<UnitSystem>) -> Result<OnFile, AnswerError> {
        let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
        let case = Case::from_text(file, text).map_err(|e| input(&e))?;
        let edit = CaseEdit::new(file, text).map_err(|e| input(&e))?;
        let per_unit =
            pim_case::edit::Quantity::Length.si_per_unit(&edit.units().map_err(|e| input(&e))?);
        Ok(OnFile {
            case,
            edit,
            units,
            per_unit,
        })
    }

    /// The page point `at` in the file's frame and length unit.
    fn point(&self, at: [f64; 2]) -> [f64; 2] {
        let (x, y) = written_frame(
            (self.case.written, &self.case.written_units),
            at,
            self.units,
        );
        [hundredth(x / self.per_unit), hundredth(y / self.per_unit)]
    }

    /// The page length `l` (a sigma, a skid) in the file's length unit.
    fn length(&self, l: f64) -> f64 {
        let units = self
            .units
            .unwrap_or_else(|| UnitSystem::of(&self.case.written_units));
        hundredth(l * units.length(1.0).recip() / self.per_unit)
    }

    /// `entries` pushed as an inline table onto the array `path`: the text, checked as a case.
    fn pushed(&mut self, path: &str, entries: &[(&str, NewValue)]) -> Result<String, AnswerError> {
        let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
        self.edit.push(path, entries).map_err(|e| input(&e))?;
        self.edit.check().map_err(|e| input(&e))?;
        Ok(self.edit.text())
    }
}

/// The case text with vehicle `vehicle`'s skid up to contact set to `length` (display length
/// unit of `units`, `None`: the case's own): `[pre_impact.vehicleN] skid` in the file's unit,
/// to a hundredth, every other byte kept; the text is checked as a case after the edit.
///
/// # Errors
/// Text that is not a valid case, a vehicle other than 1 or 2, a length that is not a finite
/// number above 0, or a case the skid makes invalid (pim's message).
pub fn set_skid(
    file: &str,
    text: &str,
    (vehicle, length): (u8, f64),
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    if !(vehicle == 1 || vehicle == 2) || !(length.is_finite() && length > 0.0) {
        return Err(AnswerError::Input(format!(
            "{file}: a skid of {length} for vehicle {vehicle} cannot be written"
        )));
    }
    let mut on = OnFile::of(file, text, units)?;
    let written = NewValue::Written(on.length(length));
    on.edit
        .set(&format!("pre_impact.vehicle{vehicle}.skid"), written)
        .map_err(|e| input(&e))?;
    on.edit.check().map_err(|e| input(&e))?;
    Ok(on.edit.text())
}

/// A friction zone drawn on the page.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
pub struct NewZone {
    /// Its corners in order, on the page (display length unit).
    pub corners: Vec<[f64; 2]>,
    /// Its friction coefficient.
    pub friction: f64,
    /// What it is ("grass verge"), for the figures.
    #[serde(default)]
    pub name: Option<String>,
}

/// The case text with a friction zone appended (`[[runout.zones]]` at the end of the file):
/// its corners from the page (display length unit of `units`, `None`: the case's own) in the
/// file's length unit and frame, to a hundredth, every other byte kept; the text is checked as
/// a case after the edit.
///
/// # Errors
/// Text that is not a valid case, fewer than three corners or one that is not a finite number,
/// or a zone the case refuses (no area, a friction out of range: pim's message).
pub fn add_zone(
    file: &str,
    text: &str,
    zone: &NewZone,
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    if zone.corners.len() < 3 || !zone.corners.iter().flatten().all(|x| x.is_finite()) {
        return Err(AnswerError::Input(format!(
            "{file}: a zone needs three corners or more, each a finite point: got {:?}",
            zone.corners
        )));
    }
    let mut on = OnFile::of(file, text, units)?;
    let corners = zone.corners.iter().map(|&at| on.point(at)).collect();
    let mut entries = Vec::new();
    if let Some(name) = zone.name.as_deref().filter(|n| !n.trim().is_empty()) {
        entries.push(("name", NewValue::Text(name.trim().to_string())));
    }
    entries.push(("friction", NewValue::Written(zone.friction)));
    entries.push(("corners", NewValue::Points(corners)));
    on.edit
        .push_table("runout.zones", &entries)
        .map_err(|e| input(&e))?;
    on.edit.check().map_err(|e| input(&e))?;
    Ok(on.edit.text())
}
