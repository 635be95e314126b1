//! TOML text to typed sections, with errors that name the file, line, column and field.

use crate::error::{InputError, Result};

/// Free text from a case made safe for every output: control characters (an escape sequence
/// for the terminal, a character XML forbids) are written as their `\u{..}` escapes.
pub fn printable(s: &str) -> String {
    s.chars()
        .map(|c| {
            if c.is_control() {
                c.escape_unicode().to_string()
            } else {
                c.to_string()
            }
        })
        .collect()
}

/// Line and column (1-based) of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let upto = &text[..offset.min(text.len())];
    let line = upto.matches('\n').count() + 1;
    let col = upto.rsplit('\n').next().map_or(0, |l| l.chars().count()) + 1;
    (line, col)
}

/// The line (and column 1) that nests deepest: the most dots in a key or table header, plus
/// the brackets and braces opened on it (for a key nested beyond the parser's limit, which it
/// reports without a place).
fn deepest_line(text: &str) -> Option<(usize, usize)> {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            let key = l.split('=').next().unwrap_or("");
            let depth = key.matches('.').count() + l.matches(['[', '{']).count();
            (depth, i)
        })
        .max_by_key(|&(d, i)| (d, std::cmp::Reverse(i)))
        .filter(|&(d, _)| d > 0)
        .map(|(_, i)| (i + 1, 1))
}

/// Parses TOML into `T`, with errors as `file:line:col: field: message` (the field as its
/// dotted path, e.g. `vehicle1.mass`).
pub fn parse_toml<T: serde::de::DeserializeOwned>(file: &str, text: &str) -> Result<T> {
    if text.trim().is_empty() {
        return Err(InputError::new(file, "the file is empty"));
    }
    let located = |e: &toml::de::Error, field: Option<String>| {
        let mut msg = plain_words(e.message().trim());
        if msg.starts_with("duplicate key") {
            // Name the key: the span covers it.
            let key = e
                .span()
                .and_then(|s| text.get(s))
                .map(|k| k.trim().trim_matches('"').to_string())
                .unwrap_or_default();
            msg = format!("duplicate key `{key}`: it is given twice in its table; give it once");
        } else if msg.contains("untagged enum Spread") {
            msg =
                "expected a standard deviation (a number) or { uniform = [low, high] }".to_string();
        } else if msg.contains("recursion limit") || msg.contains("cannot recurse") {
            msg = "tables or lists nested too deeply for a case file".to_string();
        }
        // A TOML date or time reaches serde as a table: name it for what it is.
        if msg.ends_with("got a table") {
            let written = e.span().and_then(|s| text.get(s)).unwrap_or("").trim();
            let date_like = !written.is_empty()
                && written.chars().next().is_some_and(|c| c.is_ascii_digit())
                && written
                    .chars()
                    .all(|c| c.is_ascii_digit() || "-:.TZ+ ".contains(c));
            if date_like {
                msg = format!(
                    "{}got a date or time, {written}",
                    &msg[..msg.len() - "got a table".len()]
                );
            }
        }
        let deep = msg.starts_with("tables or lists nested too deeply");
        let what = match field {
            Some(f) if !f.is_empty() && f != "." => format!("{f}: {msg}"),
            _ => msg,
        };
        match e.span().map(|s| line_col(text, s.start)).or_else(|| {
            // The parser gives no place for a key nested too deeply: the deepest line is it.
            deep.then(|| deepest_line(text)).flatten()
        }) {
            Some((line, col)) => InputError::located(file, format!("{file}:{line}:{col}: {what}")),
            None => InputError::new(file, what),
        }
    };
    let de = toml::Deserializer::parse(text).map_err(|e| located(&e, None))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let field = display_path(text, &e.path().to_string());
        located(e.inner(), Some(field))
    })
}

/// A field's path as a case file's reader names it: `observations[1].sigma` (0-based, as the
/// parser counts) is `observation 2: sigma`, or `observation "EDR front": sigma` when the entry
/// has a `name`; other paths are as they are.
pub fn display_path(text: &str, path: &str) -> String {
    let Some(rest) = path.strip_prefix("observations[") else {
        return path.to_string();
    };
    let Some((index, tail)) = rest.split_once(']') else {
        return path.to_string();
    };
    let Ok(i) = index.parse::<usize>() else {
        return path.to_string();
    };
    let label = observation_label(text, i);
    match tail.strip_prefix('.') {
        Some(field) if !field.is_empty() => format!("{label}: {field}"),
        _ => label,
    }
}

/// How the `i`-th (0-based) `[[observations]]` entry of a case text is named: by its `name`,
/// or by its 1-based position.
pub fn observation_label(text: &str, i: usize) -> String {
    use toml::de::{DeTable, DeValue};
    let name = DeTable::parse(text).ok().and_then(|root| {
        let (_, list) = root
            .get_ref()
            .iter()
            .find(|(k, _)| k.get_ref().as_ref() == "observations")?;
        let DeValue::Array(items) = list.get_ref() else {
            return None;
        };
        let DeValue::Table(entry) = items.get(i)?.get_ref() else {
            return None;
        };
        let (_, name) = entry.iter().find(|(k, _)| k.get_ref().as_ref() == "name")?;
        match name.get_ref() {
            DeValue::String(s) => Some(printable(s)),
            _ => None,
        }
    });
    match name {
        Some(n) => format!("observation {n:?}"),
        None => format!("observation {}", i + 1),
    }
}

