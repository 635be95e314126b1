//! The case file on disk: never lost, never half written, never silently overwritten.

use pim_store::{StoreError, Version, WriteOptions, MAX_CASE_BYTES};
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;

fn example() -> String {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../examples/cases");
    std::fs::read_to_string(root.join("reconstruction_us.toml")).unwrap()
}

fn folder() -> tempfile::TempDir {
    tempfile::tempdir().unwrap()
}

fn case_in(dir: &Path) -> PathBuf {
    let p = dir.join("case.toml");
    std::fs::write(&p, example()).unwrap();
    p
}

/// The example with its sedan's mass set to `mass` lb (a valid case for every mass tried).
fn with_mass(text: &str, mass: u32) -> String {
    let mut e = pim_case::edit::CaseEdit::new("case.toml", text).unwrap();
    e.set(
        "vehicle1.mass",
        pim_case::edit::NewValue::Written(f64::from(mass)),
    )
    .unwrap();
    e.text()
}

fn mass_of(text: &str) -> f64 {
    let e = pim_case::edit::CaseEdit::new("case.toml", text).unwrap();
    e.get("vehicle1.mass").unwrap().parse().unwrap()
}

#[test]
fn a_write_over_the_version_read_replaces_the_file_and_gives_the_new_version() {
    let dir = folder();
    let p = case_in(dir.path());
    let read = pim_store::read(&p, MAX_CASE_BYTES).unwrap();
    assert_eq!(read.version, Version::of(&example()));
    let new = with_mass(&read.text, 3500);
    let options = WriteOptions {
        expected: Some(&read.version.0),
        ..Default::default()
    };
    let written = pim_store::write(&p, &new, &options).unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), new);
    assert_eq!(written.version, Version::of(&new));
    assert_ne!(written.version, read.version);
    // An abbreviated version (8 characters or more) names it too; fewer do not.
    assert!(written.version.matches(&written.version.0[..8]));
    assert!(!written.version.matches(&written.version.0[..7]));
    // Nothing is left beside it.
    let left: Vec<_> = std::fs::read_dir(dir.path()).unwrap().flatten().collect();
    assert_eq!(left.len(), 1, "{left:?}");
}

#[test]
fn a_write_over_an_older_version_is_refused_and_changes_nothing() {
    let dir = folder();
    let p = case_in(dir.path());
    let read = pim_store::read(&p, MAX_CASE_BYTES).unwrap();
    // Another editor changes the friction and appends a line.
    let outside = read.text.replace("friction = 0.72", "friction = 0.65") + "# checked\n";
    std::fs::write(&p, &outside).unwrap();
    let mine = with_mass(&read.text, 3500);
    let options = WriteOptions {
        expected: Some(&read.version.0),
        ..Default::default()
    };
    match pim_store::write(&p, &mine, &options) {
        Err(StoreError::Conflict { current, .. }) => {
            assert_eq!(current.text, outside);
            assert_eq!(current.version, Version::of(&outside));
        }
        other => panic!("expected a conflict, got {other:?}"),
    }
    assert_eq!(std::fs::read_to_string(&p).unwrap(), outside);
}

#[test]
fn a_text_pim_fit_refuses_is_not_written() {
    let dir = folder();
    let p = case_in(dir.path());
    for (from, to) in [
        ("friction = 0.72", "friction = 5.0"),
        ("wheelbase = 9.2", "wheelbase = -5.0"),
        ("skid = 42.0", "skid = -42.0"),
        ("wheels = \"rolling\"", "wheels = \"flying\""),
    ] {
        let bad = example().replacen(from, to, 1);
        assert_ne!(bad, example(), "{from}");
        let e = pim_store::write(&p, &bad, &WriteOptions::default()).unwrap_err();
        assert!(matches!(e, StoreError::Refused(_)), "{to}: {e}");
        assert!(e.to_string().contains("case.toml:"), "{e}");
        assert_eq!(std::fs::read_to_string(&p).unwrap(), example());
    }
}

#[test]
fn the_mode_is_kept_and_a_read_only_file_is_refused() {
    let dir = folder();
    let p = case_in(dir.path());
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o600)).unwrap();
    pim_store::write(&p, &with_mass(&example(), 3500), &WriteOptions::default()).unwrap();
    let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o7777;
    assert_eq!(mode, 0o600);
    std::fs::set_permissions(&p, std::fs::Permissions::from_mode(0o444)).unwrap();
    let e =
        pim_store::write(&p, &with_mass(&example(), 3600), &WriteOptions::default()).unwrap_err();
    assert!(e.to_string().contains("read-only (mode 0444)"), "{e}");
    assert!((mass_of(&std::fs::read_to_string(&p).unwrap()) - 3500.0).abs() < 1e-9);
    let mode = std::fs::metadata(&p).unwrap().permissions().mode() & 0o7777;
    assert_eq!(mode, 0o444);
}

