//! Hostile and careless input, by class: every run ends within its time limit, with exit status
//! 2 and one message that names the file and field; none crashes, hangs or answers with exit 0.
use crate::common;
use common::*;

const LIMIT: u64 = 20;

/// Exit status 2 and a message containing every `words`.
fn refused(args: &[&str], words: &[&str]) {
    let out = pim_within(args, LIMIT);
    let msg = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "pim {}: {msg}", args.join(" "));
    for w in words {
        assert!(
            msg.contains(w),
            "pim {}: {msg:?} lacks {w:?}",
            args.join(" ")
        );
    }
    assert!(!msg.contains("panicked"), "{msg}");
}

#[test]
fn devices_and_pipes_are_refused_before_they_are_read() {
    for dev in ["/dev/zero", "/dev/null", "/dev/urandom"] {
        refused(&["solve", dev], &[dev, "not a regular file"]);
        refused(&["batch", dev], &[dev, "not a regular file"]);
        refused(
            &["draw", dev, "-o", "/dev/null"],
            &[dev, "not a regular file"],
        );
    }
    let dir = scratch_dir("hostile", "fifo");
    let fifo = dir.join("case.toml");
    let made = std::process::Command::new("mkfifo").arg(&fifo).status();
    if made.is_ok_and(|s| s.success()) {
        let f = fifo.display().to_string();
        refused(&["solve", &f], &[&f, "not a regular file"]);
        refused(&["uncertainty", &f], &[&f, "not a regular file"]);
    }
}

#[test]
fn unbounded_draws_and_threads_are_refused_with_the_range() {
    let case = "examples/cases/ricsac7_uncertainty.toml";
    for n in ["1000000000", "18446744073709551615", "0", "-5", "1e9"] {
        let arg = format!("--draws={n}");
        refused(&["uncertainty", case, &arg], &["--draws", "1 to 1000000"]);
    }
    for n in ["1000000000", "18446744073709551615", "1e9"] {
        refused(
            &["batch", "examples/cases", "--draws", n],
            &["--draws", "0 to 1000000"],
        );
    }
    for n in ["100000", "0", "257"] {
        refused(
            &["batch", "--threads", n],
            &["--threads", "1 to 256", "cores"],
        );
        refused(
            &["uncertainty", case, "--threads", n],
            &["--threads", "1 to 256"],
        );
    }
}

#[test]
fn non_finite_and_impossible_drawing_dimensions_are_refused() {
    let text = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml")).unwrap();
    for field in ["length", "width", "cg_to_front"] {
        for bad in ["inf", "-inf", "nan", "-3.0", "0.0", "1e300"] {
            let line = text
                .lines()
                .find(|l| l.starts_with(&format!("{field} =")))
                .unwrap();
            let case = text.replacen(line, &format!("{field} = {bad}"), 1);
            let path = scratch_file("hostile", &format!("{field}_{bad}.toml"), &case);
            for cmd in [
                vec!["draw", path.as_str(), "-o", "/dev/null"],
                vec!["solve", path.as_str()],
            ] {
                refused(&cmd, &[&path, &format!(": vehicle1.{field}: ")]);
            }
        }
    }
    // A CG outside the vehicle.
    let case = text.replacen("cg_to_front = 2.0", "cg_to_front = 9.0", 1);
    let path = scratch_file("hostile", "cg_outside.toml", &case);
    refused(
        &["draw", &path, "-o", "/dev/null"],
        &["cg_to_front", "length"],
    );
}

#[test]
fn data_rows_outside_their_physical_range_are_refused() {
    let good = std::fs::read_to_string(repo().join("data/ricsac.csv")).unwrap();
    let header: Vec<&str> = good.lines().next().unwrap().split(',').collect();
    let row: Vec<&str> = good.lines().nth(1).unwrap().split(',').collect();
    for (column, value, range) in [
        ("mass1_kg", "1e-300", "between 100 and 1000000 kg"),
        ("yaw_inertia2_kgm2", "-5", "between 10 and 250000000 kg m^2"),
        ("vi1x_mps", "1e308", "between -100 and 100 m/s"),
        ("wf2_radps", "90", "between -15 and 15 rad/s"),
        ("heading1_deg", "3.6e17", "between -360 and 360 deg"),
        ("d2_m", "-1", "between 0 and 30 m"),
        ("dv1_measured_mps", "-3", "between 0 and 100 m/s"),
    ] {
        let k = header.iter().position(|h| *h == column).unwrap();
        let mut bad = row.clone();
        bad[k] = value;
        let text = good.replacen(&row.join(","), &bad.join(","), 1);
        let path = scratch_file("hostile", &format!("{column}.csv"), &text);
        for cmd in ["batch", "predict-dv"] {
            refused(&[cmd, &path], &[&path, ":2:", column, range]);
        }
    }
}

