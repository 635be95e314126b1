//! Every command the README and the guide (`docs/`) show runs here, and its output must match
//! what they print, so that no example can drift from the program.
//!
//! The examples are the ```` ```console ```` blocks of `README.md` and `docs/*.md`: a line
//! `$ pim ...` is a command; the lines after it, up to the next command or the end of the
//! block, are its standard output. In the expected output a line `...` stands for any number of
//! lines and `[..]` within a line for any text; a line `? N` after the output says the command
//! ends with exit status N (default 0). Each command runs as a user following the guide runs it:
//! from a folder that holds the repository's `examples/` and `data/`, so that the files it
//! writes (`--out`, `--draw`) land in a scratch folder.
use crate::common;
use common::*;
use std::path::{Path, PathBuf};

/// One command of a page and what it must print.
struct Example {
    page: String,
    line: usize,
    args: Vec<String>,
    expected: Vec<String>,
    status: i32,
}

/// Splits a command line into words (double quotes group words).
fn words(line: &str) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    let mut any = false;
    for c in line.chars() {
        match c {
            '"' => {
                quoted = !quoted;
                any = true;
            }
            c if c.is_whitespace() && !quoted => {
                if any || !cur.is_empty() {
                    out.push(std::mem::take(&mut cur));
                    any = false;
                }
            }
            c => cur.push(c),
        }
    }
    if any || !cur.is_empty() {
        out.push(cur);
    }
    out
}

/// The examples of one page.
fn examples(page: &Path) -> Vec<Example> {
    let text = std::fs::read_to_string(page).unwrap();
    let name = page
        .strip_prefix(repo())
        .unwrap_or(page)
        .display()
        .to_string();
    let mut out: Vec<Example> = Vec::new();
    let mut inside = false;
    for (i, line) in text.lines().enumerate() {
        if line.starts_with("```") {
            inside = !inside && line.trim() == "```console";
            continue;
        }
        if !inside {
            continue;
        }
        if let Some(cmd) = line.strip_prefix("$ ") {
            let args = words(cmd);
            assert_eq!(
                args.first().map(String::as_str),
                Some("pim"),
                "{name}:{}: only `pim` commands are run: {line}",
                i + 1
            );
            out.push(Example {
                page: name.clone(),
                line: i + 1,
                args: args[1..].to_vec(),
                expected: Vec::new(),
                status: 0,
            });
        } else if let Some(e) = out.last_mut() {
            if let Some(code) = line.strip_prefix("? ") {
                e.status = code.trim().parse().unwrap();
            } else {
                e.expected.push(line.trim_end().to_string());
            }
        } else {
            panic!("{name}:{}: output before any command", i + 1);
        }
    }
    out
}

/// Whether `line` matches the expected line `pattern` (`[..]` matches any text).
fn line_matches(pattern: &str, line: &str) -> bool {
    let parts: Vec<&str> = pattern.split("[..]").collect();
    if parts.len() == 1 {
        return pattern == line;
    }
    let mut rest = line;
    for (k, part) in parts.iter().enumerate() {
        if k == 0 {
            match rest.strip_prefix(part) {
                Some(r) => rest = r,
                None => return false,
            }
        } else if k == parts.len() - 1 {
            return rest.ends_with(part);
        } else {
            match rest.find(part) {
                Some(at) => rest = &rest[at + part.len()..],
                None => return false,
            }
        }
    }
    true
}

/// Whether the output lines match the expected ones (`...` lines match any run of lines).
fn matches(expected: &[String], actual: &[&str]) -> bool {
    match expected.split_first() {
        None => actual.is_empty(),
        Some((e, rest)) if e == "..." => (0..=actual.len()).any(|k| matches(rest, &actual[k..])),
        Some((e, rest)) => {
            !actual.is_empty() && line_matches(e, actual[0]) && matches(rest, &actual[1..])
        }
    }
}

fn pages() -> Vec<PathBuf> {
    let mut pages = vec![repo().join("README.md")];
    let mut docs: Vec<PathBuf> = std::fs::read_dir(repo().join("docs"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "md"))
        .collect();
    docs.sort();
    pages.extend(docs);
    pages
}

/// A folder that looks like the repository to a user (its `examples/` and `data/`).
fn workdir() -> PathBuf {
    let d = scratch_dir("guide", "work");
    for name in ["examples", "data"] {
        std::os::unix::fs::symlink(repo().join(name).canonicalize().unwrap(), d.join(name))
            .unwrap();
    }
    d
}

#[test]
fn every_command_of_the_readme_and_the_guide() {
    let dir = workdir();
    let all: Vec<Example> = pages().iter().flat_map(|p| examples(p)).collect();
    assert!(all.len() >= 20, "only {} examples found", all.len());
    let mut failures = Vec::new();
    for e in &all {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_pim"))
            .args(&e.args)
            .current_dir(&dir)
            .env("COLUMNS", "100")
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout);
        let actual: Vec<&str> = stdout.lines().map(str::trim_end).collect();
        let code = out.status.code().unwrap_or(-1);
        if code != e.status || !matches(&e.expected, &actual) {
            failures.push(format!(
                "{}:{}: pim {} (exit {code}, expected {}):\n--- expected\n{}\n--- got\n{}\n--- stderr\n{}",
                e.page,
                e.line,
                e.args.join(" "),
                e.status,
                e.expected.join("\n"),
                stdout,
                stderr(&out)
            ));
        }
    }
    assert!(
        failures.is_empty(),
        "{} of {} examples differ:\n\n{}",
        failures.len(),
        all.len(),
        failures.join("\n\n")
    );
}

#[test]
fn the_matcher_is_strict_where_it_must_be() {
    let e = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    assert!(matches(&e(&["a", "...", "c"]), &["a", "b", "b", "c"]));
    assert!(matches(&e(&["a", "...", "c"]), &["a", "c"]));
    assert!(!matches(&e(&["a", "c"]), &["a", "b", "c"]));
    assert!(!matches(&e(&["a"]), &["a", "b"]));
    assert!(line_matches("speed [..] mph", "speed 37.91 mph"));
    assert!(!line_matches("speed [..] mph", "speed 37.91 km/h"));
    assert_eq!(
        words(r#"fit "my case.toml" --x"#),
        ["fit", "my case.toml", "--x"]
    );
}
