//! The RICSAC data file (`data/ricsac.csv`): one row per staged collision.
//!
//! The columns keep the papers' geometry (Brach 1983, 1984; Vossou & Koulocheris 2018), which is
//! pim-core's [`Vehicle`] form: `heading1_deg` is theta1, the direction of vehicle 1's *tail*
//! (its nose points along theta1 + 180 deg); `heading2_deg` is vehicle 2's nose; `phi1_deg`,
//! `phi2_deg` are the angles of the impact centre counter-clockwise from each vehicle's nose and
//! `d1_m`, `d2_m` its distances from the CGs; `crush_angle_deg` is the direction of the
//! crush-surface normal. In a case file's natural form (`convention = "natural"`, the default)
//! the same row reads: vehicle 1 `heading = heading1_deg + 180`, vehicle 2 `heading =
//! heading2_deg`, `d`/`phi` unchanged (or `impact_point = { x = d cos phi, y = d sin phi }`).

use crate::error::{InputError, Result};
use nalgebra::Vector6;
use pim_core::{Collision, Impact, Vehicle, Velocities};
use serde::Deserialize;

/// Largest data file accepted, bytes (for callers that read it).
pub const MAX_DATA_BYTES: u64 = 16 << 20;

/// The columns, in the required order.
pub const COLUMNS: [&str; 31] = [
    "test",
    "configuration",
    "vehicle1",
    "vehicle2",
    "mass1_kg",
    "yaw_inertia1_kgm2",
    "mass2_kg",
    "yaw_inertia2_kgm2",
    "heading1_deg",
    "heading2_deg",
    "d1_m",
    "d2_m",
    "d1_source",
    "d2_source",
    "phi1_deg",
    "phi2_deg",
    "crush_angle_deg",
    "vi1x_mps",
    "vi1y_mps",
    "wi1_radps",
    "vi2x_mps",
    "vi2y_mps",
    "wi2_radps",
    "vf1x_mps",
    "vf1y_mps",
    "wf1_radps",
    "vf2x_mps",
    "vf2y_mps",
    "wf2_radps",
    "dv1_measured_mps",
    "dv2_measured_mps",
];

/// One staged collision, as in the file (SI units, degrees).
#[derive(Debug, Clone, Deserialize)]
pub struct RicsacTest {
    /// RICSAC test number.
    pub test: u32,
    /// Impact configuration in words.
    pub configuration: String,
    /// Vehicle 1 description.
    pub vehicle1: String,
    /// Vehicle 2 description.
    pub vehicle2: String,
    /// kg.
    pub mass1_kg: f64,
    /// kg m^2.
    pub yaw_inertia1_kgm2: f64,
    /// kg.
    pub mass2_kg: f64,
    /// kg m^2.
    pub yaw_inertia2_kgm2: f64,
    /// theta1, degrees.
    pub heading1_deg: f64,
    /// theta2, degrees.
    pub heading2_deg: f64,
    /// m.
    pub d1_m: f64,
    /// m.
    pub d2_m: f64,
    /// Where d1 comes from.
    pub d1_source: String,
    /// Where d2 comes from.
    pub d2_source: String,
    /// phi1, degrees.
    pub phi1_deg: f64,
    /// phi2, degrees.
    pub phi2_deg: f64,
    /// Gamma, degrees.
    pub crush_angle_deg: f64,
    /// Initial velocities (m/s, rad/s).
    pub vi1x_mps: f64,
    /// .
    pub vi1y_mps: f64,
    /// .
    pub wi1_radps: f64,
    /// .
    pub vi2x_mps: f64,
    /// .
    pub vi2y_mps: f64,
    /// .
    pub wi2_radps: f64,
    /// Separation velocities (m/s, rad/s).
    pub vf1x_mps: f64,
    /// .
    pub vf1y_mps: f64,
    /// .
    pub wf1_radps: f64,
    /// .
    pub vf2x_mps: f64,
    /// .
    pub vf2y_mps: f64,
    /// .
    pub wf2_radps: f64,
    /// Measured |delta-V| of vehicle 1, m/s.
    pub dv1_measured_mps: f64,
    /// Measured |delta-V| of vehicle 2, m/s.
    pub dv2_measured_mps: f64,
    /// Line of the file this row was read from (1-based).
    #[serde(skip)]
    pub line: u64,
}

impl RicsacTest {
    /// The collision geometry and vehicles.
    pub fn collision(&self) -> Collision {
        Collision {
            vehicle1: Vehicle {
                mass: self.mass1_kg,
                yaw_inertia: self.yaw_inertia1_kgm2,
                heading: self.heading1_deg,
                d: self.d1_m,
                phi: self.phi1_deg,
            },
            vehicle2: Vehicle {
                mass: self.mass2_kg,
                yaw_inertia: self.yaw_inertia2_kgm2,
                heading: self.heading2_deg,
                d: self.d2_m,
                phi: self.phi2_deg,
            },
            crush_angle: self.crush_angle_deg,
        }
    }

    /// The checked impact.
    pub fn impact(&self) -> std::result::Result<Impact, pim_core::PimError> {
        Impact::new(self.collision())
    }

