//! The scenes and the fitted frictions linearised together: the rows of the refinement's
//! impact fit with the frictions projected out, and the frictions that go with a velocity
//! state.

use crate::point::Lin;
use crate::problem::{Reconstruction, FRICTION_RANGE};
use nalgebra::{DMatrix, DVector};
use pim_fit::Vector12;

/// The scenes and the fitted frictions linearised together: rows `b + A (U - at) + M dmu` (the
/// scenes' weighted residuals, then each friction's `(mu - value) / sigma`), with `A` over the
/// twelve velocities and `M` over the frictions.
pub(crate) struct FrictionStep {
    a: DMatrix<f64>,
    b: DVector<f64>,
    m: DMatrix<f64>,
    /// `(M^T M)^-1` (the frictions' own rows make it positive definite).
    mtm_inv: DMatrix<f64>,
    /// The velocities linearised at (the separation components; the rest 0).
    pub(crate) at: Vector12,
    /// The frictions linearised at.
    mus: Vec<f64>,
}

impl FrictionStep {
    pub(crate) fn new(r: &Reconstruction, lins: &[Lin]) -> FrictionStep {
        let groups = r.frictions.len();
        // Each friction as the run-outs were linearised on it.
        let mus: Vec<f64> = (0..groups)
            .map(|g| {
                let f = &r.frictions[g];
                f.vehicles
                    .iter()
                    .find_map(|&v| lins.iter().find(|l| l.vehicle == v))
                    .map_or(f.value, |l| match f.zone {
                        None => l.mu,
                        Some(k) => l.zone_mus[k],
                    })
            })
            .collect();
        let rows: usize = lins.iter().map(|l| l.lin.weighted.len()).sum::<usize>() + groups;
        let mut a = DMatrix::zeros(rows, 12);
        let mut b = DVector::zeros(rows);
        let mut m = DMatrix::zeros(rows, groups);
        let mut at = Vector12::zeros();
        let mut k = 0;
        for l in lins {
            let base = 6 + 3 * r.scene[l.vehicle].id.index();
            for c in 0..3 {
                at[base + c] = l.at[c];
            }
            let j = l.jacobian();
            let g = r.friction_of(l.vehicle);
            for i in 0..j.nrows() {
                for c in 0..3 {
                    a[(k, base + c)] = j[(i, c)];
                }
                b[k] = l.lin.weighted[i];
                if let (Some(g), Some(d)) = (g, &l.lin.friction) {
                    m[(k, g)] = d[i];
                }
                for (g, z) in r.zone_frictions_of(l.vehicle) {
                    if let Some(d) = l.lin.zones.get(z) {
                        m[(k, g)] = d[i];
                    }
                }
                k += 1;
            }
        }
        for (g, f) in r.frictions.iter().enumerate() {
            b[k] = (mus[g] - f.value) / f.sigma;
            m[(k, g)] = 1.0 / f.sigma;
            k += 1;
        }
        let mtm = m.transpose() * &m;
        let mtm_inv = mtm
            .clone()
            .try_inverse()
            .unwrap_or_else(|| DMatrix::identity(groups, groups));
        FrictionStep {
            a,
            b,
            m,
            mtm_inv,
            at,
            mus,
        }
    }

    /// `P A` and `P b` with `P = I - M (M^T M)^-1 M^T`.
    pub(crate) fn projected(&self) -> (DMatrix<f64>, DVector<f64>) {
        let mt = self.m.transpose();
        let pa = &self.a - &self.m * (&self.mtm_inv * (&mt * &self.a));
        let pb = &self.b - &self.m * (&self.mtm_inv * (&mt * &self.b));
        (pa, pb)
    }

    /// The frictions that minimise the linearised cost at the velocities `u`, kept within the
    /// searched range: `mu + dmu`, `dmu = -(M^T M)^-1 M^T (b + A (u - at))`.
    pub(crate) fn frictions_at(&self, u: &Vector12) -> Vec<f64> {
        let du = DVector::from_iterator(12, (u - self.at).iter().copied());
        let r = &self.b + &self.a * du;
        let dmu = -(&self.mtm_inv * (self.m.transpose() * r));
        self.mus
            .iter()
            .zip(dmu.iter())
            .map(|(m, d)| (m + d).clamp(FRICTION_RANGE.0, FRICTION_RANGE.1))
            .collect()
    }
}
