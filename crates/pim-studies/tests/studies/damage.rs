//! The damage of a case: CRASH3's delta-V against PIM's in a central collinear plastic
//! collision, a barrier test's crush giving its speed back through a case file, and fits with
//! the crush energy as evidence recovering the coefficients of data made by the forward model.
use approx::assert_relative_eq;
use pim_case::case::Case;
use pim_case::damage::{Damage, Side, VehicleDamage};
use pim_core::*;
use pim_crush::{EnergyRelation, Profile, ProfileSigmas, Stiffness};
use pim_fit::*;
use pim_studies::damage_assess::{assess, EnergyTerm};
use proptest::prelude::*;

/// The uniform crush depth whose energy over `width` is `energy`: with `G = A^2 / 2B`,
/// `L (A C + B C^2 / 2 + G) = E` gives `C = (sqrt(2 B E / L) - A) / B`.
fn uniform_depth(energy: f64, width: f64, s: &Stiffness) -> f64 {
    ((2.0 * s.b * energy / width).sqrt() - s.a) / s.b
}

fn vehicle(side: Side, energy: f64, factor: f64, sigma: f64) -> VehicleDamage {
    let stiffness = Stiffness {
        a: 40_000.0,
        b: 500_000.0,
    };
    let width = 1.2;
    let c = uniform_depth(energy / factor, width, &stiffness);
    assert!(c > 0.0, "energy {energy} too small for a residual crush");
    VehicleDamage {
        side,
        profile: Profile {
            width,
            depths: vec![c; 4],
        },
        offset: 0.0,
        stiffness,
        sigmas: ProfileSigmas {
            depth: sigma,
            ..Default::default()
        },
        measured: true,
        pdof: None,
    }
}

/// A central collinear collision with e = 0 (and no friction: the impulse is along the line
/// of the CGs): CRASH3's delta-V from crush energies that add up to PIM's energy loss equals
/// PIM's delta-V, for any split of the energy between the vehicles.
#[test]
fn crash3_delta_v_equals_pim_in_a_central_collinear_plastic_collision() {
    let impact = Impact::new(Collision {
        vehicle1: Vehicle {
            mass: 1600.0,
            yaw_inertia: 2500.0,
            heading: 180.0,
            d: 2.2,
            phi: 0.0,
        },
        vehicle2: Vehicle {
            mass: 1100.0,
            yaw_inertia: 1500.0,
            heading: 0.0,
            d: 1.9,
            phi: 180.0,
        },
        crush_angle: 0.0,
    })
    .unwrap();
    let initial = Velocities::from_vector(&nalgebra::Vector6::new(20.0, 0.0, 0.0, 5.0, 0.0, 0.0));
    let c = Coefficients {
        e: 0.0,
        mu: 0.0,
        em: 1.0,
    };
    let r = solve_forward(&impact, &c, &initial, &SolveOptions::default()).unwrap();
    let u = state_vector(&r.initial, &r.separation);
    let loss = initial.kinetic_energy(&impact) - r.separation.kinetic_energy(&impact);
    // m1 m2 (v1 - v2)^2 / (2 (m1 + m2)).
    assert_relative_eq!(
        loss,
        1600.0 * 1100.0 * 225.0 / (2.0 * 2700.0),
        max_relative = 1e-12
    );
    for share in [0.5, 0.2, 0.9] {
        let damage = Damage {
            relation: EnergyRelation::EnergyLoss,
            evidence: None,
            vehicles: [
                Some(vehicle(Side::Front, share * loss, 1.0, 0.0)),
                Some(vehicle(Side::Rear, (1.0 - share) * loss, 1.0, 0.0)),
            ],
        };
        let a = assess(&damage, &impact, &u).unwrap();
        assert_relative_eq!(a.crush_energy, loss, max_relative = 1e-12);
        assert!(a.difference.abs() < 1e-9 * loss);
        for v in a.vehicles.iter().flatten() {
            assert_relative_eq!(v.pdof_factor, 1.0, epsilon = 1e-15);
            assert_relative_eq!(v.effective_mass_factor, 1.0, epsilon = 1e-15);
            assert_relative_eq!(v.crash3_delta_v, v.pim_delta_v, max_relative = 1e-12);
        }
        assert_relative_eq!(
            a.vehicles[0].as_ref().unwrap().pim_delta_v,
            15.0 * 1100.0 / 2700.0,
            max_relative = 1e-12
        );
    }
}

