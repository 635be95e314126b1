//! The search spaces of a branch: the coefficient boxes, per tangential condition, and their grids.
//!
//! Sliding `(e, mu, em)` (em fixed at 1 in the zero branch) and sticking `(e, em)`
//! (mu = mu_max). When one whole state is known, e is not a dimension: every point minimises
//! over e exactly, so the boxes are `(mu, em)` and `(em)` (one point for the sticking mode of the
//! zero branch).

use crate::inner::{At, Eval, Inner, LineAt};
use crate::problem::MomentBranch;
use crate::settings::FitSettings;
use pim_core::reduction::SingularFaces;
use pim_core::{Coefficients, FrictionSign, TangentialCondition};

/// A coefficient dimension of a search space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Dim {
    pub lo: f64,
    pub hi: f64,
    pub n: usize,
}

impl Dim {
    /// Grid spacing (1 for a single point).
    pub fn spacing(&self) -> f64 {
        if self.n > 1 {
            (self.hi - self.lo) / (self.n - 1) as f64
        } else {
            1.0
        }
    }

    /// The grid points along this dimension.
    pub fn axis(&self) -> Vec<f64> {
        if self.n <= 1 {
            return vec![self.lo];
        }
        (0..self.n)
            .map(|i| self.lo + (self.hi - self.lo) * i as f64 / (self.n - 1) as f64)
            .collect()
    }
}

/// One search space: a branch and a tangential condition.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Space {
    pub branch: MomentBranch,
    pub mode: TangentialCondition,
    /// e (unless profiled), then mu (sliding only), then em (free branch only).
    pub dims: Vec<Dim>,
    /// The e range when e is not a dimension but minimised exactly at every point.
    pub profile_e: Option<[f64; 2]>,
    /// e fixed on a face of the box (not a dimension).
    pub e_fixed: Option<f64>,
    /// em fixed on a face of the box (not a dimension).
    pub em_fixed: Option<f64>,
    /// Tangential model: et is the last dimension (and em is 1).
    pub et_axis: bool,
}

impl Space {
    /// Coefficients and et of a point (clamped onto the box, against round-off of the
    /// refinement).
    pub fn coefficients(&self, p: &[f64]) -> (Coefficients, f64) {
        let c = |k: usize| p[k].clamp(self.dims[k].lo, self.dims[k].hi);
        let mut p: Vec<f64> = (0..p.len()).map(c).collect();
        let et = if self.et_axis {
            p.pop().unwrap_or(0.0)
        } else {
            0.0
        };
        let (e, p) = match (self.profile_e, self.e_fixed) {
            (Some(range), _) => (range[0], &p[..]),
            (None, Some(e)) => (e, &p[..]),
            (None, None) => (p[0], &p[1..]),
        };
        let (mu, rest) = match self.mode {
            TangentialCondition::Sliding => (p[0], &p[1..]),
            TangentialCondition::NoSlip => (0.0, p),
        };
        let em = match (self.branch, self.em_fixed) {
            (MomentBranch::Zero, _) => 1.0,
            (MomentBranch::Free, Some(em)) => em,
            (MomentBranch::Free, None) => rest[0],
        };
        (Coefficients { e, mu, em }, et)
    }

    /// The point of a coefficient triple and et (mu_eff for the sliding mode's mu).
    pub fn point_of(&self, c: &Coefficients, et: f64) -> Vec<f64> {
        let mut p = Vec::new();
        if self.profile_e.is_none() && self.e_fixed.is_none() {
            p.push(c.e);
        }
        if self.mode == TangentialCondition::Sliding {
            p.push(c.mu);
        }
        if self.branch == MomentBranch::Free && self.em_fixed.is_none() {
            p.push(c.em);
        }
        if self.et_axis {
            p.push(et);
        }
        p
    }

    /// The index of mu among the dimensions (sliding spaces only).
    pub fn mu_axis(&self) -> Option<usize> {
        (self.mode == TangentialCondition::Sliding)
            .then_some(usize::from(
                self.profile_e.is_none() && self.e_fixed.is_none(),
            ))
            .filter(|&k| self.dims.get(k).is_some_and(|d| d.n > 1))
    }

    /// True when p lies in the box (to round-off).
    pub fn inside(&self, p: &[f64]) -> bool {
        p.iter()
            .zip(&self.dims)
            .all(|(v, d)| *v >= d.lo - 1e-12 && *v <= d.hi + 1e-12)
    }

