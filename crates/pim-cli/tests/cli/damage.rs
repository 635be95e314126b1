//! The damage through the command line: the crush beside PIM's energy loss in `pim solve` and
//! `pim fit`, the fit with the crush energy as evidence, and located messages for damage that
//! cannot be.
use crate::common;
use common::*;

const EXAMPLE: &str = "examples/cases/ricsac7_damage.toml";

fn json(out: &std::process::Output) -> serde_json::Value {
    serde_json::from_slice(&out.stdout).unwrap()
}

/// The example's crush at the Q2 fit: Neades' Appendix D profiles of RICSAC 7 (rows 7.1, 7.2)
/// integrated exactly give 24.0 and 133.6 kJ before the direction-of-force factor (by hand:
/// the Chevrolet's six depths 0..16 cm over 168 cm at A 62,400 N/m, B 230,000 N/m^2).
#[test]
fn the_example_fit_sets_the_crush_beside_the_energy_loss_and_fits_it() {
    let v = json(&pim_ok(&[
        "fit", EXAMPLE, "--cost", "q2", "--format", "json",
    ]));
    let d = &v["damage"];
    let at = &d["at_fit"];
    let e1 = at["vehicles"][0]["crush_energy"].as_f64().unwrap();
    let e2 = at["vehicles"][1]["crush_energy"].as_f64().unwrap();
    // Trapezoid of C over 1.68 m in 5 intervals, and of C^2 by the exact piecewise form.
    let c = [0.0, 0.03, 0.05, 0.10, 0.13, 0.16];
    let h = 1.68 / 5.0;
    let (mut int_c, mut int_c2) = (0.0, 0.0);
    for w in c.windows(2) {
        int_c += h * (w[0] + w[1]) / 2.0;
        int_c2 += h * (w[0] * w[0] + w[0] * w[1] + w[1] * w[1]) / 3.0;
    }
    let (a, b) = (62_400.0, 230_000.0);
    let by_hand = a * int_c + b / 2.0 * int_c2 + a * a / (2.0 * b) * 1.68;
    assert!((e1 - by_hand).abs() < 1e-9 * by_hand, "{e1} vs {by_hand}");
    assert!((e1 / 1000.0 - 24.0).abs() < 0.05, "{e1}");
    assert!((e2 / 1000.0 - 133.6).abs() < 0.05, "{e2}");
    assert_eq!(d["evidence"], true);
    let f = &d["with_energy"];
    // The energy only adds to the cost: never below the certified fit without it.
    let cost = f["cost"].as_f64().unwrap();
    let bound = f["lower_bound"].as_f64().unwrap();
    assert!(cost >= bound, "{cost} < {bound}");
    let loss = f["energy_loss"].as_f64().unwrap();
    let without = at["energy_loss"].as_f64().unwrap();
    // The crush asks for more loss than the velocities alone give; the fit moves towards it.
    assert!(loss > without, "{loss} <= {without}");
    let table = String::from_utf8(pim_ok(&["fit", EXAMPLE, "--cost", "q2"]).stdout).unwrap();
    for words in [
        "crush energy",
        "PIM's energy loss",
        "CRASH3 delta-V - PIM's",
        "fit with the crush energy as evidence",
        "held at its 45 deg value",
    ] {
        assert!(table.contains(words), "{words}: {table}");
    }
}

fn case(damage: &str) -> String {
    format!(
        r#"
[units]
stiffness = "N/cm"
crush = "cm"
[vehicle1]
mass = 1500.0
yaw_inertia = 2400.0
heading = 0.0
impact_point = {{ x = 2.1, y = 0.0 }}
length = 4.5
width = 1.7
[vehicle2]
mass = 1300.0
yaw_inertia = 2000.0
heading = 90.0
impact_point = {{ x = 0.0, y = -0.9 }}
length = 4.3
width = 1.7
[impact]
crush_angle = 0.0
[coefficients]
e = 0.1
mu = 0.2
em = 1.0
[initial]
vehicle1 = {{ vx = 15.0, vy = 0.0, omega = 0.0 }}
vehicle2 = {{ vx = 0.0, vy = 5.0, omega = 0.0 }}
{damage}
"#
    )
}

