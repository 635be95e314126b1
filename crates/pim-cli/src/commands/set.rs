//! `pim set`: change values of a case file in place, keeping the rest of the file as written.

use crate::error::{Failure, EXIT_OK};
use crate::set_args::SetArgs;
use anyhow::Result;
use pim_case::edit::{CaseEdit, NewValue};
use pim_store::{StoreError, WriteOptions};
use std::process::ExitCode;

/// A value as typed: a number, `true`/`false`, or text (quotes optional).
fn value_of(text: &str) -> NewValue {
    let t = text.trim();
    if let Ok(x) = t.parse::<f64>() {
        return NewValue::Written(x);
    }
    match t {
        "true" => NewValue::Bool(true),
        "false" => NewValue::Bool(false),
        _ => NewValue::Text(
            t.strip_prefix('"')
                .and_then(|s| s.strip_suffix('"'))
                .unwrap_or(t)
                .to_string(),
        ),
    }
}

/// The failure of a read or write of the store: a changed file or the system's refusal is
/// exit status 4, anything about the text or the file given is bad input (2).
pub(crate) fn store_failure(e: StoreError) -> Failure {
    match e {
        StoreError::Conflict { .. } | StoreError::Io { .. } => Failure::Output(e.to_string()),
        StoreError::Missing { file } => {
            Failure::Input(format!("{file}: cannot read: no such file"))
        }
        _ => Failure::Input(e.to_string()),
    }
}

/// The text with every KEY=VALUE of `values` set, and what was said of each.
fn edited(
    name: &str,
    text: &str,
    values: &[String],
) -> std::result::Result<(String, Vec<String>), pim_case::InputError> {
    let mut edit = CaseEdit::new(name, text)?;
    let mut said = Vec::new();
    for pair in values {
        let Some((key, value)) = pair.split_once('=') else {
            return Err(pim_case::InputError::new(
                name,
                format!("{pair}: expected KEY=VALUE, e.g. scene.vehicle1.rest.x=12.0"),
            ));
        };
        let key = key.trim();
        let was = edit.get(key);
        edit.set(key, value_of(value))?;
        let now = edit.get(key).unwrap_or_default();
        said.push(match was {
            Some(w) => format!("{name}: {key} = {now} (was {w})"),
            None => format!("{name}: {key} = {now} (added)"),
        });
    }
    Ok((edit.text(), said))
}

/// The case file at `path` changed by `edit` and written as `pim set` writes (checked,
/// atomic); or, with `dry_run`, the changed text printed and the file left as it was.
pub fn write_or_print<E: std::fmt::Display>(
    path: &std::path::Path,
    options: &WriteOptions<'_>,
    dry_run: bool,
    edit: impl FnOnce(&pim_store::Stored) -> std::result::Result<String, E>,
) -> Result<pim_store::Stored> {
    let done = if dry_run {
        pim_store::preview(path, options, edit)
    } else {
        pim_store::update(path, options, edit)
    }
    .map_err(store_failure)?;
    if dry_run {
        super::print_out(&done.text)?;
    }
    Ok(done)
}

/// `pim set CASE KEY=VALUE...`.
pub fn run(a: &SetArgs) -> Result<ExitCode> {
    let name = a.case.display().to_string();
    if a.print_version {
        let stored = pim_store::read(&a.case, pim_store::MAX_CASE_BYTES).map_err(store_failure)?;
        super::print_out(&format!("{}\n", stored.version))?;
        return Ok(ExitCode::from(EXIT_OK));
    }
    let mut said = Vec::new();
    let options = WriteOptions {
        expected: a.if_version.as_deref(),
        ..Default::default()
    };
    let edit = |current: &pim_store::Stored| {
        let (text, s) = edited(&name, &current.text, &a.values)?;
        said = s;
        Ok::<_, pim_case::InputError>(text)
    };
    let done = write_or_print(&a.case, &options, a.dry_run, edit)?;
    for s in said {
        eprintln!("pim: {s}");
    }
    if !a.dry_run {
        eprintln!("pim: {name}: written (version {})", done.version);
    }
    Ok(ExitCode::from(EXIT_OK))
}