    /// Evaluates a point: its coefficients (with the best e when e is profiled) and result.
    pub fn eval(
        &self,
        inner: &Inner,
        p: &[f64],
        sign: FrictionSign,
        exact: bool,
        cutoff: f64,
    ) -> (At, Eval) {
        let (c, et) = self.coefficients(p);
        let (c, eval) = match self.profile_e {
            Some(e_range) => inner.evaluate_profile(&LineAt {
                e_range,
                mu: c.mu,
                em: c.em,
                mode: self.mode,
                sign,
            }),
            None => {
                let at = At {
                    c,
                    mode: self.mode,
                    sign,
                    et,
                };
                (c, inner.evaluate(&at, exact, cutoff))
            }
        };
        (
            At {
                c,
                mode: self.mode,
                sign,
                et,
            },
            eval,
        )
    }

    /// Every point of the grid.
    pub fn grid(&self) -> Vec<Vec<f64>> {
        product(self.dims.iter().map(Dim::axis))
    }
}

/// Every point of the grid spanned by `axes` (the first axis varies slowest).
pub(crate) fn product(axes: impl IntoIterator<Item = Vec<f64>>) -> Vec<Vec<f64>> {
    let mut pts: Vec<Vec<f64>> = vec![Vec::new()];
    for axis in axes {
        pts = pts
            .into_iter()
            .flat_map(|p| {
                axis.iter().map(move |&v| {
                    let mut q = p.clone();
                    q.push(v);
                    q
                })
            })
            .collect();
    }
    pts
}

/// The spaces of a branch; with `profile`, e is minimised exactly at every point instead of
/// being a dimension. The sticking mode searches e on a finer grid (2n + 1 points). Singular
/// faces of the box (pim-core's `KnownState::singular_faces`: e = 0 or em = 0, where a known
/// separation state leaves the contact state a family) are searched as spaces of their own.
pub(crate) fn spaces(
    branch: MomentBranch,
    s: &FitSettings,
    profile: bool,
    faces: SingularFaces,
) -> Vec<Space> {
    let e = Dim {
        lo: s.e[0],
        hi: s.e[1],
        n: if s.e[0] < s.e[1] { s.grid[0] } else { 1 },
    };
    let mu = Dim {
        lo: s.mu[0],
        hi: s.mu[1],
        n: if s.mu[0] < s.mu[1] { s.grid[1] } else { 1 },
    };
    let em = Dim {
        lo: -1.0,
        hi: 0.0,
        n: s.grid[2],
    };
    let fine_e = Dim {
        n: if e.n > 1 { 2 * e.n + 1 } else { 1 },
        ..e
    };
    let free = branch == MomentBranch::Free;
    if s.model.family().sticking() == crate::family::Sticking::Restitution {
        return tangential_spaces(e, fine_e, s);
    }
    let mut faces_at: Vec<(Option<f64>, Option<f64>)> = vec![(None, None)];
    if faces.e_zero && s.e[0] == 0.0 && s.e[1] > 0.0 {
        faces_at.push((Some(0.0), None));
    }
    if faces.em_zero && free {
        faces_at.push((None, Some(0.0)));
    }
    let mut out = Vec::new();
    for (e_fixed, em_fixed) in faces_at {
        for mode in [TangentialCondition::Sliding, TangentialCondition::NoSlip] {
            let mut dims = Vec::new();
            if !profile && e_fixed.is_none() {
                dims.push(if mode == TangentialCondition::Sliding {
                    e
                } else {
                    fine_e
                });
            }
            if mode == TangentialCondition::Sliding {
                dims.push(mu);
            }
            if free && em_fixed.is_none() {
                dims.push(em);
            }
            out.push(Space {
                branch,
                mode,
                dims,
                profile_e: profile.then_some(s.e),
                e_fixed,
                em_fixed,
                et_axis: false,
            });
        }
    }
    out
}

/// The spaces of the tangential model (no moment impulse, e searched): sticking over `(e, et)`
/// with the friction limit at its largest (any friction at least the impulse ratio sticks the
/// same way), and sliding over `(e, friction, et)`, where et only decides whether Routh's rule
/// slides (the answer does not depend on it).
fn tangential_spaces(e: Dim, fine_e: Dim, s: &FitSettings) -> Vec<Space> {
    let et = Dim {
        lo: s.et[0],
        hi: s.et[1],
        n: if s.et[0] < s.et[1] {
            s.grid[2].max(5)
        } else {
            1
        },
    };
    let friction = Dim {
        lo: s.friction[0],
        hi: s.friction[1],
        n: if s.friction[0] < s.friction[1] {
            s.grid[1].div_ceil(2).max(2)
        } else {
            1
        },
    };
    let space = |mode, dims| Space {
        branch: MomentBranch::Zero,
        mode,
        dims,
        profile_e: None,
        e_fixed: None,
        em_fixed: None,
        et_axis: true,
    };
    vec![
        space(TangentialCondition::Sliding, vec![e, friction, et]),
        space(TangentialCondition::NoSlip, vec![fine_e, et]),
    ]
}