/// A full-width rigid-barrier test through a case file: 1,500 kg, 1.6 m wide, at 13.4 m/s,
/// 0.5 m of uniform crush, no damage below 2.2 m/s. Its stiffness from that test (A, B in the
/// case in N/cm), a plastic head-on solve: the barrier-equivalent speed of its crush and
/// CRASH3's delta-V are the impact speed, to 1e-9.
#[test]
fn a_barrier_case_gives_its_impact_speed_back() {
    let s = Stiffness::from_barrier_test(1500.0, 1.6, 13.4, 0.5, 2.2).unwrap();
    let text = format!(
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
width = 1.6
[vehicle2]
barrier = true
[impact]
crush_angle = 0.0
[coefficients]
e = 0.0
mu = 0.0
em = 1.0
[initial]
vehicle1 = {{ vx = 13.4, vy = 0.0, omega = 0.0 }}
[damage.vehicle1]
side = "front"
width = 160
depths = [50, 50, 50, 50, 50, 50]
a = {}
b = {}
"#,
        s.a / 100.0,
        s.b / 1e4
    );
    let case = Case::from_text("barrier.toml", &text).unwrap();
    let solved =
        pim_studies::documents::solve(&case, &SolveOptions::default()).expect("the barrier solves");
    let a = solved.document.damage.expect("assessed");
    let v = a.vehicles[0].as_ref().unwrap();
    assert_relative_eq!(v.pdof_factor, 1.0, epsilon = 1e-15);
    assert!((v.barrier_equivalent_speed - 13.4).abs() < 1e-9 * 13.4);
    assert!((v.crash3_delta_v - 13.4).abs() < 1e-9 * 13.4);
    assert!((v.pim_delta_v - 13.4).abs() < 1e-9 * 13.4);
    assert!((a.energy_loss - a.crush_energy).abs() < 1e-9 * a.crush_energy);
    assert!(a.vehicles[1].is_none());
}

/// An impact of the stress family: vehicle 1's front into vehicle 2's side.
fn impact(m1: f64, m2: f64, phi2: f64) -> Impact {
    Impact::new(Collision {
        vehicle1: Vehicle {
            mass: m1,
            yaw_inertia: m1 * 1.5,
            heading: 0.0,
            d: 1.4,
            phi: 0.0,
        },
        vehicle2: Vehicle {
            mass: m2,
            yaw_inertia: m2 * 2.2,
            heading: 90.0,
            d: 1.6,
            phi: phi2,
        },
        crush_angle: 0.0,
    })
    .unwrap()
}

/// The face of `v` whose normal is nearest the PDOF at the truth.
fn nearest_side(pdof: f64) -> Side {
    [Side::Front, Side::Right, Side::Rear, Side::Left]
        .into_iter()
        .min_by(|a, b| {
            let d = |s: Side| wrap_degrees(pdof - s.normal_pdof()).abs();
            d(*a).total_cmp(&d(*b))
        })
        .unwrap()
}

struct Generated {
    impact: Impact,
    truth: Vector12,
    damage: Damage,
    coefficients: Coefficients,
}

/// Data from the forward model: the separation state of known coefficients, and crush
/// profiles whose energies (with the truth's PDOF factors) add up to the truth's energy loss.
fn generate(m1: f64, m2: f64, phi2: f64, speed: f64, e: f64, mu: f64) -> Option<Generated> {
    let impact = impact(m1, m2, phi2);
    let initial = Velocities::from_vector(&nalgebra::Vector6::new(
        -speed,
        0.0,
        0.0,
        0.0,
        0.7 * speed,
        0.0,
    ));
    // mu as a share of the signed critical friction of this contact state, so that the truth
    // slides within the friction rule the fit imposes (mu between 0 and mu_max).
    let mu_max = critical_friction(
        &impact,
        &Coefficients {
            e,
            mu: 0.0,
            em: 1.0,
        },
        &initial,
        &SolveOptions::default(),
    )
    .ok()??;
    let coefficients = Coefficients {
        e,
        mu: mu * mu_max,
        em: 1.0,
    };
    let r = solve_forward(&impact, &coefficients, &initial, &SolveOptions::default()).ok()?;
    if !r.inadmissibility_reasons().is_empty() {
        return None;
    }
    let truth = state_vector(&r.initial, &r.separation);
    let loss = r.initial.kinetic_energy(&impact) - r.separation.kinetic_energy(&impact);
    // Read the PDOFs at the truth, then make each vehicle's profile carry half the loss.
    let probe = Damage {
        relation: EnergyRelation::EnergyLoss,
        evidence: None,
        vehicles: [
            Some(vehicle(Side::Front, 1e5, 1.0, 0.0)),
            Some(vehicle(Side::Left, 1e5, 1.0, 0.0)),
        ],
    };
    let p = assess(&probe, &impact, &truth)?;
    let mut vehicles = [None, None];
    for (k, slot) in vehicles.iter_mut().enumerate() {
        let pdof = p.vehicles[k].as_ref()?.pdof;
        let side = nearest_side(pdof);
        let alpha = wrap_degrees(pdof - side.normal_pdof());
        let factor = pim_crush::pdof_factor(alpha.to_radians());
        *slot = Some(vehicle(side, 0.5 * loss, factor, 0.01));
    }
    let damage = Damage {
        relation: EnergyRelation::EnergyLoss,
        evidence: None,
        vehicles,
    };
    let check = assess(&damage, &impact, &truth)?;
    assert!(check.difference.abs() < 1e-7 * loss, "{}", check.difference);
    Some(Generated {
        impact,
        truth,
        damage,
        coefficients,
    })
}

