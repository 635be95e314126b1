//! `[survey]`: the points of a total-station or tape survey of the scene, each with the id the
//! surveyor gave it, placed in the case's frame and length unit; and the evidence that names
//! one of them.
//!
//! ```toml
//! [survey]
//! source = "hydrant_survey.csv"        # where the points came from (not read again)
//! points = [
//!   { id = "1", x = 0.0, y = 0.0, code = "HYD", description = "fire hydrant" },
//!   { id = "7", x = 48.31, y = 80.12, code = "LF", description = "SUV left front tyre" },
//! ]
//!
//! [scene.vehicle2]
//! rest_tyres = [ { wheel = "front_left", x = 48.31, y = 80.12, sigma = 0.2, point = "7" }, ... ]
//! ```
//!
//! A rest (`rest`), a mark (`marks`), a tyre point at rest (`rest_tyres`) and the impact centre
//! (`[impact] centre`) may name the survey point they were placed on (`point = "7"`); the
//! point's id is then kept with the evidence, and the case is refused when the evidence no
//! longer lies on its point (the survey corrected, the evidence not), so one place on the
//! scene is never written two ways. The survey itself is not evidence: no answer reads it.
//!
//! [`read_csv`] reads a survey's CSV (`id, x, y[, code[, description]]`, with or without a
//! header line naming those columns) and places its points in the case's frame:
//! `p = R(θ) (q - q0) · unit`, where `q0` is the survey point made the case's origin (none:
//! the survey's own origin), `θ` the turn counter-clockwise as seen on the plan, and `unit`
//! the survey's length unit over the case's.

use crate::case::Case;
use crate::error::{InputError, Result};
pub use crate::scene_sections::{SurveyPoint, SurveySection};
use pim_core::Convention;

/// How far (the case's length unit) evidence may lie from the survey point it names: the
/// thousandth [`read_csv`] writes a point to, halved.
pub const ON_POINT: f64 = 0.0005;

/// How a survey's points are placed in the case.
#[derive(Debug, Clone, PartialEq)]
pub struct Placing {
    /// The case's length units per survey unit (`0.3048 / 1.0` for a survey in feet and a
    /// case in metres).
    pub scale: f64,
    /// The id of the survey point made the case's origin (`None`: the survey's own origin).
    pub origin: Option<String>,
    /// Degrees the survey is turned, counter-clockwise as seen on the plan.
    pub rotation: f64,
    /// The case's frame (an SAE case's plan is a map: x up, y right).
    pub convention: Convention,
}

/// A survey's CSV placed in the case by `placing`: each point's id, coordinates (to a
/// thousandth of the case's length unit), code and description.
///
/// # Errors
/// A line without an id or with coordinates that are not numbers, an id given twice, an origin
/// the survey does not have, or no point at all; the message names `file`, the line and the
/// column.
pub fn read_csv(file: &str, text: &str, placing: &Placing) -> Result<Vec<SurveyPoint>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .from_reader(text.as_bytes());
    let mut columns = [0usize, 1, 2, 3, 4];
    let mut raw: Vec<(u64, SurveyPoint)> = Vec::new();
    // Each id's line, to refuse one given twice.
    let mut lines: std::collections::HashMap<String, u64> = std::collections::HashMap::new();
    for (i, record) in reader.records().enumerate() {
        let record = record.map_err(|e| InputError::new(file, e))?;
        let line = record.position().map_or(i as u64 + 1, |p| p.line());
        if record.iter().all(str::is_empty) {
            continue;
        }
        if raw.is_empty() && i == 0 && record.get(1).is_some_and(|x| x.parse::<f64>().is_err()) {
            columns = header(file, &record)?;
            continue;
        }
        let field = |k: usize| record.get(columns[k]).unwrap_or("").to_string();
        let number = |k: usize, name: &str| {
            let s = field(k);
            s.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    InputError::located(
                        file,
                        format!("{file}:{line}: {name}: expected a number, got {s:?}"),
                    )
                })
        };
        let id = field(0);
        if id.is_empty() {
            return Err(InputError::located(
                file,
                format!("{file}:{line}: id: every point needs its id (the first column)"),
            ));
        }
        if let Some(earlier) = lines.insert(id.clone(), line) {
            return Err(InputError::located(
                file,
                format!("{file}:{line}: id: {id:?} is given twice (first on line {earlier})"),
            ));
        }
        let text = |k: usize| Some(crate::parse::printable(&field(k))).filter(|s| !s.is_empty());
        raw.push((
            line,
            SurveyPoint {
                id: crate::parse::printable(&id),
                x: number(1, "x")?,
                y: number(2, "y")?,
                code: text(3),
                description: text(4),
            },
        ));
    }
    if raw.is_empty() {
        return Err(InputError::new(file, "no points: give lines `id, x, y`"));
    }
    let origin = match &placing.origin {
        None => [0.0, 0.0],
        Some(id) => raw
            .iter()
            .find(|(_, p)| &p.id == id)
            .map(|(_, p)| [p.x, p.y])
            .ok_or_else(|| {
                InputError::new(file, format!("origin: the survey has no point {id:?}"))
            })?,
    };
    // Counter-clockwise on the plan is counter-clockwise in a natural frame and clockwise in
    // an SAE one (its plan is the map, x up and y right).
    let turn = match placing.convention {
        Convention::Sae => -placing.rotation,
        _ => placing.rotation,
    }
    .to_radians();
    let (s, c) = turn.sin_cos();
    let thousandth = |x: f64| (x * 1000.0).round() / 1000.0 + 0.0;
    Ok(raw
        .into_iter()
        .map(|(_, p)| {
            let (dx, dy) = (p.x - origin[0], p.y - origin[1]);
            SurveyPoint {
                x: thousandth(placing.scale * (c * dx - s * dy)),
                y: thousandth(placing.scale * (s * dx + c * dy)),
                ..p
            }
        })
        .collect())
}

