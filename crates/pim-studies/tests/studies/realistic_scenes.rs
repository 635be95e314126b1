//! The whole reconstruction and its uncertainty study on realistic simulated crashes, written
//! as case files as a reconstructionist writes them: contact speeds of 18 to 49 mph, each
//! vehicle's wheels one of the states a crash leaves them in (locked; ABS-braked, rolling with a
//! braking share of 0.7-0.95; free rolling, rolling resistance 0.015; steered, rolling with a
//! steer angle of 4-15 degrees either way; one wheel jammed by the crush, the others free),
//! both vehicles run out to rest (up to 100 m) by the tests' independent reference model of the
//! run-out (Dormand-Prince 8(5,3) at 1e-11, not pim-runout's integrator) on the road's true
//! friction, the scene measured with a total station's noise (rests to 0.15 m and 2 degrees),
//! marks (two points the CG passed) for half the vehicles, an EDR speed for half the crashes,
//! the road friction stated exactly or, for half, with its spread (`friction_sigma`, the value
//! stated drawn about the truth). The geometry at contact is the truth's.
//!
//! Asserted: no case is refused; the reported chi-square is never above the truth's (the
//! truth is one of the states searched over; its run-outs are pim-runout's from the true
//! separation state, which follow the reference's to millimetres); the 90 % intervals of the
//! contact speeds hold the truth in 85-95 % of the cases (the full run of 200, `--ignored`; the
//! suite runs 12, every wheel state on both vehicles).
use crate::common;

use common::runout::Reference;
use common::{collision_sections, contact_evidence, described, impact, normal, on_friction};
use pim_case::case::Case;
use pim_core::{solve_forward, VehicleId, Velocities};
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::f64::consts::TAU;
use std::fmt::Write;

/// A total station's rest position (m) and heading (deg), a mark's position (m).
const SIGMA_REST: f64 = 0.15;
const SIGMA_HEADING_DEG: f64 = 2.0;
const SIGMA_MARK: f64 = 0.2;
/// An EDR's speed, m/s (about 1 mph).
const SIGMA_EDR: f64 = 0.45;
const FRICTION_SIGMA: f64 = 0.05;

/// The state a crash leaves a vehicle's wheels in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Wheels {
    Locked,
    Abs,
    Rolling,
    Steered,
    Jammed,
}

const WHEELS: [Wheels; 5] = [
    Wheels::Locked,
    Wheels::Abs,
    Wheels::Rolling,
    Wheels::Steered,
    Wheels::Jammed,
];

/// A simulated crash as a case file, and its truth.
pub(crate) struct Simulated {
    pub(crate) text: String,
    pub(crate) contact: Velocities,
    pub(crate) separation: Velocities,
    /// The road's true friction.
    pub(crate) friction: f64,
    /// Each run-out's length (m) and turns (the reference's).
    distance: [f64; 2],
    turns: [f64; 2],
}

/// One vehicle's `[runout.vehicleN]` section (SI) with the wheels `wheels`.
fn runout_section(rng: &mut StdRng, k: usize, wheels: Wheels) -> String {
    let wheelbase = rng.random_range(2.5..3.0);
    let mut s = format!(
        "[runout.vehicle{}]\nwheelbase = {wheelbase:.3}\ntrack = {:.3}\ncg_to_front_axle = {:.3}\n\
         cg_height = {:.3}\nrolling_resistance = 0.015\n",
        k + 1,
        rng.random_range(1.5..1.65),
        wheelbase * rng.random_range(0.38..0.5),
        rng.random_range(0.5..0.65),
    );
    match wheels {
        Wheels::Locked => s.push_str("wheels = \"locked\"\n"),
        Wheels::Abs => writeln!(
            s,
            "wheels = \"rolling\"\nbraking = {:.2}",
            rng.random_range(0.7..0.95)
        )
        .unwrap(),
        Wheels::Rolling => s.push_str("wheels = \"rolling\"\nbraking = 0.0\n"),
        Wheels::Steered => {
            let sign = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            writeln!(
                s,
                "wheels = \"rolling\"\nbraking = {:.2}\nsteer = {:.1}",
                rng.random_range(0.0..0.3),
                sign * rng.random_range(4.0..15.0)
            )
            .unwrap()
        }
        Wheels::Jammed => {
            let names = ["front_left", "front_right", "rear_left", "rear_right"];
            let jammed = rng.random_range(0..4);
            let each: Vec<String> = names
                .iter()
                .enumerate()
                .map(|(i, n)| {
                    let state = if i == jammed { "locked" } else { "rolling" };
                    format!("{n} = \"{state}\"")
                })
                .collect();
            writeln!(s, "wheels = {{ {} }}\nbraking = 0.0", each.join(", ")).unwrap();
        }
    }
    s
}

