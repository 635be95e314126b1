//! Editing a case file in place: change one value and write the text back with the user's
//! comments, key order, spacing and number formatting kept everywhere else.
//!
//! A [`CaseEdit`] holds the file as an edit-preserving TOML document (`toml_edit`). A value is
//! addressed by its dotted path as the file writes it (`scene.vehicle2.rest.x`,
//! `runout.vehicle1.wheels.front_left`, `observations.0.sigma` or `observations[0].sigma` for
//! the first `[[observations]]`). A number can be given as written (in the file's units) or in
//! SI with its [`Quantity`], which is then written in the unit the file's `[units]` gives that
//! quantity (a rest position dragged to 3.6576 m is written `12.0` in a file in feet). Headings
//! and other angles are always degrees in a case file; in SI they are radians.
//!
//! With no edit the text comes back byte for byte. An edit can make a case invalid (a negative
//! mass, an unknown wheel state): [`CaseEdit::check`] reads the edited text as `pim` does and
//! gives the same message.

use crate::case::Case;
use crate::error::{InputError, Result};
use crate::units::UnitsSection;
use toml_edit::{DocumentMut, Item, Table, Value};

/// What an SI number measures, so that it is written in the file's unit for it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// A distance or position (m in SI; `[units] length`).
    Length,
    /// A speed (m/s; `[units] speed`).
    Speed,
    /// A mass (kg; `[units] mass`).
    Mass,
    /// A yaw inertia (kg m^2; `[units] yaw_inertia`).
    YawInertia,
    /// A yaw rate (rad/s; `[units] yaw_rate`).
    YawRate,
    /// An angle or heading (rad; always degrees in the file).
    Angle,
    /// A crush depth, damage width or offset (m; `[units] crush`, else the length unit).
    Crush,
    /// A number without unit (a coefficient, a friction, a weight): written as given.
    Plain,
}

impl Quantity {
    /// SI per unit of this quantity in a file with these units.
    pub fn si_per_unit(self, units: &UnitsSection) -> f64 {
        match self {
            Quantity::Length => units.length.to_si(),
            Quantity::Speed => units.speed.to_si(),
            Quantity::Mass => units.mass.to_si(),
            Quantity::YawInertia => units.yaw_inertia.to_si(),
            Quantity::YawRate => units.yaw_rate.to_si(),
            Quantity::Angle => 1f64.to_radians(),
            Quantity::Crush => units
                .crush
                .map_or_else(|| units.length.to_si(), |c| c.to_si()),
            Quantity::Plain => 1.0,
        }
    }
}

/// A value to write.
#[derive(Debug, Clone, PartialEq)]
pub enum NewValue {
    /// A number in SI, written in the file's unit for its quantity.
    Si(f64, Quantity),
    /// A number as it is to be written (already in the file's units).
    Written(f64),
    /// A text (a wheel state, a description, a kind).
    Text(String),
    /// A yes/no value.
    Bool(bool),
    /// A whole number (a count, a vehicle's number).
    Integer(i64),
    /// Points `[x, y]` as they are to be written (a zone's corners, in the file's units).
    Points(Vec<[f64; 2]>),
    /// An inline table of values (`{ x = 1.0, y = 2.0 }`), in its order.
    Fields(Vec<(String, NewValue)>),
    /// An array of inline tables, one to a line (an EDR's rows).
    Rows(Vec<Vec<(String, NewValue)>>),
}

/// The keys a case reads as whole numbers (`scene.vehicleN.turns`, an observation's
/// `vehicle`): a number typed for them is written without a decimal point.
pub const WHOLE_NUMBER_KEYS: [&str; 2] = ["turns", "vehicle"];

/// A case file open for editing; see the [module docs](self).
#[derive(Debug, Clone)]
pub struct CaseEdit {
    file: String,
    doc: DocumentMut,
}

/// Only the `[units]` of a case (every other key ignored).
#[derive(serde::Deserialize)]
struct UnitsOnly {
    #[serde(default)]
    units: UnitsSection,
}

