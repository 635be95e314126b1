//! The geometry at contact moved by hand on the page: a vehicle's CG and heading, the impact
//! centre and the crush surface's direction, written back into the case text in the file's own
//! form, units and frame.
//!
//! A case gives the impact centre in one of three forms: once in the scene (`[impact] centre`)
//! with each vehicle's CG `position`; in each vehicle's frame (`impact_point`), the centre then
//! at the scene's origin; or as `d` and `phi`. The page edits the first two:
//! - a vehicle moved: its `position`, or its `impact_point = R(-heading) (C - P)` (the centre
//!   `C`, the scene's origin where the file has no `[impact] centre`, stays where it is);
//! - a vehicle turned about its CG: its `heading` (and with `impact_point`, the point turned
//!   the other way, `p' = R(heading - heading') p`, so that the centre stays);
//! - the impact centre moved: `[impact] centre` (the CGs stay: a vehicle that gives its own
//!   `impact_point` gets it rewritten; a file with no `[impact] centre` has the centre at the
//!   scene's origin, so the move is refused with the way to write it);
//! - the crush surface's normal turned: `[impact] crush_angle`, or `crush_angle_from_vehicle1`
//!   (from vehicle 1's nose) where the file writes that.
//!
//! Page points are in the display length unit, page angles in degrees counter-clockwise from
//! the page's right. The written frame is the page turned: natural (h, v) = (x, y), headings
//! as on the page; SAE (h, v) = (y, x), headings clockwise from x, so `psi = 90 - page`.

use crate::AnswerError;
use pim_case::case::Case;
use pim_case::edit::{CaseEdit, NewValue, Quantity};
use pim_case::units::UnitSystem;
use serde::Deserialize;

/// What the page moved (page points and angles; `None`: unchanged).
#[derive(Debug, Clone, Default, Deserialize)]
pub struct ContactChange {
    /// The vehicle moved or turned (1 or 2).
    #[serde(default)]
    pub vehicle: Option<u8>,
    /// Its CG at contact, on the page.
    #[serde(default)]
    pub at: Option<[f64; 2]>,
    /// Its heading at contact on the page, degrees counter-clockwise from the page's right.
    #[serde(default)]
    pub heading: Option<f64>,
    /// The impact centre, on the page.
    #[serde(default)]
    pub centre: Option<[f64; 2]>,
    /// The crush surface's normal on the page, degrees counter-clockwise from the page's
    /// right.
    #[serde(default)]
    pub normal: Option<f64>,
    /// The vehicle's heading at rest (`[scene.vehicleN] rest`) on the page, degrees
    /// counter-clockwise from the page's right: the rest turned, nothing at contact moved.
    #[serde(default)]
    pub rest_heading: Option<f64>,
    /// The survey point the impact centre was dropped on (`[survey]`'s id), if any: the centre
    /// is written at the point's own coordinates, its id kept beside them.
    #[serde(default)]
    pub point: Option<String>,
}

impl ContactChange {
    /// Whether every number of the change is finite.
    fn is_finite(&self) -> bool {
        [self.at, self.centre]
            .into_iter()
            .flatten()
            .flatten()
            .chain(self.heading)
            .chain(self.normal)
            .chain(self.rest_heading)
            .all(f64::is_finite)
    }
}

/// An angle in (-180, 180].
fn wrapped(deg: f64) -> f64 {
    let w = deg.rem_euclid(360.0);
    if w > 180.0 {
        w - 360.0
    } else {
        w
    }
}

