//! Helpers shared by the reference-data tests.
#![allow(dead_code)]

#[path = "../../crates/pim-reconstruct/tests/common/impact.rs"]
mod impact;
pub mod reference;
#[path = "../../crates/pim-runout/tests/common/runout.rs"]
pub mod runout;
pub use impact::*;
pub mod tangential;

use pim_core::{Collision, Vehicle, Velocities};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// The RICSAC tests of `data/ricsac.csv`.
pub fn ricsac_tests() -> Vec<pim_case::ricsac::RicsacTest> {
    let path = repo_path("data/ricsac.csv");
    let text = std::fs::read_to_string(&path).expect("data/ricsac.csv");
    pim_case::ricsac::parse("data/ricsac.csv", &text).expect("valid data file")
}

/// Path of a file under the repository root.
pub fn repo_path(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// A row of a reference CSV, by column name.
pub struct Row(pub HashMap<String, String>);

impl Row {
    /// A numeric cell; `None` when the cell is empty (not legible in the source).
    pub fn opt(&self, col: &str) -> Option<f64> {
        let s = self.0.get(col).unwrap_or_else(|| panic!("no column {col}"));
        if s.trim().is_empty() {
            None
        } else {
            Some(s.trim().parse().unwrap_or_else(|_| panic!("{col}: {s}")))
        }
    }
    /// A numeric cell that must be present.
    pub fn num(&self, col: &str) -> f64 {
        self.opt(col).unwrap_or_else(|| panic!("{col} is empty"))
    }
    /// A text cell.
    pub fn text(&self, col: &str) -> &str {
        self.0.get(col).map(String::as_str).unwrap_or("")
    }
}

/// Reads a reference CSV (`#` comment lines, one header line).
pub fn read_reference(rel: &str) -> Vec<Row> {
    let mut rdr = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(repo_path(rel))
        .unwrap_or_else(|e| panic!("{rel}: {e}"));
    let headers = rdr.headers().unwrap().clone();
    rdr.records()
        .map(|r| {
            let r = r.unwrap();
            Row(headers
                .iter()
                .zip(r.iter())
                .map(|(h, v)| (h.to_string(), v.to_string()))
                .collect())
        })
        .collect()
}

/// Shorthand for a vehicle.
pub fn vehicle(mass: f64, yaw_inertia: f64, heading: f64, d: f64, phi: f64) -> Vehicle {
    Vehicle {
        mass,
        yaw_inertia,
        heading,
        d,
        phi,
    }
}

/// Shorthand for a velocity state `(v1x, v1y, w1, v2x, v2y, w2)`.
pub fn state(v: [f64; 6]) -> Velocities {
    Velocities::from_vector(&nalgebra::Vector6::from(v))
}

/// RICSAC 7 as given in Brach 1983 Table 1 (crush angle -30 deg, see data/README.md).
pub fn brach1983_ricsac7() -> (Collision, Velocities) {
    let s = 13.01_f64;
    let h2 = 60.0_f64.to_radians();
    (
        Collision {
            vehicle1: vehicle(1955.0, 4723.0, 0.0, 1.8, 0.0),
            vehicle2: vehicle(1197.0, 2279.0, 60.0, 0.9, -140.0),
            crush_angle: -30.0,
        },
        state([-s, 0.0, 0.0, s * h2.cos(), s * h2.sin(), 0.0]),
    )
}

/// RICSAC 9 as given in Brach 1983 Table 1.
pub fn brach1983_ricsac9() -> (Collision, Velocities) {
    (
        Collision {
            vehicle1: vehicle(1036.0, 1348.0, 0.0, 1.4, 0.0),
            vehicle2: vehicle(2189.0, 5287.0, 90.0, 1.6, -30.0),
            crush_angle: 0.0,
        },
        state([-9.48, 0.0, 0.0, 0.0, 9.48, 0.0]),
    )
}

/// A standard normal number, for simulated measurement noise (the bootstrap's own generator).
pub fn normal(rng: &mut rand::rngs::StdRng) -> f64 {
    pim_studies::uncertainty::standard_normal(rng)
}

/// A state with measurement noise from [`normal`]: standard deviations 0.25 m/s on the
/// velocities and 0.08 rad/s on the yaw rates.
pub fn noisy(v: &Velocities, rng: &mut rand::rngs::StdRng) -> Velocities {
    let mut u = v.to_vector();
    for k in 0..6 {
        u[k] += normal(rng) * if k % 3 == 2 { 0.08 } else { 0.25 };
    }
    Velocities::from_vector(&u)
}

/// A PIM crash of the forward model with noisy estimates of both states.
#[allow(dead_code)]
pub struct NoisyDraw {
    pub impact: pim_core::Impact,
    /// The estimates ([`noisy`]) of the contact and separation states.
    pub x: Velocities,
    pub xf: Velocities,
    /// The true separation state.
    pub separation: Velocities,
}

/// A crash of [`random_impact`] solved forward, admissible and below 19 m/s at separation,
/// then the noise on both states, all drawn from `rng` in that order (`None`: draw again).
#[allow(dead_code)]
pub fn noisy_draw(rng: &mut rand::rngs::StdRng) -> Option<NoisyDraw> {
    let RandomImpact {
        impact,
        x,
        truth,
        opts,
        ..
    } = random_impact(rng)?;
    let r = pim_core::solve_forward(&impact, &truth, &x, &opts).ok()?;
    if !r.admissibility.admissible || r.separation.max_speed() > 19.0 {
        return None;
    }
    Some(NoisyDraw {
        impact,
        x: noisy(&x, rng),
        xf: noisy(&r.separation, rng),
        separation: r.separation,
    })
}

/// The geometry of RICSAC 9 (Brach 1983 Table 1) as a natural-form case file fragment.
pub const RICSAC9_GEOMETRY: &str = r#"
[vehicle1]
mass = 1036.0
yaw_inertia = 1348.0
heading = 180.0
impact_point = { x = 1.4, y = 0.0 }
[vehicle2]
mass = 2189.0
yaw_inertia = 5287.0
heading = 90.0
d = 1.6
phi = -30.0
[impact]
crush_angle = 0.0
"#;

/// A collision on the RICSAC 9 geometry with a known truth: contact state `x`, restitution `e`,
/// em = 1 and mu = `mu_fraction()` x mu_max (asked for only once mu_max exists). `None` when
/// mu_max is undefined.
pub fn ricsac9_truth(
    x: &pim_core::Velocities,
    e: f64,
    mu_fraction: impl FnOnce() -> f64,
) -> Option<(pim_core::Impact, pim_core::ImpactReport)> {
    use pim_core::{critical_friction, solve_forward, Coefficients, SolveOptions};
    let impact = pim_case::case::Case::from_text("geometry", RICSAC9_GEOMETRY)
        .unwrap()
        .impact()
        .unwrap();
    let mut truth = Coefficients {
        e,
        mu: 0.0,
        em: 1.0,
    };
    let mm = critical_friction(&impact, &truth, x, &SolveOptions::default()).ok()??;
    truth.mu = mu_fraction() * mm;
    let r = solve_forward(&impact, &truth, x, &SolveOptions::default()).unwrap();
    Some((impact, r))
}

/// Both vehicles' `{ vx, vy, omega }` lines of a case-file state from six values.
pub fn state_toml(u: &[f64]) -> String {
    format!(
        "vehicle1 = {{ vx = {}, vy = {}, omega = {} }}\nvehicle2 = {{ vx = {}, vy = {}, omega = {} }}\n",
        u[0], u[1], u[2], u[3], u[4], u[5]
    )
}

/// The same standard deviations (`sv` m/s on velocities, `sw` rad/s on yaw rates) for both
/// vehicles, as the lines of a `[sigma.*]` section.
pub fn sigma_toml(sv: f64, sw: f64) -> String {
    state_toml(&[sv, sv, sw, sv, sv, sw])
}

/// A seeded proptest runner: `cases` cases from the ChaCha stream of `seed` (reproducible, no
/// failure files).
pub fn seeded_runner(cases: u32, seed: u8) -> proptest::test_runner::TestRunner {
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    TestRunner::new_with_rng(
        Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        },
        TestRng::from_seed(RngAlgorithm::ChaCha, &[seed; 32]),
    )
}