impl CaseEdit {
    /// Opens case-file text for editing; `file` names it in messages. The text must be TOML;
    /// whether it is a valid case is [`check`](Self::check)'s question.
    pub fn new(file: &str, text: &str) -> Result<Self> {
        let doc = text.parse::<DocumentMut>().map_err(|e| {
            let at = e
                .span()
                .map(|s| crate::parse::line_col(text, s.start))
                .map_or(String::new(), |(l, c)| format!(":{l}:{c}"));
            InputError::located(
                file,
                format!("{file}{at}: {}", e.message().trim_end_matches('\n')),
            )
        })?;
        Ok(CaseEdit {
            file: file.to_string(),
            doc,
        })
    }

    /// The units the file's `[units]` gives (the defaults, SI, where it gives none).
    pub fn units(&self) -> Result<UnitsSection> {
        crate::parse::parse_toml::<UnitsOnly>(&self.file, &self.doc.to_string()).map(|u| u.units)
    }

    /// Sets the value at `path`, creating the key (and its tables) where the file has none.
    /// The comment and spacing around the old value are kept.
    pub fn set(&mut self, path: &str, value: NewValue) -> Result<()> {
        // A whole number typed for a whole-number field (a count of turns, a vehicle's number)
        // is written as one: the case reads those fields as integers.
        let value = match value {
            NewValue::Written(x) if x.fract() == 0.0 && x.abs() < 1e15 && self.whole(path) => {
                NewValue::Integer(x as i64)
            }
            v => v,
        };
        let new = self.value(path, value)?;
        let keys = segments(path);
        let Some((last, parents)) = keys.split_last() else {
            return Err(self.error(path, "is not a key"));
        };
        let mut slot = Slot::Table(self.doc.as_table_mut());
        for (i, key) in parents.iter().enumerate() {
            slot = slot.step(key, true).map_err(|what| {
                InputError::new(
                    &self.file,
                    format!("{path}: {}: {what}", keys[..=i].join(".")),
                )
            })?;
        }
        slot.put(last, new)
            .map_err(|what| InputError::new(&self.file, format!("{path}: {what}")))
    }

    /// Appends an inline table of `entries` to the array at `path` (`scene.vehicle2.marks`),
    /// creating the array and its tables where the file has none; the new entry's index. The
    /// rest of the file is kept as it was.
    pub fn push(&mut self, path: &str, entries: &[(&str, NewValue)]) -> Result<usize> {
        let mut table = toml_edit::InlineTable::new();
        for (key, value) in entries {
            table.insert(*key, self.value(&format!("{path}.{key}"), value.clone())?);
        }
        let keys = segments(path);
        let Some((last, parents)) = keys.split_last() else {
            return Err(self.error(path, "is not a key"));
        };
        let file = self.file.clone();
        let mut slot = Slot::Table(self.doc.as_table_mut());
        for (i, key) in parents.iter().enumerate() {
            slot = slot.step(key, true).map_err(|what| {
                InputError::new(&file, format!("{path}: {}: {what}", keys[..=i].join(".")))
            })?;
        }
        let array = match slot {
            Slot::Table(t) | Slot::Item(Item::Table(t)) => {
                if !t.contains_key(last) {
                    t.insert(last, Item::Value(Value::Array(toml_edit::Array::new())));
                }
                t.get_mut(last).and_then(Item::as_array_mut)
            }
            Slot::Value(Value::InlineTable(t)) | Slot::Item(Item::Value(Value::InlineTable(t))) => {
                if !t.contains_key(last) {
                    t.insert(last, Value::Array(toml_edit::Array::new()));
                }
                t.get_mut(last).and_then(Value::as_array_mut)
            }
            _ => None,
        };
        let Some(array) = array else {
            return Err(InputError::new(&file, format!("{path}: is not an array")));
        };
        // After a comma and a space; the space before the closing bracket moves to the new
        // last entry (`[ { .. } ]` stays `[ { .. }, { .. } ]`).
        let n = array.len();
        let mut v = Value::InlineTable(table);
        v.decor_mut().set_prefix(" ");
        match array.get_mut(n.wrapping_sub(1)) {
            Some(last) => {
                let suffix = last.decor().suffix().cloned();
                last.decor_mut().set_suffix("");
                if let Some(s) = suffix {
                    v.decor_mut().set_suffix(s);
                }
            }
            None => v.decor_mut().set_suffix(" "),
        }
        array.push_formatted(v);
        Ok(array.len() - 1)
    }

