//! The geometry `p = (D1, D2, D3, D4, cos G, sin G)` of a box of estimated inputs, and its
//! partial derivatives with respect to each input, enclosed by intervals.
//!
//! A vehicle's impact centre is estimated either in polar form (`d`, `phi`: `D = d (sin a,
//! cos a)` with `a = heading + phi`) or by its coordinates in the vehicle frame (`x`, `y`:
//! `D = (x sin h + y cos h, x cos h - y sin h)`, linear); vehicle 1 gives `(D3, D4)`, vehicle 2
//! `(D1, D2)` (pim-core's `Impact`). The crush-surface angle gives `(cos G, sin G)`.

use super::interval::Iv;
use crate::geometry::types::{GeometryBound, GeometryInput};
use pim_core::{Collision, Vehicle};

const RAD: f64 = std::f64::consts::PI / 180.0;

/// The map from the estimated inputs to p.
#[derive(Debug, Clone)]
pub(crate) struct Enclosure {
    base: Collision,
    inputs: Vec<GeometryInput>,
    /// Whether each vehicle's centre is estimated by its coordinates.
    cartesian: [bool; 2],
}

/// p over a box and its derivatives: `dp[i][j] = d p_j / d input_i`.
#[derive(Debug, Clone)]
pub(crate) struct PBox {
    pub p: [Iv; 6],
    pub dp: Vec<[Iv; 6]>,
}

impl Enclosure {
    pub fn new(base: &Collision, geometry: &[GeometryBound]) -> Enclosure {
        let cart = |v: u8| {
            geometry
                .iter()
                .any(|g| matches!(g.input, GeometryInput::X(w) | GeometryInput::Y(w) if w == v))
        };
        Enclosure {
            base: *base,
            inputs: geometry.iter().map(|g| g.input).collect(),
            cartesian: [cart(1), cart(2)],
        }
    }

    /// The collision at a point of the inputs.
    pub fn collision(&self, u: &[f64]) -> Collision {
        let mut c = self.base;
        for (g, &v) in self.inputs.iter().zip(u) {
            g.set(&mut c, v);
        }
        c
    }

    /// p and its derivatives over the box `[lo, hi]` of the inputs.
    pub fn over(&self, lo: &[f64], hi: &[f64]) -> PBox {
        let value = |input: GeometryInput| -> Iv {
            match self.inputs.iter().position(|&g| g == input) {
                Some(i) => Iv::new(lo[i], hi[i]),
                None => Iv::point(input.get(&self.base)),
            }
        };
        let zero = [Iv::point(0.0); 6];
        let mut dp = vec![zero; self.inputs.len()];
        let mut p = zero;
        for (v, (js, vehicle)) in [
            ((2usize, 3usize), &self.base.vehicle1),
            ((0, 1), &self.base.vehicle2),
        ]
        .into_iter()
        .enumerate()
        {
            let id = v as u8 + 1;
            let (jsin, jcos) = js;
            let h = vehicle_heading(vehicle);
            let slot = |input: GeometryInput| self.inputs.iter().position(|&g| g == input);
            if self.cartesian[v] {
                let (x, y) = (value(GeometryInput::X(id)), value(GeometryInput::Y(id)));
                let (sh, ch) = (Iv::point(h * RAD).sin(), Iv::point(h * RAD).cos());
                p[jsin] = x * sh + y * ch;
                p[jcos] = x * ch - y * sh;
                if let Some(i) = slot(GeometryInput::X(id)) {
                    dp[i][jsin] = sh;
                    dp[i][jcos] = ch;
                }
                if let Some(i) = slot(GeometryInput::Y(id)) {
                    dp[i][jsin] = ch;
                    dp[i][jcos] = -sh;
                }
            } else {
                let (d, phi) = (value(GeometryInput::D(id)), value(GeometryInput::Phi(id)));
                let a = (phi + Iv::point(h)).scale(RAD);
                let (sa, ca) = (a.sin(), a.cos());
                p[jsin] = d * sa;
                p[jcos] = d * ca;
                if let Some(i) = slot(GeometryInput::D(id)) {
                    dp[i][jsin] = sa;
                    dp[i][jcos] = ca;
                }
                if let Some(i) = slot(GeometryInput::Phi(id)) {
                    dp[i][jsin] = (d * ca).scale(RAD);
                    dp[i][jcos] = -(d * sa).scale(RAD);
                }
            }
        }
        let g = value(GeometryInput::CrushAngle).scale(RAD);
        let (cg, sg) = (g.cos(), g.sin());
        p[4] = cg;
        p[5] = sg;
        if let Some(i) = self
            .inputs
            .iter()
            .position(|&g| g == GeometryInput::CrushAngle)
        {
            dp[i][4] = (-sg).scale(RAD);
            dp[i][5] = cg.scale(RAD);
        }
        PBox { p, dp }
    }
}