const GOOD: &str = r#"
[damage.vehicle1]
side = "front"
width = 120
depths = [20, 30, 30, 20]
a = 500
b = 30
[damage.vehicle2]
side = "right"
a = 300
b = 40
"#;

/// A solve with one measured profile: the other's crush follows from the force balance and
/// the output says so.
#[test]
fn one_sided_damage_takes_the_other_crush_from_the_force_balance() {
    let file = scratch_file("damage", "one_sided.toml", case(GOOD));
    let v = json(&pim_ok(&["solve", &file, "--format", "json"]));
    let d = &v["damage"];
    assert_eq!(d["vehicles"][1]["measured"], false);
    // A1 + B1 C1 = A2 + B2 C2 in N/cm: (500 + 30 * 20 - 300) / 40 = 20 cm.
    let c = d["vehicles"][1]["depths"][0].as_f64().unwrap();
    assert!((c - 0.20).abs() < 1e-12, "{c}");
    let table = String::from_utf8(pim_ok(&["solve", &file]).stdout).unwrap();
    assert!(table.contains("(balance)"), "{table}");
}

fn refused(name: &str, damage: &str, words: &[&str]) {
    let file = scratch_file("damage", name, case(damage));
    let out = pim(&["solve", &file]);
    assert_eq!(out.status.code(), Some(2), "{name}: {}", stderr(&out));
    let err = stderr(&out);
    for w in words {
        assert!(err.contains(w), "{name}: {w:?} not in {err}");
    }
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn damage_that_cannot_be_is_refused_with_its_place() {
    refused(
        "negative.toml",
        &GOOD.replace("[20, 30, 30, 20]", "[20, -3, 30, 20]"),
        &["damage.vehicle1.depths", "C2 = -0.03", "at least 0"],
    );
    refused(
        "deep.toml",
        &GOOD.replace("[20, 30, 30, 20]", "[20, 30, 460, 20]"),
        &["damage.vehicle1.depths", "vehicle's length"],
    );
    refused(
        "wide.toml",
        &GOOD.replace("width = 120", "width = 190"),
        &["damage.vehicle1.width", "wider than the vehicle's width"],
    );
    refused(
        "b_zero.toml",
        &GOOD.replace("b = 30", "b = 0"),
        &["damage.vehicle1.b", "above 0"],
    );
    refused(
        "huge_a.toml",
        &GOOD.replace("a = 500", "a = 1e300"),
        &["damage.vehicle1.a", "beyond any vehicle's stiffness"],
    );
    refused(
        "no_stiffness.toml",
        &GOOD.replace("a = 500\n", ""),
        &["damage.vehicle1", "a: missing", "stiffness"],
    );
    refused(
        "no_side.toml",
        &GOOD.replace("side = \"front\"\n", ""),
        &["damage.vehicle1", "side: missing"],
    );
    refused(
        "bad_side.toml",
        &GOOD.replace("\"front\"", "\"roof\""),
        &["damage.vehicle1.side", "\"roof\""],
    );
    refused(
        "unmeasured.toml",
        &GOOD.replace("width = 120\ndepths = [20, 30, 30, 20]\n", ""),
        &["no vehicle's crush is measured"],
    );
    refused(
        "sigma.toml",
        &GOOD.replace("b = 30\n", "b = 30\ndepth_sigma = -1\n"),
        &["damage.vehicle1.depth_sigma"],
    );
    refused(
        "unit.toml",
        &GOOD.replace("b = 30\n", "b = 30\nthickness = 3\n"),
        &["thickness"],
    );
}

/// `pim batch data/ricsac.csv --damage data/ricsac_vehicles.csv`: every test's crush beside
/// its Q2 fit, the faces from phi and the outlines, a profile's energy by hand, and the
/// comparison over the eleven tests as data/README.md states it (crush 1.06 times the loss).
#[test]
fn the_ricsac_batch_with_its_crush() {
    let dir = scratch_dir("damage", "ricsac");
    let out = dir.join("out");
    pim_ok(&[
        "batch",
        "data/ricsac.csv",
        "--cost",
        "q2",
        "--damage",
        "data/ricsac_vehicles.csv",
        "--out",
        out.to_str().unwrap(),
    ]);
    for f in [
        "damage.txt",
        "damage.csv",
        "damage.json",
        "crush_energy.svg",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let text = std::fs::read_to_string(out.join("damage.csv")).unwrap();
    let mut rdr = csv::Reader::from_reader(text.as_bytes());
    let head = rdr.headers().unwrap().clone();
    let col = |name: &str| head.iter().position(|h| h == name).unwrap();
    let rows: Vec<csv::StringRecord> = rdr.records().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 11);
    let faces: Vec<String> = rows
        .iter()
        .map(|r| format!("{}/{}", &r[col("face1")], &r[col("face2")]))
        .collect();
    assert_eq!(
        faces,
        [
            "front/right",
            "front/rear",
            "front/rear",
            "front/rear",
            "front/right",
            "front/right",
            "front/right",
            "front/right",
            "front/right",
            "front/front",
            "front/front"
        ]
    );
    let num = |r: &csv::StringRecord, c: &str| r[col(c)].parse::<f64>().unwrap();
    // Test 3, the Torino's front (Neades' row 3.1): L 76 cm, C 5 5 4 4 5 6 cm, A 624 N/cm,
    // B 23 N/cm^2, integrated exactly; the CSV holds it times its direction-of-force factor.
    let c = [0.05, 0.05, 0.04, 0.04, 0.05, 0.06];
    let h = 0.76 / 5.0;
    let (a, b) = (62_400.0, 230_000.0);
    let mut e = a * a / (2.0 * b) * 0.76;
    for w in c.windows(2) {
        e += h
            * (a * (w[0] + w[1]) / 2.0 + b / 2.0 * (w[0] * w[0] + w[0] * w[1] + w[1] * w[1]) / 3.0);
    }
    let t3 = &rows[1];
    assert_eq!(&t3[col("test")], "3");
    let got = num(t3, "crush_energy1_j") / num(t3, "pdof_factor1");
    assert!((got - e).abs() < 1e-9 * e, "{got} vs {e}");
    let crush: f64 = rows.iter().map(|r| num(r, "crush_energy_j")).sum();
    let loss: f64 = rows.iter().map(|r| num(r, "q2_energy_loss_j")).sum();
    assert!((crush / loss - 1.06).abs() < 0.005, "{}", crush / loss);
    // Neades' Table 5.3 beside them: test 7's Brach & Smith delta-V.
    let t7 = &rows[5];
    assert_eq!(&t7[col("test")], "7");
    assert!((num(t7, "brach_smith_dv2_mps") - 8.81).abs() < 1e-12);
    // Every fit with the crush as evidence is at or above the certified fit without it.
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("damage.json")).unwrap()).unwrap();
    for r in json["records"].as_array().unwrap() {
        let f = &r["damage"]["with_energy"];
        assert!(f["cost"].as_f64().unwrap() >= f["lower_bound"].as_f64().unwrap());
    }
}

/// A batch of case files carries each case's damage on its best record (JSON lines).
#[test]
fn a_batch_of_case_files_carries_the_damage() {
    let out = pim_ok(&["batch", EXAMPLE, "--cost", "q2", "--format", "json"]);
    let lines: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    let best: Vec<&serde_json::Value> = lines.iter().filter(|r| r["best"] == true).collect();
    assert_eq!(best.len(), 1);
    assert!(best[0]["damage"]["with_energy"]["energy_z"].is_number());
    assert!(lines
        .iter()
        .filter(|r| r["best"] == false)
        .all(|r| r.get("damage").is_none()));
}
