//! Rows over the twelve velocity components whose entries are polynomials in the geometry.
//!
//! Every row of the equations depends on the geometry through `p = (D1, D2, D3, D4, cos G,
//! sin G)` (the lever terms of pim-core's `Impact` and the crush-surface normal), and at most
//! through products of one lever and one of cos G, sin G. A row is therefore fixed by its
//! coefficients on fifteen monomials, `1, c, s, D1..D4, D1 c, D1 s, ..., D4 c, D4 s`, and can be
//! evaluated at a geometry point, over a box of geometries (interval arithmetic) and
//! differentiated. The rows written here are the ones of `pim_core::equations`, checked
//! against them at random geometries in the tests.

use super::interval::Iv;

/// Number of monomials.
pub(crate) const M: usize = 15;

/// Index of the monomial 1, c, s.
const ONE: usize = 0;
const C: usize = 1;
const S: usize = 2;
/// Index of lever `D(k+1)`, of `D(k+1) c` and of `D(k+1) s`.
const fn lever(k: usize) -> usize {
    3 + k
}
const fn lever_c(k: usize) -> usize {
    7 + 2 * k
}
const fn lever_s(k: usize) -> usize {
    8 + 2 * k
}

/// A polynomial of the geometry.
type Coef = [f64; M];

/// The monomials at a geometry point `p = (D1, D2, D3, D4, c, s)`.
pub(crate) fn monomials(p: &[f64; 6]) -> [f64; M] {
    let mut m = [0.0; M];
    m[ONE] = 1.0;
    m[C] = p[4];
    m[S] = p[5];
    for k in 0..4 {
        m[lever(k)] = p[k];
        m[lever_c(k)] = p[k] * p[4];
        m[lever_s(k)] = p[k] * p[5];
    }
    m
}

/// The monomials over a box of geometries, and their partial derivatives with respect to each
/// of `p`'s six entries, as intervals.
#[derive(Debug, Clone)]
pub(crate) struct MonoBox {
    pub mono: [Iv; M],
    pub d: [[Iv; M]; 6],
}

impl MonoBox {
    /// Over the box `p[j] in ps[j]`.
    pub fn new(ps: &[Iv; 6]) -> MonoBox {
        let zero = Iv::point(0.0);
        let mut mono = [zero; M];
        let mut d = [[zero; M]; 6];
        mono[ONE] = Iv::point(1.0);
        mono[C] = ps[4];
        mono[S] = ps[5];
        d[4][C] = Iv::point(1.0);
        d[5][S] = Iv::point(1.0);
        for k in 0..4 {
            mono[lever(k)] = ps[k];
            mono[lever_c(k)] = ps[k] * ps[4];
            mono[lever_s(k)] = ps[k] * ps[5];
            d[k][lever(k)] = Iv::point(1.0);
            d[k][lever_c(k)] = ps[4];
            d[k][lever_s(k)] = ps[5];
            d[4][lever_c(k)] = ps[k];
            d[5][lever_s(k)] = ps[k];
        }
        MonoBox { mono, d }
    }
}

/// The constants of the rows: masses and yaw inertias.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Inertia {
    pub m: [f64; 2],
    pub i: [f64; 2],
}

/// A row over `U = (x, X)` (contact state, separation state) with polynomial entries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Poly(pub [Coef; 12]);

/// Which velocities a row over six components applies to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Over {
    Contact,
    Separation,
    /// The change `X - x`.
    Change,
}

fn c(k: usize, v: f64) -> Coef {
    let mut a = [0.0; M];
    a[k] = v;
    a
}

fn sum(terms: &[(usize, f64)]) -> Coef {
    let mut a = [0.0; M];
    for &(k, v) in terms {
        a[k] += v;
    }
    a
}

impl Poly {
    pub fn zero() -> Poly {
        Poly([[0.0; M]; 12])
    }

    /// A row over six components applied to x, X or X - x.
    pub fn of(six: [Coef; 6], over: Over) -> Poly {
        let mut p = Poly::zero();
        for (k, a) in six.iter().enumerate() {
            match over {
                Over::Contact => p.0[k] = *a,
                Over::Separation => p.0[6 + k] = *a,
                Over::Change => {
                    p.0[k] = a.map(|v| -v);
                    p.0[6 + k] = *a;
                }
            }
        }
        p
    }

    /// `self + k other`.
    pub fn add(&self, other: &Poly, k: f64) -> Poly {
        let mut p = *self;
        p.add_in(other, k);
        p
    }

