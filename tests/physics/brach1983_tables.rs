//! Brach 1983 Tables 3, 4, 5 and 6 recomputed from the inputs of its Table 1.
//!
//! Two sets of inputs are used:
//! - **as printed**: Table 1 exactly (d = 1.8 / 0.9 m for RICSAC 7, 1.4 / 1.6 m for RICSAC 9).
//!   Velocities then agree to 0.015 m/s, but yaw rates only to 0.06 rad/s (RICSAC 7) and
//!   0.1 rad/s (RICSAC 9), and the RICSAC 9 energy loss is 0.3-0.4 points low;
//! - **in feet**: Brach worked in US units and Table 1 rounds d to 0.1 m. With d1 = 6 ft
//!   (1.8288 m), d2 = 3 ft (0.9144 m) for RICSAC 7 and d1 = 4.5 ft (1.3716 m) for RICSAC 9,
//!   every printed number is reproduced to its printed precision (0.01 m/s, 0.01 rad/s, 0.1 % of
//!   energy, plus the rounding of the inputs), which identifies the cause of the differences.
//!   No other input was changed.
use crate::common;
use common::*;
use pim_core::*;

const COLS: [&str; 8] = ["v1x", "v1y", "w1", "dv1", "v2x", "v2y", "w2", "dv2"];
const FT: f64 = 0.3048;

fn computed(r: &ImpactReport) -> [f64; 8] {
    let s = &r.separation;
    [
        s.vehicle1.vx,
        s.vehicle1.vy,
        s.vehicle1.omega,
        r.delta_v[0].magnitude,
        s.vehicle2.vx,
        s.vehicle2.vy,
        s.vehicle2.omega,
        r.delta_v[1].magnitude,
    ]
}

/// Tolerances: (translational m/s, yaw rad/s, energy loss percentage points).
#[derive(Clone, Copy)]
struct Tol {
    v: f64,
    w: f64,
    energy: f64,
}

/// Printed precision: values are printed to 0.01 (rounding +/-0.005), inputs to 4 digits.
const TIGHT: Tol = Tol {
    v: 0.010,
    w: 0.010,
    energy: 0.10,
};

/// Compares one table; returns the worst deviations seen (v, w, energy).
fn check_table(
    file: &str,
    collision: Collision,
    initial: &Velocities,
    form: MomentForm,
    tol: Tol,
) -> [f64; 3] {
    let impact = Impact::new(collision).unwrap();
    let opts = SolveOptions {
        moment_form: form,
        ..Default::default()
    };
    let mut worst = [0.0_f64; 3];
    let rows = read_reference(file);
    assert!(!rows.is_empty(), "{file} has no rows");
    for row in rows {
        let c = Coefficients {
            e: row.num("e"),
            mu: row.num("mu"),
            em: row.num("em"),
        };
        let r = solve_forward(&impact, &c, initial, &opts).unwrap();
        let got = computed(&r);
        for (k, name) in COLS.iter().enumerate() {
            let Some(published) = row.opt(name) else {
                continue;
            };
            let (t, slot) = if name.starts_with('w') {
                (tol.w, 1)
            } else {
                (tol.v, 0)
            };
            let dev = (got[k] - published).abs();
            worst[slot] = worst[slot].max(dev);
            assert!(
                dev <= t,
                "{file} row {}: {name} computed {:.4}, published {published} (|diff| {dev:.4} > {t})",
                row.text("row"),
                got[k]
            );
        }
        if let Some(published) = row
            .0
            .get("energy_loss_percent")
            .and_then(|_| row.opt("energy_loss_percent"))
        {
            let dev = (r.energy.loss_percent - published).abs();
            worst[2] = worst[2].max(dev);
            assert!(
                dev <= tol.energy,
                "{file} row {}: energy loss computed {:.3} %, published {published} %",
                row.text("row"),
                r.energy.loss_percent
            );
        }
    }
    worst
}

fn ricsac7_feet() -> (Collision, Velocities) {
    let (mut c, v) = brach1983_ricsac7();
    c.vehicle1.d = 6.0 * FT;
    c.vehicle2.d = 3.0 * FT;
    (c, v)
}

