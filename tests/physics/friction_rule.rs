//! The one friction rule, over random collisions: the tangential impulse lies between zero and
//! the impulse that sticking needs (PIM: mu between 0 and mu_max, the sign taken from the no-slip
//! impulse where the contact point does not slide; the tangential model: a binding limit on the
//! sticking impulse's side), and the Carpenter-Welcher IMPC written here from its description.
//!
//! The collisions cover both sides of the crush surface, mu_max of both signs, contact states
//! with `vt = 0` exactly, `vt` near 0 and `vt` as drawn, both moment branches and barriers; the
//! coverage is counted and asserted.
use crate::common;
use common::*;
use nalgebra::Vector6;
use pim_core::*;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};

/// How the tangential relative velocity at C was made.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Vt {
    Zero,
    Near,
    Drawn,
}

struct Draw {
    impact: Impact,
    x: Velocities,
    vt: Vt,
}

fn random_vehicle(rng: &mut StdRng) -> Vehicle {
    let mass = rng.random_range(700.0..2800.0);
    let k: f64 = rng.random_range(1.0..1.7);
    vehicle(
        mass,
        mass * k * k,
        rng.random_range(-180.0..180.0),
        rng.random_range(0.3..2.8),
        rng.random_range(-180.0..180.0),
    )
}

/// Moves vehicle 2 (or vehicle 1 against a barrier) along the crush surface so that the
/// tangential relative velocity at C becomes `target`.
fn set_vt(impact: &Impact, x: &mut Velocities, target: f64) {
    let (_, vt) = impact.relative_velocity(x);
    let t = impact.tangent();
    let shift = vt - target;
    if impact.is_barrier() {
        x.vehicle1.vx -= shift * t[0];
        x.vehicle1.vy -= shift * t[1];
    } else {
        x.vehicle2.vx += shift * t[0];
        x.vehicle2.vy += shift * t[1];
    }
}

/// A random collision and an approaching contact state, or `None` (draw again).
fn draw(rng: &mut StdRng) -> Option<Draw> {
    let barrier = rng.random_bool(0.2);
    let v2 = if barrier {
        Vehicle::barrier()
    } else {
        random_vehicle(rng)
    };
    let impact = Impact::new(Collision {
        vehicle1: random_vehicle(rng),
        vehicle2: v2,
        crush_angle: rng.random_range(-90.0..90.0),
    })
    .ok()?;
    let mut u = [0.0; 6];
    for (k, c) in u.iter_mut().enumerate() {
        *c = if k % 3 == 2 {
            rng.random_range(-1.5..1.5)
        } else {
            rng.random_range(-20.0..20.0)
        };
    }
    if barrier {
        u[3..].fill(0.0);
    }
    let mut x = state(u);
    let vt = match rng.random_range(0..3) {
        0 => {
            set_vt(&impact, &mut x, 0.0);
            Vt::Zero
        }
        1 => {
            let tiny = rng.random_range(1e-6..1e-3) * if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            set_vt(&impact, &mut x, tiny);
            Vt::Near
        }
        _ => Vt::Drawn,
    };
    impact.check_approach(&x).ok()?;
    Some(Draw { impact, x, vt })
}

fn energy(impact: &Impact, v: &Velocities) -> f64 {
    v.kinetic_energy(impact)
}

/// The impulse ratio Pt / Pn on vehicle 1 of a solution.
fn ratio(r: &ImpactReport) -> f64 {
    r.impulse.tangential / r.impulse.normal
}

fn no_slip() -> SolveOptions {
    SolveOptions {
        tangential: TangentialCondition::NoSlip,
        moment_form: MomentForm::Corrected,
    }
}

/// "between 0 and r": same sign (or zero) and no larger, to a relative `tol`.
fn between(rho: f64, r: f64, tol: f64) -> bool {
    let slack = tol * (1.0 + r.abs());
    rho * r >= -slack * rho.abs() && rho.abs() <= r.abs() + slack
}