    /// `self += k other`.
    pub fn add_in(&mut self, other: &Poly, k: f64) {
        for (a, b) in self.0.iter_mut().zip(&other.0) {
            for (x, y) in a.iter_mut().zip(b) {
                *x += k * y;
            }
        }
    }

    /// `k self`.
    pub fn scaled(&self, k: f64) -> Poly {
        Poly(self.0.map(|a| a.map(|v| k * v)))
    }

    /// The row at a geometry point (its monomials).
    pub fn at(&self, mono: &[f64; M]) -> [f64; 12] {
        self.0
            .map(|a| a.iter().zip(mono).map(|(x, y)| x * y).sum::<f64>())
    }

    fn eval(a: &Coef, mono: &[Iv; M]) -> Iv {
        let mut s = Iv::point(0.0);
        for (k, &v) in a.iter().enumerate() {
            if v != 0.0 {
                s = s + mono[k].scale(v);
            }
        }
        s
    }

    /// The row over a box of geometries.
    pub fn over(&self, b: &MonoBox) -> [Iv; 12] {
        self.0.map(|a| Poly::eval(&a, &b.mono))
    }

    /// Its partial derivative with respect to `p[j]` over a box of geometries.
    pub fn derivative_over(&self, b: &MonoBox, j: usize) -> [Iv; 12] {
        self.0.map(|a| Poly::eval(&a, &b.d[j]))
    }
}

/// The rows of the equations.
pub(crate) mod rows {
    use crate::geometry::certify::poly::{c, sum, Inertia, Over, Poly, C, ONE, S};
    use crate::geometry::certify::poly::{lever, lever_c, lever_s, M};
    use pim_core::MomentForm;

    /// The normal relative velocity at C, `vn = n . x` (pim-core's `normal_velocity_row`).
    pub fn normal(over: Over) -> Poly {
        Poly::of(
            [
                c(C, 1.0),
                c(S, 1.0),
                sum(&[(lever_c(2), 1.0), (lever_s(3), -1.0)]),
                c(C, -1.0),
                c(S, -1.0),
                sum(&[(lever_c(0), 1.0), (lever_s(1), -1.0)]),
            ],
            over,
        )
    }

    /// The tangential relative velocity at C (`tangential_velocity_row`).
    pub fn tangential(over: Over) -> Poly {
        Poly::of(
            [
                c(S, -1.0),
                c(C, 1.0),
                sum(&[(lever_s(2), -1.0), (lever_c(3), -1.0)]),
                c(S, 1.0),
                c(C, -1.0),
                sum(&[(lever_s(0), -1.0), (lever_c(1), -1.0)]),
            ],
            over,
        )
    }

    /// The normal and tangential impulse on vehicle 1 over the change (`impulse_rows`).
    pub fn impulse(k: &Inertia) -> (Poly, Poly) {
        let z = [0.0; M];
        let m1 = k.m[0];
        (
            Poly::of([c(C, m1), c(S, m1), z, z, z, z], Over::Change),
            Poly::of([c(S, -m1), c(C, m1), z, z, z, z], Over::Change),
        )
    }

    /// Equations 1-3 over the change (`momentum_x`, `momentum_y`, `angular_momentum`).
    pub fn momentum(k: &Inertia) -> [Poly; 3] {
        let z = [0.0; M];
        let [m1, m2] = k.m;
        let [i1, i2] = k.i;
        [
            Poly::of([c(ONE, m1), z, z, c(ONE, m2), z, z], Over::Change),
            Poly::of([z, c(ONE, m1), z, z, c(ONE, m2), z], Over::Change),
            Poly::of(
                [
                    z,
                    sum(&[(lever(1), m1), (lever(3), m1)]),
                    c(ONE, i1),
                    sum(&[(lever(0), m2), (lever(2), m2)]),
                    z,
                    c(ONE, i2),
                ],
                Over::Change,
            ),
        ]
    }

    /// The relative-yaw-rate change caused by the moment impulse, over the change
    /// (`moment_b_row`).
    pub fn moment_b(k: &Inertia) -> Poly {
        let [m1, m2] = k.m;
        let [i1, i2] = k.i;
        Poly::of(
            [
                c(lever(2), -m1 / i1),
                c(lever(3), m1 / i1),
                c(ONE, 1.0),
                c(lever(0), -m2 / i2),
                c(lever(1), m2 / i2),
                c(ONE, -1.0),
            ],
            Over::Change,
        )
    }