/// The columns a header line names: `id` (or `point`, `pt`, `name`, `number`), `x`, `y`,
/// `code`, `description` (or `desc`).
fn header(file: &str, record: &csv::StringRecord) -> Result<[usize; 5]> {
    let names: [&[&str]; 5] = [
        &["id", "point", "pt", "name", "number", "no"],
        &["x"],
        &["y"],
        &["code"],
        &["description", "desc"],
    ];
    let find = |k: usize| {
        record
            .iter()
            .position(|h| names[k].contains(&h.to_ascii_lowercase().as_str()))
    };
    let mut out = [usize::MAX; 5];
    for (k, slot) in out.iter_mut().enumerate() {
        match (find(k), k) {
            (Some(i), _) => *slot = i,
            (None, 0..=2) => {
                return Err(InputError::located(
                    file,
                    format!(
                        "{file}:1: the header has no column {:?} (give id, x, y and optionally \
                         code, description; or no header, the columns in that order)",
                        names[k][0]
                    ),
                ))
            }
            (None, _) => {}
        }
    }
    Ok(out)
}

impl Case {
    /// The case's `[survey]`, if it has one.
    pub fn survey(&self) -> Option<&crate::scene_sections::SurveySection> {
        self.content.survey.as_ref()
    }

    /// Checks `[survey]` (ids given once, coordinates finite) and every piece of evidence that
    /// names a survey point: the point exists and the evidence lies on it (within
    /// [`ON_POINT`]), in the file's own units.
    pub(crate) fn check_survey(&self) -> Result<()> {
        let points = self
            .content
            .survey
            .as_ref()
            .map_or(&[][..], |s| s.points.as_slice());
        let mut ids = std::collections::HashMap::new();
        for (i, p) in points.iter().enumerate() {
            let at = format!("survey.points.{i}");
            if p.id.trim().is_empty() {
                return Err(self.error_at(&format!("{at}.id"), "every point needs its id"));
            }
            if ids.insert(p.id.as_str(), i).is_some() {
                return Err(self.error_at(
                    &format!("{at}.id"),
                    format!("{:?} is given twice: each point's id once", p.id),
                ));
            }
            if !(p.x.is_finite() && p.y.is_finite()) {
                return Err(self.error_at(&at, "x and y must be finite numbers"));
            }
        }
        for (path, id, x, y) in self.survey_references() {
            let Some(p) = ids.get(id.as_str()).map(|&i| &points[i]) else {
                let what = if points.is_empty() {
                    "the case has no [survey]".to_string()
                } else {
                    "[survey] has no such point".to_string()
                };
                return Err(self.error_at(&format!("{path}.point"), format!("{id:?}: {what}")));
            };
            if (p.x - x).abs() > ON_POINT || (p.y - y).abs() > ON_POINT {
                return Err(self.error_at(
                    &format!("{path}.point"),
                    format!(
                        "survey point {id:?} is at ({}, {}), this at ({x}, {y}): move it onto \
                         the point, or remove `point` if it no longer lies there",
                        p.x, p.y
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Every piece of evidence that names a survey point: its dotted key, the id, and where
    /// it is written.
    fn survey_references(&self) -> Vec<(String, String, f64, f64)> {
        let c = &self.content;
        let mut out = Vec::new();
        if let Some(centre) = &c.impact.centre {
            if let Some(id) = &centre.point {
                out.push(("impact.centre".into(), id.clone(), centre.x, centre.y));
            }
        }
        let scene = c.scene.as_ref();
        for (k, v) in [
            (1, scene.and_then(|s| s.vehicle1.as_ref())),
            (2, scene.and_then(|s| s.vehicle2.as_ref())),
        ] {
            let Some(v) = v else { continue };
            let at = format!("scene.vehicle{k}");
            if let Some(r) = &v.rest {
                if let Some(id) = &r.point {
                    out.push((format!("{at}.rest"), id.clone(), r.x, r.y));
                }
            }
            for (i, m) in v.marks.iter().enumerate() {
                if let Some(id) = &m.point {
                    out.push((format!("{at}.marks.{i}"), id.clone(), m.x, m.y));
                }
            }
            for (i, t) in v.rest_tyres.iter().enumerate() {
                if let Some(id) = &t.point {
                    out.push((format!("{at}.rest_tyres.{i}"), id.clone(), t.x, t.y));
                }
            }
        }
        out
    }
}

/// The case text with its `[survey]` replaced by `points` (from `source`), written at the end
/// of the file one point to a line; every other byte kept.
///
/// # Errors
/// Text that is not TOML.
pub fn with_survey(
    file: &str,
    text: &str,
    source: Option<&str>,
    points: &[SurveyPoint],
) -> Result<String> {
    let mut doc = crate::edit::CaseEdit::new(file, text)?;
    doc.remove("survey");
    let mut out = doc.text();
    while out.ends_with("\n\n") {
        out.pop();
    }
    if !out.is_empty() && !out.ends_with('\n') {
        out.push('\n');
    }
    if !out.is_empty() {
        out.push('\n');
    }
    out.push_str("[survey]\n");
    if let Some(s) = source {
        out.push_str(&format!("source = {}\n", toml_edit::Value::from(s)));
    }
    out.push_str("points = [\n");
    for p in points {
        let mut t = toml_edit::InlineTable::new();
        t.insert("id", p.id.as_str().into());
        t.insert("x", p.x.into());
        t.insert("y", p.y.into());
        if let Some(c) = &p.code {
            t.insert("code", c.as_str().into());
        }
        if let Some(d) = &p.description {
            t.insert("description", d.as_str().into());
        }
        t.fmt();
        out.push_str(&format!("  {t},\n"));
    }
    out.push_str("]\n");
    // The result is TOML (each value written by toml_edit).
    crate::edit::CaseEdit::new(file, &out)?;
    Ok(out)
}

/// How a survey's CSV is imported into a case: its length unit, the point made the case's
/// origin and its turn (see [`Placing`]).
#[derive(Debug, Clone, Default, PartialEq, serde::Deserialize)]
pub struct Import {
    /// The survey's length unit (`m` or `ft`; `None`: the case's own).
    #[serde(default)]
    pub unit: Option<crate::units::LengthUnit>,
    /// The survey point made the case's origin (`None`: the survey's own origin).
    #[serde(default)]
    pub origin: Option<String>,
    /// Degrees the survey is turned, counter-clockwise as seen on the plan.
    #[serde(default)]
    pub rotation: f64,
}

/// The case text (`file`, a case or one being built) with its `[survey]` replaced by the CSV
/// `csv` (named `source` in messages and kept as `[survey] source`) placed by `import` in the
/// case's frame and length unit; every other byte kept. The text is not checked as a case.
///
/// # Errors
/// Text whose `convention` or `[units]` do not read, a turn that is not a finite number, and
/// the CSV's faults (named at its line).
pub fn import(
    file: &str,
    text: &str,
    (source, csv): (&str, &str),
    import: &Import,
) -> Result<String> {
    #[derive(serde::Deserialize)]
    struct Frame {
        #[serde(default)]
        convention: Convention,
        #[serde(default)]
        units: crate::units::UnitsSection,
    }
    let frame: Frame = crate::parse::parse_toml(file, text)?;
    if !import.rotation.is_finite() {
        return Err(InputError::new(
            file,
            format!(
                "survey rotation {}: give a finite angle, degrees",
                import.rotation
            ),
        ));
    }
    let unit = frame.units.length;
    let placing = Placing {
        scale: import.unit.unwrap_or(unit).to_si() / unit.to_si(),
        origin: import
            .origin
            .as_deref()
            .map(str::trim)
            .filter(|o| !o.is_empty())
            .map(str::to_string),
        rotation: import.rotation,
        convention: frame.convention,
    };
    let points = read_csv(source, csv, &placing)?;
    with_survey(
        file,
        text,
        Some(source).filter(|s| !s.trim().is_empty()),
        &points,
    )
}
