//! The convex pieces of a branch over a box of geometries: PIM's sign patterns (those of the
//! convex route at a fixed geometry, [`crate::convex`]) written as rows over U whose entries are
//! polynomials in the geometry, with every number that depends on the geometry replaced by its
//! range over the box.
//!
//! At one geometry the convex route fixes the signs of the friction, of Pn, Pt and Vt, of the
//! frictionless and no-slip normal impulses and of W_lin, and needs three numbers of the
//! geometry and e_m: the side of the crush surface each vehicle is on, the sign `kappa` of
//! `dVt / dPt` along the line of impulses, and the ratios `rho_a = dPn / dPt`,
//! `rho_b = dPn / dVt` along it. Over a box they are enclosed by interval arithmetic (the line's
//! direction is a cross product of rows of the impulse parametrisation `q = (Px, Py, M)`:
//! `dV1 = P / m1`, `dV2 = -P / m2`, `dW1 = (r1 x P + M) / I1`, `dW2 = -(r2 x P + M) / I2`).
//! Where the side or kappa is not decided over the box, both values are pieces; where a ratio
//! is unbounded, its row is left out. Every piece at every geometry of the box is therefore
//! contained in a piece written here, and so is every point the fit admits (the rows are the
//! nominal conditions, without the fit's inward tolerances and its floor on |Pn|; the energy
//! condition, which is not convex, is left out): the pieces relax the branch.

use super::interval::Iv;
use super::poly::{rows, Inertia, MonoBox, Over, Poly};
use crate::problem::MomentBranch;
use crate::settings::FitSettings;

/// The rows every piece is built from, and the settings they need.
#[derive(Debug, Clone)]
pub(crate) struct Forms {
    k: Inertia,
    vn: Poly,
    big_vn: Poly,
    vt: Poly,
    big_vt: Poly,
    pn: Poly,
    pt: Poly,
    w_final: Poly,
    w_lin: Poly,
    momentum: [Poly; 3],
    b: Poly,
    w_row: Poly,
    e: [f64; 2],
    mu: [f64; 2],
    velocity: f64,
    yaw: f64,
    approach: f64,
}

impl Forms {
    pub fn new(k: Inertia, settings: &FitSettings) -> Forms {
        let form = settings.model.family().moment_form(settings.moment_form);
        let (pn, pt) = rows::impulse(&k);
        let w_final = rows::relative_yaw(form);
        let b = rows::moment_b(&k);
        Forms {
            vn: rows::normal(Over::Contact),
            big_vn: rows::normal(Over::Separation),
            vt: rows::tangential(Over::Contact),
            big_vt: rows::tangential(Over::Separation),
            pn,
            pt,
            w_lin: w_final.add(&b, 1.0),
            w_final,
            momentum: rows::momentum(&k),
            b,
            w_row: rows::relative_yaw(form),
            k,
            e: settings.e,
            mu: settings.mu,
            velocity: settings.velocity_bound,
            yaw: settings.yaw_rate_bound,
            approach: settings.search.min_approach_speed,
        }
    }

    /// The velocity bounds `|U_k| <= limit_k`.
    pub fn limits(&self) -> [f64; 12] {
        std::array::from_fn(|k| if k % 3 == 2 { self.yaw } else { self.velocity })
    }

    /// The equalities `row . U = 0`: equations 1-3, and B = 0 in the zero branch.
    pub fn equalities(&self, branch: MomentBranch) -> Vec<Poly> {
        let mut e = self.momentum.to_vec();
        if branch == MomentBranch::Zero {
            e.push(self.b);
        }
        e
    }
}

/// What a box of geometries (and an e_m interval) leaves of the numbers the pieces need.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Relax {
    pub sides: Vec<f64>,
    pub kappas: Vec<f64>,
    pub rho_a: [f64; 2],
    pub rho_b: [f64; 2],
    pub em: [f64; 2],
}

/// One piece: its signs (as in the convex route; `s_w` is 1 in the zero branch).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub(crate) struct Leaf {
    pub sign: i8,
    pub side: i8,
    pub s_w: i8,
    pub s_a: i8,
    pub s_b: i8,
    pub s_n: i8,
    pub s_t: i8,
    pub s_v: i8,
}

fn dot6(a: &[Iv; 12], offset: usize, b: &[Iv; 6]) -> Iv {
    (0..6).fold(Iv::point(0.0), |s, k| s + a[offset + k] * b[k])
}

