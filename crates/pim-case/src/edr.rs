//! An event data recorder's pre-crash table, pasted as text, written into a case.
//!
//! A crash data report prints, for each vehicle, a table of the seconds before the event:
//! time, speed, service brake on or off, accelerator pedal percent. Pasted as it comes (tabs,
//! commas, semicolons or spaces between columns; a header line naming them, or none and the
//! order time, speed, brake, accelerator), the rows become `[pre_impact.vehicleN]
//! edr_history`, oldest first, the times as seconds before contact (`-2.5` and `2.5` are the
//! same row) and the speeds in the case's unit.
//!
//! The rows are one speed history, so they are one piece of evidence, not one per row: rows a
//! tenth of a second apart are not independent measurements of the speed at contact. That
//! piece is the row nearest contact carried to contact ([`evidence_of`]):
//!
//! ```text
//! v_contact = v_last - a t_last
//! ```
//!
//! with `t_last` its time before contact and `a` the deceleration over the rows that end the
//! table with the brake on (the drop in speed over their time, from the table itself). It is
//! 0 when the brake is off at the last row (a coasting car loses about 0.01 to 0.02 g, within
//! an EDR's speed tolerance over the half second usual before contact) or on at it alone (one
//! row gives no rate). Braking that began at or after the last row is not measured by the
//! table: where the scene shows it (a skid to contact), the record's `deceleration` is the
//! place to say so. The record is written as an ordinary `edr`
//! entry, to be read and changed like one.

use crate::edit::{CaseEdit, NewValue};
use crate::error::{InputError, Result};
use crate::scene_sections::{EdrRow, EdrWritten};
use crate::units::SpeedUnit;

/// Standard gravity, m/s^2.
const GRAVITY: f64 = 9.806_65;

/// The columns of a pre-crash table.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Column {
    Time,
    Speed,
    Brake,
    Accelerator,
}

/// The column a header's field names, if any.
fn column_named(field: &str) -> Option<Column> {
    let f = field.to_ascii_lowercase();
    if f.contains("time") || f == "t" || f.starts_with("sec") {
        Some(Column::Time)
    } else if f.contains("speed") || f.contains("velocity") {
        Some(Column::Speed)
    } else if f.contains("brake") {
        Some(Column::Brake)
    } else if f.contains("accel") || f.contains("throttle") || f.contains("pedal") {
        Some(Column::Accelerator)
    } else {
        None
    }
}

/// The fields of a line, split by the first of tab, comma or semicolon it holds, else by
/// spaces (then a unit in brackets, `Speed (mph)`, stays with the word before it).
fn fields(line: &str) -> Vec<String> {
    let split: Vec<&str> = if line.contains('\t') {
        line.split('\t').collect()
    } else if line.contains(',') {
        line.split(',').collect()
    } else if line.contains(';') {
        line.split(';').collect()
    } else {
        let mut words: Vec<String> = Vec::new();
        for w in line.split_whitespace() {
            match words.last_mut() {
                Some(last) if w.starts_with(['(', '[']) => {
                    last.push(' ');
                    last.push_str(w);
                }
                _ => words.push(w.to_string()),
            }
        }
        return words;
    };
    split.into_iter().map(|f| f.trim().to_string()).collect()
}

/// A brake field: on or off (`on`, `yes`, `true`, `1`, `applied`; `off`, `no`, `false`, `0`,
/// `not applied`), or none when empty.
fn brake(s: &str) -> std::result::Result<Option<bool>, String> {
    match s.to_ascii_lowercase().as_str() {
        "" | "-" | "n/a" => Ok(None),
        "on" | "yes" | "true" | "1" | "applied" | "engaged" => Ok(Some(true)),
        "off" | "no" | "false" | "0" | "not applied" | "released" => Ok(Some(false)),
        _ => Err(format!("expected on or off, got {s:?}")),
    }
}