#[test]
fn control_characters_in_free_text_reach_no_output_raw() {
    let text = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml")).unwrap();
    let case = text
        .replace(
            "title = \"Side impact, SI units\"",
            "title = \"Side \\u001b[31mimpact\\u0007\"",
        )
        .replace(
            "description = \"striking car\"",
            "description = \"striking \\u0001car\"",
        );
    let path = scratch_file("hostile", "control.toml", &case);
    let dir = scratch_dir("hostile", "control_out");
    let out_dir = dir.join("out").display().to_string();
    let out = pim_within(&["solve", &path, "--out", &out_dir], LIMIT);
    assert!(out.status.success(), "{}", stderr(&out));
    let raw = |b: &[u8]| {
        b.iter()
            .any(|&c| c < 0x20 && c != b'\n' && c != b'\t' && c != b'\r')
    };
    assert!(!raw(&out.stdout), "a control character on the terminal");
    for f in ["diagram.svg", "report.md", "result.json"] {
        let bytes = std::fs::read(dir.join("out").join(f)).unwrap();
        assert!(!raw(&bytes), "{f} holds a raw control character");
    }
    let table = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(table.contains("\\u{1b}[31mimpact"), "{table}");
}

#[test]
fn an_output_folder_is_replaced_as_a_whole_and_never_a_users_folder() {
    let dir = scratch_dir("hostile", "outdir");
    let out = dir.join("results");
    let o = out.display().to_string();
    let run = |args: &[&str]| pim_within(args, LIMIT);
    let first = run(&["predict-dv", "--out", &o]);
    assert!(first.status.success(), "{}", stderr(&first));
    std::fs::write(out.join("stale.txt"), "from an earlier, different run").unwrap();
    // A second run replaces the folder as a whole: the stale file does not survive beside the
    // new results.
    let second = run(&["solve", "examples/cases/side_impact.toml", "--out", &o]);
    assert!(second.status.success(), "{}", stderr(&second));
    let names: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(
        !names
            .iter()
            .any(|n| n == "stale.txt" || n.starts_with("predict")),
        "{names:?}"
    );
    assert!(names.iter().any(|n| n == "result.json"), "{names:?}");
    // A run that fails on its input leaves the folder as it was.
    let before = std::fs::read(out.join("result.json")).unwrap();
    let bad = run(&["solve", "/dev/null", "--out", &o]);
    assert_eq!(bad.status.code(), Some(2));
    assert_eq!(std::fs::read(out.join("result.json")).unwrap(), before);
    // A folder that pim did not write is never replaced.
    let mine = dir.join("mine");
    std::fs::create_dir_all(&mine).unwrap();
    std::fs::write(mine.join("thesis.tex"), "years of work").unwrap();
    let m = mine.display().to_string();
    let refused = run(&["solve", "examples/cases/side_impact.toml", "--out", &m]);
    assert_eq!(refused.status.code(), Some(4), "{}", stderr(&refused));
    assert!(
        stderr(&refused).contains("did not write"),
        "{}",
        stderr(&refused)
    );
    assert_eq!(
        std::fs::read_to_string(mine.join("thesis.tex")).unwrap(),
        "years of work"
    );
    // No staging folder is left behind.
    let left: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with('.'))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// A folder batch goes on past an entry it cannot open (a link that leads nowhere or in a loop,
