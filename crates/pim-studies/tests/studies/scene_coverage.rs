//! The whole reconstruction and its uncertainty study on simulated crashes written as case
//! files, as a reconstructionist would write them: random admissible impacts, both vehicles run
//! out to rest on the road's true friction, the scene measured with noise (rest positions and
//! headings, two marks each, the directions and yaw rates at contact), in a third of the cases
//! the road friction stated with its spread (`friction_sigma`, the stated value drawn about the
//! truth), in another third the crush measured (CRASH3 profiles whose energy is the impact's
//! true loss, the depths and the stiffness stated with their spread). Each case is read,
//! reconstructed and studied as `pim fit` and `pim uncertainty` do it.
//!
//! Asserted: the reported chi-square is never above the truth's (the truth is one of the states
//! searched over), no consistent case is refused, and the 90 % intervals of the contact speeds
//! hold the truth in 85-95 % of the cases (the full run of 200 crashes, `--ignored`; the suite
//! runs 12).
use crate::common;

use common::{
    collision_sections, contact_evidence, described, impact, normal, on_friction, truth_cost,
};

use pim_case::case::Case;
use pim_core::{solve_forward, VehicleId, Velocities};
use pim_studies::damage_fit::CrushEnergy;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::fmt::Write;

const SIGMA_REST: f64 = 0.05;
const SIGMA_HEADING_DEG: f64 = 1.0;
const SIGMA_MARK: f64 = 0.05;
const FRICTION_SIGMA: f64 = 0.05;
/// Crush depth's standard deviation, in; the stiffness's, a fraction of it.
const SIGMA_DEPTH_IN: f64 = 1.0;
const SIGMA_STIFFNESS: f64 = 0.1;

/// What the case states besides the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Variant {
    Plain,
    Friction,
    Crush,
}

/// A simulated crash as a case file, and its truth.
struct Simulated {
    text: String,
    contact: Velocities,
    separation: Velocities,
    /// The road's true friction.
    friction: f64,
}

/// One vehicle's `[runout.vehicleN]` section (SI) with random wheels.
fn runout_section(rng: &mut StdRng, k: usize) -> String {
    let wheelbase = rng.random_range(2.3..3.1);
    let mut s = format!(
        "[runout.vehicle{}]\nwheelbase = {wheelbase:.3}\ntrack = {:.3}\ncg_to_front_axle = {:.3}\n\
         saturation_angle = {:.2}\nrolling_resistance = {:.4}\n",
        k + 1,
        rng.random_range(1.4..1.65),
        wheelbase * rng.random_range(0.38..0.55),
        rng.random_range(6.0..14.0),
        rng.random_range(0.01..0.02),
    );
    if rng.random_bool(0.5) {
        writeln!(s, "cg_height = {:.3}", rng.random_range(0.45..0.65)).unwrap();
    }
    match rng.random_range(0..3) {
        0 => s.push_str("wheels = \"locked\"\n"),
        1 => writeln!(
            s,
            "wheels = \"rolling\"\nbraking = {:.2}",
            rng.random_range(0.05..0.6)
        )
        .unwrap(),
        _ => {
            let names = ["front_left", "front_right", "rear_left", "rear_right"];
            let each: Vec<String> = names
                .iter()
                .map(|n| {
                    if rng.random_bool(0.4) {
                        format!("{n} = \"locked\"")
                    } else {
                        format!("{n} = {:.2}", rng.random_range(0.0..0.6))
                    }
                })
                .collect();
            writeln!(s, "wheels = {{ {} }}", each.join(", ")).unwrap();
        }
    }
    s
}

/// The damaged face of vehicle `id` (where the impact centre lies seen from its CG) and the
/// damaged width on it, in.
fn face(impact: &pim_core::Impact, id: VehicleId) -> (&'static str, f64) {
    let g = impact.cg_positions()[id.index()];
    let h = impact.nose_heading(id).to_radians();
    let (s, c) = h.sin_cos();
    // The impact centre (the origin) in the body frame: x forward, y left.
    let (px, py) = (-g[0], -g[1]);
    let (bx, by) = (c * px + s * py, -s * px + c * py);
    let angle = by.atan2(bx).to_degrees();
    if angle.abs() <= 45.0 {
        ("front", 55.0)
    } else if angle.abs() >= 135.0 {
        ("rear", 55.0)
    } else if angle > 0.0 {
        ("left", 90.0)
    } else {
        ("right", 90.0)
    }
}