/// The crash of `seed` with the wheels `wheels` (`None`: no admissible crash, or a run-out
/// shorter than a metre, longer than 100 m or not at rest within a minute). With `verge`, a
/// friction zone of 55-75 % of the road's friction lies square across vehicle 2's path from
/// half way along it (as the road's run-out would go), both vehicles run out on it, and the
/// case states it.
pub(crate) fn simulated(seed: u64, wheels: [Wheels; 2], verge: bool) -> Option<Simulated> {
    simulated_as(seed, wheels, verge, false)
}

/// [`simulated`], with the scene `measured` as a survey gives it: each rest by two tyres
/// ([`measured_scene`]), the marks left by a tyre, a yaw mark traced along a tyre's path.
/// The crash and its run-outs are the same as unmeasured.
pub(crate) fn simulated_as(
    seed: u64,
    wheels: [Wheels; 2],
    verge: bool,
    measured: bool,
) -> Option<Simulated> {
    let mut rng = StdRng::seed_from_u64(seed);
    let ri = impact::random_impact_with(&mut rng, 8.0..22.0)?;
    let report = solve_forward(&ri.impact, &ri.truth, &ri.x, &ri.opts).ok()?;
    if !report.admissibility.admissible {
        return None;
    }
    let sep = report.separation;
    let friction = rng.random_range(0.5..0.9);
    let spread = rng.random_bool(0.5);
    let stated = if spread {
        (friction + FRICTION_SIGMA * normal(&mut rng)).max(0.2)
    } else {
        friction
    };
    let mut head = collision_sections(seed, &ri, "");
    head.push_str(&contact_evidence(&ri, &mut rng));
    // An EDR for half the crashes: the speed along the heading, constant before contact.
    if rng.random_bool(0.5) {
        let id = if rng.random_bool(0.5) {
            VehicleId::One
        } else {
            VehicleId::Two
        };
        let v = if id == VehicleId::One {
            ri.x.vehicle1
        } else {
            ri.x.vehicle2
        };
        let f = ri.impact.forward_axis(id);
        let along = v.vx * f[0] + v.vy * f[1];
        write!(
            head,
            "\n[pre_impact.vehicle{}]\nedr = [ {{ speed = {:.4}, time = 0.5, deceleration = 0.0, \
             sigma = {SIGMA_EDR} }} ]\n",
            id.index() + 1,
            along + SIGMA_EDR * normal(&mut rng)
        )
        .unwrap();
    }
    write!(head, "\n[runout]\nfriction = {stated:.6}\n").unwrap();
    if spread {
        writeln!(head, "friction_sigma = {FRICTION_SIGMA}").unwrap();
    }
    for (k, w) in wheels.iter().enumerate() {
        head.push('\n');
        head.push_str(&runout_section(&mut rng, k, *w));
    }
    // Each vehicle run out by the reference model on the true friction, with the chassis the
    // case describes.
    let cr = described(&head);
    let start_of = |k: usize, v: &pim_reconstruct::SceneVehicle| {
        let s = if k == 0 { sep.vehicle1 } else { sep.vehicle2 };
        pim_runout::Motion {
            vx: s.vx,
            vy: s.vy,
            yaw_rate: s.omega,
            ..v.pose
        }
    };
    let zone = if verge {
        let v = &cr.reconstruction.scene[1];
        let zone = verge_across(v, start_of(1, v), friction, &mut rng);
        let corners: Vec<String> = zone
            .corners
            .iter()
            .map(|c| format!("[{:.4}, {:.4}]", c[0], c[1]))
            .collect();
        write!(
            head,
            "\n[[runout.zones]]\nname = \"verge\"\nfriction = {:.4}\ncorners = [ {} ]\n",
            zone.friction,
            corners.join(", ")
        )
        .unwrap();
        Some(zone)
    } else {
        None
    };
    let mut scene = String::new();
    let (mut distance, mut turns) = ([0.0; 2], [0.0; 2]);
    for (k, v) in cr.reconstruction.scene.iter().enumerate() {
        let mut chassis = on_friction(v, friction);
        chassis.zones.extend(zone.clone());
        let start = start_of(k, v);
        let reference = Reference::new(&chassis);
        let run = reference.run_out(&start);
        if !run.stopped || !(1.0..=100.0).contains(&run.distance) {
            return None;
        }
        distance[k] = run.distance;
        turns[k] = (run.rest[2] - start.heading) / TAU;
        let seen = Seen {
            reference: &reference,
            chassis: &chassis,
            start: &start,
            rest: run.rest,
            time: run.time,
        };
        scene.push_str(&if measured {
            measured_scene(k, &seen, &mut rng)
        } else {
            cg_scene(k, &seen, &mut rng)
        });
    }
    Some(Simulated {
        text: format!("{head}{scene}"),
        contact: ri.x,
        separation: sep,
        friction,
        distance,
        turns,
    })
}