/// Noisy estimates of the whole separation state of a generated crash (sigma 0.2 m/s, 0.05
/// rad/s; `noise` in sigmas) and its crush energy with a 5 % sigma: the fit with the crush
/// never reports a cost above the generating solution's, nor below the certified lower bound.
fn never_above_truth(
    g: Option<Generated>,
    noise: &[f64],
    settings: &ValidSettings,
) -> std::result::Result<(), TestCaseError> {
    let Some(mut g) = g else { return Ok(()) };
    // A 5 % standard deviation of the crush energy: the depth sigma that gives it.
    for v in g.damage.vehicles.iter_mut().flatten() {
        let e0 = pim_crush::crush_energy(&v.profile, &v.stiffness).unwrap();
        let unit = pim_crush::crush_energy_sigma(
            &v.profile,
            &v.stiffness,
            &ProfileSigmas {
                depth: 1.0,
                ..Default::default()
            },
        )
        .unwrap();
        v.sigmas.depth = 0.05 * e0 / unit;
    }
    let sigma = |k: usize| if k % 3 == 2 { 0.05 } else { 0.2 };
    let unit = 0.05f64 * 0.05;
    let mut components = [Knowledge::Unknown; 12];
    for (k, c) in components.iter_mut().enumerate() {
        *c = if k < 6 {
            Knowledge::Known { value: g.truth[k] }
        } else {
            Knowledge::Estimated {
                value: g.truth[k] + sigma(k) * noise[k - 6],
                weight: unit / sigma(k).powi(2),
            }
        };
    }
    let problem = FitProblem {
        impact: g.impact,
        components,
        observations: vec![],
        combinations: vec![],
    };
    let base = fit(&problem, settings).unwrap();
    let term = EnergyTerm {
        damage: &g.damage,
        impact: &g.impact,
    };
    let terms: [&dyn NonlinearTerm; 1] = [&term];
    let f = fit_nonlinear(&problem, &base, unit, &terms, settings)
        .unwrap()
        .expect("an answer");
    let r = term.residual(&g.truth).unwrap();
    let truth_cost = linear_cost(&problem, &g.truth) + unit * r * r;
    prop_assert!(
        f.cost <= truth_cost * (1.0 + 1e-9) + 1e-12,
        "found {} above the truth's {}",
        f.cost,
        truth_cost
    );
    prop_assert!(f.cost + 1e-12 >= f.lower_bound);
    Ok(())
}

/// The fit's settings for the generated crashes: e up to 0.6, bounds wide enough for every
/// truth, the branches given.
fn search(branches: Vec<MomentBranch>) -> ValidSettings {
    FitSettings {
        branches,
        e: [0.0, 0.6],
        velocity_bound: 100.0,
        yaw_rate_bound: 15.0,
        ..FitSettings::default()
    }
    .check()
    .unwrap()
}

fn zero_branch() -> ValidSettings {
    search(vec![MomentBranch::Zero])
}

