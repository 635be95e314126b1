//! `pim set`: change values of a case file in place, keeping the rest of the file as written.

use crate::error::{Failure, EXIT_OK};
use crate::inputs::{io_reason, read_text_file};
use crate::set_args::SetArgs;
use anyhow::Result;
use pim_case::case::MAX_CASE_BYTES;
use pim_case::edit::{CaseEdit, NewValue};
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

/// `pim set CASE KEY=VALUE...`.
pub fn run(a: &SetArgs) -> Result<ExitCode> {
    let name = a.case.display().to_string();
    let text = read_text_file(&a.case, MAX_CASE_BYTES)?;
    let mut edit = CaseEdit::new(&name, &text)?;
    let mut said = Vec::new();
    for pair in &a.values {
        let Some((key, value)) = pair.split_once('=') else {
            return Err(Failure::Input(format!(
                "{pair}: expected KEY=VALUE, e.g. scene.vehicle1.rest.x=12.0"
            ))
            .into());
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
    // The edited case must read as `pim` reads a case: the same checks and messages.
    edit.check()?;
    let edited = edit.text();
    if a.dry_run {
        super::print_out(&edited)?;
    } else {
        // Written beside the file and renamed over it: the file is never left half written.
        let tmp = a.case.with_extension("toml.pim-set");
        std::fs::write(&tmp, &edited)
            .and_then(|_| std::fs::rename(&tmp, &a.case))
            .map_err(|e| {
                let _ = std::fs::remove_file(&tmp);
                Failure::Output(format!("{name}: cannot write: {}", io_reason(&e)))
            })?;
    }
    for s in said {
        eprintln!("pim: {s}");
    }
    Ok(ExitCode::from(EXIT_OK))
}