    /// Whether `path` is a whole-number field: one the case reads as an integer
    /// ([`WHOLE_NUMBER_KEYS`]), or one the file already writes as an integer.
    fn whole(&self, path: &str) -> bool {
        let keys = segments(path);
        keys.last()
            .is_some_and(|k| WHOLE_NUMBER_KEYS.contains(&k.as_str()))
            || self.get(path).is_some_and(|v| v.parse::<i64>().is_ok())
    }

    /// A value to write at `path`.
    fn value(&self, path: &str, value: NewValue) -> Result<Value> {
        let finite = |x: f64| {
            if x.is_finite() {
                Ok(x)
            } else {
                Err(self.error(path, format!("must be a finite number, got {x}")))
            }
        };
        Ok(match value {
            NewValue::Si(x, q) => number(finite(x)? / q.si_per_unit(&self.units()?)),
            NewValue::Written(x) => number(finite(x)?),
            NewValue::Text(s) => Value::from(s),
            NewValue::Bool(b) => Value::from(b),
            NewValue::Integer(i) => Value::from(i),
            NewValue::Points(points) => {
                let mut array = toml_edit::Array::new();
                for p in points {
                    let mut pair = toml_edit::Array::new();
                    pair.push(number(finite(p[0])?));
                    pair.push(number(finite(p[1])?));
                    array.push(pair);
                }
                Value::Array(array)
            }
            NewValue::Rows(rows) => {
                let mut array = toml_edit::Array::new();
                for fields in rows {
                    let mut row = self.value(path, NewValue::Fields(fields))?;
                    row.decor_mut().set_prefix("\n  ");
                    array.push_formatted(row);
                }
                array.set_trailing_comma(true);
                array.set_trailing("\n");
                Value::Array(array)
            }
            NewValue::Fields(fields) => {
                let mut table = toml_edit::InlineTable::new();
                for (key, v) in fields {
                    table.insert(&key, self.value(&format!("{path}.{key}"), v)?);
                }
                table.fmt();
                Value::InlineTable(table)
            }
        })
    }

    /// Appends a table of `entries` to the array of tables at `path` (`runout.zones`: a new
    /// `[[runout.zones]]` at the end of the file, after a blank line); the rest of the file is
    /// kept byte for byte.
    pub fn push_table(&mut self, path: &str, entries: &[(&str, NewValue)]) -> Result<()> {
        let mut text = self.text();
        if !text.ends_with('\n') {
            text.push('\n');
        }
        text.push_str(&format!("\n[[{path}]]\n"));
        for (key, value) in entries {
            let v = self.value(&format!("{path}.{key}"), value.clone())?;
            text.push_str(&format!("{key} = {}\n", v.to_string().trim()));
        }
        *self = CaseEdit::new(&self.file, &text)?;
        Ok(())
    }