fn ricsac9_feet() -> (Collision, Velocities) {
    let (mut c, v) = brach1983_ricsac9();
    c.vehicle1.d = 4.5 * FT;
    (c, v)
}

#[test]
fn table4_ricsac7_inputs_in_feet_to_printed_precision() {
    let (c, v) = ricsac7_feet();
    let w = check_table(
        "data/reference/brach1983_table4.csv",
        c,
        &v,
        MomentForm::Brach1983,
        TIGHT,
    );
    println!(
        "table 4 (feet): worst |dv| {:.4} m/s, |dw| {:.4} rad/s",
        w[0], w[1]
    );
}

#[test]
fn table4_ricsac7_as_printed() {
    // d rounded to 0.1 m in Table 1 moves the yaw rates by up to 0.06 rad/s.
    let tol = Tol {
        v: 0.015,
        w: 0.06,
        energy: 0.0,
    };
    let (c, v) = brach1983_ricsac7();
    let w = check_table(
        "data/reference/brach1983_table4.csv",
        c,
        &v,
        MomentForm::Brach1983,
        tol,
    );
    println!(
        "table 4 (as printed): worst |dv| {:.4}, |dw| {:.4}",
        w[0], w[1]
    );
}

#[test]
fn table4_needs_the_1983_moment_form() {
    // With the corrected moment equation the em = -0.85 / -0.70 rows of Table 4 are not reproduced:
    // the table was computed with the 1983 form, whose sign error the 1984 paper corrects.
    let (c, v) = ricsac7_feet();
    let impact = Impact::new(c).unwrap();
    let row = &read_reference("data/reference/brach1983_table4.csv")[0];
    let coef = Coefficients {
        e: row.num("e"),
        mu: row.num("mu"),
        em: row.num("em"),
    };
    let r = solve_forward(&impact, &coef, &v, &SolveOptions::default()).unwrap();
    assert!((r.separation.vehicle1.omega - row.num("w1")).abs() > 0.1);
}

#[test]
fn table5_ricsac9_inputs_in_feet_to_printed_precision() {
    let (c, v) = ricsac9_feet();
    for form in [MomentForm::Corrected, MomentForm::Brach1983] {
        let w = check_table("data/reference/brach1983_table5.csv", c, &v, form, TIGHT);
        println!(
            "table 5 (feet, {form:?}): worst {:.4} m/s, {:.4} rad/s, {:.3} %",
            w[0], w[1], w[2]
        );
    }
}

#[test]
fn table5_ricsac9_as_printed() {
    // d1 = 1.4 m instead of 4.5 ft: yaw rate of vehicle 1 up to 0.1 rad/s (2.7 %) too large,
    // which keeps 0.3-0.4 points more energy in rotation.
    let tol = Tol {
        v: 0.015,
        w: 0.10,
        energy: 0.40,
    };
    let (c, v) = brach1983_ricsac9();
    let w = check_table(
        "data/reference/brach1983_table5.csv",
        c,
        &v,
        MomentForm::Corrected,
        tol,
    );
    println!(
        "table 5 (as printed): worst {:.4} m/s, {:.4} rad/s, {:.3} %",
        w[0], w[1], w[2]
    );
}

#[test]
fn table3_nominal_solutions() {
    let rows = read_reference("data/reference/brach1983_table3.csv");
    for row in rows {
        let (collision, v, form) = match row.text("test") {
            "7" => {
                let (c, v) = ricsac7_feet();
                (c, v, MomentForm::Brach1983)
            }
            _ => {
                let (c, v) = ricsac9_feet();
                (c, v, MomentForm::Corrected)
            }
        };
        let impact = Impact::new(collision).unwrap();
        let c = Coefficients {
            e: row.num("e"),
            mu: row.num("mu"),
            em: row.num("em"),
        };
        let opts = SolveOptions {
            moment_form: form,
            ..Default::default()
        };
        let r = solve_forward(&impact, &c, &v, &opts).unwrap();
        let got = computed(&r);
        for (k, name) in COLS.iter().enumerate() {
            let p = row.num(name);
            assert!(
                (got[k] - p).abs() <= 0.01,
                "Table 3 test {}: {name} {:.4} vs {p}",
                row.text("test"),
                got[k]
            );
        }
        if let Some(p) = row.opt("energy_loss_percent") {
            assert!(
                (r.energy.loss_percent - p).abs() <= 0.1,
                "{}",
                r.energy.loss_percent
            );
        }
    }
}

