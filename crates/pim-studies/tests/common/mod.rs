//! Simulated crashes written as case files, shared by the coverage tests: the collision's
//! sections (vehicles at contact, the impact), the evidence at contact (each direction of
//! travel and yaw rate, with noise), the scene's placeholder read back to the chassis the case
//! describes, and the chi-square of the truth against a case's evidence.
#![allow(dead_code)]

#[path = "../../../pim-reconstruct/tests/common/impact.rs"]
pub mod impact;
#[path = "../../../pim-runout/tests/common/runout.rs"]
pub mod runout;

use impact::RandomImpact;
use pim_case::case::Case;
use pim_core::{VehicleId, Velocities};
use pim_studies::reconstruct::{case_reconstruction, CaseReconstruction};
use rand::rngs::StdRng;
use rand::Rng;
use std::f64::consts::TAU;
use std::fmt::Write;

/// The contact evidence's standard deviations: lateral velocity (m/s) and yaw rate (rad/s).
pub const SIGMA_LATERAL: f64 = 0.3;
pub const SIGMA_YAW: f64 = 0.1;

thread_local! {
    /// The noise scale [`exactly`] sets on its thread.
    static SCALE: std::cell::Cell<Option<f64>> = const { std::cell::Cell::new(None) };
    /// The noise's own generator [`with_noise`] sets on its thread.
    static NOISE: std::cell::RefCell<Option<StdRng>> = const { std::cell::RefCell::new(None) };
}

/// A standard normal draw (Box-Muller), times `NOISE_SCALE` where the environment sets it
/// (`NOISE_SCALE=0`: the simulated scenes' measurements written exactly, the same crashes), or
/// 0 within [`exactly`].
pub fn normal(rng: &mut StdRng) -> f64 {
    let mut u1: f64 = rng.random_range(f64::EPSILON..1.0);
    let mut u2: f64 = rng.random_range(0.0..1.0);
    NOISE.with_borrow_mut(|noise| {
        if let Some(noise) = noise {
            u1 = noise.random_range(f64::EPSILON..1.0);
            u2 = noise.random_range(0.0..1.0);
        }
    });
    let scale: f64 = SCALE
        .get()
        .unwrap_or_else(|| std::env::var("NOISE_SCALE").map_or(1.0, |v| v.parse().unwrap()));
    scale * (-2.0 * u1.ln()).sqrt() * (TAU * u2).cos()
}

/// `f` with every [`normal`] draw on this thread 0: a simulated crash's measurements written
/// exactly (the same draws are taken, so the crash is the same).
#[allow(dead_code)]
pub fn exactly<T>(f: impl FnOnce() -> T) -> T {
    SCALE.set(Some(0.0));
    let out = f();
    SCALE.set(None);
    out
}

/// `f` with every [`normal`] draw on this thread taken from a generator of its own, seeded by
/// `seed`: the same crash (the crash's own draws are taken as before) measured with other
/// noise, to compare a study's spread with the spread of the answers over many measurements.
#[allow(dead_code)]
pub fn with_noise<T>(seed: u64, f: impl FnOnce() -> T) -> T {
    use rand::SeedableRng;
    NOISE.set(Some(StdRng::seed_from_u64(seed)));
    let out = f();
    NOISE.set(None);
    out
}

/// The title, `[units]` (SI, yaw rates in rad/s, and `units` besides), both vehicles at
/// contact and the impact of `ri`.
pub fn collision_sections(seed: u64, ri: &RandomImpact, units: &str) -> String {
    let cgs = ri.impact.cg_positions();
    let col = ri.impact.collision();
    let mut head =
        format!("title = \"simulated crash {seed}\"\n[units]\nyaw_rate = \"rad/s\"\n{units}");
    for id in [VehicleId::One, VehicleId::Two] {
        let k = id.index();
        let v = if k == 0 { &col.vehicle1 } else { &col.vehicle2 };
        write!(
            head,
            "\n[vehicle{}]\nmass = {:.6}\nyaw_inertia = {:.6}\nheading = {:.9}\n\
             position = {{ x = {:.9}, y = {:.9} }}\nlength = 4.6\nwidth = 1.8\ncg_to_front = 2.3\n",
            k + 1,
            v.mass,
            v.yaw_inertia,
            ri.impact.nose_heading(id),
            cgs[k][0],
            cgs[k][1],
        )
        .unwrap();
    }
    writeln!(
        head,
        "\n[impact]\ncentre = {{ x = 0.0, y = 0.0 }}\ncrush_angle = {:.9}\nvehicle1_side = \"{}\"",
        col.crush_angle,
        if ri.impact.side() > 0.0 { "+n" } else { "-n" }
    )
    .unwrap();
    head
}