    /// The relative yaw rate of equation 6 over the separation state (`relative_yaw_row`).
    pub fn relative_yaw(form: MomentForm) -> Poly {
        let row = pim_core::equations::relative_yaw_row(form);
        let z = [0.0; M];
        let mut six = [z; 6];
        for (k, a) in six.iter_mut().enumerate() {
            a[ONE] = row[k];
        }
        Poly::of(six, Over::Separation)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::RowVector6;
    use pim_core::equations as eq;
    use pim_core::MomentForm;
    use pim_core::{Collision, Impact, Vehicle};

    fn impact(seed: u64) -> Impact {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut vehicle = |m: f64| Vehicle {
            mass: m,
            yaw_inertia: 0.8 * m + 1000.0 * next(),
            heading: 360.0 * next() - 180.0,
            d: 3.0 * next(),
            phi: 360.0 * next() - 180.0,
        };
        let (v1, v2) = (vehicle(1500.0), vehicle(1100.0));
        Impact::new(Collision {
            vehicle1: v1,
            vehicle2: v2,
            crush_angle: 180.0 * next() - 90.0,
        })
        .unwrap()
    }

    fn p_of(i: &Impact) -> [f64; 6] {
        let d = i.levers();
        let n = i.normal();
        [d[0], d[1], d[2], d[3], n[0], n[1]]
    }

    fn close(a: &[f64; 12], f: &RowVector6<f64>, g: &RowVector6<f64>) {
        for k in 0..6 {
            assert!((a[k] - g[k]).abs() < 1e-9 * (1.0 + g[k].abs()), "{a:?} {g}");
            assert!(
                (a[6 + k] - f[k]).abs() < 1e-9 * (1.0 + f[k].abs()),
                "{a:?} {f}"
            );
        }
    }

    #[test]
    fn rows_are_pim_cores_at_random_geometries() {
        let z = RowVector6::zeros();
        for seed in 0..200 {
            let i = impact(seed);
            let m = monomials(&p_of(&i));
            let k = Inertia {
                m: i.masses(),
                i: i.inertias(),
            };
            let n = eq::normal_velocity_row(&i);
            close(&rows::normal(Over::Contact).at(&m), &z, &n);
            close(&rows::normal(Over::Separation).at(&m), &n, &z);
            let t = eq::tangential_velocity_row(&i);
            close(&rows::tangential(Over::Contact).at(&m), &z, &t);
            let (pn, pt) = eq::impulse_rows(&i);
            let (qn, qt) = rows::impulse(&k);
            close(&qn.at(&m), &pn, &-pn);
            close(&qt.at(&m), &pt, &-pt);
            let mom = rows::momentum(&k);
            for (poly, row) in mom.iter().zip([
                eq::momentum_x(&i),
                eq::momentum_y(&i),
                eq::angular_momentum(&i),
            ]) {
                close(&poly.at(&m), &row.0, &row.1);
            }
            let b = eq::moment_b_row(&i);
            close(&rows::moment_b(&k).at(&m), &b, &-b);
            let w = eq::relative_yaw_row(MomentForm::Corrected);
            close(&rows::relative_yaw(MomentForm::Corrected).at(&m), &w, &z);
        }
    }

    #[test]
    fn a_row_over_a_box_contains_it_at_every_point_and_so_does_its_derivative() {
        let row = rows::normal(Over::Contact)
            .add(&rows::tangential(Over::Separation), 0.7)
            .add(
                &rows::moment_b(&Inertia {
                    m: [1500.0, 1100.0],
                    i: [2500.0, 1800.0],
                }),
                -0.3,
            );
        let ps = [
            Iv::new(0.1, 0.4),
            Iv::new(-1.0, -0.6),
            Iv::new(1.9, 2.2),
            Iv::new(-0.3, 0.2),
            Iv::new(0.80, 0.86),
            Iv::new(-0.6, -0.5),
        ];
        let b = MonoBox::new(&ps);
        let over = row.over(&b);
        for i in 0..50 {
            let t = i as f64 / 49.0;
            let p = ps.map(|iv| iv.lo + t * (iv.hi - iv.lo));
            let at = row.at(&monomials(&p));
            for k in 0..12 {
                assert!(over[k].lo <= at[k] && at[k] <= over[k].hi);
            }
            // Central differences of the row lie in the derivative's enclosure.
            for j in 0..6 {
                let h = 1e-6;
                let (mut lo, mut hi) = (p, p);
                lo[j] -= h;
                hi[j] += h;
                let (a, c) = (row.at(&monomials(&lo)), row.at(&monomials(&hi)));
                let dv = row.derivative_over(&b, j);
                for k in 0..12 {
                    let fd = (c[k] - a[k]) / (2.0 * h);
                    assert!(dv[k].lo - 1e-6 <= fd && fd <= dv[k].hi + 1e-6);
                }
            }
        }
    }
}