#[test]
fn table6_level_averages() {
    // Table 6 averages Table 4 / 5 over the combinations at each level; recompute with the
    // sensitivity study at +/-10 %.
    let (c7, v7) = ricsac7_feet();
    let (c9, v9) = ricsac9_feet();
    let opts7 = SolveOptions {
        moment_form: MomentForm::Brach1983,
        ..Default::default()
    };
    let s7 = sensitivity(
        &Impact::new(c7).unwrap(),
        &Coefficients {
            e: 0.015,
            mu: 0.968,
            em: -0.774,
        },
        &v7,
        &opts7,
        10.0,
    )
    .unwrap();
    let s9 = sensitivity(
        &Impact::new(c9).unwrap(),
        &Coefficients {
            e: 0.467,
            mu: 0.486,
            em: 1.0,
        },
        &v9,
        &SolveOptions::default(),
        10.0,
    )
    .unwrap();
    assert_eq!(s7.cases.len(), 8);
    assert_eq!(s9.cases.len(), 4);
    let rows = read_reference("data/reference/brach1983_table6.csv");
    let mut checked = 0;
    for row in rows {
        let study = if row.text("table") == "a" { &s7 } else { &s9 };
        let name = match row.text("coefficient") {
            "e" => CoefficientName::E,
            "mu" => CoefficientName::Mu,
            _ => CoefficientName::Em,
        };
        let level = if row.text("level") == "low" {
            Level::Low
        } else {
            Level::High
        };
        let avg = study
            .averages
            .iter()
            .find(|a| a.coefficient == name && a.level == level)
            .expect("level present");
        for (col, got, tol) in [
            ("dv1", avg.delta_v1, 0.01),
            ("dv2", avg.delta_v2, 0.01),
            ("dw2", avg.delta_omega2, 0.01),
            ("energy_loss_percent", avg.energy_loss_percent, 0.15),
        ] {
            if let Some(p) = row.opt(col) {
                checked += 1;
                assert!(
                    (got - p).abs() <= tol,
                    "Table 6{} {:?} {:?} {col}: {got:.4} vs {p}",
                    row.text("table"),
                    name,
                    level
                );
            }
        }
    }
    assert!(checked >= 20, "only {checked} cells checked");
}

#[test]
fn table3_from_natural_case_files_in_us_units() {
    // The same published analyses written as a reconstructionist would: nose headings, impact
    // points in feet, mph, lb, slug ft^2 (examples/cases/ricsac{7,9}_us.toml). They must give
    // Table 3 to its printed rounding, as the papers' form does.
    let rows = read_reference("data/reference/brach1983_table3.csv");
    for row in rows {
        let test = row.text("test");
        let file = format!("examples/cases/ricsac{test}_us.toml");
        let text = std::fs::read_to_string(repo_path(&file)).unwrap();
        let case = pim_case::case::Case::from_text(&file, &text).unwrap();
        let impact = case.impact().unwrap();
        let (state, forward) = case.known_state().unwrap();
        assert!(forward);
        let opts = SolveOptions {
            moment_form: if test == "7" {
                MomentForm::Brach1983
            } else {
                MomentForm::Corrected
            },
            ..Default::default()
        };
        let r = solve_forward(&impact, &case.coefficients().unwrap(), &state, &opts).unwrap();
        let got = computed(&r);
        for (k, name) in COLS.iter().enumerate() {
            let p = row.num(name);
            assert!(
                (got[k] - p).abs() <= 0.01,
                "{file}: {name} {:.4} vs Table 3 {p}",
                got[k]
            );
        }
        if let Some(p) = row.opt("energy_loss_percent") {
            assert!((r.energy.loss_percent - p).abs() <= 0.1);
        }
    }
}