#[test]
fn pim_friction_lies_between_zero_and_the_no_slip_impulse() {
    let mut rng = StdRng::seed_from_u64(25);
    let (mut n, mut tries) = (0usize, 0usize);
    let mut sides = [0usize; 2];
    let mut signs = [0usize; 2];
    let mut kinds = [0usize; 3];
    let mut barriers = 0usize;
    let mut admissible = 0usize;
    while n < 12_000 {
        tries += 1;
        assert!(tries < 200_000, "too few valid draws");
        let Some(Draw { impact, x, vt }) = draw(&mut rng) else {
            continue;
        };
        let em = if rng.random_bool(0.5) {
            1.0
        } else {
            rng.random_range(-1.0..0.0)
        };
        let probe = Coefficients {
            e: rng.random_range(0.0..1.0),
            mu: 0.0,
            em,
        };
        let Ok(Some(mu_max)) = critical_friction(&impact, &probe, &x, &SolveOptions::default())
        else {
            continue;
        };
        if mu_max.abs() > 50.0 {
            // Next to a vanishing no-slip normal impulse: the ratio is ill-conditioned.
            continue;
        }
        let Ok(stick) = solve_forward(&impact, &probe, &x, &no_slip()) else {
            continue;
        };
        let lambda: f64 = rng.random_range(0.0..1.0);
        let c = Coefficients {
            mu: lambda * mu_max,
            ..probe
        };
        let Ok(r) = solve_forward(&impact, &c, &x, &SolveOptions::default()) else {
            continue;
        };
        n += 1;
        sides[usize::from(impact.side() < 0.0)] += 1;
        kinds[vt as usize] += 1;
        barriers += usize::from(impact.is_barrier());
        if vt == Vt::Drawn {
            signs[usize::from(mu_max < 0.0)] += 1;
        }
        // The sign comes from the sliding, or from the no-slip impulse where there is none.
        let sliding = impact.sliding_sign(&x);
        assert_eq!(
            r.friction_basis == FrictionBasis::NoSlipImpulse,
            sliding.is_none()
        );
        if sliding.is_none() {
            assert!(
                mu_max >= -1e-12,
                "no sliding: mu_max {mu_max} on the no-slip side"
            );
        }
        // The friction test accepts mu = lambda mu_max.
        assert!(
            r.admissibility.friction_ok,
            "{:?}",
            r.inadmissibility_reasons()
        );
        // The tangential impulse between zero and the no-slip one (ratio Pt / Pn).
        let (rho, rho_s) = (ratio(&r), ratio(&stick));
        if r.impulse.normal.abs() > 1e-6 * r.impulse.tangential.abs().max(1.0) {
            assert!(
                between(rho, rho_s, 1e-7),
                "ratio {rho} not between 0 and the no-slip {rho_s} (vt {vt:?}, lambda {lambda})"
            );
        }
        // Never energy created by an admissible answer (recomputed here).
        if r.admissibility.admissible {
            admissible += 1;
            let (t0, t1) = (energy(&impact, &x), energy(&impact, &r.separation));
            assert!(t1 <= t0 * (1.0 + 1e-9), "{t0} -> {t1}");
        }
        // mu = mu_max is the no-slip solution.
        let at_max = solve_forward(
            &impact,
            &Coefficients { mu: mu_max, ..c },
            &x,
            &SolveOptions::default(),
        )
        .unwrap();
        let d = (at_max.separation.to_vector() - stick.separation.to_vector()).amax();
        assert!(d <= 1e-8 * (1.0 + x.to_vector().amax()), "mu = mu_max: {d}");
    }
    println!(
        "{n} collisions ({tries} draws): side +/- {sides:?}, vt zero/near/drawn {kinds:?}, \
         mu_max +/- (vt drawn) {signs:?}, barriers {barriers}, admissible {admissible}"
    );
    assert!(sides.iter().all(|&s| s >= n / 10), "{sides:?}");
    assert!(kinds.iter().all(|&s| s >= n / 5), "{kinds:?}");
    assert!(signs.iter().all(|&s| s >= n / 50), "{signs:?}");
    assert!(barriers >= n / 10, "{barriers}");
}