/// What a scene shows of one vehicle's true run-out.
struct Seen<'a> {
    reference: &'a Reference<'a>,
    chassis: &'a pim_runout::Chassis,
    start: &'a pim_runout::Motion,
    /// Its rest, `[x, y, heading]`.
    rest: [f64; 3],
    /// The run-out's duration, s.
    time: f64,
}

impl Seen<'_> {
    /// Where wheel `i` (front left, front right, rear left, rear right) touches the road at
    /// `t` into the run-out (the reference's pose).
    fn tyre(&self, i: usize, t: f64) -> [f64; 2] {
        let p = self.reference.pose_at(self.start, t);
        on_ground([p[0], p[1], p[2]], self.chassis.wheel_position(i))
    }
}

/// The point `b` of a vehicle (m ahead of its CG, m to its left) at the pose `p`.
fn on_ground(p: [f64; 3], b: [f64; 2]) -> [f64; 2] {
    let (s, c) = p[2].sin_cos();
    [p[0] + c * b[0] - s * b[1], p[1] + s * b[0] + c * b[1]]
}

/// Vehicle `k`'s scene as the CG's: its rest and heading, for half the vehicles two marks the
/// CG passed (30 % and 60 % of the way through the run-out in time).
fn cg_scene(k: usize, seen: &Seen, rng: &mut StdRng) -> String {
    let mut scene = String::new();
    let mut marks = Vec::new();
    if rng.random_bool(0.5) {
        for f in [0.3, 0.6] {
            let m = seen.reference.pose_at(seen.start, f * seen.time);
            marks.push(format!(
                "{{ x = {:.4}, y = {:.4}, sigma = {SIGMA_MARK} }}",
                m[0] + SIGMA_MARK * normal(rng),
                m[1] + SIGMA_MARK * normal(rng)
            ));
        }
    }
    let rest = seen.rest;
    write!(
        scene,
        "\n[scene.vehicle{}]\nrest = {{ x = {:.4}, y = {:.4}, heading = {:.3} }}\n\
         rest_sigma = {{ x = {SIGMA_REST}, y = {SIGMA_REST}, heading = {SIGMA_HEADING_DEG} }}\n",
        k + 1,
        rest[0] + SIGMA_REST * normal(rng),
        rest[1] + SIGMA_REST * normal(rng),
        (rest[2].to_degrees() + SIGMA_HEADING_DEG * normal(rng)).rem_euclid(360.0),
    )
    .unwrap();
    if !marks.is_empty() {
        writeln!(scene, "marks = [{}]", marks.join(", ")).unwrap();
    }
    scene
}

