//! The last careless inputs: a batch read by a reader that stops early (`| head`) ends quietly,
//! and a key nested beyond the parser's limit is located by its line.
use crate::common;
use common::*;
use std::io::{BufRead, BufReader};
use std::process::{Command, Stdio};

/// `pim batch DIR --format csv | head` over 1,200 records: the batch ends when its reader
/// does, with status 0 and no "Broken pipe".
#[test]
fn a_batch_whose_reader_stops_ends_quietly() {
    let dir = scratch_dir("careless", "many");
    let text = std::fs::read_to_string(repo().join("examples/cases/ricsac7_fit.toml")).unwrap();
    for i in 0..600 {
        std::fs::write(dir.join(format!("case{i:04}.toml")), &text).unwrap();
    }
    for format in ["csv", "json"] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_pim"))
            .args([
                "batch",
                dir.to_str().unwrap(),
                "--cost",
                "q2",
                "--format",
                format,
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        {
            let out = child.stdout.take().unwrap();
            let mut lines = BufReader::new(out).lines();
            for _ in 0..10 {
                lines.next().unwrap().unwrap();
            }
            // The reader stops here (as `head` does) and closes the pipe.
        }
        let out = child.wait_with_output().unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(0), "{format}: {err}");
        assert!(!err.contains("Broken pipe"), "{format}: {err}");
    }
}

/// A dotted key nested three hundred deep: the parser gives no place; the message names the
/// line.
#[test]
fn a_key_nested_too_deeply_is_located() {
    let key = vec!["a"; 300].join(".");
    let case = scratch_file(
        "careless",
        "deep.toml",
        format!("title = \"deep\"\n# a comment\n{key} = 1\n"),
    );
    let out = pim(&["fit", &case]);
    assert_eq!(out.status.code(), Some(2));
    let err = stderr(&out);
    assert!(err.contains("deep.toml:3:1: "), "{err}");
    assert!(err.contains("nested too deeply"), "{err}");
}

/// Both CGs on one side of the crush surface, and a heavy vehicle 1 whose mobility reading
/// puts it on +n: the estimated contact velocities approach only with vehicle 1 on -n, so the
/// side is read from them (basis `velocities`, said in a warning). Without estimates mobility
/// decides (`solve.rs`).
#[test]
fn the_ambiguous_side_is_read_from_the_estimates() {
    let base = r#"
[vehicle1]
mass = 8000.0
yaw_inertia = 9000.0
heading = 0.0
impact_point = { x = 2.0, y = 0.0 }
[vehicle2]
mass = 1500.0
yaw_inertia = 2500.0
heading = 90.0
impact_point = { x = 2.0, y = -0.5 }
[impact]
crush_angle = 0.0
"#;
    let fit = format!(
        "{base}[estimates.initial]\n\
         vehicle1 = {{ vx = 15.0, vy = 0.0, omega = 0.0 }}\n\
         vehicle2 = {{ vx = 0.0, vy = 10.0, omega = 0.0 }}\n\
         [estimates.final]\n\
         vehicle1 = {{ vx = 12.0, vy = 1.0, omega = 0.0 }}\n\
         vehicle2 = {{ vx = 12.0, vy = 6.0, omega = 0.0 }}\n"
    );
    let path = scratch_file("careless", "side_velocities.toml", &fit);
    let out = pim(&["fit", &path, "--cost", "q3", "--format", "json"]);
    let err = stderr(&out);
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["side"]["basis"], "velocities", "{err}");
    assert_eq!(v["side"]["vehicle1"], "-n", "{err}");
    assert!(
        err.contains("read from the estimated contact velocities"),
        "{err}"
    );
    assert!(err.contains("vehicle1_side = \"+n\""), "{err}");
}