#[test]
fn the_tangential_model_slides_on_the_sticking_impulse_side() {
    let mut rng = StdRng::seed_from_u64(2025);
    let (mut n, mut tries) = (0usize, 0usize);
    let (mut slides, mut reversed_coupling) = (0usize, 0usize);
    while n < 10_000 {
        tries += 1;
        assert!(tries < 200_000, "too few valid draws");
        let Some(Draw { impact, x, .. }) = draw(&mut rng) else {
            continue;
        };
        let c = TangentialCoefficients {
            e: rng.random_range(0.0..1.0),
            et: if rng.random_bool(0.3) {
                0.0
            } else {
                rng.random_range(-1.0..1.0)
            },
            friction: rng.random_range(0.0..1.5),
        };
        let Ok(t) = solve_tangential(&impact, &c, &x) else {
            continue;
        };
        // The sticking ratio, independently: the same model with a limit that cannot bind.
        let free = solve_tangential(
            &impact,
            &TangentialCoefficients {
                friction: 100.0,
                ..c
            },
            &x,
        )
        .unwrap();
        if free.mode != ContactMode::Stick {
            continue;
        }
        n += 1;
        let rho_s = free.impulse_ratio;
        assert!((t.stick_ratio - rho_s).abs() <= 1e-9 * (1.0 + rho_s.abs()));
        let r = &t.report;
        assert!(
            between(t.impulse_ratio, rho_s, 1e-9),
            "ratio {} not between 0 and the sticking {rho_s}",
            t.impulse_ratio
        );
        if r.admissibility.admissible {
            let (t0, t1) = (energy(&impact, &x), energy(&impact, &r.separation));
            assert!(t1 <= t0 * (1.0 + 1e-9), "{t0} -> {t1}");
        }
        if t.mode == ContactMode::Slide {
            slides += 1;
            // PIM with em = 1 and the limit on the sticking impulse's side.
            let side = rho_s.signum() * r.friction_sign.value();
            let pim = solve_forward(
                &impact,
                &Coefficients {
                    e: c.e,
                    mu: c.friction * side,
                    em: 1.0,
                },
                &x,
                &SolveOptions::default(),
            )
            .unwrap();
            let d = (pim.separation.to_vector() - r.separation.to_vector()).amax();
            assert!(d <= 1e-8 * (1.0 + x.to_vector().amax()), "{d}");
            // With et = 0 the sticking impulse is PIM's no-slip impulse: the side is PIM's
            // mu_max side, and PIM's own friction test accepts the answer.
            if c.et == 0.0 {
                let mm = pim.mu_max.unwrap();
                assert!(mm * side >= 0.0, "mu_max {mm}, side {side}");
                assert!(pim.admissibility.friction_ok);
                if let Some(s) = impact.sliding_sign(&x) {
                    reversed_coupling += usize::from(mm < 0.0 && s == r.friction_sign);
                }
            }
        }
    }
    println!(
        "{n} collisions ({tries} draws): {slides} slide at the limit, of which {reversed_coupling} \
         with et = 0 where the coupling reverses the sliding (friction along the initial sliding)"
    );
    assert!(slides >= n / 5 && reversed_coupling >= 10);
}