/// A tyre's contact point surveyed at rest or on a mark, m.
const SIGMA_TYRE: f64 = 0.1;

/// Vehicle `k`'s scene as a survey gives it: the rest by its left front and left rear tyres
/// (each to [`SIGMA_TYRE`]); for vehicle 1 two points of its right front tyre's mark (30 % and
/// 60 % of the way through the run-out in time, to [`SIGMA_MARK`]); for vehicle 2 a yaw mark of
/// its left front tyre traced by five points from 10 % to 50 % of the way.
fn measured_scene(k: usize, seen: &Seen, rng: &mut StdRng) -> String {
    let mut noisy =
        |p: [f64; 2], sigma: f64| [p[0] + sigma * normal(rng), p[1] + sigma * normal(rng)];
    let mut scene = format!("\n[scene.vehicle{}]\nrest_tyres = [", k + 1);
    for (n, (i, name)) in [(0, "front_left"), (2, "rear_left")]
        .into_iter()
        .enumerate()
    {
        let p = noisy(
            on_ground(seen.rest, seen.chassis.wheel_position(i)),
            SIGMA_TYRE,
        );
        let comma = if n == 0 { "" } else { "," };
        write!(
            scene,
            "{comma} {{ wheel = \"{name}\", x = {:.4}, y = {:.4}, sigma = {SIGMA_TYRE} }}",
            p[0], p[1]
        )
        .unwrap();
    }
    scene.push_str(" ]\n");
    if k == 0 {
        let marks: Vec<String> = [0.3, 0.6]
            .iter()
            .map(|f| {
                let p = noisy(seen.tyre(1, f * seen.time), SIGMA_MARK);
                format!(
                    "{{ x = {:.4}, y = {:.4}, sigma = {SIGMA_MARK}, wheel = \"front_right\" }}",
                    p[0], p[1]
                )
            })
            .collect();
        writeln!(scene, "marks = [ {} ]", marks.join(", ")).unwrap();
    } else {
        let points: Vec<String> = (0..5)
            .map(|j| {
                let p = noisy(seen.tyre(0, (0.1 + 0.1 * j as f64) * seen.time), SIGMA_MARK);
                format!("[{:.4}, {:.4}]", p[0], p[1])
            })
            .collect();
        writeln!(
            scene,
            "traces = [ {{ wheel = \"front_left\", points = [ {} ], sigma = {SIGMA_MARK} }} ]",
            points.join(", ")
        )
        .unwrap();
    }
    scene
}

/// A zone of 55-75 % of the road's `friction` (to 4 decimals, as the case states it), 60 m
/// deep and 120 m wide, whose near edge lies square across the path of vehicle `v` (from
/// `start`, as the reference runs it out on the road alone) half way along it in time.
fn verge_across(
    v: &pim_reconstruct::SceneVehicle,
    start: pim_runout::Motion,
    friction: f64,
    rng: &mut StdRng,
) -> pim_runout::Zone {
    let chassis = on_friction(v, friction);
    let reference = Reference::new(&chassis);
    let run = reference.run_out(&start);
    let half = reference.pose_at(&start, 0.5 * run.time);
    let (dx, dy) = (run.rest[0] - start.x, run.rest[1] - start.y);
    let n = dx.hypot(dy).max(1e-9);
    let (d, m) = ([dx / n, dy / n], [-dy / n, dx / n]);
    let corner = |along: f64, side: f64| {
        [0, 1].map(|i| ((half[i] + along * d[i] + side * m[i]) * 1e4).round() / 1e4)
    };
    pim_runout::Zone {
        corners: vec![
            corner(0.0, -60.0),
            corner(60.0, -60.0),
            corner(60.0, 60.0),
            corner(0.0, 60.0),
        ],
        friction: (friction * rng.random_range(0.55..0.75) * 1e4).round() / 1e4,
    }
}

