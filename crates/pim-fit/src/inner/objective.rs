//! The cost over U and its reduction to the contact state x.
//!
//! The cost `sum w (a.U - t)^2` is `U' H U - 2 g' U + c`. With `X = R x` it is a quadratic in the
//! six contact components; components held fixed are linear equalities `E x = f`, and writing
//! `x = xp + Z y` with Z a basis of their null space leaves an unconstrained problem in y.

use super::qp::{general_null_space, to_d};
use crate::problem::{FitProblem, Knowledge, Vector12};
use nalgebra::{DMatrix, DVector, Matrix6, SMatrix, Vector6};
use std::borrow::Cow;

/// How the fixed components constrain x: `x = xp + Z y`. Where neither depends on the transfer
/// matrix they are built once (and borrowed by every evaluation).
#[derive(Debug, Clone)]
pub(crate) enum Fixed {
    /// Nothing fixed: `xp = 0`, `Z = I`.
    None(DMatrix<f64>),
    /// Only contact components fixed: `xp` holds their values, `Z` selects the free ones.
    Initial(Vector6<f64>, DMatrix<f64>),
    /// Anything else (depends on the transfer matrix).
    General,
}

/// The cost over U, the fixed components, and the cost restricted to the unknown state when one
/// whole state is known.
#[derive(Debug, Clone)]
pub(crate) struct Objective {
    hu: SMatrix<f64, 12, 12>,
    gu: Vector12,
    c0: f64,
    /// When the cost couples no two components: the square roots of the separation weights.
    split: Option<Vector6<f64>>,
    /// Fixed components (index into U, value).
    pub fixed: Vec<(usize, f64)>,
    kind: Fixed,
    /// Largest |value| of the data (at least 1), m/s: a scale for tolerances.
    pub scale: f64,
}

/// The cost at one transfer matrix, over x, and the null-space form of the fixed components.
pub(crate) struct OverX<'a> {
    pub r: Matrix6<f64>,
    pub h: Matrix6<f64>,
    pub g: Vector6<f64>,
    /// `x = xp + Z y` spans the x that satisfy the fixed components.
    pub xp: Vector6<f64>,
    pub z: Cow<'a, DMatrix<f64>>,
}

impl OverX<'_> {
    /// The reduced Hessian and gradient: `y' hy y - 2 gy' y + const`.
    pub fn reduced(&self) -> (DMatrix<f64>, DVector<f64>) {
        let hd = DMatrix::from_iterator(6, 6, self.h.iter().copied());
        let hy = self.z.transpose() * &hd * &*self.z;
        let gy = self.z.transpose() * to_d(&(self.g - self.h * self.xp));
        (hy, gy)
    }
}

impl Objective {
    /// The cost of a problem.
    pub fn new(problem: &FitProblem) -> Self {
        let mut hu = SMatrix::<f64, 12, 12>::zeros();
        let mut gu = Vector12::zeros();
        let mut c0 = 0.0;
        let mut fixed = Vec::new();
        let mut scale: f64 = 1.0;
        for (k, c) in problem.components.iter().enumerate() {
            match *c {
                Knowledge::Known { value } => {
                    fixed.push((k, value));
                    scale = scale.max(value.abs());
                }
                Knowledge::Estimated { value, weight } => {
                    hu[(k, k)] += weight;
                    gu[k] += weight * value;
                    c0 += weight * value * value;
                    scale = scale.max(value.abs());
                }
                Knowledge::Unknown => {}
            }
        }
        for o in &problem.observations {
            let a = o.row(&problem.impact);
            hu += a * a.transpose() * o.weight;
            gu += a * (o.weight * o.value);
            c0 += o.weight * o.value * o.value;
            scale = scale.max(o.value.abs());
        }
        for c in &problem.combinations {
            hu += c.row * c.row.transpose() * c.weight;
            gu += c.row * (c.weight * c.value);
            c0 += c.weight * c.value * c.value;
        }
        let diagonal = (0..12).all(|i| (0..12).all(|j| i == j || hu[(i, j)] == 0.0));
        let split =
            diagonal.then(|| Vector6::from_iterator((6..12).map(|k| hu[(k, k)].max(0.0).sqrt())));
        let kind = if fixed.is_empty() {
            Fixed::None(DMatrix::identity(6, 6))
        } else if fixed.iter().all(|(k, _)| *k < 6) {
            let free: Vec<usize> = (0..6)
                .filter(|k| fixed.iter().all(|(f, _)| f != k))
                .collect();
            let mut xp = Vector6::zeros();
            for &(k, v) in &fixed {
                xp[k] = v;
            }
            let mut z = DMatrix::zeros(6, free.len());
            for (c, &k) in free.iter().enumerate() {
                z[(k, c)] = 1.0;
            }
            Fixed::Initial(xp, z)
        } else {
            Fixed::General
        };
        Objective {
            hu,
            gu,
            c0,
            split,
            fixed,
            kind,
            scale,
        }
    }

