//! Every command: a closed standard output is an error, Ctrl-C is said and exits 130.
use crate::common;
use common::*;
use std::process::{Command, Stdio};

#[test]
fn a_closed_stdout_is_exit_status_4_with_a_message() {
    let data = repo().join("data/ricsac.csv");
    let out_dir = scratch_dir("signals", "closed");
    let script = format!(
        "exec \"$0\" batch '{}' --out '{}' >&-",
        data.display(),
        out_dir.display()
    );
    let out = Command::new("sh")
        .args(["-c", &script, env!("CARGO_BIN_EXE_pim")])
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(4), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("standard output is closed"),
        "{}",
        stderr(&out)
    );
    // A failing one (a full device) too.
    let case = repo().join("examples/cases/side_impact.toml");
    let out = Command::new(env!("CARGO_BIN_EXE_pim"))
        .args(["solve", &case.display().to_string()])
        .stdout(
            std::fs::OpenOptions::new()
                .write(true)
                .open("/dev/full")
                .unwrap(),
        )
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(4), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("cannot write to stdout"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn ctrl_c_says_interrupted_and_exits_130() {
    let case = repo().join("examples/cases/reconstruction_us.toml");
    let child = Command::new(env!("CARGO_BIN_EXE_pim"))
        .args([
            "uncertainty",
            &case.display().to_string(),
            "--draws",
            "100000",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(500));
    let sent = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(130), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("pim: interrupted"),
        "{}",
        stderr(&out)
    );
}
