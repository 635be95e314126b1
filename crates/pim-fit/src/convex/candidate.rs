//! The answer of one sign pattern's optimum in the fit's terms: the coefficients read from z,
//! the two states (known components at their values) and the cost.

use super::dual::N;
use super::form::dot;
use super::{Formulation, Pattern, Signs};
use crate::inner::{At, Candidate, Inner};
use pim_core::{Coefficients, TangentialCondition};

impl Formulation {
    /// The candidate of a pattern's optimum: coefficients read from z (onto their box against
    /// round-off), the states and the cost.
    pub(super) fn candidate(&self, inner: &Inner, p: &Pattern, z: &[f64; N]) -> (At, Candidate) {
        match p {
            Pattern::Pim(p) => self.pim_candidate(inner, p, z),
            Pattern::Tangential(m) => self.mode_candidate(inner, m, z),
        }
    }

    /// The states of z (known components at their values).
    pub(super) fn states(
        &self,
        inner: &Inner,
        z: &[f64; N],
    ) -> (nalgebra::Vector6<f64>, nalgebra::Vector6<f64>) {
        let r = self.n - 6;
        let mut x = nalgebra::Vector6::zeros();
        let mut xf = nalgebra::Vector6::zeros();
        for k in 0..6 {
            x[k] = z[k];
            xf[k] = z[k] + (0..r).map(|c| self.d[k][c] * z[6 + c]).sum::<f64>();
        }
        // A known component is its value, not the value plus the subspace map's round-off.
        for &(k, v) in &inner.objective.fixed {
            if k < 6 {
                x[k] = v;
            } else {
                xf[k - 6] = v;
            }
        }
        (x, xf)
    }

    /// e of z (onto its box against round-off).
    pub(super) fn restitution(&self, inner: &Inner, z: &[f64; N]) -> f64 {
        let a = -self.side * dot(&self.vn, z);
        let b = self.side * dot(&self.big_vn, z);
        (b / a).clamp(inner.e_range[0], inner.e_range[1])
    }

    /// The candidate of PIM's sign pattern.
    fn pim_candidate(&self, inner: &Inner, p: &Signs, z: &[f64; N]) -> (At, Candidate) {
        let r = self.n - 6;
        let (x, xf) = self.states(inner, z);
        let scale = inner.objective.scale;
        let e = self.restitution(inner, z);
        let em = if r == 2 {
            1.0
        } else {
            let (wf, wl) = (dot(&self.w_final, z), dot(&self.w_lin, z));
            if wl.abs() <= 1e-12 * (scale + wf.abs()) {
                0.5 * (p.em[0] + p.em[1])
            } else {
                // A ratio at round-off from an end of the branch's box is that end (-6e-17
                // is e_m = 0).
                let em = (wf / wl).clamp(p.em[0], p.em[1]);
                [-1.0, 0.0]
                    .into_iter()
                    .find(|end| (em - end).abs() <= 1e-12)
                    .unwrap_or(em)
            }
        };
        let (pn, pt) = (dot(&self.pn, z), dot(&self.pt, z));
        let s = p.sign.value();
        // No tangential impulse (to round-off): frictionless and no-slip are then the same
        // answer, reported as mu = 0, which the forward model reproduces without dividing by
        // an impulse that is not there.
        let mu = if pn.abs() <= 1e-12 * pt.abs() || pn == 0.0 || pt.abs() <= 1e-10 * pn.abs() {
            0.0
        } else {
            (s * pt / pn).clamp(inner.mu_bounds[0], inner.mu_bounds[1])
        };
        let sticking = dot(&self.big_vt, z).abs() <= 1e-10 * scale && mu != 0.0;
        let (mode, c_mu) = if sticking {
            (TangentialCondition::NoSlip, 0.0)
        } else {
            (TangentialCondition::Sliding, mu)
        };
        let at = At {
            c: Coefficients { e, mu: c_mu, em },
            mode,
            sign: p.sign,
            et: 0.0,
        };
        let candidate = Candidate {
            cost: inner.objective.cost(&x, &xf),
            x,
            xf,
            mu_eff: mu,
            qp: true,
            lambda: 0.0,
            flat: false,
        };
        (at, candidate)
    }
}