    /// Measured velocities at contact.
    pub fn initial(&self) -> Velocities {
        Velocities::from_vector(&Vector6::new(
            self.vi1x_mps,
            self.vi1y_mps,
            self.wi1_radps,
            self.vi2x_mps,
            self.vi2y_mps,
            self.wi2_radps,
        ))
    }

    /// Measured velocities at separation.
    pub fn separation(&self) -> Velocities {
        Velocities::from_vector(&Vector6::new(
            self.vf1x_mps,
            self.vf1y_mps,
            self.wf1_radps,
            self.vf2x_mps,
            self.vf2y_mps,
            self.wf2_radps,
        ))
    }

    /// The test as a fit case (the papers' convention, SI): its geometry, and its measured
    /// velocities at contact and separation as `[estimates]`. `file` names the case in messages
    /// (e.g. `data/ricsac.csv test 7`).
    pub fn case(&self, file: &str) -> crate::error::Result<crate::case::Case> {
        let state = |v: &Velocities| {
            let x = v.to_vector();
            format!(
                "vehicle1 = {{ vx = {:?}, vy = {:?}, omega = {:?} }}\n\
                 vehicle2 = {{ vx = {:?}, vy = {:?}, omega = {:?} }}\n",
                x[0], x[1], x[2], x[3], x[4], x[5]
            )
        };
        let vehicle = |n: u8, m: f64, i: f64, h: f64, d: f64, phi: f64| {
            format!(
                "[vehicle{n}]\nmass = {m:?}\nyaw_inertia = {i:?}\nheading = {h:?}\nd = {d:?}\n\
                 phi = {phi:?}\n"
            )
        };
        let text = format!(
            "title = \"RICSAC test {}\"\nconvention = \"brach\"\n{}{}[impact]\n\
             crush_angle = {:?}\n[estimates.initial]\n{}[estimates.final]\n{}",
            self.test,
            vehicle(
                1,
                self.mass1_kg,
                self.yaw_inertia1_kgm2,
                self.heading1_deg,
                self.d1_m,
                self.phi1_deg
            ),
            vehicle(
                2,
                self.mass2_kg,
                self.yaw_inertia2_kgm2,
                self.heading2_deg,
                self.d2_m,
                self.phi2_deg
            ),
            self.crush_angle_deg,
            state(&self.initial()),
            state(&self.separation()),
        );
        crate::case::Case::from_text(file, &text)
    }

    /// Every numeric cell with its column name.
    fn numeric(&self) -> [(&'static str, f64); 25] {
        [
            ("mass1_kg", self.mass1_kg),
            ("yaw_inertia1_kgm2", self.yaw_inertia1_kgm2),
            ("mass2_kg", self.mass2_kg),
            ("yaw_inertia2_kgm2", self.yaw_inertia2_kgm2),
            ("heading1_deg", self.heading1_deg),
            ("heading2_deg", self.heading2_deg),
            ("d1_m", self.d1_m),
            ("d2_m", self.d2_m),
            ("phi1_deg", self.phi1_deg),
            ("phi2_deg", self.phi2_deg),
            ("crush_angle_deg", self.crush_angle_deg),
            ("vi1x_mps", self.vi1x_mps),
            ("vi1y_mps", self.vi1y_mps),
            ("wi1_radps", self.wi1_radps),
            ("vi2x_mps", self.vi2x_mps),
            ("vi2y_mps", self.vi2y_mps),
            ("wi2_radps", self.wi2_radps),
            ("vf1x_mps", self.vf1x_mps),
            ("vf1y_mps", self.vf1y_mps),
            ("wf1_radps", self.wf1_radps),
            ("vf2x_mps", self.vf2x_mps),
            ("vf2y_mps", self.vf2y_mps),
            ("wf2_radps", self.wf2_radps),
            ("dv1_measured_mps", self.dv1_measured_mps),
            ("dv2_measured_mps", self.dv2_measured_mps),
        ]
    }
}

/// The physical range of a numeric column.
fn range_of(column: &str) -> crate::ranges::Range {
    use crate::ranges::*;
    match column {
        c if c.starts_with("mass") => MASS,
        c if c.starts_with("yaw_inertia") => YAW_INERTIA,
        c if c.starts_with("d1") || c.starts_with("d2") => DISTANCE,
        c if c.starts_with("dv") => DELTA_V,
        c if c.ends_with("_deg") => ANGLE,
        c if c.ends_with("_radps") => YAW_RATE,
        _ => SPEED,
    }
}

/// Maps a pim-core field name (`vehicle1.mass`) to the column of this file.
fn column_of(field: &str) -> &'static str {
    match field {
        "vehicle1.mass" => "mass1_kg",
        "vehicle2.mass" => "mass2_kg",
        "vehicle1.yaw_inertia" => "yaw_inertia1_kgm2",
        "vehicle2.yaw_inertia" => "yaw_inertia2_kgm2",
        "vehicle1.d" => "d1_m",
        "vehicle2.d" => "d2_m",
        _ => "",
    }
}

