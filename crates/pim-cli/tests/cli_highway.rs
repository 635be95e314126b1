//! A crash at highway speed written as a reconstructionist would (US units): no default bound
//! decides its answer.
mod common;
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
