//! `pim set`: a value changed in place with the rest of the file as the user wrote it; a value
//! the case refuses leaves the file untouched with the message every command gives.
use crate::common;
use common::*;

fn example() -> String {
    std::fs::read_to_string(repo().join("examples/cases/reconstruction_us.toml")).unwrap()
}

#[test]
fn set_changes_the_named_values_and_nothing_else() {
    let text = example();
    let f = scratch_file("set", "edited.toml", &text);
    let out = pim_ok(&[
        "set",
        &f,
        "scene.vehicle1.rest.x=12.0",
        "runout.vehicle1.wheels.front_right=locked",
    ]);
    let err = stderr(&out);
    assert!(
        err.contains("scene.vehicle1.rest.x = 12.0 (was 11.9)"),
        "{err}"
    );
    let edited = std::fs::read_to_string(&f).unwrap();
    let changed: Vec<(&str, &str)> = text
        .lines()
        .zip(edited.lines())
        .filter(|(a, b)| a != b)
        .collect();
    assert_eq!(text.lines().count(), edited.lines().count());
    assert_eq!(changed.len(), 2, "{changed:#?}");
    // [runout] comes before [scene] in the file.
    assert!(
        changed[0].1.contains("front_right = \"locked\""),
        "{changed:#?}"
    );
    assert!(
        changed[1]
            .1
            .starts_with("rest = { x = 12.0, y = 2.9, heading = 144.0 }     # ft"),
        "{changed:#?}"
    );
    // The edited file is a case every command reads.
    pim_ok(&["fit", &f, "--format", "json"]);
}