fn column_number(name: &str) -> usize {
    COLUMNS.iter().position(|c| *c == name).map_or(0, |i| i + 1)
}

/// Parses the text of a RICSAC data file; `file` names it in messages.
pub fn parse(file: &str, text: &str) -> Result<Vec<RicsacTest>> {
    if text.trim().is_empty() {
        return Err(InputError::located(
            file,
            format!("{file}: the file is empty"),
        ));
    }
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let headers = rdr
        .headers()
        .map_err(|e| InputError::located(file, format!("{file}:1: cannot read the header: {e}")))?
        .clone();
    check_header(file, &headers)?;
    let mut tests: Vec<RicsacTest> = Vec::new();
    for result in rdr.records() {
        let record = result.map_err(|e| csv_error(file, &e))?;
        let line = record.position().map_or(0, |p| p.line());
        let mut row: RicsacTest = record.deserialize(Some(&headers)).map_err(|e| {
            let col = match e.kind() {
                csv::ErrorKind::Deserialize { err, .. } => err.field().map(|f| f as usize),
                _ => None,
            };
            match col {
                Some(c) => InputError::located(
                    file,
                    format!(
                        "{file}:{line}: column {} `{}`: {} (got `{}`)",
                        c + 1,
                        COLUMNS.get(c).unwrap_or(&"?"),
                        deserialize_reason(&e),
                        record.get(c).unwrap_or("")
                    ),
                ),
                None => csv_error(file, &e),
            }
        })?;
        row.line = line;
        for (name, value) in row.numeric() {
            if let Err(why) = range_of(name).check(value) {
                return Err(InputError::located(
                    file,
                    format!(
                        "{file}:{line}: column {} `{name}`: {why}",
                        column_number(name)
                    ),
                ));
            }
        }
        if let Err(e) = row.impact() {
            let field = match &e {
                pim_core::PimError::NotPositive { vehicle, field, .. } => {
                    column_of(&format!("{vehicle}.{field}"))
                }
                pim_core::PimError::NegativeDistance { vehicle, .. } => {
                    column_of(&format!("{vehicle}.d"))
                }
                _ => "",
            };
            return Err(InputError::located(
                file,
                format!(
                    "{file}:{line}: column {} `{field}`: {e}",
                    column_number(field)
                ),
            ));
        }
        if let Some(first) = tests.iter().find(|t| t.test == row.test) {
            return Err(InputError::located(
                file,
                format!(
                    "{file}:{line}: column 1 `test`: test {} appears twice (lines {} and {line})",
                    row.test, first.line
                ),
            ));
        }
        tests.push(row);
    }
    if tests.is_empty() {
        return Err(InputError::located(
            file,
            format!("{file}: the header is there but there are no data rows"),
        ));
    }
    Ok(tests)
}

/// The header `headers` of the file `file`: the columns of [`COLUMNS`] in their order, no
/// more and no fewer.
fn check_header(file: &str, headers: &csv::StringRecord) -> Result<()> {
    let got: Vec<&str> = headers.iter().collect();
    for (i, want) in COLUMNS.iter().enumerate() {
        match got.get(i) {
            Some(g) if g == want => {}
            Some(g) => {
                return Err(InputError::located(
                    file,
                    format!(
                        "{file}:1: column {} is `{g}`, expected `{want}` (the columns must be, in \
                     this order: {})",
                        i + 1,
                        COLUMNS.join(",")
                    ),
                ))
            }
            None => {
                return Err(InputError::located(
                    file,
                    format!(
                    "{file}:1: missing column {} `{want}` (the header has {} columns, {} expected)",
                    i + 1,
                    got.len(),
                    COLUMNS.len()
                ),
                ))
            }
        }
    }
    if got.len() > COLUMNS.len() {
        return Err(InputError::located(
            file,
            format!(
                "{file}:1: unexpected extra column {} `{}`",
                COLUMNS.len() + 1,
                got[COLUMNS.len()]
            ),
        ));
    }
    Ok(())
}

fn deserialize_reason(e: &csv::Error) -> String {
    match e.kind() {
        csv::ErrorKind::Deserialize { err, .. } => match err.kind() {
            csv::DeserializeErrorKind::ParseFloat(_) => "expected a number".to_string(),
            csv::DeserializeErrorKind::ParseInt(_) => {
                "expected a whole non-negative number".to_string()
            }
            other => other.to_string(),
        },
        _ => e.to_string(),
    }
}

fn csv_error(file: &str, e: &csv::Error) -> InputError {
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            pos,
            expected_len,
            len,
        } => InputError::located(
            file,
            format!(
                "{file}:{}: the row has {len} fields, the header {expected_len}",
                pos.as_ref().map_or(0, |p| p.line())
            ),
        ),
        csv::ErrorKind::Utf8 { pos, .. } => InputError::located(
            file,
            format!(
                "{file}:{}: the row is not UTF-8 text",
                pos.as_ref().map_or(0, |p| p.line())
            ),
        ),
        _ => InputError::located(file, format!("{file}: {e}")),
    }
}