/// What one case gave.
pub(crate) struct Outcome {
    pub(crate) seed: u64,
    pub(crate) wheels: [Wheels; 2],
    pub(crate) truth: f64,
    pub(crate) found: Option<f64>,
    pub(crate) refused: Option<String>,
    /// The reported 90 % intervals of the speeds at contact hold the truth.
    pub(crate) covered: [bool; 2],
    /// The draws' intervals (p05 to p95) hold it.
    pub(crate) drawn: [bool; 2],
    /// The profile intervals hold it.
    pub(crate) profiled: [bool; 2],
    pub(crate) seconds: f64,
}

fn run_case(seed: u64, wheels: [Wheels; 2], draws: usize) -> Option<Outcome> {
    // `NOISE=k`: each crash measured with the `k`-th other noise (the same crashes).
    let s = match std::env::var("NOISE") {
        Ok(k) => common::with_noise(k.parse().expect("a whole number"), || {
            simulated(seed, wheels, false)
        })?,
        Err(_) => simulated(seed, wheels, false)?,
    };
    run_simulated(seed, wheels, s, draws)
}

/// [`run_case`] of the crash `s`.
pub(crate) fn run_simulated(
    seed: u64,
    wheels: [Wheels; 2],
    s: Simulated,
    draws: usize,
) -> Option<Outcome> {
    let case = Case::from_text(&format!("realistic_{seed}.toml"), &s.text).expect("a valid case");
    let truth = common::truth_cost(&case, &s.contact, &s.separation, s.friction);
    let started = std::time::Instant::now();
    let done = reconstructed(&case);
    let seconds = started.elapsed().as_secs_f64();
    let found = done.outcome.best.as_ref().map(|b| b.chi_square);
    let refused = (done.outcome.status != pim_reconstruct::Status::Found).then(|| {
        format!(
            "{:?}: {}",
            done.outcome.status,
            done.outcome.reason.clone().unwrap_or_default()
        )
    });
    let study = (draws > 0).then(|| studied(&case, &done, draws, seed));
    let truth_speeds = [s.contact.vehicle1.speed(), s.contact.vehicle2.speed()];
    let held = match (&study, done.document.best.as_ref()) {
        (Some(Ok(study)), Some(best)) => intervals_held(study, best, truth_speeds, (seed, wheels)),
        _ => Held::default(),
    };
    let covered = held.reported;
    eprintln!(
        "seed {seed} {wheels:?}: truth {truth:.3}, found {found:?}, {:.2} s, run-outs {:.1?} m, \
         turns {:.2?}, covered {covered:?}{}",
        seconds,
        s.distance,
        s.turns,
        refused
            .as_deref()
            .map(|r| format!(", REFUSED {r}"))
            .unwrap_or_default()
    );
    Some(Outcome {
        seed,
        wheels,
        truth,
        found,
        refused,
        covered,
        drawn: held.drawn,
        profiled: held.profiled,
        seconds,
    })
}

/// Which of a study's intervals of each speed at contact hold the truth.
#[derive(Debug, Default)]
struct Held {
    reported: [bool; 2],
    drawn: [bool; 2],
    profiled: [bool; 2],
}

/// [`Held`] of `study` around the answer `best`, each vehicle's intervals printed (m/s).
fn intervals_held(
    study: &pim_documents::reconstruct_study::ReconstructionStudy,
    best: &pim_documents::reconstruct_doc::BestOut,
    truth: [f64; 2],
    (seed, wheels): (u64, [Wheels; 2]),
) -> Held {
    let mut held = Held::default();
    for (k, &t) in truth.iter().enumerate() {
        let name = format!("vehicle{}.speed_at_contact", k + 1);
        let inside = |lo: f64, hi: f64| lo <= t && t <= hi;
        let q = study.quantities.get(&name);
        let p = study.profiles.get(&name);
        let r = study.intervals.get(&name);
        held.drawn[k] = q.is_some_and(|q| inside(q.p05, q.p95));
        held.profiled[k] = p.is_some_and(|p| inside(p.lower.speed, p.upper.speed));
        held.reported[k] = r.is_some_and(|r| inside(r[0], r[1]));
        eprintln!(
            "interval {seed} {wheels:?} vehicle{}: answer {:.4} truth {:.4} draws {:.4?} \
             profile {:.4?} reported {:.4?}",
            k + 1,
            best.vehicles[k].speed_at_contact,
            t,
            q.map(|q| (q.p05, q.p95)),
            p.map(|p| (
                p.lower.speed,
                p.upper.speed,
                p.lower.reached,
                p.upper.reached
            )),
            r
        );
    }
    held
}