impl Forms {
    /// The values of e_m in `(lo, hi)` where the line's Pt or Vt slope vanishes at a geometry
    /// point (the poles of the ratios; the slopes are affine in e_m).
    pub fn poles(&self, point: &MonoBox, em: [f64; 2]) -> Vec<f64> {
        let at = |e: f64| {
            let (_, pt, vt) = self.slopes(point, MomentBranch::Free, [e, e]);
            [pt.mid(), vt.mid()]
        };
        let (a, b) = (at(0.0), at(1.0));
        let mut out: Vec<f64> = (0..2)
            .filter_map(|i| {
                let slope = b[i] - a[i];
                (slope != 0.0).then(|| -a[i] / slope)
            })
            .filter(|&r| r > em[0] && r < em[1])
            .collect();
        out.sort_by(f64::total_cmp);
        out
    }

    /// The slopes `(dPn, dPt, dVt)` along the line of impulses over a box and an e_m interval
    /// (one common scale).
    fn slopes(&self, mono: &MonoBox, branch: MomentBranch, em: [f64; 2]) -> (Iv, Iv, Iv) {
        let [m1, m2] = self.k.m;
        let [i1, i2] = self.k.i;
        let pt = |v: f64| Iv::point(v);
        let p = |j: usize| mono.mono[3 + j];
        let (c, s) = (mono.mono[1], mono.mono[2]);
        let z = pt(0.0);
        // Columns of the change of U for q = (Px, Py, M).
        let cols = [
            [
                pt(1.0 / m1),
                z,
                p(2).scale(1.0 / i1),
                pt(-1.0 / m2),
                z,
                p(0).scale(1.0 / i2),
            ],
            [
                z,
                pt(1.0 / m1),
                p(3).scale(-1.0 / i1),
                z,
                pt(-1.0 / m2),
                p(1).scale(-1.0 / i2),
            ],
            [z, z, pt(1.0 / i1), z, z, pt(-1.0 / i2)],
        ];
        let n_row = self.big_vn.over(mono);
        let t_row = self.big_vt.over(mono);
        let w_row = self.w_row.over(mono);
        let u1 = cols.map(|col| dot6(&n_row, 6, &col));
        let dvt = cols.map(|col| dot6(&t_row, 6, &col));
        let delta = match branch {
            MomentBranch::Zero => [-u1[1], u1[0], z],
            MomentBranch::Free => {
                let e = Iv::new(em[0], em[1]);
                let dwf = cols.map(|col| dot6(&w_row, 6, &col));
                let db = [z, z, pt(1.0 / i1 + 1.0 / i2)];
                let u2: [Iv; 3] = std::array::from_fn(|j| (pt(1.0) - e) * dwf[j] - e * db[j]);
                [
                    u1[1] * u2[2] - u1[2] * u2[1],
                    u1[2] * u2[0] - u1[0] * u2[2],
                    u1[0] * u2[1] - u1[1] * u2[0],
                ]
            }
        };
        let pn = c * delta[0] + s * delta[1];
        let ptan = -(s * delta[0]) + c * delta[1];
        let vt = dvt[0] * delta[0] + dvt[1] * delta[1] + dvt[2] * delta[2];
        (pn, ptan, vt)
    }

    /// The side, kappa and the ratios over a box (its monomials) and an e_m interval.
    pub fn relax(&self, mono: &MonoBox, branch: MomentBranch, em: [f64; 2]) -> Relax {
        let [m1, m2] = self.k.m;
        let p = |j: usize| mono.mono[3 + j];
        let (c, s) = (mono.mono[1], mono.mono[2]);
        let (pn, ptan, vt) = self.slopes(mono, branch, em);
        let both = vec![1.0, -1.0];
        let kappas = (ptan * vt).sign().map_or(both.clone(), |k| vec![k]);
        let range = |i: Iv| [i.lo, i.hi];
        // The side: the sign of the mobility-weighted heights of the CGs above the crush plane
        // (pim-core's Impact::side); undecided (0, read as +1 by the fit) counts as both.
        let (w1, w2) = (m2 / (m1 + m2), m1 / (m1 + m2));
        let h1 = p(3) * c + p(2) * s;
        let h2 = -(p(1) * c + p(0) * s);
        let sep = h1.scale(w1) - h2.scale(w2);
        let scale =
            (p(2).sqr() + p(3).sqr()).hi.sqrt() * w1 + (p(0).sqr() + p(1).sqr()).hi.sqrt() * w2;
        let sides = match sep.sign() {
            Some(v) if sep.lo.abs().min(sep.hi.abs()) > 2e-9 * scale => vec![v],
            _ => both,
        };
        Relax {
            sides,
            kappas,
            rho_a: range(pn.div(ptan)),
            rho_b: range(pn.div(vt)),
            em: match branch {
                MomentBranch::Zero => [1.0, 1.0],
                MomentBranch::Free => em,
            },
        }
    }