    /// Removes the key at `path` (or the entry of an array of tables, `observations.0`);
    /// `false` when the file does not write it.
    pub fn remove(&mut self, path: &str) -> bool {
        let keys = segments(path);
        let Some((last, parents)) = keys.split_last() else {
            return false;
        };
        let mut slot = Slot::Table(self.doc.as_table_mut());
        for key in parents {
            match slot.step(key, false) {
                Ok(next) => slot = next,
                Err(_) => return false,
            }
        }
        let index = last.parse::<usize>().ok();
        match slot {
            Slot::Table(t) => t.remove(last).is_some(),
            // An entry of an array of tables (`observations.0`) or of an inline array.
            Slot::Item(Item::ArrayOfTables(a)) => match index.filter(|&i| i < a.len()) {
                Some(i) => {
                    a.remove(i);
                    true
                }
                None => false,
            },
            Slot::Value(Value::InlineTable(t)) => remove_inline(t, last),
            Slot::Item(Item::Table(t)) => t.remove(last).is_some(),
            Slot::Item(Item::Value(Value::InlineTable(t))) => remove_inline(t, last),
            _ => false,
        }
    }

    /// The value written at `path`, as written (`12.0`, `"locked"`), if the file writes it.
    pub fn get(&self, path: &str) -> Option<String> {
        let mut doc = self.doc.clone();
        let mut slot = Slot::Table(doc.as_table_mut());
        for key in segments(path) {
            slot = slot.step(&key, false).ok()?;
        }
        match slot {
            // The value alone: the spaces and the comment around it are the file's layout.
            Slot::Value(v) | Slot::Item(Item::Value(v)) => {
                let mut v = v.clone();
                v.decor_mut().clear();
                Some(v.to_string())
            }
            _ => None,
        }
    }

    /// Whether the file writes `path` (a table, a key or an entry of an array).
    pub fn has(&self, path: &str) -> bool {
        let mut doc = self.doc.clone();
        let mut slot = Slot::Table(doc.as_table_mut());
        for key in segments(path) {
            match slot.step(&key, false) {
                Ok(next) => slot = next,
                Err(_) => return false,
            }
        }
        true
    }

    /// The edited text: the file as it was but for the edits.
    pub fn text(&self) -> String {
        self.doc.to_string()
    }

    /// Reads the edited text as a case, with the same checks and messages as `pim`.
    pub fn check(&self) -> Result<Case> {
        Case::from_text(&self.file, &self.text())
    }

    fn error(&self, path: &str, what: impl std::fmt::Display) -> InputError {
        InputError::new(&self.file, format!("{path}: {what}"))
    }
}

/// `key` removed from the inline table `t`; the last entry removed gives the closing brace's
/// space to the one before it (`{ x = 1.0, y = 2.0 }` becomes `{ x = 1.0 }`).
fn remove_inline(t: &mut toml_edit::InlineTable, key: &str) -> bool {
    let was_last = t.iter().last().is_some_and(|(k, _)| k == key);
    let Some(removed) = t.remove(key) else {
        return false;
    };
    if let (true, Some(suffix), Some((_, last))) =
        (was_last, removed.decor().suffix(), t.iter_mut().last())
    {
        last.decor_mut().set_suffix(suffix.clone());
    }
    true
}

/// `a.b[0].c` and `a.b.0.c` as segments.
fn segments(path: &str) -> Vec<String> {
    path.replace('[', ".")
        .replace(']', "")
        .split('.')
        .filter(|s| !s.is_empty())
        .map(str::to_string)
        .collect()
}

/// A number as a TOML float, rounded to nine significant digits (what a unit conversion adds
/// beyond them is noise) and written in its shortest form.
fn number(x: f64) -> Value {
    let rounded: f64 = format!("{x:.8e}").parse().unwrap_or(x);
    // Adding zero turns a negative zero into a zero.
    Value::from(rounded + 0.0)
}