/// a FIFO): each is a failed record naming the entry and why, like a file that does not parse;
/// the other files are fitted and the run exits 0. A batch in which no entry could be read or
/// fitted exits 2. Extensions are matched in any case; a data file among case files is named.
#[test]
fn a_directory_batch_names_entries_it_cannot_open_and_goes_on() {
    let dir = scratch_dir("hostile", "links");
    std::fs::copy(
        repo().join("examples/cases/ricsac7_fit.toml"),
        dir.join("a.toml"),
    )
    .unwrap();
    std::fs::copy(
        repo().join("examples/cases/ricsac7_fit.toml"),
        dir.join("B.TOML"),
    )
    .unwrap();
    let d = dir.display().to_string();
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink("nowhere.toml", dir.join("dangling.toml")).unwrap();
        std::os::unix::fs::symlink("loop2.toml", dir.join("loop1.toml")).unwrap();
        std::os::unix::fs::symlink("loop1.toml", dir.join("loop2.toml")).unwrap();
        let fifo = dir.join("pipe.toml");
        let fifo_made = std::process::Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .is_ok_and(|s| s.success());
        let out = pim(&["batch", &d, "--format", "json"]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(0), "{err}");
        for (name, why) in [
            ("dangling.toml", "leads nowhere"),
            ("loop1.toml", "fix or remove it"),
            ("loop2.toml", "fix or remove it"),
        ] {
            assert!(err.contains(name) && err.contains(why), "{name}: {err}");
        }
        if fifo_made {
            assert!(
                err.contains("pipe.toml") && err.contains("not a regular file"),
                "{err}"
            );
        }
        let records: Vec<serde_json::Value> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(|l| serde_json::from_str(l).unwrap())
            .collect();
        let of = |f: &str| -> Vec<&serde_json::Value> {
            records
                .iter()
                .filter(|r| r["file"].as_str().unwrap().ends_with(f))
                .collect()
        };
        assert!(of("dangling.toml").iter().all(|r| r["outcome"] == "failed"));
        assert!(of("a.toml").iter().any(|r| r["outcome"] == "optimal"));
        assert!(
            of("B.TOML").iter().any(|r| r["outcome"] == "optimal"),
            "the capital extension"
        );
        // Nothing readable at all: exit 2.
        std::fs::remove_file(dir.join("a.toml")).unwrap();
        std::fs::remove_file(dir.join("B.TOML")).unwrap();
        let out = pim(&["batch", &d]);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert!(stderr(&out).contains("none of the"), "{}", stderr(&out));
    }
    // A data file among case files is named as such.
    refused(
        &[
            "batch",
            "examples/cases/ricsac7_fit.toml",
            "data/ricsac.csv",
        ],
        &["data/ricsac.csv", "a data file (CSV) among case files"],
    );
}

#[test]
fn bounds_spreads_and_sigmas_outside_their_domains_are_refused() {
    let base =
        std::fs::read_to_string(repo().join("examples/cases/ricsac7_uncertainty.toml")).unwrap();
    let with = |extra: &str| base.replacen("[bounds]\n", &format!("{extra}\n"), 1);
    let cases: [(&str, String, &[&str]); 6] = [
        (
            "three_values",
            with("[bounds]\ne = [0.0, 0.1, 0.2]"),
            &["bounds.e", "two numbers; got 3 values"],
        ),
        (
            "huge_crush_bounds",
            with("[bounds]\ncrush_angle = [-1e300, 1e300]"),
            &[": bounds.crush_angle: ", "-360 <= low <= high <= 360"],
        ),
        (
            "reversed_bounds",
            with("[bounds]\nmu = [0.9, 0.1]"),
            &["mu = [0.9, 0.1]", "low <= high"],
        ),
        (
            "huge_uniform",
            base.replace("uniform = [58.0, 62.0]", "uniform = [-1e308, 1e308]"),
            &["vehicle2.heading", "within -360 and 360 deg"],
        ),
        (
            "mass_sd",
            base.replace("mass = 50.0, d = 0.2", "mass = 5000.0, d = 0.2"),
            &["vehicle1.mass", "not smaller than the value"],
        ),
        (
            "tiny_sigma",
            base.replacen(
                "vehicle1 = { vx = 0.5, vy = 0.5, omega = 0.1 }",
                "vehicle1 = { vx = 1e-300, vy = 0.5, omega = 0.1 }",
                1,
            ),
            &[": sigma.initial.vehicle1.vx: 1e-300", "at least 0.000001"],
        ),
    ];
    for (name, text, words) in cases {
        assert_ne!(
            text, base,
            "{name}: the mistake was not written into the case"
        );
        let path = scratch_file("hostile", &format!("{name}.toml"), &text);
        let mut all = vec![path.as_str()];
        all.extend_from_slice(words);
        refused(&["uncertainty", &path, "--draws", "5"], &all);
    }
}