    /// The pieces of a box.
    pub fn leaves(&self, relax: &Relax, branch: MomentBranch) -> Vec<Leaf> {
        let s_ws: &[i8] = match branch {
            MomentBranch::Zero => &[1],
            MomentBranch::Free => &[1, -1],
        };
        let mut out = Vec::new();
        for sign in [1i8, -1] {
            for &side in &relax.sides {
                for &s_w in s_ws {
                    for s_a in [1i8, -1] {
                        for s_b in [s_a, -s_a] {
                            let s_ns: &[i8] = if s_a == s_b { &[1] } else { &[1, -1] };
                            for &rel in s_ns {
                                for s_t in [1i8, -1] {
                                    for &kappa in &relax.kappas {
                                        let s_v = -(kappa as i8) * s_a * s_b * s_t;
                                        out.push(Leaf {
                                            sign,
                                            side: side as i8,
                                            s_w,
                                            s_a,
                                            s_b,
                                            s_n: s_a * rel,
                                            s_t,
                                            s_v,
                                        });
                                    }
                                }
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// The rows `row . U >= rhs` of a piece.
    pub fn rows(&self, leaf: &Leaf, relax: &Relax, branch: MomentBranch) -> Vec<(Poly, f64)> {
        let f = |v: i8| v as f64;
        let side = f(leaf.side);
        // (The velocity bounds are the domain of the bound's minimisation, [`super::bound`].)
        let mut out = Vec::with_capacity(16);
        // Approach, restitution within [e_min, e_max] (a = -side vn, b = side Vn).
        out.push((self.vn.scaled(-side), self.approach));
        let (a, b) = (self.vn.scaled(-side), self.big_vn.scaled(side));
        out.push((b.add(&a, -self.e[0]), 0.0));
        out.push((a.scaled(self.e[1]).add(&b, -1.0), 0.0));
        // Sliding direction of the friction sign: sgn(vt) = -sign side (closed).
        out.push((self.vt.scaled(-f(leaf.sign) * side), 0.0));
        // mu = sign Pt / Pn within its bounds for the sign of Pn.
        let spt = self.pt.scaled(f(leaf.sign));
        let s_n = f(leaf.s_n);
        out.push((self.pn.scaled(s_n), 0.0));
        let [mlo, mhi] = self.mu;
        if mlo.is_finite() {
            out.push((spt.add(&self.pn, -mlo).scaled(s_n), 0.0));
        }
        if mhi.is_finite() {
            out.push((spt.add(&self.pn, -mhi).scaled(-s_n), 0.0));
        }
        // mu between 0 and mu_max: the signs of Pt and Vt, and of Pn0 and Pn* for some ratio.
        out.push((self.pt.scaled(f(leaf.s_t)), 0.0));
        out.push((self.big_vt.scaled(f(leaf.s_v)), 0.0));
        for (form, sf, sg, rho) in [
            (&self.pt, f(leaf.s_t), f(leaf.s_a), relax.rho_a),
            (&self.big_vt, f(leaf.s_v), f(leaf.s_b), relax.rho_b),
        ] {
            let r = if sg * sf > 0.0 { rho[0] } else { rho[1] };
            if r.is_finite() {
                out.push((self.pn.add(form, -r).scaled(sg), 0.0));
            }
        }
        if branch == MomentBranch::Free {
            let s_w = f(leaf.s_w);
            let [lo, hi] = relax.em;
            out.push((self.w_lin.scaled(s_w), 0.0));
            out.push((self.w_final.add(&self.w_lin, -lo).scaled(s_w), 0.0));
            out.push((self.w_final.add(&self.w_lin, -hi).scaled(-s_w), 0.0));
        }
        out
    }
}