/// `R(deg) p`.
fn turned(deg: f64, p: [f64; 2]) -> [f64; 2] {
    let (s, c) = deg.to_radians().sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

/// The impact point in a vehicle's frame, `R(-heading') (C' - P')`, of a vehicle whose CG was
/// at `C - R(heading) p` (`was`: p, heading, C) and is now at `P'` (`None`: where it was) with
/// the heading `heading'` and the centre at `C'` (`now`).
fn impact_point(
    was: ([f64; 2], f64, [f64; 2]),
    now: (Option<[f64; 2]>, f64, [f64; 2]),
) -> [f64; 2] {
    let ((p, heading, c), (cg, new_heading, new_c)) = (was, now);
    let cg = cg.unwrap_or_else(|| {
        let g = turned(heading, p);
        [c[0] - g[0], c[1] - g[1]]
    });
    turned(-new_heading, [new_c[0] - cg[0], new_c[1] - cg[1]])
}

/// The case text with vehicle `k`'s rest heading set to the page angle `page` (degrees
/// counter-clockwise from the page's right), written from 0 to 360 degrees in the file's
/// convention, to a hundredth; the text checked as a case after the edit.
fn turn_rest(file: &str, text: &str, k: u8, page: f64) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    if !(k == 1 || k == 2) {
        return Err(AnswerError::Input(format!(
            "{file}: vehicle {k}: the vehicles are 1 and 2"
        )));
    }
    let case = Case::from_text(file, text).map_err(|e| input(&e))?;
    if !case.written.heads_by_nose() {
        return Err(AnswerError::Input(format!(
            "{file}: a case in the papers' convention is edited in its TOML"
        )));
    }
    let written = case.written.angle_from_page(page);
    let mut edit = CaseEdit::new(file, text).map_err(|e| input(&e))?;
    edit.set(
        &format!("scene.vehicle{k}.rest.heading"),
        hundredth(written.rem_euclid(360.0)),
    )
    .map_err(|e| input(&e))?;
    edit.check().map_err(|e| input(&e))?;
    Ok(edit.text())
}

/// To a hundredth, as a scene diagram gives positions and angles.
/// `[impact] centre` moved from `old` to `c` (written frame and unit), or placed on the survey
/// point `point` (`c` its coordinates); a vehicle that gives its own impact point keeps its
/// CG, the point following the centre.
fn move_centre(
    case: &Case,
    edit: &mut CaseEdit,
    (old, c): ([f64; 2], [f64; 2]),
    point: Option<&str>,
) -> Result<(), AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let set_point = |edit: &mut CaseEdit, key: &str, p: [f64; 2]| {
        for (axis, v) in [("x", p[0]), ("y", p[1])] {
            edit.set(&format!("{key}.{axis}"), hundredth(v))
                .map_err(|e| input(&e))?;
        }
        Ok::<_, AnswerError>(())
    };
    for name in ["vehicle1", "vehicle2"] {
        let heading = num(edit, &format!("{name}.heading")).unwrap_or(0.0);
        let (Some(px), Some(py)) = (
            num(edit, &format!("{name}.impact_point.x")),
            num(edit, &format!("{name}.impact_point.y")),
        ) else {
            continue;
        };
        let p = impact_point(([px, py], heading, old), (None, heading, c));
        set_point(edit, &format!("{name}.impact_point"), p)?;
    }
    if point.is_some() {
        crate::survey::placed_on(case, edit, "impact.centre", point)?;
    } else {
        set_point(edit, "impact.centre", c)?;
        edit.remove("impact.centre.point");
    }
    Ok(())
}

fn hundredth(x: f64) -> NewValue {
    NewValue::Written(crate::edits::hundredth(x))
}

