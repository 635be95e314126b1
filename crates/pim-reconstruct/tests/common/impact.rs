//! Random realistic collisions with a known truth (the stress corpus of the impact fit, the
//! simulated crashes of the reconstruction).
#![allow(dead_code)]

/// A random realistic collision with a known truth, drawn as the stress corpus draws it.
#[allow(dead_code)]
pub struct RandomImpact {
    pub impact: pim_core::Impact,
    /// Contact state.
    pub x: pim_core::Velocities,
    pub truth: pim_core::Coefficients,
    /// The truth sticks (mu = mu_max, equation 5a).
    pub stick: bool,
    pub mu_max: f64,
    /// The solve options of the truth.
    pub opts: pim_core::SolveOptions,
}

/// Masses 800-2,600 kg, both sides of the crush surface, mu_max of both signs, e_m in both
/// branches, a quarter sticking truths (`None`: the draw is no admissible impact; draw again).
#[allow(dead_code)]
pub fn random_impact(rng: &mut rand::rngs::StdRng) -> Option<RandomImpact> {
    random_impact_with(rng, 4.0..18.0)
}

/// As [`random_impact`], the speeds at contact drawn from `speeds` (m/s).
#[allow(dead_code)]
pub fn random_impact_with(
    rng: &mut rand::rngs::StdRng,
    speeds: std::ops::Range<f64>,
) -> Option<RandomImpact> {
    use pim_core::*;
    use rand::rngs::StdRng;
    use rand::Rng;
    let vehicle = |rng: &mut StdRng| {
        let mass = rng.random_range(800.0..2600.0);
        let k = rng.random_range(1.1..1.6f64); // radius of gyration, m
        Vehicle {
            mass,
            yaw_inertia: mass * k * k,
            heading: rng.random_range(-180.0..180.0),
            d: rng.random_range(0.4..2.6),
            phi: rng.random_range(-180.0..180.0),
        }
    };
    let v1 = vehicle(rng);
    let v2 = vehicle(rng);
    let impact = Impact::new(Collision {
        vehicle1: v1,
        vehicle2: v2,
        crush_angle: rng.random_range(-90.0..90.0),
    })
    .ok()?;
    // Travel directions: vehicle 1 forward is its heading + 180 deg in the papers' geometry.
    let motion = |heading: f64, rng: &mut StdRng| {
        let speed: f64 = rng.random_range(speeds.clone());
        let dir = (heading + rng.random_range(-12.0..12.0)).to_radians();
        VehicleVelocity {
            vx: speed * dir.cos(),
            vy: speed * dir.sin(),
            omega: rng.random_range(-0.4..0.4),
        }
    };
    let x = Velocities {
        vehicle1: motion(v1.heading + 180.0, rng),
        vehicle2: motion(v2.heading, rng),
    };
    impact.check_approach(&x).ok()?;
    let (_, vt) = impact.relative_velocity(&x);
    if vt.abs() < 0.3 {
        return None;
    }
    let em = if rng.random_bool(0.5) {
        1.0
    } else {
        rng.random_range(-1.0..0.0)
    };
    let mut truth = Coefficients {
        e: rng.random_range(0.0..0.2),
        mu: 0.0,
        em,
    };
    let mu_max = critical_friction(&impact, &truth, &x, &SolveOptions::default()).ok()??;
    if !(0.02..1.15).contains(&mu_max.abs()) {
        return None;
    }
    let stick = rng.random_bool(0.25);
    truth.mu = if stick {
        mu_max
    } else {
        mu_max * rng.random_range(0.05..0.95)
    };
    let opts = truth_options(stick);
    Some(RandomImpact {
        impact,
        x,
        truth,
        stick,
        mu_max,
        opts,
    })
}

/// Solve options of a truth that sticks (equation 5a) or slides (equation 5).
#[allow(dead_code)]
pub fn truth_options(stick: bool) -> pim_core::SolveOptions {
    pim_core::SolveOptions {
        tangential: if stick {
            pim_core::TangentialCondition::NoSlip
        } else {
            pim_core::TangentialCondition::Sliding
        },
        ..Default::default()
    }
}
