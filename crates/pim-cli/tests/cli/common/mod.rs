//! Helpers shared by the end-to-end tests: run the real `pim` binary from the repository root,
//! read its output, and write scratch files.
#![allow(dead_code)] // each module uses its own subset

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository root (the binary runs there, so paths like `data/ricsac.csv` work).
pub fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Runs `pim` with `args` from the repository root.
pub fn pim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_pim"))
        .args(args)
        .current_dir(repo())
        .output()
        .expect("run pim")
}

/// Runs `pim` and asserts that it succeeded (the message shows its stderr).
pub fn pim_ok(args: &[&str]) -> Output {
    let out = pim(args);
    assert!(
        out.status.success(),
        "pim {}: status {:?}, stderr {}",
        args.join(" "),
        out.status,
        stderr(&out)
    );
    out
}

/// The standard error of a run, as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).to_string()
}

/// A fresh, empty scratch directory `group/name` under the target's test directory.
pub fn scratch_dir(group: &str, name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join(group)
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `content` to `group/name` under the target's test directory; the path as text.
pub fn scratch_file(group: &str, name: &str, content: impl AsRef<[u8]>) -> String {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(group);
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    std::fs::write(&p, content).unwrap();
    p.display().to_string()
}

/// Runs `pim` with `args` and fails the test if it has not finished within `seconds` (a hang is
/// a defect, not a slow test): the process is killed and the test panics. Its output is read
/// while it runs, so that a large output cannot block it.
pub fn pim_within(args: &[&str], seconds: u64) -> Output {
    use std::io::Read;
    use std::process::Stdio;
    let mut child = Command::new(env!("CARGO_BIN_EXE_pim"))
        .args(args)
        .current_dir(repo())
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run pim");
    let drain = |mut r: Box<dyn Read + Send>| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            let _ = r.read_to_end(&mut buf);
            buf
        })
    };
    let out = drain(Box::new(child.stdout.take().expect("stdout")));
    let err = drain(Box::new(child.stderr.take().expect("stderr")));
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(seconds);
    loop {
        if let Some(status) = child.try_wait().expect("wait for pim") {
            return Output {
                status,
                stdout: out.join().expect("stdout reader"),
                stderr: err.join().expect("stderr reader"),
            };
        }
        if std::time::Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            panic!("pim {} did not finish within {seconds} s", args.join(" "));
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}
