//! The CRASH3 energy: the published 2-, 4- and 6-point forms equal the exact integral, a uniform
//! profile gives `L (A C + B C^2 / 2 + G)`, the direction-of-force factor is 1 at 0 deg and 2 at
//! 45 deg and beyond, and a barrier test's own stiffness gives its speed back.
use approx::assert_relative_eq;
use pim_crush::*;
use proptest::prelude::*;

proptest! {
    #[test]
    fn published_forms_equal_the_exact_integral(
        width in 0.3..2.0f64,
        a in 0.0..100_000.0f64,
        b in 10_000.0..2_000_000.0f64,
        depths in prop::collection::vec(0.0..0.8f64, 6),
        n in prop::sample::select(vec![2usize, 4, 6]),
    ) {
        let p = Profile { width, depths: depths[..n].to_vec() };
        let s = Stiffness { a, b };
        let exact = crush_energy(&p, &s).unwrap();
        let published = crash3_energy(&p, &s).unwrap();
        prop_assert!((exact - published).abs() <= 1e-12 * exact.max(1.0), "{exact} vs {published}");
    }
}

#[test]
fn a_uniform_profile() {
    let s = Stiffness {
        a: 35_000.0,
        b: 1_200_000.0,
    };
    for n in [2, 3, 4, 6, 11] {
        let p = Profile {
            width: 1.5,
            depths: vec![0.3; n],
        };
        let expected = 1.5 * (s.a * 0.3 + s.b * 0.09 / 2.0 + s.g());
        assert_relative_eq!(
            crush_energy(&p, &s).unwrap(),
            expected,
            max_relative = 1e-14
        );
    }
}

#[test]
fn the_direction_of_force_factor() {
    assert_relative_eq!(pdof_factor(0.0), 1.0);
    assert_relative_eq!(pdof_factor(45f64.to_radians()), 2.0, max_relative = 1e-14);
    assert_relative_eq!(pdof_factor(-60f64.to_radians()), 2.0, max_relative = 1e-14);
    assert_relative_eq!(
        pdof_factor(30f64.to_radians()),
        4.0 / 3.0,
        max_relative = 1e-14
    );
}

/// A full-width barrier test: 1,500 kg, 1.6 m wide, 13.4 m/s (30 mph), 0.5 m of uniform crush,
/// no damage below 2.2 m/s (5 mph). Its own stiffness gives 13.4 m/s back from the crush.
#[test]
fn a_barrier_test_gives_its_speed_back() {
    let (m, w, v, c, b0) = (1500.0, 1.6, 13.4, 0.5, 2.2);
    let s = Stiffness::from_barrier_test(m, w, v, c, b0).unwrap();
    let p = Profile {
        width: w,
        depths: vec![c; 6],
    };
    let e = crush_energy(&p, &s).unwrap();
    let back = barrier_equivalent_speed(e, m).unwrap();
    assert!((back - v).abs() < 1e-9, "{back}");
    // G is the energy of the no-damage speed.
    assert_relative_eq!(s.g() * w, 0.5 * m * b0 * b0, max_relative = 1e-12);
}

#[test]
fn bad_input_is_named() {
    let s = Stiffness { a: 1.0, b: 0.0 };
    let p = Profile {
        width: 1.0,
        depths: vec![0.1, -0.2],
    };
    let e = crush_energy(&p, &Stiffness { a: 1.0, b: 1.0 }).unwrap_err();
    assert!(e.to_string().contains("C2"), "{e}");
    assert!(crush_energy(
        &Profile {
            width: 1.0,
            depths: vec![0.1]
        },
        &Stiffness { a: 1.0, b: 1.0 }
    )
    .is_err());
    assert!(s.check().unwrap_err().to_string().starts_with("b:"));
    assert!(Stiffness::from_barrier_test(1500.0, 1.6, 2.0, 0.5, 2.2).is_err());
}