fn both_branches() -> ValidSettings {
    search(MomentBranch::ALL.to_vec())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    /// Noise-free data made by the forward model, the separation state estimated and the
    /// crush energy (with the PDOF factors of the impulse) as evidence: the fit recovers e and
    /// mu, at a cost of 0, proven optimal.
    #[test]
    fn the_fit_with_the_crush_energy_recovers_known_coefficients(
        m1 in 900.0..2500.0f64,
        m2 in 900.0..2500.0f64,
        phi2 in -60.0..-10.0f64,
        speed in 8.0..20.0f64,
        e in 0.02..0.4f64,
        mu in 0.1..0.95f64,
    ) {
        let Some(g) = generate(m1, m2, phi2, speed, e, mu) else { return Ok(()) };
        let mut components = [Knowledge::Unknown; 12];
        for (k, c) in components.iter_mut().enumerate() {
            *c = if k < 6 {
                Knowledge::Known { value: g.truth[k] }
            } else {
                Knowledge::Estimated { value: g.truth[k], weight: 1.0 }
            };
        }
        let problem = FitProblem { impact: g.impact, components, observations: vec![], combinations: vec![] };
        let settings = zero_branch();
        let base = fit(&problem, &settings).unwrap();
        let term = EnergyTerm { damage: &g.damage, impact: &g.impact };
        let terms: [&dyn NonlinearTerm; 1] = [&term];
        let f = fit_nonlinear(&problem, &base, 1.0, &terms, &settings).unwrap().expect("an answer");
        prop_assert!(f.cost < 1e-12, "cost {}", f.cost);
        prop_assert!(f.proven);
        let u = state_vector(&f.solution.initial, &f.solution.separation);
        prop_assert!((u - g.truth).amax() < 1e-6);
        prop_assert!((f.solution.e - g.coefficients.e).abs() < 1e-6, "e {} vs {}", f.solution.e, g.coefficients.e);
        // Sticking at the truth reports mu_max, the least mu that gives the same answer.
        if !f.solution.sticking {
            prop_assert!((f.solution.mu - g.coefficients.mu).abs() < 1e-6, "mu {} vs {}", f.solution.mu, g.coefficients.mu);
        }
    }

    /// Noise-free data that leave the coefficients open without the crush: the contact state
    /// known and of the separation state only vehicle 1's x velocity. Its estimate alone is met
    /// along a curve of (e, mu); with the crush energy the fit moves along it to an answer that
    /// meets both exactly (cost 0, the truth's, proven). The answer need not be the truth:
    /// the energy of that curve can cross the crush energy twice (e.g. e 0.020 / mu 0.342 and e
    /// 0.026 / mu 0.206 for one crash), and one velocity and one energy cannot tell them apart.
    #[test]
    fn the_crush_energy_on_a_curve_the_velocities_leave_open(
        m1 in 900.0..2500.0f64,
        m2 in 900.0..2500.0f64,
        phi2 in -60.0..-10.0f64,
        speed in 8.0..20.0f64,
        e in 0.02..0.4f64,
        mu in 0.1..0.95f64,
    ) {
        let Some(g) = generate(m1, m2, phi2, speed, e, mu) else { return Ok(()) };
        let mut components = [Knowledge::Unknown; 12];
        for (k, c) in components.iter_mut().enumerate().take(6) {
            *c = Knowledge::Known { value: g.truth[k] };
        }
        components[6] = Knowledge::Estimated { value: g.truth[6], weight: 1.0 };
        let problem = FitProblem { impact: g.impact, components, observations: vec![], combinations: vec![] };
        let settings = zero_branch();
        let base = fit(&problem, &settings).unwrap();
        let term = EnergyTerm { damage: &g.damage, impact: &g.impact };
        let terms: [&dyn NonlinearTerm; 1] = [&term];
        let f = fit_nonlinear(&problem, &base, 1.0, &terms, &settings).unwrap().expect("an answer");
        prop_assert!(f.cost < 1e-10, "cost {}", f.cost);
        prop_assert!(f.proven);
        let u = state_vector(&f.solution.initial, &f.solution.separation);
        prop_assert!(term.residual(&u).unwrap().abs() < 1e-5);
        prop_assert!((u[6] - g.truth[6]).abs() < 1e-5);
    }

    /// Noisy estimates of the whole separation state (sigma 0.2 m/s, 0.05 rad/s) and the
    /// crush energy with a 5 % sigma: the fit never reports a cost above that of the
    /// generating solution.
    #[test]
    fn the_fit_with_the_crush_energy_never_costs_more_than_the_truth(
        m1 in 900.0..2500.0f64,
        m2 in 900.0..2500.0f64,
        phi2 in -60.0..-10.0f64,
        speed in 8.0..20.0f64,
        e in 0.02..0.4f64,
        mu in 0.1..0.95f64,
        noise in prop::collection::vec(-1.0..1.0f64, 6),
    ) {
        never_above_truth(generate(m1, m2, phi2, speed, e, mu), &noise, &zero_branch())?;
    }

    /// The same with both moment branches searched (the free branch's optimum is a start
    /// too): never above the generating solution.
    #[test]
    fn with_both_moment_branches_the_fit_never_costs_more_than_the_truth(
        m1 in 900.0..2500.0f64,
        m2 in 900.0..2500.0f64,
        phi2 in -60.0..-10.0f64,
        speed in 8.0..20.0f64,
        e in 0.02..0.4f64,
        mu in 0.1..0.95f64,
        noise in prop::collection::vec(-1.0..1.0f64, 6),
    ) {
        never_above_truth(generate(m1, m2, phi2, speed, e, mu), &noise, &both_branches())?;
    }
}