#[test]
fn answers_are_continuous_as_vt_passes_through_zero() {
    let mut rng = StdRng::seed_from_u64(7);
    let mut n = 0usize;
    while n < 2000 {
        let Some(Draw { impact, mut x, .. }) = draw(&mut rng) else {
            continue;
        };
        set_vt(&impact, &mut x, 0.0);
        let scale = 1.0 + x.to_vector().amax();
        let delta = 1e-7 * scale;
        let around: Vec<Velocities> = [-2.0 * delta, -delta, 0.0, delta, 2.0 * delta]
            .iter()
            .map(|&v| {
                let mut y = x;
                set_vt(&impact, &mut y, v);
                y
            })
            .collect();
        if around.iter().any(|y| impact.check_approach(y).is_err()) {
            continue;
        }
        let probe = Coefficients {
            e: rng.random_range(0.0..1.0),
            mu: 0.0,
            em: if rng.random_bool(0.5) {
                1.0
            } else {
                rng.random_range(-1.0..0.0)
            },
        };
        let lambda: f64 = rng.random_range(0.0..1.0);
        let opts = SolveOptions::default();
        // PIM at a fixed fraction mu / mu_max (mu changes sign with the convention).
        let pim: Option<Vec<Vector6<f64>>> = around
            .iter()
            .map(|y| {
                let m = critical_friction(&impact, &probe, y, &opts).ok()??;
                (m.abs() < 50.0).then_some(())?;
                let c = Coefficients {
                    mu: lambda * m,
                    ..probe
                };
                Some(
                    solve_forward(&impact, &c, y, &opts)
                        .ok()?
                        .separation
                        .to_vector(),
                )
            })
            .collect();
        // The tangential model at fixed coefficients.
        let tc = TangentialCoefficients {
            e: probe.e,
            et: rng.random_range(-1.0..1.0),
            friction: rng.random_range(0.0..1.5),
        };
        let tan: Vec<Vector6<f64>> = around
            .iter()
            .map(|y| {
                solve_tangential(&impact, &tc, y)
                    .unwrap()
                    .report
                    .separation
                    .to_vector()
            })
            .collect();
        let Some(pim) = pim else { continue };
        n += 1;
        // No jump: the change across vt = 0 is no larger than a linear function's would be,
        // judged by the steps of the same size on either side (the answers of an
        // ill-conditioned impact move fast, but smoothly).
        for (name, set) in [("pim", &pim), ("tangential", &tan)] {
            let step = |a: usize, b: usize| (set[a] - set[b]).amax();
            let across = step(3, 1);
            let beside = step(4, 3).max(step(1, 0));
            assert!(
                across <= 4.0 * beside + 1e-10 * scale,
                "{name}: jump {across} across vt = 0 (steps beside it {beside})"
            );
            assert!(step(2, 1).max(step(3, 2)) <= 4.0 * beside + 1e-10 * scale);
        }
    }
}

/// Carpenter & Welcher's impulse-momentum model (IMPC), written here from its description: the
/// impulse that brings the relative velocity at C to rest (both axes) for two rigid bodies, times
/// (1 + e); when its ratio |Pt / Pn| exceeds the friction coefficient, the ratio is capped at it
/// (on the same side) and the normal impulse restores the normal velocity with e. No moment
/// impulse. Returns the separation velocities.
fn impc(impact: &Impact, x: &Velocities, e: f64, friction: f64) -> Vector6<f64> {
    let [m1, m2] = impact.masses();
    let [i1, i2] = impact.inertias();
    let [r1, r2] = impact.lever_arms();
    let (n, t) = (impact.normal(), impact.tangent());
    // Relative velocity at C (1 minus 2) in n, t.
    let p = impact.contact_point_velocities(x);
    let rel = [p[0][0] - p[1][0], p[0][1] - p[1][1]];
    let (vn, vt) = (rel[0] * n[0] + rel[1] * n[1], rel[0] * t[0] + rel[1] * t[1]);
    // Velocity change at C per unit impulse along a (on 1; -a on 2), measured along b.
    let w = |a: [f64; 2], b: [f64; 2]| {
        let cross = |r: [f64; 2], v: [f64; 2]| r[0] * v[1] - r[1] * v[0];
        let lin = (1.0 / m1 + 1.0 / m2) * (a[0] * b[0] + a[1] * b[1]);
        lin + cross(r1, a) * cross(r1, b) / i1 + cross(r2, a) * cross(r2, b) / i2
    };
    let (a, b, cc, d) = (w(n, n), w(t, n), w(n, t), w(t, t));
    // Common velocity: a Pn + b Pt = -vn, cc Pn + d Pt = -vt.
    let det = a * d - b * cc;
    let pn0 = (-vn * d + vt * b) / det;
    let pt0 = (-vt * a + vn * cc) / det;
    let (pn, pt) = if (pt0 / pn0).abs() <= friction {
        ((1.0 + e) * pn0, (1.0 + e) * pt0)
    } else {
        let rho = friction * (pt0 / pn0).signum();
        let pn = -(1.0 + e) * vn / (a + b * rho);
        (pn, rho * pn)
    };
    let imp = [pn * n[0] + pt * t[0], pn * n[1] + pt * t[1]];
    let cross = |r: [f64; 2]| r[0] * imp[1] - r[1] * imp[0];
    let mut out = x.to_vector();
    out[0] += imp[0] / m1;
    out[1] += imp[1] / m1;
    out[2] += cross(r1) / i1;
    out[3] -= imp[0] / m2;
    out[4] -= imp[1] / m2;
    out[5] -= cross(r2) / i2;
    out
}

