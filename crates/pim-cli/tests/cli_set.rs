//! `pim set`: a value changed in place with the rest of the file as the user wrote it; a value
//! the case refuses leaves the file untouched with the message every command gives.
mod common;
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