/// A place in the document a path passes through.
enum Slot<'a> {
    Table(&'a mut Table),
    Item(&'a mut Item),
    Value(&'a mut Value),
}

/// Why a key path cannot be followed, or a value written, in the text.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
enum PathError {
    #[error("is not written in the file")]
    NotWritten,
    #[error("the file has {0} of them; give an index 0 to {last}", last = .0.saturating_sub(1))]
    TableIndex(usize),
    #[error("the array has {0} entries; give an index 0 to {last}", last = .0.saturating_sub(1))]
    ArrayIndex(usize),
    #[error("the array has {0} entries")]
    Beyond(usize),
    #[error("is a value, not a table")]
    NotTable,
    #[error("is a table, not a value")]
    NotValue,
    #[error("is a table or an array, not a value")]
    NotScalar,
    #[error("is not inside a table")]
    NotInside,
}

impl<'a> Slot<'a> {
    /// One step down the path: a key of a table, an index of an array. With `create`, a key a
    /// table does not have becomes a new table.
    fn step(self, key: &str, create: bool) -> std::result::Result<Slot<'a>, PathError> {
        let index = key.parse::<usize>().ok();
        match self {
            Slot::Table(t) => {
                if create && !t.contains_key(key) {
                    let mut new = Table::new();
                    new.set_implicit(true);
                    t.insert(key, Item::Table(new));
                }
                t.get_mut(key).map(Slot::Item).ok_or(PathError::NotWritten)
            }
            Slot::Item(Item::Table(t)) => Slot::Table(t).step(key, create),
            Slot::Item(Item::ArrayOfTables(a)) => {
                let n = a.len();
                index
                    .and_then(|i| a.get_mut(i))
                    .map(Slot::Table)
                    .ok_or(PathError::TableIndex(n))
            }
            Slot::Item(Item::Value(v)) => Slot::Value(v).step(key, create),
            Slot::Value(Value::InlineTable(t)) => {
                if create && !t.contains_key(key) {
                    t.insert(key, Value::InlineTable(toml_edit::InlineTable::new()));
                }
                t.get_mut(key).map(Slot::Value).ok_or(PathError::NotWritten)
            }
            Slot::Value(Value::Array(a)) => {
                let n = a.len();
                index
                    .and_then(|i| a.get_mut(i))
                    .map(Slot::Value)
                    .ok_or(PathError::ArrayIndex(n))
            }
            _ => Err(PathError::NotTable),
        }
    }

    /// Writes `new` under `key` here, keeping the old value's comment and spacing.
    fn put(self, key: &str, mut new: Value) -> std::result::Result<(), PathError> {
        match self {
            Slot::Table(t) => match t.get_mut(key) {
                Some(Item::Value(old)) => {
                    *new.decor_mut() = old.decor().clone();
                    *old = new;
                    Ok(())
                }
                Some(_) => Err(PathError::NotValue),
                None => {
                    t.insert(key, Item::Value(new));
                    Ok(())
                }
            },
            Slot::Item(Item::Table(t)) => Slot::Table(t).put(key, new),
            Slot::Item(Item::Value(v)) => Slot::Value(v).put(key, new),
            Slot::Value(Value::InlineTable(t)) => match t.get_mut(key) {
                Some(old) => {
                    if old.is_inline_table() || old.is_array() {
                        return Err(PathError::NotScalar);
                    }
                    *new.decor_mut() = old.decor().clone();
                    *old = new;
                    Ok(())
                }
                None => {
                    // After the last entry, which gives the closing brace's space up to it
                    // (`{ x = 1.0 }` becomes `{ x = 1.0, y = 2.0 }`).
                    let mut suffix = None;
                    if let Some((_, last)) = t.iter_mut().last() {
                        suffix = last.decor().suffix().cloned();
                        last.decor_mut().set_suffix("");
                    }
                    new.decor_mut().set_prefix(" ");
                    if let Some(s) = suffix {
                        new.decor_mut().set_suffix(s);
                    }
                    t.insert(key, new);
                    Ok(())
                }
            },
            Slot::Value(Value::Array(a)) => {
                let n = a.len();
                match key.parse::<usize>().ok().and_then(|i| a.get_mut(i)) {
                    Some(old) => {
                        *new.decor_mut() = old.decor().clone();
                        *old = new;
                        Ok(())
                    }
                    None => Err(PathError::Beyond(n)),
                }
            }
            _ => Err(PathError::NotInside),
        }
    }
}