/// serde's type messages in the words of a case file: `invalid type: string "heavy", expected
/// f64` becomes `expected a number, got the text "heavy"`.
fn plain_words(msg: &str) -> String {
    // `unknown variant `sea`, expected one of `natural`, `brach`, `sae``, and the same of a
    // field: what is wrong; what is accepted.
    for (prefix, what) in [
        ("unknown variant ", "is not an accepted value"),
        ("unknown field ", "is not a field of this table"),
    ] {
        if let Some(rest) = msg.strip_prefix(prefix) {
            if let Some((got, want)) = rest.split_once(", expected ") {
                let want = want.strip_prefix("one of ").unwrap_or(want);
                return format!("{got} {what}; accepted: {want}");
            }
            if let Some((got, _)) = rest.split_once(", there are no ") {
                return format!("{got} {what}; this table takes none");
            }
        }
    }
    // A whole number that does not fit the field (`invalid value: integer `300`, expected
    // u8`, or one beyond 64 bits, which the TOML reader reports `as i128`).
    if let Some(rest) = msg
        .strip_prefix("invalid value: integer ")
        .or_else(|| msg.strip_prefix("invalid type: integer "))
    {
        let numeric = |w: &str| {
            [
                "u8", "u16", "u32", "u64", "usize", "i32", "i64", "f64", "f32",
            ]
            .contains(&w)
        };
        if let Some((got, want)) = rest
            .split_once(", expected ")
            .filter(|(_, want)| numeric(want))
        {
            let got = got.trim_end_matches(" as i128").trim_matches('`');
            let range = match want {
                "u8" => "a whole number from 0 to 255".to_string(),
                "u32" => "a whole number from 0 to 4294967295".to_string(),
                "u64" | "usize" => "a whole number from 0 to 18446744073709551615".to_string(),
                "i64" => "a whole number that fits in 64 bits".to_string(),
                "f64" | "f32" => "a number".to_string(),
                w => w.to_string(),
            };
            return format!("{got} is out of range; accepted: {range}");
        }
    }
    let Some(rest) = msg.strip_prefix("invalid type: ") else {
        return msg.to_string();
    };
    let Some((got, want)) = rest.split_once(", expected ") else {
        return msg.to_string();
    };
    let got = if let Some(t) = got.strip_prefix("string ") {
        format!("the text {t}")
    } else if let Some(t) = got.strip_prefix("integer ") {
        format!("the whole number {}", t.trim_matches('`'))
    } else if let Some(t) = got.strip_prefix("floating point ") {
        format!("the number {}", t.trim_matches('`'))
    } else if let Some(t) = got.strip_prefix("boolean ") {
        t.trim_matches('`').to_string()
    } else if got == "sequence" {
        "a list".to_string()
    } else if got == "map" {
        "a table".to_string()
    } else {
        got.to_string()
    };
    let want = match want {
        "f64" | "f32" => "a number".to_string(),
        "u8" | "u16" | "u32" | "u64" | "usize" | "i32" | "i64" => "a whole number".to_string(),
        "a string" => "text in quotes".to_string(),
        // A section or inline table (serde names the Rust type): say what the file writes.
        w if w.starts_with("struct ") || w == "a map" => {
            "a table: a [section] or { key = value, ... }".to_string()
        }
        w if w.starts_with("a sequence") => "a list [ ... ]".to_string(),
        w => w.to_string(),
    };
    format!("expected {want}, got {got}")
}

/// Where the value at a dotted path (`vehicle1.width`, `bounds.crush_angle`) is written in a
/// TOML text, as `(line, column)`; `None` when the path is not written there (a default).
pub fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    use toml::de::{DeTable, DeValue};
    let root = DeTable::parse(text).ok()?;
    let mut table: &DeTable = root.get_ref();
    let keys: Vec<&str> = path.split('.').collect();
    let mut start = None;
    for (i, key) in keys.iter().enumerate() {
        // `observations[2]`: the third entry of an array of tables.
        let (key, index) = match key.split_once('[') {
            Some((k, rest)) => (k, Some(rest.trim_end_matches(']').parse::<usize>().ok()?)),
            None => (*key, None),
        };
        let (_, mut value) = table.iter().find(|(k, _)| k.get_ref().as_ref() == key)?;
        if let Some(n) = index {
            match value.get_ref() {
                DeValue::Array(items) => value = items.get(n)?,
                _ => return None,
            }
        }
        start = Some(value.span().start);
        if i + 1 < keys.len() {
            match value.get_ref() {
                DeValue::Table(t) => table = t,
                _ => return None,
            }
        }
    }
    start.map(|s| line_col(text, s))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_dotted_path_is_found_in_sections_and_inline_tables() {
        let text = "title = \"t\"\n[vehicle1]\nmass = 1.0\nwidth = 2.0\n[bounds]\nvehicle1 = { d = [1.0, 2.0] }\n";
        assert_eq!(locate(text, "vehicle1.width"), Some((4, 9)));
        assert_eq!(locate(text, "bounds.vehicle1.d"), Some((6, 18)));
        assert_eq!(locate(text, "vehicle1.length"), None);
    }
}
