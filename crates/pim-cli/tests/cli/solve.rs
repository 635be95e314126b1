//! End-to-end tests of `pim solve` and `pim sensitivity`: the real binary, its JSON and exit codes.
use crate::common;
use common::*;

/// Writes a case file into the test's scratch directory.
fn write_case(name: &str, text: &str) -> String {
    scratch_file("cli_solve", name, text)
}
use serde_json::Value;
use std::process::Output;

fn example() -> String {
    std::fs::read_to_string(repo().join("examples/cases/ricsac7_brach1983.toml")).unwrap()
}

fn json_of(out: &Output) -> Value {
    assert!(
        out.status.success(),
        "status {:?}, stderr {}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

#[test]
fn solve_json_reproduces_brach1983_table3_ricsac7() {
    let out = pim(&[
        "solve",
        "examples/cases/ricsac7_brach1983.toml",
        "--format",
        "json",
        "--moment-form",
        "brach1983",
    ]);
    let j = json_of(&out);
    assert!(out.stderr.is_empty());
    // Table 3: V1x -7.33, V1y 1.42, V2x -2.78, V2y 8.94 m/s; |dV| 5.86 / 9.57 m/s; loss 53.1 %.
    // (Inputs as printed in Table 1: d rounded to 0.1 m, see tests/physics/brach1983_tables.rs.)
    let f = &j["final"];
    for (v, want) in [
        (&f["vehicle1"]["vx"], -7.33),
        (&f["vehicle1"]["vy"], 1.42),
        (&f["vehicle2"]["vx"], -2.78),
        (&f["vehicle2"]["vy"], 8.94),
        (&j["delta_v"]["vehicle1"], 5.86),
        (&j["delta_v"]["vehicle2"], 9.57),
    ] {
        assert!((v.as_f64().unwrap() - want).abs() < 0.015, "{v} vs {want}");
    }
    assert!((j["energy"]["loss_percent"].as_f64().unwrap() - 53.1).abs() < 0.5);
    assert!(j["energy"]["initial"].as_f64().unwrap() > j["energy"]["final"].as_f64().unwrap());
    for k in ["px", "py", "normal", "tangential", "moment"] {
        assert!(j["impulse"][k].is_f64(), "impulse.{k}");
    }
    assert!(j["mu_max"].as_f64().unwrap() > 0.968);
    assert_eq!(j["sliding"], Value::Bool(true));
    assert_eq!(j["admissible"], Value::Bool(true));
    assert!(j["max_residual"].as_f64().unwrap() < 1e-12);
}

#[test]
fn solve_backward_from_final_returns_the_contact_velocities() {
    // The 1983 moment form, with which this case is admissible (mu < mu_max).
    let fwd = json_of(&pim(&[
        "solve",
        "examples/cases/ricsac7_brach1983.toml",
        "--format",
        "json",
        "--moment-form",
        "brach1983",
    ]));
    assert_eq!(fwd["admissible"], Value::Bool(true));
    let f = &fwd["final"];
    let fmt = |v: &Value| {
        format!(
            "{{ vx = {}, vy = {}, omega = {} }}",
            v["vx"], v["vy"], v["omega"]
        )
    };
    let text = example().replace(
        "[initial]              # or [final], to solve backwards from separation velocities\nvehicle1 = { vx = -13.01, vy = 0.0, omega = 0.0 }\nvehicle2 = { vx = 6.505, vy = 11.267, omega = 0.0 }",
        &format!(
            "[final]\nvehicle1 = {}\nvehicle2 = {}",
            fmt(&f["vehicle1"]),
            fmt(&f["vehicle2"])
        ),
    );
    assert!(text.contains("[final]"));
    let path = write_case("backward.toml", &text);
    let back = json_of(&pim(&[
        "solve",
        &path,
        "--format",
        "json",
        "--moment-form",
        "brach1983",
    ]));
    assert_eq!(back["direction"], "backward");
    let i = &back["initial"];
    for (v, want) in [
        (&i["vehicle1"]["vx"], -13.01),
        (&i["vehicle1"]["vy"], 0.0),
        (&i["vehicle2"]["vx"], 6.505),
        (&i["vehicle2"]["vy"], 11.267),
        (&i["vehicle2"]["omega"], 0.0),
    ] {
        assert!((v.as_f64().unwrap() - want).abs() < 1e-9, "{v} vs {want}");
    }
}

#[test]
fn backward_with_zero_restitution_is_an_explained_no_answer() {
    let text = example()
        .replace("e = 0.015", "e = 0.0")
        .replace("[initial]  ", "[final]  ");
    let path = write_case("backward_e0.toml", &text);
    let out = pim(&["solve", &path]);
    assert_eq!(out.status.code(), Some(3), "{}", stderr(&out));
    let msg = stderr(&out);
    assert!(msg.contains(&path), "{msg}");
    assert!(
        msg.contains("equation 4 (restitution)") && msg.contains("e = 0"),
        "{msg}"
    );
    assert!(out.stdout.is_empty());
}

#[test]
fn no_slip_reports_sticking_and_the_implied_friction() {
    let j = json_of(&pim(&[
        "solve",
        "examples/cases/ricsac7_brach1983.toml",
        "--format",
        "json",
        "--no-slip",
    ]));
    assert_eq!(j["sliding"], Value::Bool(false));
    assert_eq!(j["tangential"], "sticking");
    assert!(
        j["relative_velocity"]["tangential_final"]
            .as_f64()
            .unwrap()
            .abs()
            < 1e-9
    );
}

#[test]
fn sensitivity_json_lists_every_combination_and_level() {
    let j = json_of(&pim(&[
        "sensitivity",
        "examples/cases/ricsac7_brach1983.toml",
        "--percent",
        "10",
        "--format",
        "json",
        "--moment-form",
        "brach1983",
    ]));
    let combos = j["combinations"].as_array().unwrap();
    assert_eq!(combos.len(), 8);
    assert_eq!(j["averages"].as_array().unwrap().len(), 6);
    // First combination is (e low, mu low, em low) as in Brach 1983 Table 4 row 1.
    let c0 = &combos[0];
    assert!((c0["coefficients"]["e"].as_f64().unwrap() - 0.0135).abs() < 1e-12);
    assert!((c0["coefficients"]["mu"].as_f64().unwrap() - 0.8712).abs() < 1e-12);
    assert!((c0["coefficients"]["em"].as_f64().unwrap() + 0.8514).abs() < 1e-12);
    assert!((c0["final"]["vehicle1"]["vx"].as_f64().unwrap() + 7.58).abs() < 0.015);
    for c in combos {
        assert!(c["energy"]["loss_percent"].is_f64());
        assert!(c["admissible"].is_boolean());
    }
}

#[test]
fn sensitivity_rejects_a_level_outside_the_domain() {
    let text = example().replace("em = -0.774", "em = -0.95");
    let path = write_case("sens_em.toml", &text);
    let out = pim(&["sensitivity", &path, "--percent", "10"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("em x 1.1"), "{}", stderr(&out));
}

#[test]
fn bad_case_files_exit_2_naming_file_and_field() {
    let cases: &[(&str, String, &str)] = &[
        ("neg_mass.toml", example().replace("mass = 1955.0", "mass = -5.0"), "vehicle1.mass"),
        ("zero_inertia.toml", example().replace("yaw_inertia = 2279.0", "yaw_inertia = 0.0"), "vehicle2.yaw_inertia"),
        ("neg_d.toml", example().replace("d = 0.9", "d = -0.9"), "vehicle2.d"),
        ("text_angle.toml", example().replace("heading = 60.0", "heading = \"sixty\""), ":21:"),
        ("missing.toml", example().replace("yaw_inertia = 2279.0\n", ""), "vehicle2.yaw_inertia: missing"),
        ("typo.toml", example().replace("crush_angle", "crush_angel"), "crush_angel"),
        ("nan.toml", example().replace("vx = -13.01", "vx = nan"), "initial.vehicle1.vx"),
        ("inf.toml", example().replace("mass = 1197.0", "mass = inf"), "vehicle2.mass"),
        ("e_range.toml", example().replace("e = 0.015", "e = 1.5"), "e = 1.5"),
        ("em_range.toml", example().replace("em = -0.774", "em = 0.5"), "em = 0.5"),
        ("no_coef.toml", example().replace("[coefficients]", "[coefficientz]"), "coefficientz"),
        ("empty.toml", String::new(), "empty"),
        ("apart.toml", example().replace("vx = -13.01", "vx = 30.0"), "do not approach"),
        ("twice.toml", example().replace("d = 0.9", "impact_point = { x = 0.1, y = 0.2 }\nd = 0.9"), "[vehicle2] gives the impact centre twice"),
        ("no_phi.toml", example().replace("phi = -140.0", ""), "[vehicle2] phi: missing"),
        ("bad_unit.toml", format!("{}\n[units]\nspeed = \"knots\"\n", example()), "units.speed"),
        ("both.toml", format!("{}\n[final]\nvehicle1 = {{ vx = 1.0, vy = 0.0, omega = 0.0 }}\nvehicle2 = {{ vx = 1.0, vy = 0.0, omega = 0.0 }}\n", example()), "not both"),
    ];
    for (name, text, needle) in cases {
        let path = write_case(name, text);
        let out = pim(&["solve", &path, "--format", "json"]);
        let msg = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {msg}");
        assert!(
            msg.contains(&path),
            "{name}: message does not name the file: {msg}"
        );
        assert!(
            msg.contains(needle),
            "{name}: message does not name `{needle}`: {msg}"
        );
        assert_eq!(msg.lines().count(), 1, "{name}: one line expected: {msg}");
        assert!(out.stdout.is_empty(), "{name}: printed a result");
    }
    for (args, needle) in [
        (vec!["solve", "no/such/case.toml"], "no such file"),
        (vec!["solve", "examples"], "is a directory"),
        (
            vec![
                "solve",
                "examples/cases/ricsac7_brach1983.toml",
                "--format",
                "xml",
            ],
            "xml",
        ),
        (
            vec![
                "sensitivity",
                "examples/cases/ricsac7_brach1983.toml",
                "--percent",
                "abc",
            ],
            "abc",
        ),
    ] {
        let out = pim(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(needle), "{args:?}: {}", stderr(&out));
    }
}

#[test]
fn help_documents_the_case_file_and_exit_codes() {
    let out = pim(&["solve", "--help"]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    for needle in [
        "CASE FILE",
        "yaw_inertia",
        "crush_angle",
        "EXIT STATUS",
        "--moment-form",
        "brach1983",
    ] {
        assert!(text.contains(needle), "help lacks {needle}");
    }
}

#[test]
fn natural_side_impact_gives_the_physics_in_si_and_us_units() {
    // Car 1 (nose along +x, 15 m/s) hits the middle of the left side of car 2 (standing, nose
    // along +y); equal masses, e = 0.1: momentum and restitution give V1 = 15 (1 - 1.1 / 2) =
    // 6.75 and V2 = 15 x 1.1 / 2 = 8.25 m/s. vt = 0 at contact and the impulse passes through
    // both CGs, so the no-slip impulse has no tangential part: mu_max = 0, the example's mu = 0
    // is the one admissible value, and there is no tangential impulse and no yaw.
    // The US file holds the same numbers rounded to its printed digits (1e-8 relative).
    for (file, tol) in [
        ("examples/cases/side_impact.toml", 1e-12),
        ("examples/cases/side_impact_us.toml", 1e-6),
    ] {
        let j = json_of(&pim(&["solve", file, "--format", "json"]));
        let f = |path: &str| j.pointer(path).and_then(Value::as_f64).unwrap();
        assert!(
            (f("/final/vehicle1/vx") - 6.75).abs() < tol * 10.0,
            "{file}"
        );
        assert!(
            (f("/final/vehicle2/vx") - 8.25).abs() < tol * 10.0,
            "{file}"
        );
        for p in [
            "/final/vehicle1/vy",
            "/final/vehicle2/vy",
            "/final/vehicle1/omega",
            "/final/vehicle2/omega",
            "/impulse/tangential",
        ] {
            assert!(f(p).abs() < 1e-9, "{file} {p} = {}", f(p));
        }
        assert_eq!(j["tangential"], "sticking", "{file}");
        assert_eq!(j["friction_basis"], "no_slip_impulse", "{file}");
        assert!(f("/mu_max").abs() < 1e-12, "{file}");
        assert_eq!(j["admissible"], true, "{file}");
        // Car 1 is slowed along its axis: PDOF 0 deg, 12 o'clock; car 2 is struck on its left
        // side: pushed to its right, PDOF -90 deg, 9 o'clock.
        assert!((f("/vehicles/0/delta_v_longitudinal") + 8.25).abs() < tol * 10.0);
        assert!((f("/vehicles/1/delta_v_lateral") + 8.25).abs() < tol * 10.0);
        assert!(f("/vehicles/0/pdof").abs() < 1e-9);
        assert!((f("/vehicles/1/pdof") + 90.0).abs() < 1e-9);
        assert_eq!(j["vehicles"][0]["clock"], 12);
        assert_eq!(j["vehicles"][1]["clock"], 9);
        assert!((f("/energy/loss_percent") - 49.5).abs() < 1e-6, "{file}");
    }
    // The table in US units prints mph.
    let out = pim(&[
        "solve",
        "examples/cases/side_impact_us.toml",
        "--units",
        "us",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        text.contains("speed at contact [mph]") && text.contains("33.55"),
        "{text}"
    );
}

#[test]
fn a_case_written_in_the_other_convention_says_where_everything_is() {
    // The side impact with vehicle 1's heading written as its tail (the papers' form) but read
    // in the natural form: the bodies move apart, and the message says why.
    let text = std::fs::read_to_string(repo().join("examples/cases/side_impact.toml"))
        .unwrap()
        .replace("heading = 0.0 ", "heading = 180.0 ");
    let path = write_case("side_apart.toml", &text);
    let out = pim(&["solve", &path]);
    assert_eq!(out.status.code(), Some(2));
    let msg = stderr(&out);
    assert!(msg.contains("vehicle 1's CG at (2.00, 0.00) m"), "{msg}");
    assert!(msg.contains("vehicle 2's CG at (0.90, 0.00) m"), "{msg}");
    assert!(msg.contains("with convention = \"brach\""), "{msg}");
    assert!(msg.contains("would make an impact"), "{msg}");
    // With convention = "brach" the same file is the impact of the example.
    let brach = format!("convention = \"brach\"\n{text}");
    let path = write_case("side_brach.toml", &brach);
    let j = json_of(&pim(&["solve", &path, "--format", "json"]));
    assert!((j["final"]["vehicle2"]["vx"].as_f64().unwrap() - 8.25).abs() < 1e-9);
}

#[test]
fn the_case_file_of_the_help_text_solves_as_written() {
    // A user who copies the example of `pim solve --help` gets the side impact's physics.
    let out = pim(&["solve", "--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    let start = help.find("CASE FILE (TOML").expect("CASE FILE in the help");
    let body: String = help[start..]
        .lines()
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .map(|l| format!("{}\n", &l[2..]))
        .collect();
    let path = write_case("from_help.toml", &body);
    let j = json_of(&pim(&["solve", &path, "--format", "json"]));
    assert!(
        (j["final"]["vehicle1"]["vx"].as_f64().unwrap() - 6.75).abs() < 1e-9,
        "{body}"
    );
    assert!((j["final"]["vehicle2"]["vx"].as_f64().unwrap() - 8.25).abs() < 1e-9);
    assert!(j["final"]["vehicle2"]["omega"].as_f64().unwrap().abs() < 1e-12);
}

#[test]
fn plausibility_warnings_go_to_stderr_and_the_solve_still_runs() {
    let text = example()
        .replace("heading = 60.0", "heading = 1.047")
        .replace("yaw_inertia = 2279.0", "yaw_inertia = 22790.0")
        .replace("vx = -13.01", "vx = -80.0");
    let path = write_case("implausible.toml", &text);
    let out = pim(&["solve", &path, "--format", "json"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let msg = stderr(&out);
    assert!(
        msg.contains("vehicle2.heading: 1.047 is read as degrees; it looks like radians"),
        "{msg}"
    );
    assert!(msg.contains("yaw_inertia / mass = 19.04 m^2"), "{msg}");
    assert!(msg.contains("initial.vehicle1.vx: speed 80.0 m/s"), "{msg}");
    // The example itself is plausible: no warning.
    let out = pim(&[
        "solve",
        "examples/cases/ricsac7_brach1983.toml",
        "--format",
        "json",
    ]);
    assert!(stderr(&out).is_empty(), "{}", stderr(&out));
}

#[test]
fn the_tangential_model_is_selected_by_its_coefficients() {
    let with = |coefficients: &str| {
        let text = example();
        let start = text.find("[coefficients]").unwrap();
        let end = start + text[start..].find("\n\n").unwrap_or(text.len() - start);
        format!(
            "{}[coefficients]\n{coefficients}{}",
            &text[..start],
            &text[end..]
        )
    };
    // Sliding: the same as PIM with mu = friction and em = 1.
    let t = json_of(&pim(&[
        "solve",
        &write_case(
            "tangential.toml",
            &with("e = 0.1\net = 0.0\nfriction = 0.5\n"),
        ),
        "--format",
        "json",
    ]));
    assert_eq!(t["model"]["name"], "tangential");
    assert_eq!(t["model"]["mode"], "slide");
    assert!(t["model"]["stick_ratio"].as_f64().unwrap().abs() > 0.5);
    let p = json_of(&pim(&[
        "solve",
        &write_case(
            "pim_equivalent.toml",
            &with("e = 0.1\nmu = 0.5\nem = 1.0\n"),
        ),
        "--format",
        "json",
    ]));
    assert!(p.get("model").is_none());
    for v in ["vehicle1", "vehicle2"] {
        for k in ["vx", "vy", "omega"] {
            let (a, b) = (
                t["final"][v][k].as_f64().unwrap(),
                p["final"][v][k].as_f64().unwrap(),
            );
            assert!((a - b).abs() < 1e-9, "{v}.{k}: {a} vs {b}");
        }
    }
    // Sticking with a generous limit: vt' = et vt.
    let s = json_of(&pim(&[
        "solve",
        &write_case(
            "sticking.toml",
            &with("e = 0.1\net = -0.2\nfriction = 5.0\n"),
        ),
        "--format",
        "json",
    ]));
    assert_eq!(s["model"]["mode"], "stick");
    // A mix of the two models' coefficients is refused, naming what was given.
    let out = pim(&[
        "solve",
        &write_case("mixed.toml", &with("e = 0.1\nmu = 0.5\net = 0.0\n")),
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("[coefficients] gives e, mu, et"),
        "{}",
        stderr(&out)
    );
}

/// Every example case file says in its header how to run it; the command must run as written.
#[test]
fn every_example_case_runs_as_its_header_says() {
    let dir = repo().join("examples/cases");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 8);
    for path in files {
        let text = std::fs::read_to_string(&path).unwrap();
        let name = format!(
            "examples/cases/{}",
            path.file_name().unwrap().to_str().unwrap()
        );
        let header: String = text
            .lines()
            .take_while(|l| l.starts_with('#'))
            .collect::<Vec<_>>()
            .join(" ");
        let at = header
            .find(&format!(" {name}"))
            .unwrap_or_else(|| panic!("{name}: its header gives no command"));
        let start = header[..at]
            .rfind("pim ")
            .expect("the command starts with pim");
        let args: Vec<&str> = header[start + 4..]
            .split_whitespace()
            .take_while(|w| !w.starts_with('#') && !w.starts_with('('))
            .collect();
        let out = pim(&args);
        assert!(
            out.status.success(),
            "{name}: pim {}: {}",
            args.join(" "),
            stderr(&out)
        );
    }
}

#[test]
fn an_sae_case_in_us_units_is_answered_in_its_own_frame_and_units() {
    let out = pim(&["solve", "examples/cases/tbone_sae_us.toml"]);
    assert_eq!(out.status.code(), Some(0), "{}", stderr(&out));
    let table = String::from_utf8(out.stdout).unwrap();
    for needle in [
        "frame: SAE J670",
        "vx [mph]",
        "omega [deg/s]",
        "heading of the nose [deg, clockwise]",
        "lateral, right + [mph]",
        "ft lbf",
        "lbf s",
    ] {
        assert!(table.contains(needle), "{needle}:\n{table}");
    }
    // The pickup's nose is dragged to its right by the sedan crossing from its left: in SAE's
    // frame its lateral delta-V and its yaw rate after the impact are positive (right,
    // clockwise), and the JSON (SI, natural frame) has them with the opposite sign.
    let sep = table
        .lines()
        .find(|l| l.starts_with("vehicle1  separation"))
        .unwrap();
    let v: Vec<f64> = sep
        .split_whitespace()
        .skip(2)
        .map(|x| x.parse().unwrap())
        .collect();
    assert!(v[1] > 0.0 && v[2] > 0.0, "{sep}");
    let json = pim(&[
        "solve",
        "examples/cases/tbone_sae_us.toml",
        "--format",
        "json",
    ]);
    let doc: serde_json::Value = serde_json::from_slice(&json.stdout).unwrap();
    let w = doc["final"]["vehicle1"]["omega"].as_f64().unwrap();
    assert!(
        (w.to_degrees() + v[2]).abs() < 1e-3 * v[2].abs(),
        "{w} against {}",
        v[2]
    );
}

#[test]
fn the_sensitivity_table_of_a_us_case_reads_in_mph() {
    let us = String::from_utf8_lossy(
        &pim_ok(&["sensitivity", "examples/cases/side_impact_us.toml"]).stdout,
    )
    .to_string();
    // e low (0.09): |dV1| 8.175 m/s = 18.287 mph.
    assert!(us.contains("|dV1| mph"), "{us}");
    assert!(us.contains("e     low       0.0900 |    18.287"), "{us}");
    let si = String::from_utf8_lossy(
        &pim_ok(&[
            "sensitivity",
            "examples/cases/side_impact_us.toml",
            "--units",
            "si",
        ])
        .stdout,
    )
    .to_string();
    assert!(si.contains("e     low       0.0900 |     8.175"), "{si}");
}

#[test]
fn every_diagram_key_stays_on_its_canvas() {
    // Each example drawn (solved, fitted cases with their estimates): every text of the SVG
    // starts inside the canvas, the key's last line included.
    let mut n = 0;
    for entry in std::fs::read_dir(repo().join("examples/cases")).unwrap() {
        let p = entry.unwrap().path();
        if p.extension().is_none_or(|x| x != "toml") {
            continue;
        }
        let dir = scratch_dir("key_on_canvas", &p.file_stem().unwrap().to_string_lossy());
        let svg_path = dir.join("d.svg");
        pim_ok(&[
            "draw",
            &p.display().to_string(),
            "-o",
            &svg_path.display().to_string(),
        ]);
        let svg = std::fs::read_to_string(&svg_path).unwrap();
        let attr = |tag: &str, name: &str| -> Vec<f64> {
            svg.split(&format!("<{tag} "))
                .skip(1)
                .filter_map(|t| {
                    let v = t.split(&format!(" {name}=\"")).nth(1)?;
                    v.split('"').next()?.parse().ok()
                })
                .collect()
        };
        let height = attr("svg", "height")[0];
        let width = attr("svg", "width")[0];
        for y in attr("text", "y") {
            assert!(
                y > 0.0 && y + 6.0 < height,
                "{}: text at y {y} of {height}",
                p.display()
            );
        }
        for x in attr("text", "x") {
            assert!(
                x >= 0.0 && x < width,
                "{}: text at x {x} of {width}",
                p.display()
            );
        }
        n += 1;
    }
    assert!(n >= 13, "{n} examples");
}

/// The friction line says what happens in the model solved, for every model and friction
/// class: PIM sliding, sticking (mu = mu_max), reversed, nothing sliding, the no-slip condition
/// with and without sliding; the second model sticking with et = 0 (sliding ends), sticking
/// with et != 0 (sliding continues at et vt), sliding at its limit; IMPC at its cap.
#[test]
fn the_friction_line_says_what_each_model_does() {
    let line = |args: &[&str]| -> String {
        let out = pim_ok(args);
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .find(|l| l.starts_with("friction "))
            .unwrap_or_else(|| panic!("{args:?}: no friction line"))
            .to_string()
    };
    let side = "examples/cases/side_impact.toml";
    let r7 = "examples/cases/ricsac7_brach1983.toml";
    let tang =
        std::fs::read_to_string(repo().join("examples/cases/ricsac7_tangential.toml")).unwrap();
    let with = |name: &str, from: &str, to: &str| {
        let text = tang.replace(from, to);
        assert_ne!(text, tang, "{name}: nothing replaced");
        scratch_file("friction_line", name, text)
    };
    let stick0 = with("stick0.toml", "friction = 0.8 ", "friction = 2.0 ");
    let stick = scratch_file(
        "friction_line",
        "stick_et.toml",
        tang.replace("friction = 0.8 ", "friction = 2.0 ")
            .replace("et = 0.0 ", "et = 0.3 "),
    );
    let r7_text = std::fs::read_to_string(repo().join(r7)).unwrap();
    let r7_mu = scratch_file(
        "friction_line",
        "r7_sliding.toml",
        r7_text.replace("mu = 0.968", "mu = 0.5"),
    );
    // mu at mu_max to full precision: the sticking class.
    let doc: serde_json::Value =
        serde_json::from_slice(&pim_ok(&["solve", r7, "--format", "json"]).stdout).unwrap();
    let mu_max = doc["mu_max"].as_f64().unwrap();
    let r7_stick = scratch_file(
        "friction_line",
        "r7_stick.toml",
        r7_text.replace("mu = 0.968", &format!("mu = {mu_max:?}")),
    );
    for (args, says) in [
        (vec!["solve", &r7_mu], "still sliding at separation"),
        (
            vec!["solve", &r7_stick],
            "sliding ends by separation (mu = mu_max)",
        ),
        (vec!["solve", r7], "sliding reversed"),
        (vec!["solve", side], "no sliding at all"),
        (vec!["solve", side, "--no-slip"], "no sliding at all"),
        (
            vec!["solve", r7, "--no-slip"],
            "the no-slip condition (5a) ends the sliding",
        ),
        (
            vec!["solve", &stick0],
            "sticks: the sliding at C ends by separation",
        ),
        (
            vec!["solve", &stick],
            "sliding continues at et = 0.300 times",
        ),
        (
            vec!["solve", "examples/cases/ricsac7_tangential.toml"],
            "slides throughout",
        ),
        (
            vec!["solve", "examples/cases/barrier_small_overlap_impc.toml"],
            "slides throughout",
        ),
    ] {
        let l = line(&args);
        assert!(l.contains(says), "{args:?}: {l}");
        // Only the plain PIM sticking class may say "mu = mu_max".
        if !says.contains("mu = mu_max") {
            assert!(
                !l.contains("sliding ends by separation (mu = mu_max)"),
                "{args:?}: {l}"
            );
        }
    }
}

/// Both CGs on one side of the crush plane: the side is a reading (weighted by mobility), said
/// in a warning naming [impact], the two heights and the reading taken; the case can state it
/// (`[impact] vehicle1_side`); the JSON says the side and its basis (`geometry`, `mobility`,
/// `case`).
#[test]
fn the_side_of_the_crush_surface_is_said_and_settable() {
    let case = r#"
[vehicle1]
mass = 1500.0
yaw_inertia = 2500.0
heading = 0.0
impact_point = { x = 2.0, y = 0.0 }
[vehicle2]
mass = 1500.0
yaw_inertia = 2500.0
heading = 90.0
impact_point = { x = 2.0, y = -0.5 }
[impact]
crush_angle = 0.0
[coefficients]
e = 0.1
mu = 0.3
em = 1.0
[initial]
vehicle1 = { vx = 15.0, vy = 0.0, omega = 0.0 }
vehicle2 = { vx = 0.0, vy = 10.0, omega = 0.0 }
"#;
    let json = |path: &str| -> (serde_json::Value, String) {
        let out = pim_ok(&["solve", path, "--format", "json"]);
        (serde_json::from_slice(&out.stdout).unwrap(), stderr(&out))
    };
    // Read from the heights: a warning with both heights and the reading.
    let path = scratch_file("side", "read.toml", case);
    let (v, err) = json(&path);
    assert_eq!(v["side"]["vehicle1"], "-n");
    assert_eq!(v["side"]["basis"], "mobility");
    assert!(
        err.contains(":13:15: impact.crush_angle: both centres of gravity lie on the -n side"),
        "{err}"
    );
    assert!(
        err.contains("vehicle 1 -2.000 m, vehicle 2 -0.500 m"),
        "{err}"
    );
    assert!(err.contains("vehicle1_side = \"+n\""), "{err}");
    // Stated as read: the same answer, no warning, basis `case`.
    let stated = case.replace(
        "crush_angle = 0.0",
        "crush_angle = 0.0\nvehicle1_side = \"-n\"",
    );
    let path = scratch_file("side", "stated.toml", &stated);
    let (w, err) = json(&path);
    assert_eq!(w["side"]["basis"], "case");
    assert!(!err.contains("both centres"), "{err}");
    assert_eq!(w["final"], v["final"]);
    // Stated the other way: then the vehicles do not approach.
    let other = case.replace(
        "crush_angle = 0.0",
        "crush_angle = 0.0\nvehicle1_side = \"+n\"",
    );
    let path = scratch_file("side", "other.toml", &other);
    let out = pim(&["solve", &path]);
    assert_ne!(out.status.code(), Some(0));
    assert!(stderr(&out).contains("do not approach"), "{}", stderr(&out));
    // A value that is not a side.
    let bad = case.replace(
        "crush_angle = 0.0",
        "crush_angle = 0.0\nvehicle1_side = \"up\"",
    );
    let path = scratch_file("side", "bad.toml", &bad);
    let out = pim(&["solve", &path]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        stderr(&out).contains("impact.vehicle1_side: \"up\": accepted \"+n\""),
        "{}",
        stderr(&out)
    );
    // Opposite sides: the geometry decides, no warning.
    let (g, err) = json("examples/cases/side_impact.toml");
    assert_eq!(g["side"]["basis"], "geometry");
    assert!(!err.contains("both centres"), "{err}");
    // With an estimated geometry the stated side holds at every geometry tried: stated as the
    // geometry reads it, the same fit; the proof over the geometry, which reads the side from
    // the geometry, is not attempted and says why.
    let text =
        std::fs::read_to_string(repo().join("examples/cases/ricsac6_geometry.toml")).unwrap();
    let fit = |text: &str, name: &str| -> serde_json::Value {
        let path = scratch_file("side", name, text);
        let out = pim(&["fit", &path, "--cost", "q2", "--format", "json"]);
        serde_json::from_slice(&out.stdout).unwrap()
    };
    let read = fit(&text, "geometry_read.toml");
    let stated = fit(
        &text.replacen("[impact]\n", "[impact]\nvehicle1_side = \"+n\"\n", 1),
        "geometry_stated.toml",
    );
    assert_eq!(stated["side"]["basis"], "case");
    let pairs = read["branches"].as_array().unwrap().iter();
    for (a, b) in pairs.zip(stated["branches"].as_array().unwrap()) {
        assert_eq!(a["cost"], b["cost"]);
        let proof = &b["geometry"]["search"]["proof"];
        assert_eq!(proof["status"], "not_attempted", "{proof}");
        assert!(
            proof["reason"]
                .as_str()
                .unwrap()
                .contains("states the side"),
            "{proof}"
        );
    }
}