/// The uncertainty study of `draws` draws around the reconstruction `done` of `case`.
pub(crate) fn studied(
    case: &Case,
    done: &pim_studies::reconstruct::Reconstructed,
    draws: usize,
    seed: u64,
) -> Result<
    pim_documents::reconstruct_study::ReconstructionStudy,
    pim_studies::documents::DocumentError,
> {
    let unwatched = pim_studies::watch::Unwatched;
    pim_studies::reconstruct_study::run_around(case, done, draws, seed, &unwatched)
}

/// The whole reconstruction of `case` (both moment branches).
pub(crate) fn reconstructed(case: &Case) -> pim_studies::reconstruct::Reconstructed {
    pim_studies::reconstruct::reconstruct(
        case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    )
    .expect("reconstructed")
}

/// The wheels of the `i`-th case: every pair of states in turn over 25 cases.
fn wheels_of(i: usize) -> [Wheels; 2] {
    [WHEELS[i % 5], WHEELS[(i / 5 + i) % 5]]
}

/// The seeds and wheels of the first `crashes` admissible crashes from `first_seed`.
pub(crate) fn chosen(crashes: usize, first_seed: u64) -> Vec<(u64, [Wheels; 2])> {
    let mut chosen = Vec::new();
    let mut seed = first_seed;
    while chosen.len() < crashes {
        let wheels = wheels_of(chosen.len());
        if simulated(seed, wheels, false).is_some() {
            chosen.push((seed, wheels));
        }
        seed += 1;
    }
    chosen
}

/// `crashes` cases from `first_seed`, `draws` draws each.
fn sweep(crashes: usize, first_seed: u64, draws: usize) -> Vec<Outcome> {
    use rayon::prelude::*;
    chosen(crashes, first_seed)
        .par_iter()
        .filter_map(|&(seed, wheels)| run_case(seed, wheels, draws))
        .collect()
}

/// None refused, none above the truth's chi-square; the coverage rate.
pub(crate) fn check(results: &[Outcome]) -> f64 {
    let mut failures = Vec::new();
    for r in results {
        let above = r.found.is_none_or(|f| f > r.truth + 1e-6 * (1.0 + r.truth));
        if above || r.refused.is_some() {
            failures.push(format!(
                "seed {} {:?}: chi-square {:?} against the truth's {:.4}{}",
                r.seed,
                r.wheels,
                r.found,
                r.truth,
                r.refused.as_deref().unwrap_or("")
            ));
        }
    }
    let mut seconds: Vec<f64> = results.iter().map(|r| r.seconds).collect();
    seconds.sort_by(f64::total_cmp);
    eprintln!(
        "reconstruction: median {:.3} s, longest {:.3} s",
        seconds[seconds.len() / 2],
        seconds[seconds.len() - 1]
    );
    let covered = results
        .iter()
        .flat_map(|r| r.covered)
        .filter(|c| *c)
        .count();
    let n = 2 * results.len();
    eprintln!("coverage {covered}/{n} = {:.3}", covered as f64 / n as f64);
    let count = |pick: fn(&Outcome) -> [bool; 2]| {
        results.iter().flat_map(pick).filter(|c| *c).count() as f64 / n as f64
    };
    eprintln!(
        "the draws' intervals alone {:.3}, the profiles' alone {:.3}",
        count(|r| r.drawn),
        count(|r| r.profiled)
    );
    assert!(failures.is_empty(), "{}", failures.join("\n"));
    covered as f64 / n as f64
}

/// 12 cases (each wheel state on each vehicle at least twice): none refused, none above the
/// truth's chi-square. The intervals of realistic crashes are drawn by `realistic_cases_200`
/// (`--ignored`; these twelve with 20 draws each held the truth in 21 of 24); the study's
/// coverage is asserted in the suite by `scene_coverage`.
#[test]
#[ignore = "long: tests/long runs it"]
fn realistic_cases_are_answered() {
    let results = sweep(12, 90_000, 0);
    assert_eq!(results.len(), 12);
    check(&results);
}