/// The evidence at contact: each vehicle's yaw rate (an estimate) and direction of travel (a
/// lateral velocity), the truth's with noise.
pub fn contact_evidence(ri: &RandomImpact, rng: &mut StdRng) -> String {
    let mut contact = String::from("\n[estimates.initial]\n");
    let mut sigmas = String::from("\n[sigma.initial]\n");
    let mut observations = String::new();
    for id in [VehicleId::One, VehicleId::Two] {
        let k = id.index();
        let v = if k == 0 { ri.x.vehicle1 } else { ri.x.vehicle2 };
        let f = ri.impact.forward_axis(id);
        let lateral = -v.vx * f[1] + v.vy * f[0];
        writeln!(
            contact,
            "vehicle{} = {{ omega = {:.9} }}",
            k + 1,
            v.omega + SIGMA_YAW * normal(rng)
        )
        .unwrap();
        writeln!(sigmas, "vehicle{} = {{ omega = {SIGMA_YAW} }}", k + 1).unwrap();
        write!(
            observations,
            "\n[[observations]]\nkind = \"lateral_velocity\"\nvehicle = {}\nvalue = {:.9}\n\
             sigma = {SIGMA_LATERAL}\n",
            k + 1,
            lateral + SIGMA_LATERAL * normal(rng)
        )
        .unwrap();
    }
    format!("{contact}{sigmas}{observations}")
}

/// The case `head` (everything but the scene) read with placeholder rests: the chassis and
/// poses the case describes.
pub fn described(head: &str) -> CaseReconstruction {
    let placeholder = format!(
        "{head}\n[scene.vehicle1]\nrest = {{ x = 0.0, y = 0.0, heading = 0.0 }}\n\
         rest_sigma = {{ x = 1.0, y = 1.0, heading = 1.0 }}\n[scene.vehicle2]\n\
         rest = {{ x = 0.0, y = 0.0, heading = 0.0 }}\nrest_sigma = {{ x = 1.0, y = 1.0, heading = 1.0 }}\n"
    );
    let case = Case::from_text("simulated.toml", &placeholder).expect("a valid case");
    reconstruction(&case)
}

pub fn reconstruction(case: &Case) -> CaseReconstruction {
    case_reconstruction(
        case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    )
    .expect("a reconstruction")
}

/// The chassis of scene vehicle `v` on the road's true `friction`.
pub fn on_friction(v: &pim_reconstruct::SceneVehicle, friction: f64) -> pim_runout::Chassis {
    let mut chassis = v.chassis.clone();
    chassis.friction = friction;
    chassis.rolling_resistance = chassis.rolling_resistance.min(0.5 * friction);
    chassis
}

/// The chi-square of the truth against the case's evidence: the contact evidence at the true
/// contact state, each scene against the true run-out (pim-runout's, on the true `friction`)
/// with its true count of turns, the stated friction against the true one.
pub fn truth_cost(
    case: &Case,
    contact: &Velocities,
    separation: &Velocities,
    friction: f64,
) -> f64 {
    let cr = reconstruction(case);
    let r = &cr.reconstruction;
    let u = pim_fit::state_vector(contact, separation);
    let mut total = r.contact_chi_square(&u);
    for (k, v) in r.scene.iter().enumerate() {
        let chassis = on_friction(v, friction);
        let sv = if k == 0 {
            separation.vehicle1
        } else {
            separation.vehicle2
        };
        let start = pim_runout::Motion {
            vx: sv.vx,
            vy: sv.vy,
            yaw_rate: sv.omega,
            ..v.pose
        };
        let settings = pim_runout::Settings::default();
        let run = pim_runout::simulate(&chassis, &start, &settings).expect("the true run-out");
        let h = v
            .evidence
            .rest
            .and_then(|r| r.heading)
            .expect("a rest heading");
        let nearest = h + TAU * ((v.pose.heading - h) / TAU).round();
        let turns = ((run.rest.heading - nearest) / TAU).round() as i64;
        let lin = pim_runout::linearise(&chassis, &start, &v.evidence, turns, &settings, false)
            .expect("the true run-out linearised");
        total += lin.cost;
    }
    // The road's priors (a zone's fitted friction is not the road's).
    for f in r.frictions.iter().filter(|f| f.zone.is_none()) {
        total += ((friction - f.value) / f.sigma).powi(2);
    }
    total
}

/// The seed of `SEED` (the tests that write one case to look at).
pub fn seed_from_env() -> u64 {
    std::env::var("SEED")
        .expect("SEED")
        .parse()
        .expect("a number")
}

/// `text` written into the temporary folder as `NAME.toml`, and its truth printed: the
/// chi-square of the truth and the velocities at contact and separation.
pub fn write_with_truth(
    name: &str,
    text: &str,
    (contact, separation, friction): (&Velocities, &Velocities, f64),
) {
    let file = std::env::temp_dir().join(format!("{name}.toml"));
    std::fs::write(&file, text).expect("written");
    let case = Case::from_text(&format!("{name}.toml"), text).expect("a valid case");
    eprintln!(
        "{}: truth's chi-square {:.3}, true friction {friction}\ncontact {contact:?}\nseparation {separation:?}",
        file.display(),
        truth_cost(&case, contact, separation, friction),
    );
}
