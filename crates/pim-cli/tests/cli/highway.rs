//! A crash at highway speed written as a reconstructionist would (US units): no default bound
//! decides its answer.
use crate::common;
use common::*;

#[test]
fn a_sixty_mph_side_impact_is_fitted_at_sixty_mph() {
    // The side impact of the README at 60 mph (26.8 m/s, beyond the RICSAC setting of 20 m/s),
    // solved forwards, then fitted back from its own velocities (Q2): the fitted speed is the
    // speed of the crash, not a bound.
    let text = std::fs::read_to_string(repo().join("examples/cases/side_impact_us.toml")).unwrap();
    let solve = text.replace(
        "vehicle1 = { vx = 33.554044, vy = 0.0, omega = 0.0 }",
        "vehicle1 = { vx = 60.0, vy = 0.0, omega = 0.0 }",
    );
    assert_ne!(solve, text);
    let path = scratch_file("highway", "solve.toml", &solve);
    let j: serde_json::Value =
        serde_json::from_slice(&pim_ok(&["solve", &path, "--format", "json"]).stdout).unwrap();
    let mph = |x: &serde_json::Value| x.as_f64().unwrap() / 0.44704;
    let state = |s: &str, v: &str| {
        let u = &j[s][v];
        format!(
            "{{ vx = {}, vy = {}, omega = {} }}",
            mph(&u["vx"]),
            mph(&u["vy"]),
            u["omega"].as_f64().unwrap().to_degrees()
        )
    };
    let start = solve.find("[coefficients]").unwrap();
    let fit = format!(
        "{}[estimates.initial]\nvehicle1 = {}\nvehicle2 = {}\n\n[estimates.final]\nvehicle1 = {}\n\
         vehicle2 = {}\n",
        &solve[..start],
        state("initial", "vehicle1"),
        state("initial", "vehicle2"),
        state("final", "vehicle1"),
        state("final", "vehicle2"),
    );
    let path = scratch_file("highway", "fit.toml", &fit);
    let out = pim_ok(&["fit", &path, "--cost", "q2", "--format", "json"]);
    let f: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let best = f["best"].as_str().unwrap();
    let b = f["branches"]
        .as_array()
        .unwrap()
        .iter()
        .find(|b| b["moment"] == best)
        .unwrap();
    let v1 = b["initial"]["vehicle1"]["vx"].as_f64().unwrap();
    assert!((v1 / 0.44704 - 60.0).abs() < 1e-6, "{v1} m/s");
    assert!(b["cost"].as_f64().unwrap() < 1e-10, "{}", b["cost"]);
    assert!(!stderr(&out).contains("bound"), "{}", stderr(&out));
}

#[test]
fn the_sixty_mph_tbone_reads_in_mph_and_no_bound_cuts_its_intervals() {
    // examples/cases/tbone_sae_us.toml: SAE frame, US units, speeds and directions; one file
    // for its solve and its fit. Its uncertainty table is in mph, no interval reaches a bound
    // and --strict accepts it.
    let case = "examples/cases/tbone_sae_us.toml";
    let args = [
        "uncertainty",
        case,
        "--cost",
        "q3",
        "--draws",
        "100",
        "--strict",
    ];
    let out = pim(&args);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let table = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        table.contains("speeds at contact and delta-V in mph"),
        "{table}"
    );
    assert!(!table.contains("ENDED BY"), "{table}");
    let speed1 = table
        .lines()
        .find(|l| l.starts_with("speed1"))
        .and_then(|l| l.split_whitespace().nth(1))
        .and_then(|x| x.parse::<f64>().ok())
        .unwrap();
    assert!((speed1 - 60.0).abs() < 1.0, "nominal speed 1 {speed1} mph");
    let mut json_args = args.to_vec();
    json_args.extend(["--format", "json"]);
    let j: serde_json::Value = serde_json::from_slice(&pim_ok(&json_args).stdout).unwrap();
    // JSON stays SI.
    let p50 = j["quantities"]["speed1"]["p50"].as_f64().unwrap();
    assert!((p50 / 0.44704 - 60.0).abs() < 2.0, "{p50} m/s");
    for (q, s) in j["quantities"].as_object().unwrap() {
        assert!(s["reaches_bound"].is_null(), "{q}: {s}");
    }

    // The same crash under a velocity bound of 40 mph set in the file: the speed intervals are
    // ended by it, the table, the JSON and the histogram say so, and --strict accepts the
    // bound because the file sets it.
    let text = std::fs::read_to_string(repo().join(case)).unwrap();
    let bounded = scratch_file(
        "highway",
        "tbone_bounded.toml",
        format!("{text}\n[bounds]\nvelocity = 40.0\n"),
    );
    let dir = scratch_dir("highway", "tbone_bounded_out");
    let out = pim(&[
        "uncertainty",
        &bounded,
        "--cost",
        "q3",
        "--draws",
        "60",
        "--strict",
        "--out",
        &dir.display().to_string(),
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let table = String::from_utf8_lossy(&out.stdout).to_string();
    let row = table.lines().find(|l| l.starts_with("speed1")).unwrap();
    assert!(
        row.contains("ENDED BY the velocity bound (set in [bounds]"),
        "{row}"
    );
    let svg = std::fs::read_to_string(dir.join("histograms.svg")).unwrap();
    assert!(svg.contains("(ended by the velocity bound)"));
    assert!(svg.contains("[mph]"));
}

#[test]
fn the_oblique_example_reads_in_mph_and_no_bound_cuts_its_intervals() {
    // examples/cases/oblique_sae_us.toml: e's interval reaches 0.28, beyond the [0, 0.2] that
    // suits RICSAC and that once bounded every case file: nothing cuts it now.
    let case = "examples/cases/oblique_sae_us.toml";
    let out = pim(&[
        "uncertainty",
        case,
        "--cost",
        "q3",
        "--draws",
        "100",
        "--strict",
    ]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let table = String::from_utf8_lossy(&out.stdout).to_string();
    assert!(
        table.contains("delta-V in mph") && !table.contains("ENDED BY"),
        "{table}"
    );
    let e_p95: f64 = table
        .lines()
        .find(|l| l.starts_with("e "))
        .and_then(|l| l.split_whitespace().nth(4))
        .and_then(|x| x.parse().ok())
        .unwrap();
    assert!(e_p95 > 0.2, "e p95 {e_p95}");
    let solve = String::from_utf8_lossy(&pim_ok(&["solve", case]).stdout).to_string();
    assert!(
        solve.contains("delta-V [mph]                             31.60"),
        "{solve}"
    );
}