#[test]
fn the_impc_preset_is_carpenter_and_welchers_model() {
    let mut rng = StdRng::seed_from_u64(1997);
    let (mut n, mut capped) = (0usize, 0usize);
    while n < 1000 {
        let Some(Draw { impact, x, .. }) = draw(&mut rng) else {
            continue;
        };
        let (e, friction) = (rng.random_range(0.0..0.6), rng.random_range(0.0..1.2));
        let ours =
            solve_tangential(&impact, &TangentialCoefficients::impc(e, friction), &x).unwrap();
        let theirs = impc(&impact, &x, e, friction);
        n += 1;
        capped += usize::from(ours.mode == ContactMode::Slide);
        let d = (ours.report.separation.to_vector() - theirs).amax();
        assert!(d <= 1e-9 * (1.0 + x.to_vector().amax()), "{d}");
    }
    assert!((200..=800).contains(&capped), "{capped} of 1000 capped");
}

#[test]
fn a_barrier_and_a_very_heavy_vehicle_read_the_same() {
    let mut rng = StdRng::seed_from_u64(3);
    let (mut n, mut refused) = (0usize, 0usize);
    while n < 2000 {
        let v1 = random_vehicle(&mut rng);
        let crush_angle = rng.random_range(-90.0..90.0);
        let barrier = Impact::new(Collision {
            vehicle1: v1,
            vehicle2: Vehicle::barrier(),
            crush_angle,
        })
        .unwrap();
        let heavy = Impact::new(Collision {
            vehicle1: v1,
            vehicle2: Vehicle {
                mass: 1e7,
                yaw_inertia: 1e10,
                ..random_vehicle(&mut rng)
            },
            crush_angle,
        })
        .unwrap();
        // vehicle 1's CG clearly off the crush plane (on the plane the barrier cannot tell).
        let [r1, _] = barrier.lever_arms();
        let nn = barrier.normal();
        if (r1[0] * nn[0] + r1[1] * nn[1]).abs() < 1e-3 * v1.d {
            continue;
        }
        n += 1;
        assert!((barrier.side() - heavy.side()).abs() < 0.5, "sides differ");
        let x = state([
            rng.random_range(-20.0..20.0),
            rng.random_range(-20.0..20.0),
            rng.random_range(-1.0..1.0),
            0.0,
            0.0,
            0.0,
        ]);
        let (a, b) = (barrier.check_approach(&x), heavy.check_approach(&x));
        assert_eq!(a.is_ok(), b.is_ok());
        refused += usize::from(a.is_err());
        if a.is_ok() {
            let c = Coefficients {
                e: 0.2,
                mu: 0.0,
                em: 1.0,
            };
            let opts = SolveOptions::default();
            let sa = solve_forward(&barrier, &c, &x, &opts).unwrap().separation;
            let sb = solve_forward(&heavy, &c, &x, &opts).unwrap().separation;
            let d = (sa.to_vector() - sb.to_vector()).fixed_rows::<3>(0).amax();
            assert!(d <= 1e-3 * (1.0 + x.to_vector().amax()), "{d}");
        }
    }
    assert!(
        refused >= n / 5 && refused <= 4 * n / 5,
        "{refused} of {n} refused"
    );
}
