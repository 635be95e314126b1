//! Fuzzing the parsers and the solver entry points with arbitrary and hostile input (proptest,
//! seeded): no panic, every call returns, and every error names a culprit. Inputs that once
//! broke something are kept in `tests/fuzz-corpus/` and replayed first.
use crate::mutate;
use mutate::{hostile_number, replace_number};
use pim_case::case::Case;
use pim_case::ricsac;
use pim_core::*;
use pim_studies::fitcase;
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
use std::path::Path;

fn runner(cases: u32, seed: u8) -> TestRunner {
    TestRunner::new_with_rng(
        Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}

fn repo(rel: &str) -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../..")
            .join(rel),
    )
    .unwrap()
}

/// Runs everything a case file can drive; panics only on a bug.
fn exercise_case(text: &str) {
    // PIM_FUZZ_LOG=FILE keeps the input being exercised, to catch one that hangs.
    if let Ok(p) = std::env::var("PIM_FUZZ_LOG") {
        std::fs::write(p, text).unwrap();
    }
    let case = match Case::from_text("fuzz.toml", text) {
        Ok(c) => c,
        Err(e) => {
            assert!(
                e.message.starts_with("fuzz.toml"),
                "message must name the file: {e}"
            );
            return;
        }
    };
    let Ok(impact) = case.impact() else { return };
    if let (Ok(c), Ok((state, forward))) = (case.coefficients(), case.known_state()) {
        let opts = SolveOptions::default();
        let r = if forward {
            solve_forward(&impact, &c, &state, &opts)
        } else {
            solve_backward(&impact, &c, &state, &opts)
        };
        if let Ok(r) = r {
            let _ = r.residuals(&impact);
            let _ = r.inadmissibility_reasons();
        }
        if forward {
            let _ = sensitivity(&impact, &c, &state, &opts, 10.0);
        }
    }
    if case.content.estimates.is_some() {
        for choice in [
            fitcase::CostChoice::Custom,
            fitcase::CostChoice::Preset(pim_fit::CostPreset::Q3),
        ] {
            if let (Ok(p), Ok(s)) = (
                fitcase::problem(&case, choice),
                fitcase::settings(
                    &case,
                    pim_fit::FitModel::Pim,
                    MomentForm::Corrected,
                    vec![pim_fit::MomentBranch::Zero],
                ),
            ) {
                let _ = pim_fit::fit(&p, &s);
            }
        }
    }
}

#[test]
fn corpus_of_past_failures_replays_cleanly() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tests/fuzz-corpus");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let p = entry.unwrap().path();
        if !p.is_file() {
            continue; // tests/fuzz-corpus/slow: valid inputs too slow to replay in every run
        }
        let text = std::fs::read_to_string(&p).unwrap();
        match p.extension().and_then(|e| e.to_str()) {
            Some("toml") => exercise_case(&text),
            Some("csv") => {
                let _ = ricsac::parse("corpus.csv", &text);
            }
            _ => continue,
        }
        n += 1;
    }
    assert!(n >= 1, "the corpus is empty");
}

#[test]
fn arbitrary_text_as_a_case_file_never_panics() {
    runner(400, 1)
        .run(&".{0,400}", |text| {
            exercise_case(&text);
            Ok(())
        })
        .unwrap();
}

#[test]
fn hostile_values_in_real_case_files_never_panic() {
    let bases = [
        repo("examples/cases/ricsac7_brach1983.toml"),
        repo("examples/cases/ricsac7_fit.toml"),
    ];
    runner(300, 2)
        .run(
            &(
                0..2usize,
                prop::collection::vec((0..64usize, hostile_number()), 1..4),
            ),
            |(b, edits)| {
                let mut text = bases[b].clone();
                for (k, v) in &edits {
                    text = replace_number(&text, *k, v);
                }
                exercise_case(&text);
                Ok(())
            },
        )
        .unwrap();
}

#[test]
fn mutated_ricsac_files_never_panic_and_errors_name_line_and_column() {
    let base = repo("data/ricsac.csv");
    let lines: Vec<String> = base.lines().map(str::to_string).collect();
    let strat = (
        1..lines.len(),
        0..31usize,
        prop_oneof![
            hostile_number(),
            ".{0,8}",
            Just(",".to_string()),
            Just("\"".to_string())
        ],
        any::<bool>(),
    );
    runner(400, 3)
        .run(&strat, |(line, col, value, drop_line)| {
            let mut ls = lines.clone();
            if drop_line {
                ls.remove(line);
            } else {
                let mut cells: Vec<String> = ls[line].split(',').map(str::to_string).collect();
                let c = col % cells.len();
                cells[c] = value.clone();
                ls[line] = cells.join(",");
            }
            match ricsac::parse("d.csv", &(ls.join("\n") + "\n")) {
                Ok(tests) => {
                    // Solve what parsed forwards with the Table 1B-like coefficients.
                    for t in tests.iter().take(2) {
                        if let Ok(impact) = t.impact() {
                            let _ = solve_forward(
                                &impact,
                                &Coefficients {
                                    e: 0.1,
                                    mu: 0.3,
                                    em: 1.0,
                                },
                                &t.initial(),
                                &SolveOptions::default(),
                            );
                        }
                    }
                }
                Err(e) => prop_assert!(e.message.starts_with("d.csv"), "{e}"),
            }
            Ok(())
        })
        .unwrap();
}

fn nasty() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(f64::NAN),
        Just(f64::INFINITY),
        Just(f64::NEG_INFINITY),
        Just(1e300),
        Just(-1e300),
        Just(5e-324),
        Just(0.0),
        -1e6..1e6f64,
        -30.0..30.0f64,
    ]
}

#[test]
fn solver_entry_points_never_panic_on_hostile_numbers() {
    let strat = (
        prop::array::uniform16(nasty()),
        prop::array::uniform8(nasty()),
    );
    runner(600, 4)
        .run(&strat, |(g, v)| {
            let veh = |o: usize| Vehicle {
                mass: g[o],
                yaw_inertia: g[o + 1],
                heading: g[o + 2],
                d: g[o + 3],
                phi: g[o + 4],
            };
            let collision = Collision {
                vehicle1: veh(0),
                vehicle2: veh(5),
                crush_angle: g[10],
            };
            let c = Coefficients {
                e: g[11].abs() % 1.0,
                mu: g[12],
                em: -(g[13].abs() % 1.0),
            };
            let state = Velocities::from_vector(&nalgebra::Vector6::new(
                v[0], v[1], v[2], v[3], v[4], v[5],
            ));
            if let Ok(impact) = Impact::new(collision) {
                let opts = SolveOptions::default();
                let _ = solve_forward(&impact, &c, &state, &opts);
                let _ = solve_backward(&impact, &c, &state, &opts);
                let _ = critical_friction(&impact, &c, &state, &opts);
                let _ = sensitivity(&impact, &c, &state, &opts, g[14].abs() % 100.0);
                let settings = pim_fit::FitSettings {
                    branches: vec![pim_fit::MomentBranch::Zero],
                    grid: [3, 5, 3],
                    ..Default::default()
                }
                .check()
                .unwrap();
                let p = pim_fit::FitProblem::from_preset(
                    impact,
                    pim_fit::CostPreset::Q2,
                    &state,
                    &state,
                    None,
                );
                let _ = pim_fit::fit(&p, &settings);
            }
            Ok(())
        })
        .unwrap();
}
