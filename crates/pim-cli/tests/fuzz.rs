//! The command under fuzzing: example case files with hostile numbers, dropped and doubled
//! lines, run through `pim solve`, `pim fit` and `pim draw` as a careless script would. The
//! property: the command ends within its time limit, with a documented exit status (0 to 4),
//! never a panic; a run that exits 0 prints only finite numbers (JSON has no NaN or infinity,
//! and every number it prints must read as finite), and a fit that exits 0 has an admissible
//! best branch.
//!
//! Bounded in time: `PIM_FUZZ_SECONDS` (default 10) of mutations in a fixed, seeded order, so
//! that a run is reproducible up to where the time ends; `PIM_FUZZ_SEED` picks another order.
//! Each failing input is written to `target/tmp/cli_fuzz_failures/` (add it to
//! `tests/fuzz-corpus/`, which is replayed through the command first, every run).
//!
//! A test binary of its own, beside `cli/`: its time limit is the command's own, measured on a
//! machine the other end-to-end tests do not share at the same moment.
#[path = "cli/common/mod.rs"]
mod common;
// The mutations of the parsers' fuzz tests.
#[path = "../../pim-studies/tests/mutate/mod.rs"]
mod mutate;
use common::*;
use mutate::{hostile_number, replace_number};
use proptest::prelude::*;
use proptest::strategy::ValueTree;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use serde_json::Value;

/// Time limit of one run of the command, s.
const RUN_LIMIT: u64 = 20;

/// One edit of a case text.
#[derive(Debug, Clone)]
enum Edit {
    Number(usize, String),
    DropLine(usize),
    DoubleLine(usize),
}

fn apply(text: &str, edit: &Edit) -> String {
    match edit {
        Edit::Number(k, new) => replace_number(text, *k, new),
        Edit::DropLine(k) | Edit::DoubleLine(k) => {
            let mut lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return text.to_string();
            }
            let i = k % lines.len();
            if matches!(edit, Edit::DropLine(_)) {
                lines.remove(i);
            } else {
                lines.insert(i, lines[i]);
            }
            lines.join("\n") + "\n"
        }
    }
}

fn edit() -> impl Strategy<Value = Edit> {
    prop_oneof![
        6 => (0..200usize, hostile_number()).prop_map(|(k, v)| Edit::Number(k, v)),
        1 => (0..200usize).prop_map(Edit::DropLine),
        1 => (0..200usize).prop_map(Edit::DoubleLine),
    ]
}

/// Every number printed in a text table reads as finite (no `NaN`, `inf`).
fn finite_text(text: &str) -> bool {
    !text
        .split(|c: char| c.is_whitespace() || c == ',' || c == '(' || c == ')')
        .any(|w| {
            let w = w.trim_end_matches(['%', ';', ':']);
            w.eq_ignore_ascii_case("nan") || w.eq_ignore_ascii_case("inf") || w == "-inf"
        })
}

