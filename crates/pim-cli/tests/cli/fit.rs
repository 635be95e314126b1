//! End-to-end tests of `pim fit`: the real binary, its JSON, exit codes and messages.
use crate::common;
use common::*;

fn write_case(name: &str, text: &str) -> String {
    scratch_file("cli_fit", name, text)
}
use serde_json::Value;

fn case_text() -> String {
    std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/cases/ricsac7_fit.toml"
    ))
    .unwrap()
}

#[test]
fn fit_json_has_both_branches_and_the_best() {
    for cost in ["q1", "q2", "q3"] {
        let out = pim(&[
            "fit",
            "examples/cases/ricsac7_fit.toml",
            "--cost",
            cost,
            "--format",
            "json",
        ]);
        assert!(out.status.success(), "{cost}: {}", stderr(&out));
        assert!(out.stderr.is_empty(), "json runs print nothing on stderr");
        let j: Value = serde_json::from_slice(&out.stdout).unwrap();
        assert_eq!(j["cost_function"], cost);
        let branches = j["branches"].as_array().unwrap();
        assert_eq!(branches.len(), 2);
        assert_eq!(branches[0]["moment"], "free");
        assert_eq!(branches[1]["moment"], "zero");
        for b in branches {
            assert_eq!(b["status"], "optimal");
            for k in [
                "e",
                "mu",
                "em",
                "cost",
                "max_residual",
                "energy_loss_percent",
                "mu_max",
            ] {
                assert!(b[k].is_f64(), "{cost} {k}");
            }
            assert!(b["max_residual"].as_f64().unwrap() < 1e-10);
            assert!((b["em"].as_f64().unwrap() - 1.0).abs() < 1e-12 || b["moment"] == "free");
            for state in ["initial", "final"] {
                for v in ["vehicle1", "vehicle2"] {
                    for c in ["vx", "vy", "omega"] {
                        assert!(b[state][v][c].is_f64());
                    }
                }
            }
        }
        let best = j["best"].as_str().unwrap();
        let costs: Vec<f64> = branches
            .iter()
            .map(|b| b["cost"].as_f64().unwrap())
            .collect();
        let best_cost = branches.iter().find(|b| b["moment"] == best).unwrap()["cost"]
            .as_f64()
            .unwrap();
        assert!(costs.iter().all(|c| best_cost <= c + 1e-6 * (1.0 + c)));
    }
    // Q1 holds the separation velocities fixed.
    let j: Value = serde_json::from_slice(
        &pim(&[
            "fit",
            "examples/cases/ricsac7_fit.toml",
            "--cost",
            "q1",
            "--format",
            "json",
        ])
        .stdout,
    )
    .unwrap();
    assert!(
        (j["branches"][1]["final"]["vehicle1"]["vx"]
            .as_f64()
            .unwrap()
            + 7.74)
            .abs()
            < 1e-9
    );
}

