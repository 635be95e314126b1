//! `pim.edit_case`: values of a case file changed in place, the rest of the file kept.

use crate::convert::{input_error, read};
use pim_case::edit::{CaseEdit, NewValue};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyString};

/// Changes values of a case file (`pim set`): `values` maps dotted paths as the file writes
/// them (`scene.vehicle1.rest.x`, `observations.0.sigma`) to numbers (in the file's units),
/// booleans or text. The edited case is checked as every command reads it; with `write` the
/// file is written back (comments, order and number formatting kept everywhere else). The
/// edited text is returned.
#[pyfunction]
#[pyo3(signature = (path, values, write = true))]
pub(crate) fn edit_case(
    path: std::path::PathBuf,
    values: &Bound<'_, PyDict>,
    write: bool,
) -> PyResult<String> {
    let name = path.display().to_string();
    let text = read(&path, pim_case::case::MAX_CASE_BYTES)?;
    let mut edit = CaseEdit::new(&name, &text).map_err(|e| input_error(e.message))?;
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
    edit.check().map_err(|e| input_error(e.message))?;
    let edited = edit.text();
    if write {
        let tmp = path.with_extension("toml.pim-set");
        std::fs::write(&tmp, &edited)
            .and_then(|_| std::fs::rename(&tmp, &path))
            .map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                pyo3::exceptions::PyOSError::new_err(format!("{name}: cannot write: {e}"))
            })?;
    }
    Ok(edited)
}
