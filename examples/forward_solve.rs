//! A forward solve of RICSAC 9 (Brach 1983 Table 1, coefficients of its Table 3):
//! `cargo run --example forward_solve`.
//!
//! The solve reports the result as not admissible: Brach's 1983 least-squares mu = 0.486 exceeds
//! the critical mu_max = 0.454 of this impact, so the tangential impulse overshoots and reverses
//! the sliding. Brach 1984 (section 5) says exactly this of his earlier fits ("a value of mu
//! higher than mu_m by a few percent") and refits with the constraint mu <= mu_m; `pim fit`
//! always enforces it.
use pim_core::*;

fn main() -> Result<()> {
    let impact = Impact::new(Collision {
        vehicle1: Vehicle {
            mass: 1036.0,
            yaw_inertia: 1348.0,
            heading: 0.0,
            d: 1.4,
            phi: 0.0,
        },
        vehicle2: Vehicle {
            mass: 2189.0,
            yaw_inertia: 5287.0,
            heading: 90.0,
            d: 1.6,
            phi: -30.0,
        },
        crush_angle: 0.0,
    })?;
    let initial = Velocities {
        vehicle1: VehicleVelocity {
            vx: -9.48,
            vy: 0.0,
            omega: 0.0,
        },
        vehicle2: VehicleVelocity {
            vx: 0.0,
            vy: 9.48,
            omega: 0.0,
        },
    };
    let coefficients = Coefficients {
        e: 0.467,
        mu: 0.486,
        em: 1.0,
    };
    let r = solve_forward(&impact, &coefficients, &initial, &SolveOptions::default())?;
    for (k, v) in [r.separation.vehicle1, r.separation.vehicle2]
        .iter()
        .enumerate()
    {
        println!(
            "vehicle {}: V = ({:.2}, {:.2}) m/s, W = {:.2} rad/s, |dV| = {:.2} m/s",
            k + 1,
            v.vx,
            v.vy,
            v.omega,
            r.delta_v[k].magnitude
        );
    }
    println!(
        "energy loss {:.1} %, mu_max {:.3}, admissible: {}",
        r.energy.loss_percent,
        r.mu_max.unwrap_or(f64::NAN),
        r.admissibility.admissible
    );
    Ok(())
}