/// A crash of the full sweep (seed 100150: the sedan ABS-braked 38 m, the SUV locked) once
/// refused at 203.7 where the truth's chi-square is 21.9: its true combination of counts had
/// the second-lowest momentum bound (7.0), but the first step of its refinement overshot into
/// a basin at 8,500 and it was set aside. Before a refusal such a combination is continued
/// from the impact's side (the scenes' deviations widened, then narrowed): it answers.
#[test]
fn a_combination_whose_first_step_overshot_is_continued() {
    let r = run_case(100_150, [Wheels::Abs, Wheels::Locked], 0).expect("an admissible crash");
    check(&[r]);
}

/// Two crashes of the full sweep that the second search's starts from the first search's
/// answers (the impact's side of each scene) once made refused, when their ends were mixed with
/// the scene's own alternatives and crowded out the truth's basin: 100285 (the sedan jammed
/// 9.9 m, the SUV steered 50 m; refused at 182.0, truth 7.7) and 100453 (both rolling, 49.5 and
/// 97.5 m; refused at 10,210, truth 17.5). Kept apart, they answer at 3.41 and 7.04.
#[test]
#[ignore = "long: tests/long runs it"]
fn the_impacts_starts_do_not_crowd_out_the_scenes_own() {
    let results: Vec<Outcome> = [
        (100_285, [Wheels::Jammed, Wheels::Steered]),
        (100_453, [Wheels::Rolling, Wheels::Rolling]),
    ]
    .into_iter()
    .map(|(seed, wheels)| run_case(seed, wheels, 0).expect("an admissible crash"))
    .collect();
    check(&results);
}

/// Crash 100788 of the full sweep (the sedan locked 16.5 m; the SUV steered, rolling 76 m and
/// turning once around): the SUV's states that reach its rest all have yaw rates between -1
/// and 0 rad/s (its steered wheels hold its yaw rate near v tan(delta) / L), a closed branch of
/// the rest curve that the scatter's planes at whole yaw rates never cross. Refused at 11,834
/// (the truth's chi-square 24.8) until the last look before a refusal maps the steered scene's
/// grid at every quarter rad/s: answered at 6.61.
#[test]
#[ignore = "long: tests/long runs it"]
fn a_car_steered_once_around_is_found_by_the_last_look() {
    let r = run_case(100_788, [Wheels::Locked, Wheels::Steered], 0).expect("an admissible crash");
    check(&[r]);
}

/// Crash 100285 written exactly (its measurements without noise): the SUV steered 50 m with no
/// marks, so its rest is three equations in its three unknowns, met exactly by at least five
/// states of count 0. With three alternatives kept per count the truth's was dropped and the
/// scene refused at 136.5; every alternative that meets the scene as its data expect is now a
/// start, and each combination of counts is refined once before any is refined again (so the
/// extra starts cannot spend the budget that 100235's true combination needs): answered at
/// the truth.
#[test]
fn every_exact_solution_of_a_scene_is_a_start() {
    let wheels = [Wheels::Jammed, Wheels::Steered];
    let s = common::exactly(|| simulated(100_285, wheels, false)).expect("an admissible crash");
    let r = run_simulated(100_285, wheels, s, 0).expect("answered");
    assert!(
        r.truth < 1e-3,
        "an exact scene: the truth's chi-square {}",
        r.truth
    );
    assert!(r.found.is_some_and(|f| f < 1e-4), "{:?}", r.found);
    check(&[r]);
}