/// Runs one command on one text; `Err` with the reason when the property fails.
fn check(command: usize, text: &str, scratch: &str) -> Result<(), String> {
    let path = scratch_file("cli_fuzz", &format!("{scratch}.toml"), text);
    let svg = format!("{path}.svg");
    let args: Vec<&str> = match command {
        0 => vec!["solve", &path, "--format", "json"],
        1 => vec!["solve", &path],
        2 => vec!["fit", &path, "--cost", "q2", "--format", "json"],
        3 => vec!["fit", &path, "--format", "json"],
        _ => vec!["draw", &path, "-o", &svg],
    };
    let out = std::panic::catch_unwind(|| pim_within(&args, RUN_LIMIT))
        .map_err(|_| format!("pim {} did not end within {RUN_LIMIT} s", args.join(" ")))?;
    let err = stderr(&out);
    let code = out
        .status
        .code()
        .ok_or_else(|| format!("killed by a signal: {err}"))?;
    if !(0..=4).contains(&code) || err.contains("panicked") {
        return Err(format!("exit {code}: {err}"));
    }
    if code != 0 {
        if !err.starts_with("pim: ") {
            return Err(format!("exit {code} without a `pim: ` message: {err}"));
        }
        return Ok(());
    }
    let stdout = String::from_utf8_lossy(&out.stdout);
    match command {
        0 | 2 | 3 => {
            let j: Value = serde_json::from_str(&stdout)
                .map_err(|e| format!("exit 0 with output that is not JSON ({e}): {stdout}"))?;
            if command == 3 && j["kind"] == "reconstruction" {
                // A case with scene evidence: the three phases in one fit.
                if j["status"] != "found" {
                    return Err(format!("exit 0 with status {}", j["status"]));
                }
                let b = &j["best"];
                for k in ["e", "mu", "em", "chi_square"] {
                    if !b[k].as_f64().is_some_and(f64::is_finite) {
                        return Err(format!("exit 0 with {k} = {}", b[k]));
                    }
                }
            } else if command >= 2 {
                let best = j["best"].as_str().ok_or("exit 0 without a best branch")?;
                let b = j["branches"]
                    .as_array()
                    .and_then(|a| a.iter().find(|b| b["moment"] == best))
                    .ok_or("the best branch is missing")?;
                if b["admissible"] != Value::Bool(true) {
                    return Err(format!("exit 0 with an inadmissible best branch: {b}"));
                }
                for k in ["e", "mu", "em", "cost"] {
                    if !b[k].as_f64().is_some_and(f64::is_finite) {
                        return Err(format!("exit 0 with {k} = {}", b[k]));
                    }
                }
            }
        }
        1 => {
            // The numbers, not the title and descriptions the user wrote (its first lines).
            let numbers: String = stdout.lines().skip(2).collect::<Vec<_>>().join("\n");
            if !finite_text(&numbers) {
                return Err(format!("exit 0 with a number that is not finite: {stdout}"));
            }
        }
        _ => {
            let svg = std::fs::read_to_string(&svg).map_err(|e| format!("no SVG: {e}"))?;
            // Coordinates and sizes are attribute values; text the user wrote is not.
            let attributes: Vec<&str> = svg
                .split("=\"")
                .skip(1)
                .filter_map(|a| a.split('"').next())
                .collect();
            if attributes
                .iter()
                .any(|a| !finite_text(a) || a.contains("NaN"))
            {
                return Err("exit 0 with an SVG holding a non-finite number".into());
            }
        }
    }
    Ok(())
}

fn bases() -> Vec<(String, String)> {
    let mut out = Vec::new();
    for entry in std::fs::read_dir(repo().join("examples/cases")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let name = p.file_stem().unwrap().to_string_lossy().to_string();
            out.push((name, std::fs::read_to_string(&p).unwrap()));
        }
    }
    out.sort();
    out
}

fn fail(name: &str, command: usize, text: &str, why: &str) -> String {
    let dir = scratch_dir_keep("cli_fuzz_failures");
    let p = dir.join(format!("{name}_command{command}.toml"));
    std::fs::write(&p, text).unwrap();
    format!("{}: {why}", p.display())
}

/// A directory under the target's test directory, created if needed and not emptied.
fn scratch_dir_keep(name: &str) -> std::path::PathBuf {
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn the_corpus_replays_through_every_command() {
    let dir = repo().join("tests/fuzz-corpus");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_some_and(|x| x == "toml") {
            let text = std::fs::read_to_string(&p).unwrap();
            let name = p.file_stem().unwrap().to_string_lossy().to_string();
            for command in 0..5 {
                if let Err(why) = check(command, &text, &format!("corpus_{name}_{command}")) {
                    panic!("{}", fail(&name, command, &text, &why));
                }
            }
            n += 1;
        }
    }
    assert!(n >= 2, "{n} corpus files");
}

#[test]
fn mutated_example_cases_through_the_command() {
    let seconds: u64 = std::env::var("PIM_FUZZ_SECONDS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(10);
    let seed: u8 = std::env::var("PIM_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(11);
    let bases = bases();
    let mut runner = TestRunner::new_with_rng(
        Config::default(),
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    );
    let strategy = (
        0..bases.len(),
        0..5usize,
        prop::collection::vec(edit(), 1..4),
    );
    let end = std::time::Instant::now() + std::time::Duration::from_secs(seconds);
    let mut runs = 0;
    while std::time::Instant::now() < end && runs < 5000 {
        let (b, command, edits) = strategy.new_tree(&mut runner).unwrap().current();
        let (name, base) = &bases[b];
        let text = edits.iter().fold(base.clone(), |t, e| apply(&t, e));
        if let Err(why) = check(command, &text, "mutant") {
            panic!("{}", fail(name, command, &text, &why));
        }
        runs += 1;
    }
    assert!(runs >= 20, "only {runs} runs in {seconds} s");
    eprintln!("cli_fuzz: {runs} mutated inputs in {seconds} s, none failed");
}