fn vehicle_heading(v: &Vehicle) -> f64 {
    v.heading
}

#[cfg(test)]
mod tests {
    use super::*;
    use pim_core::Impact;

    fn base() -> Collision {
        let v = |m: f64, heading: f64, d: f64, phi: f64| Vehicle {
            mass: m,
            yaw_inertia: m * 2.0,
            heading,
            d,
            phi,
        };
        Collision {
            vehicle1: v(1950.0, 10.0, 2.5, -17.9),
            vehicle2: v(1190.0, 60.0, 0.7, -80.0),
            crush_angle: -30.0,
        }
    }

    fn check(geometry: &[GeometryBound]) {
        let e = Enclosure::new(&base(), geometry);
        let lo: Vec<f64> = geometry.iter().map(|g| g.bounds[0]).collect();
        let hi: Vec<f64> = geometry.iter().map(|g| g.bounds[1]).collect();
        let b = e.over(&lo, &hi);
        let p_at = |u: &[f64]| {
            let i = Impact::new(e.collision(u)).unwrap();
            let (d, n) = (i.levers(), i.normal());
            [d[0], d[1], d[2], d[3], n[0], n[1]]
        };
        for s in 0..40 {
            let u: Vec<f64> = lo
                .iter()
                .zip(&hi)
                .enumerate()
                .map(|(i, (l, h))| l + (h - l) * (((s * (i + 3)) % 17) as f64 / 16.0))
                .collect();
            let p = p_at(&u);
            for j in 0..6 {
                assert!(
                    b.p[j].lo <= p[j] && p[j] <= b.p[j].hi,
                    "p[{j}] {p:?} {:?}",
                    b.p
                );
            }
            for i in 0..u.len() {
                let step = 1e-6 * (hi[i] - lo[i]).max(1e-3);
                let (mut a, mut c) = (u.clone(), u.clone());
                a[i] -= step;
                c[i] += step;
                let (pa, pc) = (p_at(&a), p_at(&c));
                for j in 0..6 {
                    let fd = (pc[j] - pa[j]) / (2.0 * step);
                    assert!(
                        b.dp[i][j].lo - 1e-5 <= fd && fd <= b.dp[i][j].hi + 1e-5,
                        "dp[{i}][{j}] {fd} {:?}",
                        b.dp[i][j]
                    );
                }
            }
        }
    }

    #[test]
    fn polar_and_cartesian_boxes_contain_the_impacts_geometry_and_its_derivatives() {
        let b = |input, lo, hi| GeometryBound {
            input,
            bounds: [lo, hi],
        };
        check(&[
            b(GeometryInput::D(1), 2.4, 2.6),
            b(GeometryInput::Phi(1), -25.0, -15.0),
            b(GeometryInput::D(2), 0.6, 0.76),
            b(GeometryInput::Phi(2), -90.0, -60.0),
            b(GeometryInput::CrushAngle, -40.0, -20.0),
        ]);
        check(&[
            b(GeometryInput::X(1), 2.2, 2.5),
            b(GeometryInput::Y(2), -0.8, -0.5),
            b(GeometryInput::CrushAngle, -35.0, -30.0),
        ]);
        check(&[b(GeometryInput::Phi(2), -100.0, 80.0)]);
    }
}