#[test]
fn dry_run_prints_and_a_refused_value_leaves_the_file() {
    let text = example();
    let f = scratch_file("set", "kept.toml", &text);
    let out = pim_ok(&["set", &f, "observations.0.sigma=2.5", "--dry-run"]);
    let printed = String::from_utf8(out.stdout).unwrap();
    assert!(
        printed.contains("sigma = 2.5                         # mph"),
        "{printed}"
    );
    assert_eq!(std::fs::read_to_string(&f).unwrap(), text);

    let out = pim(&["set", &f, "vehicle1.mass=-5"]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(
        err.contains("vehicle1.mass") && err.contains("kept.toml:"),
        "{err}"
    );
    assert_eq!(
        std::fs::read_to_string(&f).unwrap(),
        text,
        "the file is left as it was"
    );

    let out = pim(&["set", &f, "observations.9.sigma=1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("has 2"), "{}", stderr(&out));
    let out = pim(&["set", &f, "mass"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("KEY=VALUE"), "{}", stderr(&out));
    assert_eq!(std::fs::read_to_string(&f).unwrap(), text);
}

/// The values `pim set` once wrote and `pim fit` then refused (exit 0 then 2): each refused now
/// with `pim fit`'s own message, located at the key, and the file left as it was.
#[test]
fn every_value_pim_fit_refuses_is_refused_before_writing() {
    let text = example();
    let f = scratch_file("set", "refused.toml", &text);
    for (kv, at) in [
        (
            "observations.0.sigma=-1",
            "observation \"sedan tracking\": sigma",
        ),
        (
            "observations.0.sigma=0",
            "observation \"sedan tracking\": sigma",
        ),
        ("pre_impact.vehicle1.skid=-42", "pre_impact.vehicle1.skid"),
        ("runout.vehicle1.wheelbase=-5", "runout.vehicle1.wheelbase"),
        (
            "pre_impact.vehicle1.braking=7",
            "pre_impact.vehicle1.braking",
        ),
        ("runout.vehicle2.wheels=flying", "runout.vehicle2.wheels"),
        ("runout.friction=-1", "runout.friction"),
        ("runout.friction=0", "runout.friction"),
        ("runout.friction=5", "runout.friction"),
        ("runout.friction=1e-320", "runout.friction"),
        (
            "scene.vehicle1.rest.heading=1e9",
            "scene.vehicle1.rest.heading",
        ),
        ("runout.vehicle1.braking=7", "runout.vehicle1"),
        (
            "scene.vehicle1.rest_sigma.x=-1",
            "scene.vehicle1.rest_sigma.x",
        ),
        (
            "pre_impact.vehicle2.edr.0.sigma=0",
            "pre_impact.vehicle2.edr[0]",
        ),
    ] {
        let out = pim(&["set", &f, kv]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{kv}: {err}");
        assert!(err.contains("refused.toml:"), "{kv}: {err}");
        assert!(err.contains(at), "{kv}: {err}");
        assert_eq!(std::fs::read_to_string(&f).unwrap(), text, "{kv}");
        // `pim fit` of the value gives the same message.
        let (k, v) = kv.split_once('=').unwrap();
        let mut e = pim_case::edit::CaseEdit::new("x", &text).unwrap();
        let value = v
            .parse::<f64>()
            .map_or(pim_case::edit::NewValue::Text(v.into()), |x| {
                pim_case::edit::NewValue::Written(x)
            });
        e.set(k, value).unwrap();
        let g = scratch_file("set", "refused-fit.toml", e.text());
        let fit = pim(&["fit", &g]);
        assert_eq!(fit.status.code(), Some(2), "{kv}");
        let message = |s: &str| s.split_once(".toml:").map(|(_, m)| m.to_string());
        assert_eq!(message(&stderr(&fit)), message(&err), "{kv}");
    }
    // A count of turns typed as a whole number is written as one, and read.
    pim_ok(&["set", &f, "scene.vehicle1.turns=0"]);
    assert!(std::fs::read_to_string(&f).unwrap().contains("turns = 0\n"));
}

#[test]
fn if_version_writes_only_over_the_version_named() {
    let text = example();
    let f = scratch_file("set", "versioned.toml", &text);
    let out = pim_ok(&["set", &f, "--print-version"]);
    let v = String::from_utf8(out.stdout).unwrap().trim().to_string();
    assert_eq!(v.len(), 64, "{v}");
    // Another editor changes the file: the version no longer names it.
    std::fs::write(&f, text.replace("friction = 0.72", "friction = 0.65")).unwrap();
    let out = pim(&["set", &f, "vehicle1.mass=3500", "--if-version", &v]);
    assert_eq!(out.status.code(), Some(4), "{}", stderr(&out));
    assert!(stderr(&out).contains("changed on disk"), "{}", stderr(&out));
    let now = std::fs::read_to_string(&f).unwrap();
    assert!(now.contains("friction = 0.65") && now.contains("mass = 3400.0"));
    // With the version of the file as it is now, it goes through.
    let v = String::from_utf8(pim_ok(&["set", &f, "--print-version"]).stdout).unwrap();
    pim_ok(&[
        "set",
        &f,
        "vehicle1.mass=3500",
        "--if-version",
        &v.trim()[..12],
    ]);
    assert!(std::fs::read_to_string(&f)
        .unwrap()
        .contains("mass = 3500.0"));
}

/// Two `pim set` loops on one file, each setting its own value: every run exits 0 and the
/// file ends with both last values (no update lost, no false "cannot write").
#[test]
fn two_set_loops_on_one_file_lose_nothing() {
    let f = scratch_file("set", "two-loops.toml", example());
    let runs = 25;
    let loops: Vec<_> = ["vehicle1.mass", "vehicle2.mass"]
        .into_iter()
        .map(|key| {
            let f = f.clone();
            std::thread::spawn(move || {
                for i in 0..runs {
                    let out = pim(&["set", &f, &format!("{key}={}", 3000 + i)]);
                    assert!(out.status.success(), "{key} {i}: {}", stderr(&out));
                }
            })
        })
        .collect();
    for l in loops {
        l.join().unwrap();
    }
    let e = pim_case::edit::CaseEdit::new("x", &std::fs::read_to_string(&f).unwrap()).unwrap();
    let last = format!("{}.0", 3000 + runs - 1);
    assert_eq!(e.get("vehicle1.mass").unwrap(), last);
    assert_eq!(e.get("vehicle2.mass").unwrap(), last);
    let dir = std::path::Path::new(&f).parent().unwrap();
    let left: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".two-loops.toml.") && n.ends_with(".pim-tmp"))
        .collect();
    assert!(left.is_empty(), "{left:?}");
}

/// The temporaries of `f` beside it (a writer killed between writing and renaming leaves one).
fn temporaries(f: &str) -> Vec<String> {
    let p = std::path::Path::new(f);
    let prefix = format!(".{}.", p.file_name().unwrap().to_string_lossy());
    std::fs::read_dir(p.parent().unwrap())
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(&prefix) && n.ends_with(".pim-tmp"))
        .collect()
}

/// `pim set` killed (SIGKILL) at every moment of its run, 40 times from 0.25 ms to 370 ms: the file is always the
/// old version or the new one, whole.
#[test]
fn a_set_killed_at_any_moment_leaves_the_old_file_or_the_new() {
    let old = example();
    let f = scratch_file("set", "killed.toml", &old);
    let new_of = |before: &str, i: u32| {
        let mut e = pim_case::edit::CaseEdit::new("x", before).unwrap();
        e.set(
            "vehicle1.mass",
            pim_case::edit::NewValue::Written(f64::from(3000 + i)),
        )
        .unwrap();
        e.text()
    };
    let mut seen_new = 0;
    for i in 0..40u32 {
        let before = std::fs::read_to_string(&f).unwrap();
        let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_pim"))
            .args(["set", &f, &format!("vehicle1.mass={}", 3000 + i)])
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        // Killed from at once (0.25 ms) to well after its usual end (about 370 ms), in steps
        // growing by a fifth, so that a machine slowed by other work still sees both ends.
        let wait = 250.0 * 1.2f64.powi(i32::try_from(i).unwrap());
        std::thread::sleep(std::time::Duration::from_micros(wait as u64));
        let _ = child.kill();
        let _ = child.wait();
        let after = std::fs::read_to_string(&f).unwrap();
        if after == new_of(&before, i) {
            seen_new += 1;
        } else {
            assert_eq!(after, before, "round {i}: neither the old file nor the new");
        }
    }
    // The test kills some runs before and lets some end after their write.
    assert!(
        seen_new > 0,
        "no run wrote before its kill: the kill came too early every time"
    );
    // What a killed run left beside the file, the next write removes.
    pim_ok(&["set", &f, "vehicle1.mass=3400"]);
    assert!(temporaries(&f).is_empty(), "{:?}", temporaries(&f));
}

/// `pim survey`: the CSV placed from its origin point in the case's feet, written as
/// `[survey]` with every other byte kept; evidence then named on a point must lie on it; a bad
/// line is refused at the CSV's line with the file untouched (exit 2).
#[test]
fn a_survey_is_imported_and_evidence_on_its_points_checked() {
    let text = example();
    let f = scratch_file("survey", "surveyed.toml", &text);
    let csv = repo().join("examples/scene/intersection_survey.csv");
    let csv = csv.to_str().unwrap();
    let out = pim_ok(&["survey", &f, csv, "--unit", "ft", "--origin", "POI"]);
    assert!(
        stderr(&out).contains("[survey] of 5 points"),
        "{}",
        stderr(&out)
    );
    let written = std::fs::read_to_string(&f).unwrap();
    assert!(written.starts_with(text.trim_end()));
    assert!(written.contains(
        "  { id = \"R1\", x = 11.9, y = 2.9, code = \"REST\", description = \"sedan at rest (CG)\" },\n"
    ));
    // The sedan's rest is R1: named, it reads; moved off it, it is refused at its line.
    pim_ok(&["set", &f, "scene.vehicle1.rest.point=R1"]);
    let off = pim(&["set", &f, "scene.vehicle1.rest.x=12.5"]);
    assert_eq!(off.status.code(), Some(2));
    assert!(
        stderr(&off).contains(
            "scene.vehicle1.rest.point: survey point \"R1\" is at (11.9, 2.9), this at (12.5, 2.9)"
        ),
        "{}",
        stderr(&off)
    );
    let before = std::fs::read_to_string(&f).unwrap();
    let bad = scratch_file("survey", "bad.csv", "id,x,y\nA,1,2\nB,one,2\n");
    let out = pim(&["survey", &f, &bad]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("bad.csv:3: x: expected a number, got \"one\""),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read_to_string(&f).unwrap(), before);
    // A survey imported again that drops the point in use is refused, naming the evidence.
    let fewer = scratch_file("survey", "fewer.csv", "id,x,y\nPOI,1000,2000\n");
    let out = pim(&["survey", &f, &fewer, "--origin", "POI"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("\"R1\": [survey] has no such point"),
        "{}",
        stderr(&out)
    );
    assert_eq!(std::fs::read_to_string(&f).unwrap(), before);
}
