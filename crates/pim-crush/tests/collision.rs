//! From crush energy to the collision: CRASH3's delta-V against the point-mass delta-V of a
//! central collinear plastic collision, the effective mass against the rigid-body impulse
//! response, the force balance, and the energy's standard deviation against finite
//! differences.
use approx::assert_relative_eq;
use pim_crush::*;
use proptest::prelude::*;

proptest! {
    /// A central collinear collision with e = 0: both vehicles end at the common velocity
    /// `(m1 v1 + m2 v2) / (m1 + m2)`; the kinetic energy lost is `m1 m2 (v1 - v2)^2 /
    /// (2 (m1 + m2))`. CRASH3's delta-V from that energy (factors 1: the impulse's line passes
    /// through both CGs) is each vehicle's change of speed.
    #[test]
    fn crash3_delta_v_of_a_central_plastic_collision_is_the_point_mass_delta_v(
        m1 in 500.0..40_000.0f64,
        m2 in 500.0..40_000.0f64,
        v1 in -40.0..40.0f64,
        v2 in -40.0..40.0f64,
    ) {
        let common = (m1 * v1 + m2 * v2) / (m1 + m2);
        // The loss in its closed form: as a difference of the kinetic energies it cancels to
        // 1e-16 of them (two cars at 32.3154 and 32.3152 m/s lose 2e-5 J out of 2e7 J, which
        // leaves it a relative 1e-4 off), and that is the test's round-off, not CRASH3's.
        let loss = m1 * m2 * (v1 - v2) * (v1 - v2) / (2.0 * (m1 + m2));
        let dv = crash3_delta_v(loss, [m1, m2], [1.0, 1.0]).unwrap();
        let scale = 1.0 + (v1 - v2).abs();
        prop_assert!((dv[0] - (common - v1).abs()).abs() <= 1e-9 * scale);
        prop_assert!((dv[1] - (common - v2).abs()).abs() <= 1e-9 * scale);
    }

    /// A rigid body hit by an impulse P at a point h off its CG, normal to the arm: the point's
    /// velocity along P changes by P/m + P h^2/I = P / (gamma m).
    #[test]
    fn the_effective_mass_is_the_impulse_response_of_the_struck_point(
        m in 500.0..40_000.0f64,
        k in 0.5..3.0f64,
        h in 0.0..3.0f64,
        p in 100.0..50_000.0f64,
    ) {
        let i = m * k * k;
        let point = p / m + p * h * h / i;
        let gamma = effective_mass_factor(m, i, h);
        prop_assert!((point - p / (gamma * m)).abs() <= 1e-12 * point);
    }

    /// The energy's standard deviation is the first-order propagation of its inputs' sigmas:
    /// each partial derivative against a central difference.
    #[test]
    fn the_energy_sigma_is_the_first_order_propagation(
        width in 0.3..2.5f64,
        a in 1_000.0..100_000.0f64,
        b in 50_000.0..2_000_000.0f64,
        depths in prop::collection::vec(0.0..0.8f64, 2..8),
        which in 0usize..4,
    ) {
        let p = Profile { width, depths };
        let s = Stiffness { a, b };
        let one = |sig: ProfileSigmas| crush_energy_sigma(&p, &s, &sig).unwrap();
        let e = |p: &Profile, s: &Stiffness| crush_energy(p, s).unwrap();
        let (sigma, numeric) = match which {
            0 => {
                let h = 1e-4 * a;
                let d = (e(&p, &Stiffness { a: a + h, b }) - e(&p, &Stiffness { a: a - h, b })) / (2.0 * h);
                (one(ProfileSigmas { a: 1.0, ..Default::default() }), d.abs())
            }
            1 => {
                let h = 1e-4 * b;
                let d = (e(&p, &Stiffness { a, b: b + h }) - e(&p, &Stiffness { a, b: b - h })) / (2.0 * h);
                (one(ProfileSigmas { b: 1.0, ..Default::default() }), d.abs())
            }
            2 => {
                let h = 1e-4 * width;
                let up = Profile { width: width + h, ..p.clone() };
                let down = Profile { width: width - h, ..p.clone() };
                (one(ProfileSigmas { width: 1.0, ..Default::default() }), ((e(&up, &s) - e(&down, &s)) / (2.0 * h)).abs())
            }
            _ => {
                // Every depth with sigma 1: the root sum of squares of the partials.
                let h = 1e-6;
                let mut sum = 0.0;
                for i in 0..p.depths.len() {
                    let mut up = p.clone();
                    up.depths[i] += h;
                    let mut down = p.clone();
                    down.depths[i] = (down.depths[i] - h).max(0.0);
                    let step = up.depths[i] - down.depths[i];
                    sum += ((e(&up, &s) - e(&down, &s)) / step).powi(2);
                }
                (one(ProfileSigmas { depth: 1.0, ..Default::default() }), sum.sqrt())
            }
        };
        prop_assert!((sigma - numeric).abs() <= 1e-6 * numeric.max(1.0), "{sigma} vs {numeric}");
    }
}

/// Against a barrier (infinite mass) CRASH3's delta-V is the barrier-equivalent speed of the
/// energy when the impulse passes through the CG, and the barrier does not move.
#[test]
fn against_a_barrier() {
    let dv = crash3_delta_v(120_000.0, [1500.0, f64::INFINITY], [1.0, 1.0]).unwrap();
    assert_relative_eq!(
        dv[0],
        barrier_equivalent_speed(120_000.0, 1500.0).unwrap(),
        max_relative = 1e-15
    );
    assert_relative_eq!(dv[1], 0.0, epsilon = 1e-15);
    assert!(crash3_delta_v(-1.0, [1500.0, 1500.0], [1.0, 1.0]).is_err());
    assert!(crash3_delta_v(1.0, [1500.0, 1500.0], [0.0, 1.0]).is_err());
}

/// The force balance: the other face's crush carries the same force per unit width, and none
/// where the measured face's force stays below the other's onset of crush.
#[test]
fn the_force_balance_gives_the_other_crush() {
    let measured = Profile {
        width: 1.2,
        depths: vec![0.0, 0.1, 0.3, 0.2],
    };
    let s1 = Stiffness {
        a: 40_000.0,
        b: 600_000.0,
    };
    let s2 = Stiffness {
        a: 60_000.0,
        b: 300_000.0,
    };
    let other = balanced_profile(&measured, &s1, &s2).unwrap();
    assert_relative_eq!(other.width, 1.2, epsilon = 1e-15);
    for (c1, c2) in measured.depths.iter().zip(&other.depths) {
        let f1 = s1.a + s1.b * c1;
        if f1 <= s2.a {
            assert_relative_eq!(*c2, 0.0, epsilon = 1e-15);
        } else {
            assert_relative_eq!(s2.a + s2.b * c2, f1, max_relative = 1e-14);
        }
    }
    assert_relative_eq!(other.depths[0], 0.0, epsilon = 1e-15);
    assert_relative_eq!(
        other.depths[2],
        (40_000.0 + 180_000.0 - 60_000.0) / 300_000.0
    );
}

#[test]
fn the_relations() {
    assert_relative_eq!(
        EnergyRelation::EnergyLoss.expected_loss(100.0, 0.3),
        100.0,
        epsilon = 1e-15
    );
    assert_relative_eq!(
        EnergyRelation::Compression.expected_loss(100.0, 0.3),
        91.0,
        max_relative = 1e-15
    );
}
