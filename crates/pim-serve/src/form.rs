//! The case text as forms: one per section the file writes (`[vehicle1]`, `[runout.vehicle2]`,
//! each `[[observations]]`), a field per value it writes (an inline table's values each as a
//! field, `position.x`; an array of inline tables' values by index, `marks.0.sigma`), the
//! comment after a value as the field's help, in the file's own units. A field edited on the
//! page is written back with [`CaseEdit`] (every other byte kept), so the form and the TOML are
//! two views of one text.

use crate::AnswerError;
use pim_case::edit::{CaseEdit, NewValue};
use serde::{Deserialize, Serialize};
use toml_edit::{DocumentMut, Item, Table, Value};

/// One section of the case as a form.
#[derive(Debug, Serialize)]
pub struct FormSection {
    /// Its dotted name (`runout.vehicle1`, `observations.0`; empty for the top of the file).
    pub name: String,
    /// Its values.
    pub fields: Vec<FormField>,
}

/// One value of a section.
#[derive(Debug, Serialize)]
pub struct FormField {
    /// Its whole dotted key (`vehicle1.position.x`), as pim's messages name it.
    pub key: String,
    /// The key within the section (`position.x`).
    pub label: String,
    /// `number`, `integer`, `text`, `bool`, or `list` (an array of numbers, shown, edited in
    /// the TOML).
    pub kind: &'static str,
    /// The value as the file writes it (`3400.0`, `locked`, `true`, `[16, 22, 26]`).
    pub value: String,
    /// The comment after it in the file, if any; for a value not written, what stands for it.
    pub comment: Option<String>,
    /// A value the file may leave out: emptied, it is removed, and the case estimates it (a
    /// vehicle's `yaw_inertia` beside its `length` and `width`, [`pim_case::inertia`]).
    pub optional: bool,
}

/// A field's new value from the page.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum FieldValue {
    /// A yes/no value.
    Bool(bool),
    /// A number or a text, as typed (a number when it reads as one and the field is a number).
    Typed(String),
}

fn comment_of(v: &Value) -> Option<String> {
    let s = v.decor().suffix()?.as_str()?.trim();
    let c = s.strip_prefix('#')?.trim();
    (!c.is_empty()).then(|| c.to_string())
}

fn scalar(key: &str, label: &str, v: &Value, out: &mut Vec<FormField>) {
    let (kind, value) = match v {
        Value::Float(f) => ("number", f.display_repr().to_string()),
        Value::Integer(i) => ("integer", i.value().to_string()),
        Value::String(s) => ("text", s.value().clone()),
        Value::Boolean(b) => ("bool", b.value().to_string()),
        Value::Array(a) if a.iter().all(|x| x.is_float() || x.is_integer()) => {
            ("list", a.to_string().trim().to_string())
        }
        Value::InlineTable(t) => {
            for (k, x) in t.iter() {
                scalar(&format!("{key}.{k}"), &format!("{label}.{k}"), x, out);
            }
            return;
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                scalar(&format!("{key}.{i}"), &format!("{label}.{i}"), x, out);
            }
            return;
        }
        Value::Datetime(_) => return,
    };
    out.push(FormField {
        key: key.to_string(),
        label: label.to_string(),
        kind,
        value,
        comment: comment_of(v),
        optional: false,
    });
}

fn section(name: &str, table: &Table, out: &mut Vec<FormSection>) {
    let mut fields = Vec::new();
    let mut nested = Vec::new();
    for (k, item) in table.iter() {
        let key = if name.is_empty() {
            k.to_string()
        } else {
            format!("{name}.{k}")
        };
        match item {
            Item::Value(v) => scalar(&key, k, v, &mut fields),
            Item::Table(t) => nested.push((key, t)),
            Item::ArrayOfTables(a) => {
                for (i, t) in a.iter().enumerate() {
                    section(&format!("{key}.{i}"), t, out);
                }
            }
            Item::None => {}
        }
    }
    if !fields.is_empty() {
        out.push(FormSection {
            name: name.to_string(),
            fields,
        });
    }
    for (key, t) in nested {
        section(&key, t, out);
    }
}