#[test]
fn a_link_is_followed_to_its_file_and_kept_a_link() {
    let dir = folder();
    let real = case_in(dir.path());
    let link = dir.path().join("link.toml");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    pim_store::write(
        &link,
        &with_mass(&example(), 3500),
        &WriteOptions::default(),
    )
    .unwrap();
    assert!(std::fs::symlink_metadata(&link)
        .unwrap()
        .file_type()
        .is_symlink());
    assert!((mass_of(&std::fs::read_to_string(&real).unwrap()) - 3500.0).abs() < 1e-9);
    // A link to nothing is not written through (it would create a file where it points).
    let dangling = dir.path().join("dangling.toml");
    let target = dir.path().join("elsewhere/new.toml");
    std::os::unix::fs::symlink(&target, &dangling).unwrap();
    let e = pim_store::write(&dangling, &example(), &WriteOptions::default()).unwrap_err();
    assert!(
        e.to_string().contains("link to a file that does not exist"),
        "{e}"
    );
    assert!(!target.exists());
    // With a folder given, a link out of it is refused.
    let inner = dir.path().join("served");
    std::fs::create_dir(&inner).unwrap();
    let out = inner.join("out.toml");
    std::os::unix::fs::symlink(&real, &out).unwrap();
    let options = WriteOptions {
        inside: Some(&inner),
        ..Default::default()
    };
    let e = pim_store::write(&out, &example(), &options).unwrap_err();
    assert!(e.to_string().contains("outside the folder"), "{e}");
}

#[test]
fn a_fifo_a_folder_and_a_huge_file_are_refused_without_waiting() {
    let dir = folder();
    let fifo = dir.path().join("pipe.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .unwrap();
    assert!(made.success());
    let started = std::time::Instant::now();
    let e = pim_store::read(&fifo, MAX_CASE_BYTES).unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
    let e = pim_store::write(&fifo, &example(), &WriteOptions::default()).unwrap_err();
    assert!(e.to_string().contains("not a regular file"), "{e}");
    assert!(started.elapsed().as_secs() < 5);
    let e = pim_store::read(dir.path(), MAX_CASE_BYTES).unwrap_err();
    assert!(e.to_string().contains("directory"), "{e}");
    let huge = dir.path().join("huge.toml");
    let f = std::fs::File::create(&huge).unwrap();
    f.set_len(60 << 20).unwrap();
    let e = pim_store::read(&huge, MAX_CASE_BYTES).unwrap_err();
    assert!(e.to_string().contains("larger than"), "{e}");
}

#[test]
fn a_killed_writers_temporary_is_removed_by_the_next_write() {
    let dir = folder();
    let p = case_in(dir.path());
    let stale = dir.path().join(".case.toml.a1B2c3.pim-tmp");
    std::fs::write(&stale, "half").unwrap();
    let other = dir.path().join(".other.toml.a1B2c3.pim-tmp");
    std::fs::write(&other, "another file's").unwrap();
    pim_store::write(&p, &with_mass(&example(), 3500), &WriteOptions::default()).unwrap();
    assert!(!stale.exists());
    assert!(
        other.exists(),
        "only the file's own temporaries are its to remove"
    );
}

/// Two writers, each setting its own value 100 times from the file as it is (read, edit,
/// write under the lock), while a reader reads all along: no update is lost, no read sees a
/// part of a file.
#[test]
fn two_writers_lose_no_update_and_a_reader_never_sees_a_part() {
    let dir = folder();
    let p = Arc::new(case_in(dir.path()));
    let done = Arc::new(AtomicBool::new(false));
    let reads = Arc::new(AtomicUsize::new(0));
    let reader = {
        let (p, done, reads) = (p.clone(), done.clone(), reads.clone());
        std::thread::spawn(move || {
            while !done.load(Ordering::Relaxed) {
                let text = std::fs::read_to_string(&*p).unwrap();
                assert!(
                    pim_case::case::Case::from_text("case.toml", &text).is_ok(),
                    "a read saw {} bytes that do not parse",
                    text.len()
                );
                reads.fetch_add(1, Ordering::Relaxed);
            }
        })
    };
    let writers: Vec<_> = ["vehicle1.mass", "vehicle2.mass"]
        .into_iter()
        .map(|key| {
            let p = p.clone();
            std::thread::spawn(move || {
                for i in 0..100u32 {
                    pim_store::update(&p, &WriteOptions::default(), |current| {
                        let mut e = pim_case::edit::CaseEdit::new("case.toml", &current.text)?;
                        e.set(key, pim_case::edit::NewValue::Written(f64::from(3000 + i)))?;
                        Ok::<_, pim_case::InputError>(e.text())
                    })
                    .unwrap();
                }
            })
        })
        .collect();
    for w in writers {
        w.join().unwrap();
    }
    done.store(true, Ordering::Relaxed);
    reader.join().unwrap();
    let last = std::fs::read_to_string(&*p).unwrap();
    let e = pim_case::edit::CaseEdit::new("case.toml", &last).unwrap();
    assert_eq!(e.get("vehicle1.mass").unwrap(), "3099.0");
    assert_eq!(e.get("vehicle2.mass").unwrap(), "3099.0");
    assert!(reads.load(Ordering::Relaxed) > 10);
}

#[test]
fn a_write_with_the_version_read_after_an_outside_change_goes_through() {
    // The page's "save mine over it": the conflict's current version names the file now.
    let dir = folder();
    let p = case_in(dir.path());
    std::fs::write(&p, example() + "# outside\n").unwrap();
    let now = pim_store::read(&p, MAX_CASE_BYTES).unwrap();
    let mine = with_mass(&example(), 3500);
    let options = WriteOptions {
        expected: Some(&now.version.0),
        ..Default::default()
    };
    pim_store::write(&p, &mine, &options).unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), mine);
}