/// The rows of a pasted pre-crash table `text` (named `source` in messages), its speeds in
/// `from` converted to `to` (the case's unit); oldest row first.
///
/// # Errors
/// A row whose time or speed is not a number, a speed below 0, an accelerator outside 0 to
/// 100 %, a brake that is neither on nor off, two rows at one time, or no row; the message
/// names the line and the column.
pub fn parse_table(
    source: &str,
    text: &str,
    from: SpeedUnit,
    to: SpeedUnit,
) -> Result<Vec<EdrRow>> {
    let factor = from.to_si() / to.to_si();
    let mut order: Vec<Option<Column>> = [
        Column::Time,
        Column::Speed,
        Column::Brake,
        Column::Accelerator,
    ]
    .map(Some)
    .to_vec();
    let mut rows: Vec<(EdrRow, usize)> = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let n = i + 1;
        let f = fields(line);
        if f.iter().all(|x| x.is_empty()) {
            continue;
        }
        let numeric = f[0].trim_start_matches(['-', '+']).parse::<f64>().is_ok();
        if !numeric && rows.is_empty() {
            // A header: the columns it names, in its order (a field it does not name is
            // skipped).
            let named: Vec<Option<Column>> = f.iter().map(|x| column_named(x)).collect();
            if named.contains(&Some(Column::Time)) && named.contains(&Some(Column::Speed)) {
                order = named;
                continue;
            }
        }
        let bad = |col: &str, what: String| {
            InputError::located(source, format!("{source}:{n}: {col}: {what}"))
        };
        let mut row = EdrRow {
            time: f64::NAN,
            speed: f64::NAN,
            brake: None,
            accelerator: None,
        };
        for (value, column) in f.iter().zip(&order) {
            let number = |col: &str| {
                value
                    .trim_end_matches('%')
                    .trim()
                    .parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| bad(col, format!("expected a number, got {value:?}")))
            };
            let Some(column) = column else { continue };
            match column {
                Column::Time => row.time = number("time")?.abs(),
                Column::Speed => row.speed = number("speed")? * factor,
                Column::Brake => row.brake = brake(value).map_err(|e| bad("brake", e))?,
                Column::Accelerator if value.is_empty() => {}
                Column::Accelerator => row.accelerator = Some(number("accelerator")?),
            }
        }
        if row.time.is_nan() || row.speed.is_nan() {
            return Err(bad("speed", "every row needs its time and speed".into()));
        }
        if row.speed < 0.0 {
            return Err(bad("speed", format!("{}: below 0", row.speed)));
        }
        if let Some(a) = row.accelerator.filter(|a| !(0.0..=100.0).contains(a)) {
            return Err(bad("accelerator", format!("{a}: a percentage, 0 to 100")));
        }
        if let Some((_, at)) = rows.iter().find(|(r, _)| (r.time - row.time).abs() < 1e-9) {
            return Err(bad(
                "time",
                format!("{} s is given twice (first on line {at})", row.time),
            ));
        }
        rows.push((row, n));
    }
    if rows.is_empty() {
        return Err(InputError::new(
            source,
            "no rows: give lines of time, speed[, brake, accelerator]",
        ));
    }
    let mut rows: Vec<EdrRow> = rows.into_iter().map(|(r, _)| r).collect();
    rows.sort_by(|a, b| b.time.total_cmp(&a.time));
    Ok(rows)
}

/// The one piece of evidence a table gives: its row nearest contact carried to contact (see
/// the module's docs), with the standard deviation `sigma` (speed unit of the rows; `speed_si`
/// m/s per that unit, for the deceleration in g).
pub fn evidence_of(rows: &[EdrRow], sigma: f64, speed_si: f64) -> Option<EdrWritten> {
    // Newest first: the row nearest contact, then the rows that end the table braking.
    let mut by_time: Vec<&EdrRow> = rows.iter().collect();
    by_time.sort_by(|a, b| a.time.total_cmp(&b.time));
    let last = *by_time.first()?;
    let braking: Vec<&EdrRow> = by_time
        .into_iter()
        .take_while(|r| r.brake == Some(true))
        .collect();
    let deceleration = match (braking.first(), braking.last()) {
        (Some(end), Some(first)) if first.time > end.time => {
            (first.speed - end.speed) * speed_si / (first.time - end.time) / GRAVITY
        }
        _ => 0.0,
    };
    Some(EdrWritten {
        speed: last.speed,
        time: last.time,
        deceleration: (deceleration * 1000.0).round() / 1000.0,
        sigma,
    })
}