/// A case in SAE's frame and US units: A in lbf/in and B in lbf/in^2, crush in inches, the
/// front damage's offset positive to the right (SAE's y), read into SI and the natural frame.
/// The pickup's PDOF given by the case is used as given.
#[test]
fn sae_and_us_units_are_read_into_si_and_the_natural_frame() {
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/cases/tbone_sae_us.toml"
    ))
    .unwrap();
    let text = base.replace(
        "yaw_rate = \"deg/s\"",
        "yaw_rate = \"deg/s\"\nstiffness = \"lbf/in\"\ncrush = \"in\"",
    ) + r#"
[damage.vehicle1]
side = "front"
width = 60
depths = [10, 12, 12, 10]
offset = 4
a = 300
b = 50
pdof = 10
[damage.vehicle2]
side = "right"
width = 100
depths = [4, 10, 14, 10, 6, 2]
offset = -6
a = 100
b = 40
"#;
    let case = Case::from_text("tbone_damage.toml", &text).unwrap();
    let d = Damage::of(&case).unwrap().unwrap();
    let v1 = d.vehicles[0].as_ref().unwrap();
    let lbf = 4.448_221_615_260_5;
    assert_relative_eq!(v1.stiffness.a, 300.0 * lbf / 0.0254, max_relative = 1e-14);
    assert_relative_eq!(
        v1.stiffness.b,
        50.0 * lbf / (0.0254 * 0.0254),
        max_relative = 1e-14
    );
    assert_relative_eq!(v1.profile.width, 1.524, max_relative = 1e-14);
    assert_relative_eq!(v1.profile.depths[1], 0.3048, max_relative = 1e-14);
    // 4 in to the right (SAE) is 4 in to the right: -0.1016 m in the natural frame (+ left).
    assert_relative_eq!(v1.offset, -0.1016, max_relative = 1e-14);
    // A side's offset runs along the length: the same in both frames.
    assert_relative_eq!(
        d.vehicles[1].as_ref().unwrap().offset,
        -0.1524,
        max_relative = 1e-14
    );
    let solved = pim_studies::documents::solve(&case, &SolveOptions::default()).unwrap();
    let a = solved.document.damage.unwrap();
    let p1 = a.vehicles[0].as_ref().unwrap();
    assert_eq!(p1.pdof_from, "case");
    assert_relative_eq!(p1.pdof, 10.0, max_relative = 1e-14);
    assert_relative_eq!(
        p1.pdof_factor,
        1.0 + 10f64.to_radians().tan().powi(2),
        max_relative = 1e-14
    );
    assert_eq!(a.vehicles[1].as_ref().unwrap().pdof_from, "impulse");
}

/// The compression relation expects `(1 - e^2)` of the crush energy as the loss, with e the
/// restitution at the states (here the solve's 0.3).
#[test]
fn the_compression_relation_expects_less_loss() {
    let impact = impact(1500.0, 1300.0, -30.0);
    let initial = Velocities::from_vector(&nalgebra::Vector6::new(-15.0, 0.0, 0.0, 0.0, 8.0, 0.0));
    let c = Coefficients {
        e: 0.3,
        mu: 0.0,
        em: 1.0,
    };
    let r = solve_forward(&impact, &c, &initial, &SolveOptions::default()).unwrap();
    let u = state_vector(&r.initial, &r.separation);
    let mut damage = Damage {
        relation: EnergyRelation::EnergyLoss,
        evidence: None,
        vehicles: [Some(vehicle(Side::Front, 60_000.0, 1.0, 0.0)), None],
    };
    let loss_reading = assess(&damage, &impact, &u).unwrap();
    damage.relation = EnergyRelation::Compression;
    let compression = assess(&damage, &impact, &u).unwrap();
    assert_relative_eq!(compression.e, 0.3, max_relative = 1e-9);
    assert_relative_eq!(
        compression.expected_loss,
        0.91 * loss_reading.expected_loss,
        max_relative = 1e-9
    );
    assert!(compression.relation_note.contains("0.910"));
    assert!(loss_reading
        .warnings
        .iter()
        .any(|w| w.contains("vehicle 2 has no [damage.vehicle2]")));
}
