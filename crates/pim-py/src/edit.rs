//! `pim.edit_case`: values of a case file changed in place, the rest of the file kept.

use crate::convert::input_error;
use pim_case::edit::{CaseEdit, NewValue};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};

/// The edited text of `text`: every value of `values` set.
fn edited(name: &str, text: &str, values: &Bound<'_, PyDict>) -> PyResult<String> {
    let mut edit = CaseEdit::new(name, text).map_err(|e| input_error(e.message))?;
    for (k, v) in values.iter() {
        let key: String = k
            .extract()
            .map_err(|_| input_error(format!("{name}: the keys of values must be text")))?;
        // A bool is an int in Python: asked first.
        let value = if v.is_instance_of::<PyBool>() {
            NewValue::Bool(v.extract()?)
        } else if v.is_instance_of::<PyInt>() || v.is_instance_of::<PyFloat>() {
            NewValue::Written(v.extract()?)
        } else if v.is_instance_of::<PyString>() {
            NewValue::Text(v.extract()?)
        } else {
            return Err(input_error(format!(
                "{name}: {key}: a number, a bool or text, got {}",
                v.get_type().name()?
            )));
        };
        edit.set(&key, value).map_err(|e| input_error(e.message))?;
    }
    Ok(edit.text())
}

/// A store's refusal as Python raises it: a changed file or a failed write `OSError`, the
/// rest `ValueError` (pim's input error).
fn store_error(e: pim_store::StoreError) -> PyErr {
    use pim_store::StoreError as E;
    match e {
        E::Conflict { .. } | E::Io { .. } => pyo3::exceptions::PyOSError::new_err(e.to_string()),
        _ => input_error(e.to_string()),
    }
}

/// Changes values of a case file (`pim set`): `values` maps dotted paths as the file writes
/// them (`scene.vehicle1.rest.x`, `observations.0.sigma`) to numbers (in the file's units),
/// booleans or text. The edited case is checked with every check `pim fit` makes; with
/// `write` the file is written back (comments, order and number formatting kept everywhere
/// else) as `pim set` writes it: beside the file, then renamed over it, its mode kept, under
/// the file's lock. With `if_version` (as `case_version` gave it) nothing is written, and
/// `OSError` raised, when the file changed since. The edited text is returned.
#[pyfunction]
#[pyo3(signature = (path, values, write = true, if_version = None))]
pub(crate) fn edit_case(
    path: std::path::PathBuf,
    values: &Bound<'_, PyDict>,
    write: bool,
    if_version: Option<String>,
) -> PyResult<String> {
    let name = path.display().to_string();
    let mut failed = None;
    let options = pim_store::WriteOptions {
        expected: if_version.as_deref(),
        ..Default::default()
    };
    let edit = |current: &pim_store::Stored| {
        edited(&name, &current.text, values).map_err(|e| {
            let message = e.to_string();
            failed = Some(e);
            message
        })
    };
    let done = if write {
        pim_store::update(&path, &options, edit)
    } else {
        pim_store::preview(&path, &options, edit)
    };
    match (done, failed) {
        (Ok(stored), _) => Ok(stored.text),
        (Err(_), Some(e)) => Err(e),
        (Err(e), None) => Err(store_error(e)),
    }
}

/// The version of a case file: the SHA-256 of its text (64 hex digits), as `pim set
/// --print-version` prints it; `edit_case(..., if_version=...)` takes it.
#[pyfunction]
pub(crate) fn case_version(path: std::path::PathBuf) -> PyResult<String> {
    pim_store::read(&path, pim_store::MAX_CASE_BYTES)
        .map(|s| s.version.0)
        .map_err(store_error)
}