/// The case text with vehicle `vehicle`'s (1 or 2) `[pre_impact.vehicleN] edr_history`
/// replaced by `rows`, one to a line, and, when `evidence` is given, its `edr` records
/// replaced by that one; every other byte kept.
///
/// # Errors
/// Text that is not TOML, or a vehicle other than 1 or 2.
pub fn with_history(
    file: &str,
    text: &str,
    vehicle: u8,
    rows: &[EdrRow],
    evidence: Option<EdrWritten>,
) -> Result<String> {
    if !(1..=2).contains(&vehicle) {
        return Err(InputError::new(file, format!("vehicle {vehicle}: 1 or 2")));
    }
    let at = format!("pre_impact.vehicle{vehicle}");
    let mut edit = CaseEdit::new(file, text)?;
    let row = |r: &EdrRow| {
        let mut f = vec![
            ("time".to_string(), NewValue::Written(r.time)),
            ("speed".to_string(), NewValue::Written(round(r.speed))),
        ];
        if let Some(b) = r.brake {
            f.push(("brake".to_string(), NewValue::Bool(b)));
        }
        if let Some(a) = r.accelerator {
            f.push(("accelerator".to_string(), NewValue::Written(a)));
        }
        f
    };
    edit.set(
        &format!("{at}.edr_history"),
        NewValue::Rows(rows.iter().map(row).collect()),
    )?;
    if let Some(e) = evidence {
        edit.set(
            &format!("{at}.edr"),
            NewValue::Rows(vec![vec![
                ("speed".to_string(), NewValue::Written(round(e.speed))),
                ("time".to_string(), NewValue::Written(e.time)),
                (
                    "deceleration".to_string(),
                    NewValue::Written(e.deceleration),
                ),
                ("sigma".to_string(), NewValue::Written(e.sigma)),
            ]]),
        )?;
    }
    Ok(edit.text())
}

/// A speed converted between units, to a thousandth (what a report prints is coarser).
fn round(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// How a pasted table is imported: which vehicle, the table's speed unit, the record's
/// standard deviation and whether to write it.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
pub struct Import {
    /// 1 or 2.
    pub vehicle: u8,
    /// The table's speed unit (`None`: the case's own).
    #[serde(default)]
    pub unit: Option<SpeedUnit>,
    /// The standard deviation of the record made from the table, in the case's speed unit
    /// (`None`: [`DEFAULT_SIGMA`] m/s in the case's unit).
    #[serde(default)]
    pub sigma: Option<f64>,
    /// Whether to replace the vehicle's `edr` records by the one the table gives.
    #[serde(default = "yes")]
    pub record: bool,
}

fn yes() -> bool {
    true
}

/// The record's standard deviation when none is given, m/s (about 1 mph: the speed an EDR
/// stores is usually within 1 km/h to 1 mph, and the last row is up to half a second from
/// contact).
pub const DEFAULT_SIGMA: f64 = 0.45;

/// The case text with the table `table` (named `source` in messages) imported as `import`
/// says (see [`parse_table`], [`evidence_of`], [`with_history`]).
///
/// # Errors
/// Text that is not TOML, the table's faults (named at its line), a vehicle other than 1 or
/// 2, a sigma that is not above 0.
pub fn import(
    file: &str,
    text: &str,
    (source, table): (&str, &str),
    import: &Import,
) -> Result<String> {
    let units = CaseEdit::new(file, text)?.units()?;
    let unit = import.unit.unwrap_or(units.speed);
    let rows = parse_table(source, table, unit, units.speed)?;
    let sigma = import
        .sigma
        .unwrap_or((DEFAULT_SIGMA / units.speed.to_si() * 100.0).round() / 100.0);
    if !(sigma.is_finite() && sigma > 0.0) {
        return Err(InputError::new(
            file,
            format!("sigma {sigma}: a standard deviation above 0"),
        ));
    }
    let record = if import.record {
        evidence_of(&rows, sigma, units.speed.to_si())
    } else {
        None
    };
    with_history(file, text, import.vehicle, &rows, record)
}