    /// The cost as `U' H U - 2 g' U + c0`: `(H, g, c0)`.
    pub fn quadratic(&self) -> (&SMatrix<f64, 12, 12>, &Vector12, f64) {
        (&self.hu, &self.gu, self.c0)
    }

    /// Sum of weight x target^2 over the data.
    pub fn data_scale(&self) -> f64 {
        self.c0
    }

    /// The whole state held fixed, if one is: `(state, true)` for the contact state.
    pub fn known_state(&self) -> Option<(Vector6<f64>, bool)> {
        for (initial, range) in [(true, 0..6), (false, 6..12)] {
            let mut v = Vector6::zeros();
            let mut n = 0;
            for &(k, value) in &self.fixed {
                if range.contains(&k) {
                    v[k - range.start] = value;
                    n += 1;
                }
            }
            if n == 6 {
                return Some((v, initial));
            }
        }
        None
    }

    /// Whether nothing but the contact state is fixed (then the friction sign is known).
    pub fn fixed_contact(&self) -> Option<Vector6<f64>> {
        self.known_state()
            .filter(|(_, initial)| *initial)
            .map(|(v, _)| v)
    }

    /// The cost of a state pair.
    pub fn cost(&self, x: &Vector6<f64>, xf: &Vector6<f64>) -> f64 {
        let mut u = Vector12::zeros();
        u.fixed_rows_mut::<6>(0).copy_from(x);
        u.fixed_rows_mut::<6>(6).copy_from(xf);
        ((u.transpose() * self.hu * u)[0] - 2.0 * self.gu.dot(&u) + self.c0).max(0.0)
    }

    /// The cost along `U = U0 + t U1` as `[c0, c1, c2]` of `c0 + c1 t + c2 t^2`.
    pub fn along(&self, x: [&Vector6<f64>; 2], xf: [&Vector6<f64>; 2]) -> [f64; 3] {
        let stack = |a: &Vector6<f64>, b: &Vector6<f64>| {
            let mut u = Vector12::zeros();
            u.fixed_rows_mut::<6>(0).copy_from(a);
            u.fixed_rows_mut::<6>(6).copy_from(b);
            u
        };
        let u0 = stack(x[0], xf[0]);
        let u1 = stack(x[1], xf[1]);
        let hu1 = self.hu * u1;
        [
            (u0.transpose() * self.hu * u0)[0] - 2.0 * self.gu.dot(&u0) + self.c0,
            2.0 * (u0.dot(&hu1) - self.gu.dot(&u1)),
            u1.dot(&hu1),
        ]
    }

    /// The cost over x at transfer matrix R, with the null space of the fixed components;
    /// `None` when the fixed components admit no x.
    pub fn over_x(&self, r: Matrix6<f64>) -> Option<OverX<'_>> {
        let a = self.hu.fixed_view::<6, 6>(0, 0);
        let h = match &self.split {
            // Weights on separate components only: R' C R = (S R)' (S R), S = sqrt(C).
            Some(sqrt_c) => {
                let sr = Matrix6::from_diagonal(sqrt_c) * r;
                a + sr.transpose() * sr
            }
            None => {
                let b = self.hu.fixed_view::<6, 6>(0, 6);
                let c = self.hu.fixed_view::<6, 6>(6, 6);
                let br = b * r;
                a + br + br.transpose() + r.transpose() * c * r
            }
        };
        let g = self.gu.fixed_rows::<6>(0) + r.transpose() * self.gu.fixed_rows::<6>(6);
        let (xp, z) = match &self.kind {
            Fixed::None(z) => (Vector6::zeros(), Cow::Borrowed(z)),
            Fixed::Initial(xp, z) => (*xp, Cow::Borrowed(z)),
            Fixed::General => {
                let (xp, z) = general_null_space(&self.fixed, &r)?;
                (xp, Cow::Owned(z))
            }
        };
        Some(OverX { r, h, g, xp, z })
    }

    /// True when nothing is fixed (the equality optimum is a plain solve).
    pub fn nothing_fixed(&self) -> bool {
        matches!(self.kind, Fixed::None(_))
    }
}