#[test]
fn infeasible_data_are_an_explained_outcome() {
    // RICSAC 1 as in data/ricsac.csv: the measured separation velocities still approach at C.
    let text = "\
convention = \"brach\"
[vehicle1]
mass = 2096.0
yaw_inertia = 5054.0
heading = 0.0
d = 2.425
phi = -19.8
[vehicle2]
mass = 1398.0
yaw_inertia = 2659.0
heading = 60.0
d = 1.045
phi = -38.7
[impact]
crush_angle = -30.0
[estimates.initial]
vehicle1 = { vx = -8.95, vy = 0.0, omega = 0.0 }
vehicle2 = { vx = 4.43, vy = 7.67, omega = 0.0 }
[estimates.final]
vehicle1 = { vx = -3.76, vy = 2.41, omega = -1.57 }
vehicle2 = { vx = -2.07, vy = 5.17, omega = 0.0 }
";
    let path = write_case("ricsac1.toml", text);
    let out = pim(&["fit", &path, "--cost", "q1", "--format", "json"]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(j["best"], Value::Null);
    for b in j["branches"].as_array().unwrap() {
        assert_eq!(b["status"], "infeasible");
        assert!(b["reason"]
            .as_str()
            .unwrap()
            .contains("still approach at the impact centre"));
        assert_eq!(b["e"], Value::Null);
    }
    assert!(stderr(&out).contains(&path) && stderr(&out).contains("no branch"));
    // Q2 of the same data has an answer.
    assert!(pim(&["fit", &path, "--cost", "q2"]).status.success());
}

#[test]
fn bad_fit_cases_exit_2_naming_the_culprit() {
    let base = case_text();
    let cases: Vec<(&str, String, Vec<&str>, &str)> = vec![
        ("missing.toml", base.replace("vehicle2 = { vx = -2.22, vy = 8.64, omega = -3.35 }", "vehicle2 = { vx = -2.22, vy = 8.64 }"), vec!["--cost", "q2"], "final.vehicle2.omega is missing"),
        ("weight.toml", format!("{base}\n[weights.final]\nvehicle1 = {{ vx = 1.5 }}\n"), vec!["--cost", "q2"], "weights.final.vehicle1.vx: weight 1.5"),
        ("obs.toml", format!("{base}\n[[observations]]\nkind = \"delta_v_longitudinal\"\nvehicle = 3\nvalue = 1.0\n"), vec!["--cost", "q2"], ":44:11: observation 1: vehicle: 3; accepted: 1 or 2"),
        ("obskind.toml", format!("{base}\n[[observations]]\nkind = \"delta_v_sideways\"\nvehicle = 1\nvalue = 1.0\n"), vec!["--cost", "q2"], "observation 1: kind: `delta_v_sideways` is not an accepted value; accepted: `delta_v_longitudinal`"),
        ("both.toml", format!("{base}\n[known.initial]\nvehicle1 = {{ vx = -13.01 }}\n"), vec![], "both in [known] and in [estimates]"),
        ("known_with_cost.toml", format!("{base}\n[known.initial]\nvehicle1 = {{ vx = -13.01 }}\n"), vec!["--cost", "q3"], "[known] is for fits without --cost"),
        ("coef.toml", format!("{}\n[coefficients]\ne = 0.1\nmu = 0.5\nem = 1.0\n", base.replace("[estimates.", "[")), vec!["--cost", "q2"], "[coefficients] is for `pim solve`"),
        ("bounds.toml", base.replace("e = [0.0, 0.2]", "e = [0.3, 0.2]"), vec!["--cost", "q2"], "[bounds] e = [0.3, 0.2]"),
        ("nan.toml", base.replace("vx = -7.74", "vx = nan"), vec!["--cost", "q2"], "final.vehicle1.vx"),
        ("over.toml", format!("{}\n[known.final]\nvehicle1 = {{ vx = -7.74, vy = 1.48, omega = -0.52 }}\nvehicle2 = {{ vx = -2.22 }}\n", base.replace("[estimates.final]\nvehicle1 = { vx = -7.74, vy = 1.48, omega = -0.52 }\nvehicle2 = { vx = -2.22, vy = 8.64, omega = -3.35 }", "").replace("[estimates.initial]", "[known.initial]")), vec![], "at most six components"),
    ];
    for (name, text, extra, needle) in cases {
        let path = write_case(name, &text);
        let mut args = vec!["fit", path.as_str()];
        args.extend(extra);
        let out = pim(&args);
        let msg = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {msg}");
        assert!(msg.contains(&path), "{name}: {msg}");
        assert!(msg.contains(needle), "{name}: `{needle}` not in {msg}");
        assert!(out.stdout.is_empty(), "{name}");
        // Two vehicles: no word of a barrier.
        assert!(!msg.contains("barrier"), "{name}: {msg}");
    }
}

#[test]
fn fit_help_documents_the_case_file() {
    let out = pim(&["fit", "--help"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "[estimates.initial]",
        "[[observations]]",
        "delta_v_longitudinal",
        "q2",
        "EXIT STATUS",
    ] {
        assert!(text.contains(needle), "{needle}");
    }
}

#[test]
fn a_fit_case_in_the_other_convention_is_explained() {
    // The natural-form example with vehicle 1's heading written as Brach's theta1 (its tail).
    let text = case_text().replace("heading = 180.0", "heading = 0.0");
    let path = write_case("wrong_convention.toml", &text);
    let out = pim(&["fit", &path, "--cost", "q2", "--format", "json"]);
    let msg = stderr(&out);
    // Both CGs on one side: the side is read from the estimates (under which they approach),
    // and the warning says the other convention would put the CGs on opposite sides.
    assert!(
        msg.contains("read from the estimated contact velocities"),
        "{msg}"
    );
    assert!(msg.contains("vehicle 1's CG at (-1.80, 0.00) m"), "{msg}");
    assert!(msg.contains("With convention = \"brach\""), "{msg}");
}

#[test]
fn geometry_bounds_estimate_the_impact_centres_and_never_cost_more() {
    let case = "examples/cases/ricsac6_geometry.toml";
    let out = pim_ok(&["fit", case, "--cost", "q2", "--format", "json"]);
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    // The same case with the geometry as given (no geometry bounds).
    let text = std::fs::read_to_string(repo().join(case)).unwrap();
    let fixed: String = text
        .lines()
        .filter(|l| !(l.starts_with("vehicle") && l.contains("= [")))
        .filter(|l| !l.starts_with("crush_angle = ["))
        .collect::<Vec<_>>()
        .join("\n");
    assert!(!fixed.contains("d = [2.44"), "{fixed}");
    let plain = pim_ok(&[
        "fit",
        &write_case("ricsac6_fixed.toml", &fixed),
        "--cost",
        "q2",
        "--format",
        "json",
    ]);
    let p: Value = serde_json::from_slice(&plain.stdout).unwrap();
    assert!(p["branches"][0].get("geometry").is_none());
    let bounds = [
        ("vehicle1.d", 2.44, 2.56),
        ("vehicle1.phi", -25.0, -15.0),
        ("vehicle2.d", 0.61, 0.76),
        ("vehicle2.phi", -90.0, -60.0),
        ("crush_angle", -40.0, -20.0),
    ];
    for (b, q) in j["branches"]
        .as_array()
        .unwrap()
        .iter()
        .zip(p["branches"].as_array().unwrap())
    {
        let g = &b["geometry"];
        for k in ["vehicle1", "vehicle2"] {
            assert!(g[k]["d"].is_number() && g[k]["phi"].is_number(), "{g}");
        }
        assert!(g["crush_angle"].is_number());
        let ranges = g["ranges"].as_array().unwrap();
        assert_eq!(ranges.len(), 5);
        for (r, (name, lo, hi)) in ranges.iter().zip(bounds) {
            assert_eq!(r["input"], name);
            let v = r["value"].as_f64().unwrap();
            assert!(v >= lo - 1e-9 && v <= hi + 1e-9, "{name} {v}");
            assert!(r["low"].as_f64().unwrap() <= v && v <= r["high"].as_f64().unwrap());
        }
        assert!(g["search"]["fits"].as_u64().unwrap() > 244);
        // The case's own geometry is one of the points searched.
        let (c, c0) = (b["cost"].as_f64().unwrap(), q["cost"].as_f64().unwrap());
        assert!(c <= c0 * (1.0 + 1e-9), "{}: {c} > {c0}", b["moment"]);
    }
}

#[test]
fn impact_point_bounds_in_the_natural_form_and_bad_geometry_bounds() {
    let text = case_text();
    let with = |bounds: &str| text.replacen("[bounds]", &format!("[bounds]\n{bounds}"), 1);
    let ok = write_case(
        "r7_point_bounds.toml",
        &with("vehicle1 = { impact_point = { x = [1.6, 2.0], y = [-0.3, 0.3] } }"),
    );
    let out = pim_ok(&["fit", &ok, "--cost", "q2", "--format", "json"]);
    let j: Value = serde_json::from_slice(&out.stdout).unwrap();
    let r = &j["branches"][0]["geometry"]["ranges"];
    assert_eq!(r[0]["input"], "vehicle1.impact_point.x");
    assert_eq!(r[1]["input"], "vehicle1.impact_point.y");
    let x = r[0]["value"].as_f64().unwrap();
    assert!((1.6..=2.0).contains(&x), "{x}");
    for (name, bounds, says) in [
        (
            "outside.toml",
            "vehicle1 = { impact_point = { x = [2.0, 2.4] } }",
            "does not contain the case's value",
        ),
        (
            "both.toml",
            "vehicle1 = { d = [1.6, 2.0], impact_point = { y = [-0.3, 0.3] } }",
            "not both",
        ),
        (
            "reversed.toml",
            "crush_angle = [10.0, -10.0]",
            "low <= high",
        ),
    ] {
        let out = pim(&["fit", &write_case(name, &with(bounds)), "--cost", "q2"]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        let err = stderr(&out);
        assert!(err.contains(name) && err.contains(says), "{name}: {err}");
    }
}

#[test]
fn one_file_holds_a_solve_and_a_fit_of_the_same_crash() {
    // The fit case plus what `pim solve` needs: each command reads its own sections, and each
    // answer is the one of the file without the other's sections.
    let base = case_text();
    let solve_part = "\n[coefficients]\ne = 0.1\nmu = 0.3\nem = 1.0\n\n[initial]\n\
                      vehicle1 = { vx = -13.01, vy = 0.0, omega = 0.0 }\n\
                      vehicle2 = { vx = 6.50, vy = 11.27, omega = 0.0 }\n";
    let both = write_case("both_solve_and_fit.toml", &format!("{base}{solve_part}"));
    let fit_only = write_case("fit_only.toml", &base);
    let header: String = base
        .lines()
        .take_while(|l| !l.starts_with("[estimates") && !l.starts_with("[bounds"))
        .map(|l| format!("{l}\n"))
        .collect();
    let solve_only = write_case("solve_only.toml", &format!("{header}{solve_part}"));
    let json = |args: &[&str]| -> Value {
        let out = pim(args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        serde_json::from_slice(&out.stdout).unwrap()
    };
    for cost in ["q1", "q2", "q3"] {
        assert_eq!(
            json(&["fit", &both, "--cost", cost, "--format", "json"]),
            json(&["fit", &fit_only, "--cost", cost, "--format", "json"]),
            "{cost}"
        );
    }
    assert_eq!(
        json(&["solve", &both, "--format", "json"]),
        json(&["solve", &solve_only, "--format", "json"])
    );
}

#[test]
fn an_answer_on_a_default_bound_says_so_and_fails_under_strict() {
    // A sideswipe whose friction is 1.5 (mu_max 1.86, still sliding at separation): the
    // velocities of the forward solve as estimates, fitted without [bounds] mu, rest on the
    // default mu <= 1.2. The table and the JSON say so and --strict exits 1; the same fit with
    // the bound set in the file says it was set there and --strict accepts it.
    let side = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml")).unwrap();
    let geometry: String = side
        .lines()
        .take_while(|l| !l.starts_with("[coefficients]"))
        .map(|l| format!("{l}\n"))
        .collect();
    let estimates = "[estimates.initial]\n\
                     vehicle1 = { vx = 5.0, vy = 0.0, omega = 0.0 }\n\
                     vehicle2 = { vx = 0.0, vy = 25.0, omega = 0.0 }\n\
                     [estimates.final]\n\
                     vehicle1 = { vx = 2.25, vy = 4.125, omega = 4.95 }\n\
                     vehicle2 = { vx = 2.75, vy = 20.875, omega = 2.2275 }\n";
    let by_default = write_case("mu_default.toml", &format!("{geometry}{estimates}"));
    let by_case = write_case(
        "mu_set.toml",
        &format!("{geometry}{estimates}[bounds]\nmu = [0.0, 1.2]\n"),
    );
    let best_bounds = |path: &str| -> Vec<Value> {
        let out = pim(&["fit", path, "--cost", "q3", "--format", "json"]);
        assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
        let j: Value = serde_json::from_slice(&out.stdout).unwrap();
        let best = j["branches"]
            .as_array()
            .unwrap()
            .iter()
            .find(|b| b["moment"] == j["best"])
            .unwrap()
            .clone();
        best["bounds_reached"]
            .as_array()
            .cloned()
            .unwrap_or_default()
    };
    let mu = |source: &str| {
        serde_json::json!({
            "bound": "mu", "limit": 1.2, "at": "mu=max", "source": source
        })
    };
    assert_eq!(best_bounds(&by_default), vec![mu("default")]);
    assert_eq!(best_bounds(&by_case), vec![mu("case")]);
    let strict = pim(&["fit", &by_default, "--cost", "q3", "--strict"]);
    assert_eq!(strict.status.code(), Some(1), "{}", stderr(&strict));
    assert!(
        stderr(&strict).contains("--strict: the best branch rests on a default bound"),
        "{}",
        stderr(&strict)
    );
    assert!(
        String::from_utf8_lossy(&strict.stdout).contains(
            "(best) rests on a bound (the bound, not the data, ends it): mu=max at [bounds] mu = \
             1.200 (the default, not set for this crash)"
        ),
        "{}",
        String::from_utf8_lossy(&strict.stdout)
    );
    let strict = pim(&["fit", &by_case, "--cost", "q3", "--strict"]);
    assert_eq!(strict.status.code(), Some(0), "{}", stderr(&strict));
    assert!(String::from_utf8_lossy(&strict.stdout).contains("mu = 1.200 (set in [bounds])"));
}

#[test]
fn an_observation_is_named_the_same_way_everywhere() {
    // By its `name`, else by its 1-based position, in parse errors and semantic errors alike
    // (the uncertainty study names its inputs with the same label).
    let base = case_text();
    let obs = |name: &str, extra: &str| {
        format!(
            "{base}\n[[observations]]\nkind = \"delta_v_lateral\"\nvehicle = 1\nvalue = 1.0\n\
             \n[[observations]]\n{name}kind = \"delta_v_longitudinal\"\nvehicle = 2\n{extra}"
        )
    };
    let run = |file: &str, text: String| {
        let path = write_case(file, &text);
        let out = pim(&["fit", &path, "--cost", "q2"]);
        assert_eq!(out.status.code(), Some(2), "{file}");
        stderr(&out)
    };
    // A parse error (a value that is not a number) and a semantic one (a sigma of 0), each
    // with its line and column.
    let text = obs("", "value = \"x\"\n");
    let line = text.lines().position(|l| l == "value = \"x\"").unwrap() + 1;
    let msg = run("obs_parse.toml", text);
    assert!(
        msg.contains(&format!(
            ":{line}:9: observation 2: value: expected a number"
        )),
        "{msg}"
    );
    let text = obs("name = \"EDR rear\"\n", "value = -3.0\nsigma = 0.0\n");
    let line = text.lines().position(|l| l == "sigma = 0.0").unwrap() + 1;
    let msg = run("obs_sigma.toml", text);
    assert!(
        msg.contains(&format!(
            ":{line}:9: observation \"EDR rear\": sigma: 0: a standard"
        )),
        "{msg}"
    );
    let text = obs("name = \"EDR rear\"\n", "value = \"x\"\n");
    let msg = run("obs_parse_named.toml", text);
    assert!(msg.contains("observation \"EDR rear\": value"), "{msg}");
}