/// The case text with the geometry at contact changed as the page moved it; see the [module
/// docs](self). The text is checked as a case after the edit.
///
/// # Errors
/// Text that is not a valid case, a change that is no number, a vehicle other than 1 or 2, a
/// case written in a form the page does not edit (`d` and `phi`, the papers' convention, a
/// barrier), or a case the change makes invalid (pim's message).
pub fn edit_contact(
    file: &str,
    text: &str,
    change: &ContactChange,
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let refuse = |why: String| AnswerError::Input(format!("{file}: {why}"));
    if !change.is_finite() {
        return Err(refuse(
            "the geometry moved on the page is not a number".into(),
        ));
    }
    if let (Some(k), Some(page)) = (change.vehicle, change.rest_heading) {
        return turn_rest(file, text, k, page);
    }
    let case = Case::from_text(file, text).map_err(|e| input(&e))?;
    if !case.written.heads_by_nose() {
        return Err(refuse(
            "a case in the papers' convention is edited in its TOML (the page moves vehicles \
             of the natural and SAE forms)"
                .into(),
        ));
    }
    let units = units.unwrap_or_else(|| UnitSystem::of(&case.written_units));
    let mut edit = CaseEdit::new(file, text).map_err(|e| input(&e))?;
    let per_unit = Quantity::Length.si_per_unit(&edit.units().map_err(|e| input(&e))?);
    // Page point (display unit) to the written frame (file unit); page angle to written.
    let metres = units.length(1.0).recip();
    let point = |p: [f64; 2]| case.written.from_page(p.map(|x| x * metres / per_unit));
    let angle = |page: f64| wrapped(case.written.angle_from_page(page));
    let set =
        |edit: &mut CaseEdit, path: &str, v: NewValue| edit.set(path, v).map_err(|e| input(&e));
    let set_point = |edit: &mut CaseEdit, key: &str, p: [f64; 2]| {
        set(edit, &format!("{key}.x"), hundredth(p[0]))?;
        set(edit, &format!("{key}.y"), hundredth(p[1]))
    };
    let centre = match (num(&edit, "impact.centre.x"), num(&edit, "impact.centre.y")) {
        (Some(x), Some(y)) => Some([x, y]),
        _ => None,
    };
    if let Some(k) = change.vehicle {
        if !(k == 1 || k == 2) {
            return Err(refuse(format!("vehicle {k}: the vehicles are 1 and 2")));
        }
        let name = format!("vehicle{k}");
        if case.vehicle(usize::from(k - 1)).barrier {
            return Err(refuse(format!("{name} is a barrier: it does not move")));
        }
        let heading = num(&edit, &format!("{name}.heading")).unwrap_or(0.0);
        let new_heading = change.heading.map_or(heading, angle);
        let written = |key: &str| {
            (
                num(&edit, &format!("{name}.{key}.x")),
                num(&edit, &format!("{name}.{key}.y")),
            )
        };
        match (written("position"), written("impact_point")) {
            ((Some(_), Some(_)), _) => {
                if let Some(p) = change.at.map(point) {
                    set_point(&mut edit, &format!("{name}.position"), p)?;
                }
            }
            (_, (Some(px), Some(py))) => {
                // The centre C (the scene's origin without [impact] centre) stays.
                let c = centre.unwrap_or([0.0, 0.0]);
                let p = impact_point(
                    ([px, py], heading, c),
                    (change.at.map(point), new_heading, c),
                );
                set_point(&mut edit, &format!("{name}.impact_point"), p)?;
            }
            _ => {
                return Err(refuse(format!(
                    "[{name}] gives its impact centre as d and phi: the page moves vehicles \
                     whose case gives impact_point, or [impact] centre with each position"
                )))
            }
        }
        if change.heading.is_some() {
            set(
                &mut edit,
                &format!("{name}.heading"),
                hundredth(new_heading),
            )?;
        }
    }
    let snapped = match (&change.point, change.centre) {
        (Some(id), Some(_)) => Some(crate::survey::survey_point(&case.file, case.survey(), id)?),
        _ => None,
    };
    if let Some(c) = snapped.or(change.centre.map(point)) {
        let Some(old) = centre else {
            return Err(refuse(
                "the impact centre of this case is each vehicle's impact_point (the centre at \
                 the origin): move the vehicles, or write [impact] centre with each vehicle's \
                 CG position to move the centre"
                    .into(),
            ));
        };
        move_centre(
            &case,
            &mut edit,
            (old, c),
            snapped.and(change.point.as_deref()),
        )?;
    }
    if let Some(n) = change.normal.map(angle) {
        set_normal(&mut edit, n).map_err(|e| input(&e))?;
    }
    edit.check().map_err(|e| input(&e))?;
    Ok(edit.text())
}

/// The crush surface's normal `n` (degrees, the written frame) written as the case gives it:
/// as an angle from vehicle 1's heading where it writes one, else as the crush angle.
fn set_normal(edit: &mut CaseEdit, n: f64) -> Result<(), pim_case::InputError> {
    if edit.get("impact.crush_angle_from_vehicle1").is_some() {
        let nose = num(edit, "vehicle1.heading").unwrap_or(0.0);
        edit.set(
            "impact.crush_angle_from_vehicle1",
            hundredth(wrapped(n - nose)),
        )
    } else {
        edit.set("impact.crush_angle", hundredth(n))
    }
}

/// The number the case writes at `path`, if it writes one there.
fn num(edit: &CaseEdit, path: &str) -> Option<f64> {
    edit.get(path).and_then(|s| s.parse::<f64>().ok())
}