/// The `[damage]` sections: uniform depths `depth` (in) on both vehicles, measured as `depths`.
fn damage_sections(
    faces: &[(&str, f64); 2],
    stiffness: &[(f64, f64); 2],
    depths: &[[f64; 6]; 2],
) -> String {
    let mut s = String::from("[damage]\nrelation = \"energy_loss\"\n");
    for k in 0..2 {
        let (side, width) = faces[k];
        let (a, b) = stiffness[k];
        let d: Vec<String> = depths[k].iter().map(|x| format!("{x:.2}")).collect();
        write!(
            s,
            "\n[damage.vehicle{}]\nside = \"{side}\"\nwidth = {width}\ndepths = [{}]\na = {a:.2}\n\
             b = {b:.3}\na_sigma = {:.2}\nb_sigma = {:.3}\ndepth_sigma = {SIGMA_DEPTH_IN}\n",
            k + 1,
            d.join(", "),
            SIGMA_STIFFNESS * a,
            SIGMA_STIFFNESS * b,
        )
        .unwrap();
    }
    s
}

/// A case of seed `seed` (`None`: the draw is no admissible crash, a run-out shorter than a
/// metre, or a loss the crush cannot carry).
fn simulated(seed: u64, variant: Variant) -> Option<Simulated> {
    let mut rng = StdRng::seed_from_u64(seed);
    let ri = impact::random_impact_with(&mut rng, 4.0..18.0)?;
    let report = solve_forward(&ri.impact, &ri.truth, &ri.x, &ri.opts).ok()?;
    if !report.admissibility.admissible {
        return None;
    }
    let sep = report.separation;
    let friction = rng.random_range(0.45..0.9);
    let stated = match variant {
        Variant::Friction => (friction + FRICTION_SIGMA * normal(&mut rng)).max(0.2),
        _ => friction,
    };
    let units = if variant == Variant::Crush {
        "stiffness = \"lbf/in\"\ncrush = \"in\"\n"
    } else {
        ""
    };
    let mut head = collision_sections(seed, &ri, units);
    head.push_str(&contact_evidence(&ri, &mut rng));
    write!(head, "\n[runout]\nfriction = {stated:.6}\n").unwrap();
    if variant == Variant::Friction {
        writeln!(head, "friction_sigma = {FRICTION_SIGMA}").unwrap();
    }
    for k in 0..2 {
        head.push('\n');
        head.push_str(&runout_section(&mut rng, k));
    }
    // Each vehicle run out on the true friction, with the chassis the case describes.
    let cr = described(&head);
    let mut scene = String::new();
    for (k, v) in cr.reconstruction.scene.iter().enumerate() {
        let chassis = on_friction(v, friction);
        let s = if k == 0 { sep.vehicle1 } else { sep.vehicle2 };
        let start = pim_runout::Motion {
            vx: s.vx,
            vy: s.vy,
            yaw_rate: s.omega,
            ..v.pose
        };
        let run = pim_runout::simulate(&chassis, &start, &pim_runout::Settings::default()).ok()?;
        if run.distance < 1.0 || run.end != pim_runout::End::Rest {
            return None;
        }
        let marks: Vec<String> = [0.3, 0.6]
            .iter()
            .map(|f| {
                let m = run.at(f * run.time);
                format!(
                    "{{ x = {:.6}, y = {:.6}, sigma = {SIGMA_MARK} }}",
                    m.x + SIGMA_MARK * normal(&mut rng),
                    m.y + SIGMA_MARK * normal(&mut rng)
                )
            })
            .collect();
        write!(
            scene,
            "\n[scene.vehicle{}]\nrest = {{ x = {:.6}, y = {:.6}, heading = {:.6} }}\n\
             rest_sigma = {{ x = {SIGMA_REST}, y = {SIGMA_REST}, heading = {SIGMA_HEADING_DEG} }}\n\
             marks = [{}]\n",
            k + 1,
            run.rest.x + SIGMA_REST * normal(&mut rng),
            run.rest.y + SIGMA_REST * normal(&mut rng),
            (run.rest.heading.to_degrees() + SIGMA_HEADING_DEG * normal(&mut rng))
                .rem_euclid(360.0),
            marks.join(", ")
        )
        .unwrap();
    }
    let mut text = format!("{head}{scene}");
    if variant == Variant::Crush {
        let faces = [
            face(&ri.impact, VehicleId::One),
            face(&ri.impact, VehicleId::Two),
        ];
        let stiffness: [(f64, f64); 2] =
            std::array::from_fn(|_| (rng.random_range(120.0..320.0), rng.random_range(2.5..9.0)));
        // The true depth: where the crush energy of both profiles (with their PDOF factors at
        // the true impulse) equals the impact's true loss.
        let u = pim_fit::state_vector(&ri.x, &sep);
        let residual = |depth: f64| -> Option<f64> {
            let t = format!(
                "{text}\n{}",
                damage_sections(&faces, &stiffness, &[[depth; 6]; 2])
            );
            let case = Case::from_text("simulated.toml", &t).ok()?;
            let (term, _) = CrushEnergy::of_case(&case, &ri.impact).ok()?;
            pim_reconstruct::StateEvidence::residual(&term?, &u).map(|r| r.0)
        };
        let (mut lo, mut hi) = (0.5, 60.0);
        let (r_lo, r_hi) = (residual(lo)?, residual(hi)?);
        if r_lo.signum() == r_hi.signum() {
            return None;
        }
        for _ in 0..60 {
            let mid = 0.5 * (lo + hi);
            if residual(mid)?.signum() == r_lo.signum() {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let depth = 0.5 * (lo + hi);
        let measured: [[f64; 6]; 2] = std::array::from_fn(|_| {
            std::array::from_fn(|_| (depth + SIGMA_DEPTH_IN * normal(&mut rng)).max(0.0))
        });
        let stated = stiffness.map(|(a, b)| {
            (
                a * (1.0 + SIGMA_STIFFNESS * normal(&mut rng)),
                b * (1.0 + SIGMA_STIFFNESS * normal(&mut rng)),
            )
        });
        text.push('\n');
        text.push_str(&damage_sections(&faces, &stated, &measured));
    }
    Some(Simulated {
        text,
        contact: ri.x,
        separation: sep,
        friction,
    })
}

/// What one case gave: the truth's and the answer's chi-square, whether each contact speed's
/// 90 % interval holds the truth.
struct Result {
    seed: u64,
    variant: Variant,
    truth: f64,
    found: Option<f64>,
    covered: [bool; 2],
}

fn run_case(seed: u64, variant: Variant, draws: usize) -> Option<Result> {
    let s = simulated(seed, variant)?;
    let case = Case::from_text(&format!("simulated_{seed}.toml"), &s.text).expect("a valid case");
    let truth = truth_cost(&case, &s.contact, &s.separation, s.friction);
    let study = pim_studies::reconstruct_study::run(
        &case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
        draws,
        seed,
        &pim_studies::watch::Unwatched,
    );
    let (found, covered) = match &study {
        Ok((study, done)) => {
            let found = done.outcome.best.as_ref().map(|b| b.chi_square);
            let truth_speeds = [s.contact.vehicle1.speed(), s.contact.vehicle2.speed()];
            let covered = std::array::from_fn(|k| {
                // The interval reported: the draws' widened to the profile's.
                study
                    .intervals
                    .get(&format!("vehicle{}.speed_at_contact", k + 1))
                    .is_some_and(|[lo, hi]| *lo <= truth_speeds[k] && truth_speeds[k] <= *hi)
            });
            (found, covered)
        }
        Err(e) => {
            eprintln!("seed {seed} ({variant:?}): {e}");
            (None, [false, false])
        }
    };
    Some(Result {
        seed,
        variant,
        truth,
        found,
        covered,
    })
}

/// `crashes` cases from `first_seed`, the variants in turn, `draws` draws each.
fn sweep(crashes: usize, first_seed: u64, draws: usize) -> Vec<Result> {
    use rayon::prelude::*;
    let variants = [Variant::Plain, Variant::Friction, Variant::Crush];
    let mut chosen = Vec::new();
    let mut seed = first_seed;
    while chosen.len() < crashes {
        let variant = variants[chosen.len() % 3];
        if simulated(seed, variant).is_some() {
            chosen.push((seed, variant));
        }
        seed += 1;
    }
    chosen
        .par_iter()
        .filter_map(|&(seed, variant)| {
            let r = run_case(seed, variant, draws)?;
            eprintln!(
                "seed {seed} ({variant:?}): truth {:.3}, found {:?}, covered {:?}",
                r.truth, r.found, r.covered
            );
            Some(r)
        })
        .collect()
}

/// Every case answered, none above the truth's chi-square; the coverage rate.
fn check(results: &[Result]) -> f64 {
    let mut failures = Vec::new();
    for r in results {
        match r.found {
            Some(f) if f <= r.truth + 1e-6 * (1.0 + r.truth) => {}
            other => failures.push(format!(
                "seed {} ({:?}): chi-square {other:?} against the truth's {:.4}",
                r.seed, r.variant, r.truth
            )),
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    let covered = results
        .iter()
        .flat_map(|r| r.covered)
        .filter(|c| *c)
        .count();
    let n = 2 * results.len();
    for v in [Variant::Plain, Variant::Friction, Variant::Crush] {
        let of: Vec<&Result> = results.iter().filter(|r| r.variant == v).collect();
        let c = of.iter().flat_map(|r| r.covered).filter(|c| *c).count();
        eprintln!("{v:?}: {c} of {} intervals hold the truth", 2 * of.len());
    }
    eprintln!("coverage {covered}/{n} = {:.3}", covered as f64 / n as f64);
    covered as f64 / n as f64
}

/// The case as written reads back the simulated collision: the same centres of mass, crush
/// normal and side, so the truth is the case's truth.
#[test]
fn the_written_case_is_the_simulated_collision() {
    let mut checked = 0;
    for seed in 1.. {
        if checked == 6 {
            break;
        }
        let mut rng = StdRng::seed_from_u64(seed);
        let Some(ri) = impact::random_impact_with(&mut rng, 4.0..18.0) else {
            continue;
        };
        let Some(s) = simulated(seed, [Variant::Plain, Variant::Crush][checked % 2]) else {
            continue;
        };
        let case = Case::from_text("simulated.toml", &s.text).unwrap();
        let read = case.impact().unwrap();
        for k in 0..2 {
            for j in 0..2 {
                assert!((read.cg_positions()[k][j] - ri.impact.cg_positions()[k][j]).abs() < 1e-6);
            }
        }
        let (a, b) = (read.normal(), ri.impact.normal());
        assert!(
            (a[0] - b[0]).abs() < 1e-9 && (a[1] - b[1]).abs() < 1e-9,
            "seed {seed}"
        );
        assert!(
            (read.side() - ri.impact.side()).abs() < 1e-12,
            "seed {seed}"
        );
        checked += 1;
    }
}

/// 12 cases (4 of each kind), 40 draws: every one answered at no more than the truth's
/// chi-square; the intervals hold the truth in most (a binomial 90 % gives fewer than 17 of
/// 24 with probability 0.2 %).
#[test]
#[ignore = "long: tests/long runs it"]
fn simulated_cases_are_answered_and_their_intervals_cover() {
    let results = sweep(12, 7_000, 40);
    assert_eq!(results.len(), 12);
    let rate = check(&results);
    assert!(rate >= 17.0 / 24.0, "coverage {rate}");
}

/// The full figure: 200 cases (a third each plain, with the friction fitted, with the crush),
/// 100 draws each: the 90 % intervals of the contact speeds hold the truth in 85-95 %.
#[test]
#[ignore]
fn simulated_cases_200() {
    let results = sweep(200, 70_000, 100);
    assert_eq!(results.len(), 200);
    let rate = check(&results);
    assert!((0.85..=0.95).contains(&rate), "coverage {rate}");
}

/// Two cases the search once refused (its first six refinements all ended far above their
/// linearised bounds: short, slow, spinning run-outs of 1.3 to 8 m whose scenes alone fit other
/// counts of turns better); they are answered below the truth's chi-square.
#[test]
#[ignore = "long: tests/long runs it"]
fn cases_whose_linearisation_does_not_hold_are_answered() {
    for (seed, variant) in [(70_000, Variant::Plain), (71_222, Variant::Crush)] {
        let r = run_case(seed, variant, 4).expect("drawn");
        check(std::slice::from_ref(&r));
    }
}

/// Writes the simulated case of `SEED` (and `VARIANT`: Plain, Friction or Crush) into the
/// temporary folder as `simulated_SEED.toml` and prints its truth, to look at one case.
#[test]
#[ignore]
fn write_a_simulated_case() {
    let seed = common::seed_from_env();
    let variant = match std::env::var("VARIANT").as_deref() {
        Ok("Friction") => Variant::Friction,
        Ok("Crush") => Variant::Crush,
        _ => Variant::Plain,
    };
    let s = simulated(seed, variant).expect("an admissible crash");
    common::write_with_truth(
        &format!("simulated_{seed}"),
        &s.text,
        (&s.contact, &s.separation, s.friction),
    );
}