#[test]
#[cfg(unix)]
fn writing_to_a_device_leaves_the_device() {
    use std::os::unix::fs::FileTypeExt;
    let out = pim_within(
        &["draw", "examples/cases/side_impact.toml", "-o", "/dev/null"],
        LIMIT,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let t = std::fs::metadata("/dev/null").unwrap().file_type();
    assert!(t.is_char_device(), "/dev/null is no longer a device");
}

#[test]
fn sensitivity_out_writes_its_results() {
    let dir = scratch_dir("hostile", "sensitivity");
    let o = dir.join("out").display().to_string();
    let out = pim_within(
        &[
            "sensitivity",
            "examples/cases/ricsac7_brach1983.toml",
            "--percent",
            "10",
            "--out",
            &o,
        ],
        LIMIT,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("out/sensitivity.json")).unwrap()).unwrap();
    assert_eq!(json["combinations"].as_array().unwrap().len(), 8);
    assert_eq!(json["averages"].as_array().unwrap().len(), 6);
    let table = std::fs::read_to_string(dir.join("out/sensitivity.txt")).unwrap();
    assert_eq!(table, String::from_utf8_lossy(&out.stdout));
}

#[test]
fn weights_on_components_held_fixed_are_said_to_have_no_effect() {
    let case = "examples/cases/ricsac7_uncertainty.toml";
    let out = pim_within(&["fit", case, "--cost", "q1", "--format", "json"], LIMIT);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let notes: Vec<String> = j["notes"]
        .as_array()
        .unwrap()
        .iter()
        .map(|n| n.as_str().unwrap().to_string())
        .collect();
    assert!(
        notes
            .iter()
            .any(|n| n.contains("[sigma] of final.vehicle1.vx")
                && n.contains("cost q1 holds these components fixed")),
        "{notes:?}"
    );
    // Q3 holds nothing fixed: no such note.
    let out = pim_within(&["fit", case, "--cost", "q3", "--format", "json"], LIMIT);
    let j: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(
        !j["notes"].to_string().contains("no effect"),
        "{}",
        j["notes"]
    );
}

#[test]
fn a_full_disk_is_an_output_error_naming_the_file() {
    // /dev/full fails every write with "no space left on device", as a full disk does.
    if !std::path::Path::new("/dev/full").exists() {
        return;
    }
    let out = pim_within(
        &["draw", "examples/cases/side_impact.toml", "-o", "/dev/full"],
        20,
    );
    assert_eq!(out.status.code(), Some(4), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("/dev/full: cannot write: No space left on device"),
        "{}",
        stderr(&out)
    );
    // Standard output on a full disk: exit 4 with the reason, not a panic.
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_pim"))
        .args([
            "solve",
            "examples/cases/side_impact.toml",
            "--format",
            "json",
        ])
        .current_dir(repo())
        .stdout(std::fs::File::create("/dev/full").unwrap())
        .stderr(std::process::Stdio::piped())
        .output()
        .unwrap();
    assert_eq!(status.status.code(), Some(4));
    assert!(stderr(&status).contains("cannot write to stdout: No space left on device"));
}

#[test]
fn negative_numbers_for_flags_reach_their_check() {
    // A negative value is the flag's value, refused by its own check in the one message form,
    // not taken for an unknown flag.
    let case = "examples/cases/oblique_sae_us.toml";
    refused(
        &["uncertainty", case, "--draws", "-5"],
        &["pim: --draws: \"-5\" is not a whole number; --draws takes 1 to 1000000"],
    );
    refused(
        &["uncertainty", case, "--seed", "-1"],
        &["pim: --seed: \"-1\""],
    );
    refused(&["batch", "--threads", "-2"], &["pim: --threads: \"-2\""]);
    refused(
        &["predict-dv", "--e", "-0.5"],
        &["--e -0.5: must be in [0, 1]"],
    );
    refused(&["batch", "--e-max", "-1"], &["pim: --e-max -1"]);
}
