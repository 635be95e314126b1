//! Every failure mode of the input paths: exit status, and a message that names the culprit.
//! (Case-file field errors are in cli/solve.rs and cli/fit.rs, CSV cell errors in
//! ricsac_loader.rs; this file covers the rest.)
use crate::common;
use common::*;

fn scratch(name: &str, content: &[u8]) -> String {
    scratch_file("cli_robustness", name, content)
}

fn err(o: &std::process::Output) -> String {
    stderr(o)
}

fn ricsac() -> String {
    std::fs::read_to_string(repo().join("data/ricsac.csv")).unwrap()
}

#[test]
fn huge_files_are_refused_by_size() {
    let big = vec![b'#'; 2 << 20];
    let path = scratch("huge.toml", &big);
    let out = pim(&["solve", &path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        err(&out).contains(&path) && err(&out).contains("larger than the 1048576 bytes"),
        "{}",
        err(&out)
    );
    let mut csv = ricsac().into_bytes();
    csv.resize(17 << 20, b'\n');
    let path = scratch("huge.csv", &csv);
    let out = pim(&["batch", &path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        err(&out).contains("larger than the 16777216 bytes"),
        "{}",
        err(&out)
    );
}

#[test]
fn batch_data_file_problems_name_file_line_and_column() {
    let good = ricsac();
    let swapped = good.replacen(
        "mass1_kg,yaw_inertia1_kgm2",
        "yaw_inertia1_kgm2,mass1_kg",
        1,
    );
    let mut lines: Vec<&str> = good.lines().collect();
    let dup_line = lines[2].replacen("3,", "1,", 1);
    lines[2] = &dup_line;
    let dup = lines.join("\n");
    let bad_cell = good.replacen("2096", "heavy", 1);
    let not_utf8 = [good.as_bytes(), &[0xff, 0xfe, b'\n']].concat();
    for (name, content, needle) in [
        (
            "order.csv",
            swapped.into_bytes(),
            ":1: column 5 is `yaw_inertia1_kgm2`, expected `mass1_kg`",
        ),
        (
            "dup.csv",
            dup.into_bytes(),
            ":3: column 1 `test`: test 1 appears twice (lines 2 and 3)",
        ),
        (
            "cell.csv",
            bad_cell.into_bytes(),
            ":2: column 5 `mass1_kg`: expected a number (got `heavy`)",
        ),
        ("empty.csv", Vec::new(), "the file is empty"),
        ("binary.csv", not_utf8, "is not UTF-8"),
    ] {
        let path = scratch(name, &content);
        let out = pim(&["batch", &path]);
        assert_eq!(out.status.code(), Some(2), "{name}: {}", err(&out));
        assert!(
            err(&out).contains(&path) && err(&out).contains(needle),
            "{name}: {}",
            err(&out)
        );
        assert!(out.stdout.is_empty(), "{name}");
    }
    let out = pim(&["batch", "data"]);
    assert_eq!(out.status.code(), Some(2));
    // A directory is a directory of case files; this one has none.
    assert!(err(&out).contains("data: no .toml case files in this directory"));
}

#[test]
fn implausible_values_are_input_errors() {
    let case =
        std::fs::read_to_string(repo().join("examples/cases/ricsac7_brach1983.toml")).unwrap();
    for (name, text, needle) in [
        (
            "mass.toml",
            case.replace("mass = 1955.0", "mass = 1e308"),
            "vehicle1.mass: must be a number between 100 and 1000000 kg, got 1e308",
        ),
        (
            "speed.toml",
            case.replace("vx = -13.01", "vx = -1e9"),
            "initial.vehicle1.vx: must be a number between -100 and 100 m/s, got -1e9",
        ),
        (
            "d.toml",
            case.replace("d = 0.9", "d = 5e3"),
            "vehicle2.d: must be a number between 0 and 30 m, got 5000",
        ),
    ] {
        let path = scratch(name, text.as_bytes());
        let out = pim(&["solve", &path]);
        assert_eq!(out.status.code(), Some(2), "{name}: {}", err(&out));
        let line = text
            .lines()
            .position(|l| l.contains("1e308") || l.contains("-1e9") || l.contains("5e3"))
            .unwrap()
            + 1;
        assert!(
            err(&out).contains(&format!(":{line}:")) && err(&out).contains(needle),
            "{name}: {}",
            err(&out)
        );
    }
}

#[test]
fn bounds_that_make_the_fit_infeasible_are_an_explained_outcome() {
    let case = std::fs::read_to_string(repo().join("examples/cases/ricsac7_fit.toml"))
        .unwrap()
        .replacen("velocity = 20.0", "velocity = 5.0", 1);
    assert!(case.contains("velocity = 5.0"));
    let path = scratch("tight.toml", case.as_bytes());
    let out = pim(&["fit", &path, "--cost", "q2", "--format", "json"]);
    assert_eq!(out.status.code(), Some(3), "{}", err(&out));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for b in j["branches"].as_array().unwrap() {
        assert_eq!(b["status"], "infeasible");
        assert!(
            b["reason"].as_str().unwrap().contains("|v| <= 5 m/s"),
            "{}",
            b["reason"]
        );
    }
}

#[test]
fn separation_velocities_with_reversed_sliding_under_q1_are_explained() {
    // Separation velocities of an impact whose friction (mu = 2.5) exceeds mu_max (1.29), so the
    // tangential relative velocity has reversed. Held fixed (Q1), no admissible contact state
    // within the default bounds produces them; the reason names what fails.
    let solve = std::fs::read_to_string(repo().join("examples/cases/ricsac7_brach1983.toml"))
        .unwrap()
        .replace("mu = 0.968", "mu = 2.5")
        .replace("em = -0.774", "em = 1.0")
        .replace("e = 0.015", "e = 0.1");
    let path = scratch("reversed_solve.toml", solve.as_bytes());
    let j: serde_json::Value =
        serde_json::from_slice(&pim(&["solve", &path, "--format", "json"]).stdout).unwrap();
    assert_eq!(j["tangential"], "reversed");
    assert_eq!(j["admissible"], false);
    let f = &j["final"];
    let fmt = |v: &serde_json::Value| {
        format!(
            "{{ vx = {}, vy = {}, omega = {} }}",
            v["vx"], v["vy"], v["omega"]
        )
    };
    let fit = std::fs::read_to_string(repo().join("examples/cases/ricsac7_fit.toml")).unwrap();
    let start = fit.find("[estimates.final]").unwrap();
    let end = fit.find("[bounds]").unwrap();
    let fit = format!(
        "{}[estimates.final]\nvehicle1 = {}\nvehicle2 = {}\n\n{}",
        &fit[..start],
        fmt(&f["vehicle1"]),
        fmt(&f["vehicle2"]),
        &fit[end..]
    );
    let path = scratch("reversed_fit.toml", fit.as_bytes());
    let out = pim(&["fit", &path, "--cost", "q1", "--format", "json"]);
    assert_eq!(out.status.code(), Some(3), "{}", err(&out));
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for b in j["branches"].as_array().unwrap() {
        assert_eq!(b["status"], "infeasible");
        let reason = b["reason"].as_str().unwrap();
        assert!(
            reason.contains("no coefficients in the box") && reason.contains('%'),
            "{reason}"
        );
    }
}

#[test]
fn the_same_input_gives_the_same_bytes() {
    for args in [
        vec![
            "solve",
            "examples/cases/ricsac7_brach1983.toml",
            "--format",
            "json",
        ],
        vec![
            "sensitivity",
            "examples/cases/ricsac7_brach1983.toml",
            "--format",
            "json",
        ],
        vec![
            "fit",
            "examples/cases/ricsac7_fit.toml",
            "--cost",
            "q3",
            "--format",
            "json",
        ],
        vec!["fit", "examples/cases/ricsac7_fit.toml", "--cost", "q3"],
    ] {
        let a = pim(&args);
        let b = pim(&args);
        assert!(!a.stdout.is_empty());
        assert!(a.stdout == b.stdout, "{args:?} differs between runs");
    }
}

#[test]
fn top_level_help_teaches_and_exit_codes_are_documented() {
    let out = pim(&["--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "batch",
        "compare-costs",
        "fit",
        "solve",
        "sensitivity",
        "EXIT STATUS",
        "pim: <file>",
    ] {
        assert!(text.contains(needle), "{needle}");
    }
    let out = pim(&["frobnicate"]);
    assert_eq!(out.status.code(), Some(2));
    let out = pim(&[]);
    assert_eq!(out.status.code(), Some(2));
}

/// `--out` failures name the folder given (and the part of it that failed), never the staging
/// folder pim writes beside it.
#[test]
fn out_errors_name_the_folder_given() {
    let dir = scratch_dir("robustness", "out_under_a_file");
    let file = dir.join("a_file");
    std::fs::write(&file, "not a folder").unwrap();
    let given = file.join("results");
    let g = given.display().to_string();
    for args in [
        vec!["solve", "examples/cases/side_impact.toml", "--out", &g],
        vec!["batch", "examples/cases/ricsac7_fit.toml", "--out", &g],
        vec!["batch", "data/ricsac.csv", "--tests", "7", "--out", &g],
    ] {
        let out = pim(&args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(4), "{args:?}: {err}");
        assert!(
            err.starts_with(&format!("pim: {g}: cannot create the folder")),
            "{err}"
        );
        assert!(err.contains("is a file"), "{err}");
        assert!(!err.contains(".pim-"), "a staging path: {err}");
    }
}