/// The case text as forms, section by section in the file's order.
///
/// # Errors
/// Text that is not TOML (the message names the line).
pub fn form(file: &str, text: &str) -> Result<Vec<FormSection>, AnswerError> {
    let doc = text.parse::<DocumentMut>().map_err(|e| {
        AnswerError::Input(format!("{file}: {}", e.message().trim_end_matches('\n')))
    })?;
    let mut out = Vec::new();
    section("", doc.as_table(), &mut out);
    offer_inertias(file, text, &mut out);
    Ok(out)
}

/// Each vehicle section that writes its `length` and `width` gets its `yaw_inertia` as an
/// optional field: written, it may be emptied; not written, it is offered empty, its comment
/// the estimate the case makes instead (once the text loads as a case).
fn offer_inertias(file: &str, text: &str, out: &mut [FormSection]) {
    let estimates = pim_case::case::Case::from_text(file, text)
        .map(|c| c.estimated())
        .unwrap_or_default();
    for s in out
        .iter_mut()
        .filter(|s| matches!(s.name.as_str(), "vehicle1" | "vehicle2"))
    {
        let writes = |k: &str| s.fields.iter().any(|f| f.label == k);
        if !(writes("length") && writes("width")) || writes("barrier") {
            continue;
        }
        let key = format!("{}.yaw_inertia", s.name);
        if let Some(f) = s.fields.iter_mut().find(|f| f.key == key) {
            f.optional = true;
            continue;
        }
        let said = estimates
            .iter()
            .find_map(|e| e.strip_prefix(&format!("{key}: not given, ")));
        let comment = match said {
            Some(e) => e.to_string(),
            None => format!(
                "not given: estimated from mass, length and width as {}",
                pim_case::inertia::RULE
            ),
        };
        // After the mass, where the templates and the examples write it.
        let at = s
            .fields
            .iter()
            .position(|f| f.label == "mass")
            .map_or(0, |i| i + 1);
        s.fields.insert(
            at,
            FormField {
                key,
                label: "yaw_inertia".to_string(),
                kind: "number",
                value: String::new(),
                comment: Some(comment),
                optional: true,
            },
        );
    }
}

/// The case text with the value at `key` (a field of [`form`]) set to `value`: a number where
/// the file writes a number (refused when the text is none), a text where it writes a text, a
/// yes/no where it writes one; every other byte kept. The case is not checked here: its answer
/// says what is wrong, at the field.
///
/// # Errors
/// Text that is not TOML, a key the file does not write, or a value of the wrong kind.
pub fn set_field(
    file: &str,
    text: &str,
    key: &str,
    value: &FieldValue,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let fields = form(file, text)?;
    let Some(field) = fields.iter().flat_map(|s| &s.fields).find(|f| f.key == key) else {
        return Err(AnswerError::Input(format!(
            "{file}: {key}: the file writes no such value"
        )));
    };
    if let (true, FieldValue::Typed(s)) = (field.optional, value) {
        if s.trim().is_empty() {
            let mut edit = CaseEdit::new(file, text).map_err(|e| input(&e))?;
            edit.remove(key);
            return Ok(edit.text());
        }
    }
    let new = match (field.kind, value) {
        ("bool", FieldValue::Bool(b)) => NewValue::Bool(*b),
        ("number", FieldValue::Typed(s)) => match s.trim().parse::<f64>() {
            Ok(x) if x.is_finite() => NewValue::Written(x),
            _ => {
                return Err(AnswerError::Input(format!(
                    "{file}: {key}: {s:?} is not a number"
                )))
            }
        },
        ("integer", FieldValue::Typed(s)) => match s.trim().parse::<i64>() {
            Ok(i) => NewValue::Integer(i),
            _ => {
                return Err(AnswerError::Input(format!(
                    "{file}: {key}: {s:?} is not a whole number"
                )))
            }
        },
        ("text", FieldValue::Typed(s)) => NewValue::Text(s.clone()),
        (kind, _) => {
            return Err(AnswerError::Input(format!(
                "{file}: {key}: a {kind} field{}",
                if kind == "list" {
                    " (edit it in the TOML)"
                } else {
                    ""
                }
            )))
        }
    };
    let mut edit = CaseEdit::new(file, text).map_err(|e| input(&e))?;
    edit.set(key, new).map_err(|e| input(&e))?;
    Ok(edit.text())
}