/// Crash 100150 measured with other noise (the eleventh of `one_crash_measured_many_times`):
/// the sedan ABS-braked 38 m without marks, the SUV locked 14 m. Its rest gives the sedan's
/// three unknowns three equations, and along the sedan's speed against its turn the
/// linearisation is poor: from the scene's candidate of the true counts (and from the truth
/// itself) the undamped first step leapt to a chi-square of 8,531 in another basin, which
/// refined to 1,946, and the case was refused at 223.9 (the truth's 8.14). The start itself,
/// the impact fitted with its separation state held, is refined too: answered at 1.72.
#[test]
#[ignore = "long: tests/long runs it"]
fn a_start_near_the_answer_is_not_thrown_out_by_its_first_step() {
    let wheels = [Wheels::Abs, Wheels::Locked];
    let s = common::with_noise(11, || simulated(100_150, wheels, false)).expect("a crash");
    let r = run_simulated(100_150, wheels, s, 0).expect("answered");
    check(&[r]);
}

/// Crash 100532 measured with other noise (the first): the sedan, free rolling, spins at
/// 4 rad/s and then rolls 70 m backwards, 87 m in all, three quarters of a turn. One per cent
/// of its separation speed moves its rest by tens of metres along its rolling line (0.5 % of
/// friction by 15 m), so no cell of the grid of CG velocities held its rest, and its true
/// count's best scene state cost 602 (the case refused at 8,190, the truth's chi-square
/// 12.34). Found through its rest heading, which changes smoothly: answered at 3.80.
#[test]
#[ignore = "long: tests/long runs it"]
fn a_long_rolling_runout_is_found_through_its_rest_heading() {
    let wheels = [Wheels::Rolling, Wheels::Locked];
    let s = common::with_noise(1, || simulated(100_532, wheels, false)).expect("a crash");
    let r = run_simulated(100_532, wheels, s, 0).expect("answered");
    check(&[r]);
}

/// The full figure: 200 cases, 100 draws each (`CASES` and `DRAWS` change them, for a shorter
/// look; `NOISE=k` measures the same crashes with other noise): none refused, none above the truth's chi-square, the 90 % intervals of the contact
/// speeds hold the truth in 85-95 %.
#[test]
#[ignore]
fn realistic_cases_200() {
    let number = |name: &str, default: usize| {
        std::env::var(name).map_or(default, |v| v.parse().expect("a whole number"))
    };
    let (cases, draws) = (number("CASES", 200), number("DRAWS", 100));
    let results = sweep(cases, 100_000, draws);
    assert_eq!(results.len(), cases);
    let rate = check(&results);
    assert!((0.85..=0.95).contains(&rate), "coverage {rate}");
}

/// Writes the realistic case of `SEED` (wheels `WHEELS`, e.g. `Rolling,Jammed`; with `VERGE`
/// set, onto a verge; with `MEASURED` set, its scene measured at tyres) into the temporary
/// folder as `realistic_SEED.toml` and prints its truth, to look at one case (`MEASUREMENT=k`:
/// measured with the `k`-th noise of `one_crash_measured_many_times`).
#[test]
#[ignore]
fn write_a_realistic_case() {
    let seed = common::seed_from_env();
    let wheels = wheels_named(&std::env::var("WHEELS").unwrap_or_else(|_| "Locked,Locked".into()));
    let env = |name: &str| std::env::var(name).is_ok();
    let write = || simulated_as(seed, wheels, env("VERGE"), env("MEASURED"));
    // `MEASUREMENT=k`: the same crash measured with the `k`-th other noise.
    let s = match std::env::var("MEASUREMENT") {
        Ok(k) => common::with_noise(k.parse().expect("a whole number"), write),
        Err(_) => write(),
    }
    .expect("an admissible crash");
    eprintln!("run-outs {:.1?} m, turns {:.2?}", s.distance, s.turns);
    common::write_with_truth(
        &format!("realistic_{seed}"),
        &s.text,
        (&s.contact, &s.separation, s.friction),
    );
}

/// The wheels named as `Rolling,Jammed` (vehicle 1's, vehicle 2's).
pub(crate) fn wheels_named(names: &str) -> [Wheels; 2] {
    let pick = |n: &str| {
        *WHEELS
            .iter()
            .find(|w| format!("{w:?}") == n.trim())
            .expect("Locked, Abs, Rolling, Steered or Jammed")
    };
    let mut it = names.split(',');
    [pick(it.next().unwrap()), pick(it.next().unwrap())]
}
