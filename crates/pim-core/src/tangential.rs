//! A second impact model beside PIM: normal and tangential restitution with a friction limit
//! (Kisilowski & Zalewski, equations 4.1-4.6; the family of PC-Crash's and Virtual CRASH's
//! impulse models).
//!
//! The impulse `P` acts at the impact centre C (on vehicle 1; `-P` on vehicle 2) and no moment
//! impulse acts. With `v = (vn, vt)` the relative velocity at C (vehicle 1 minus vehicle 2) and
//! `K` the 2x2 collision matrix of the two bodies at C,
//!
//! ```text
//! K = (1/m1 + 1/m2) I + (1/I1) r1p r1p' + (1/I2) r2p r2p'      (rp = (-ry, rx): r turned 90 deg)
//! v' - v = K P                                                   (in n, t components)
//! ```
//!
//! the model asks for `vn' = -e vn` (normal restitution) and `vt' = et vt` (tangential
//! restitution, `et` in [-1, 1]; `et = 0` ends the sliding, `et < 0` reverses it). When the
//! impulse that does so needs more than the friction limit, `|Pt| > friction |Pn|`, the vehicles
//! slide instead: `Pt = friction s Pn` with `s` the sign of that sticking impulse's ratio
//! `Pt_s / Pn_s` (the edge of the friction cone on the sticking impulse's side, the friction
//! rule of the crate docs: the ratio lies between 0 and the sticking ratio), and `Pn` from the
//! normal restitution alone. Where the coupling of the collision matrix does not reverse the
//! sliding, `s = sgn(vn) sgn(vt)`, friction against the initial sliding; where it does (PIM's
//! `mu_max < 0`), pushing against the initial sliding for the whole impulse would drive the
//! sliding past where sticking ends it, and the sticking impulse's side is the physical one.
//!
//! With `et = -e` this is the impulse-momentum model of Carpenter & Welcher (IMPC: the impulse
//! ratio capped at a friction coefficient, `P = (1 + e)` times the no-slip impulse of the
//! coupled bodies when the cap does not bind, no moment impulse); [`TangentialCoefficients::impc`]
//! builds its coefficients.
//!
//! Its exact relations to PIM, both with `e_m = 1` (no moment impulse): sticking with `et = 0`
//! is PIM's no-slip form, and sliding is PIM's sliding form with `mu = friction` on the sticking
//! impulse's side (`mu = -friction` where the coupling reverses the sliding). The solution is
//! reported as PIM's [`ImpactReport`] with these equivalent coefficients (`mu` = the impulse
//! ratio used in PIM's sign convention), and [`TangentialReport`] says which mode acted. Its
//! admissibility is the friction rule's test on the model's own sticking ratio
//! ([`crate::classify_friction`]; it holds by construction where the normal impulse pushes the
//! vehicles apart) and the energy balance: the model does not guarantee that no kinetic energy is
//! created (tangential restitution with a coupled collision matrix can add energy).

use crate::coefficients::{Coefficients, SolveOptions, TangentialCondition};
use crate::error::{PimError, Result};
use crate::friction::TangentialOutcome;
use crate::model::{Impact, Velocities};
use crate::report::ImpactReport;
use crate::{classify_friction, CriticalImpulse, MomentForm};

/// Relative tolerance of "the sticking ratio is within the friction limit" (Routh's condition):
/// the forward model's stick/slide decision and the fit's check of it use this one value.
pub const RATIO_TOL: f64 = 1e-12;
use nalgebra::{Matrix6, Vector6};
use serde::{Deserialize, Serialize};

/// Coefficients of the tangential-restitution model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TangentialCoefficients {
    /// Normal restitution: `vn' = -e vn`, in [0, 1].
    pub e: f64,
    /// Tangential restitution: `vt' = et vt` while sticking, in [-1, 1].
    pub et: f64,
    /// Friction limit: `|Pt| <= friction |Pn|`, >= 0.
    pub friction: f64,
}

impl TangentialCoefficients {
    /// The Carpenter-Welcher impulse-momentum model (IMPC) as this model: restitution `e` on
    /// both axes while the impulse ratio stays within `friction` (`et = -e`: sticking restores
    /// the tangential velocity at C with `-e`, as the normal one), the impulse ratio capped at
    /// `friction` otherwise.
    ///
    /// ```
    /// let c = pim_core::TangentialCoefficients::impc(0.1, 0.3);
    /// assert_eq!((c.e, c.et, c.friction), (0.1, -0.1, 0.3));
    /// ```
    pub fn impc(e: f64, friction: f64) -> Self {
        TangentialCoefficients {
            e,
            et: -e,
            friction,
        }
    }

    /// Checks the domains.
    pub fn validate(&self) -> Result<()> {
        for (name, value, ok, domain) in [
            ("e", self.e, (0.0..=1.0).contains(&self.e), "0 <= e <= 1"),
            (
                "et",
                self.et,
                (-1.0..=1.0).contains(&self.et),
                "-1 <= et <= 1",
            ),
            (
                "friction",
                self.friction,
                self.friction >= 0.0 && self.friction <= 100.0,
                "0 <= friction <= 100",
            ),
        ] {
            if !value.is_finite() {
                return Err(PimError::NonFiniteValue { field: name, value });
            }
            if !ok {
                return Err(PimError::CoefficientOutOfRange {
                    name,
                    value,
                    domain,
                });
            }
        }
        Ok(())
    }
}

/// Which condition decided the tangential impulse.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ContactMode {
    /// The tangential restitution was reached within the friction limit.
    Stick,
    /// Sticking would need more than the friction limit: the vehicles slide with
    /// `|Pt| = friction |Pn|`.
    Slide,
}

/// The solution of the tangential-restitution model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TangentialReport {
    /// The model's coefficients.
    pub coefficients: TangentialCoefficients,
    /// Stick or slide.
    pub mode: ContactMode,
    /// The impulse ratio `Pt / Pn` that acted.
    pub impulse_ratio: f64,
    /// The impulse ratio that sticking (`vt' = et vt`) would need.
    pub stick_ratio: f64,
    /// The solution as PIM's report, with the equivalent coefficients `e`, `mu` (the impulse
    /// ratio relative to the sliding direction) and `e_m = 1`; its admissibility is the
    /// model's own (no kinetic energy created; the friction limit holds by construction).
    pub report: ImpactReport,
}

/// The 2x2 collision matrix in `(n, t)` components: `[[Knn, Knt], [Ktn, Ktt]]`.
fn collision_matrix(impact: &Impact) -> [[f64; 2]; 2] {
    let [m1, m2] = impact.masses();
    let [i1, i2] = impact.inertias();
    let [r1, r2] = impact.lever_arms();
    let (n, t) = (impact.normal(), impact.tangent());
    let k = |a: [f64; 2], b: [f64; 2]| {
        let dot = a[0] * b[0] + a[1] * b[1];
        let term = |r: [f64; 2], inertia: f64| {
            let rp = [-r[1], r[0]];
            (rp[0] * a[0] + rp[1] * a[1]) * (rp[0] * b[0] + rp[1] * b[1]) / inertia
        };
        (1.0 / m1 + 1.0 / m2) * dot + term(r1, i1) + term(r2, i2)
    };
    [[k(n, n), k(n, t)], [k(t, n), k(t, t)]]
}

/// The impulse `(Pn, Pt)` on vehicle 1 that gives `vn' = -e vn` and `vt' = et vt` from the
/// relative velocity `(vn, vt)` at C, for the collision matrix `k`.
fn stick_impulse(k: &[[f64; 2]; 2], e: f64, et: f64, vn: f64, vt: f64) -> (f64, f64) {
    let [[knn, knt], [ktn, ktt]] = *k;
    let det = knn * ktt - knt * ktn;
    let (dn, dt) = (-(1.0 + e) * vn, (et - 1.0) * vt);
    ((ktt * dn - knt * dt) / det, (knn * dt - ktn * dn) / det)
}

/// The velocities after an impulse `(pn, pt)` (crush-surface components, on vehicle 1; `-P` on
/// vehicle 2) acts at C on the state `x`.
fn apply_impulse(impact: &Impact, pn: f64, pt: f64, x: &Vector6<f64>) -> Vector6<f64> {
    let (n, t) = (impact.normal(), impact.tangent());
    let p = [pn * n[0] + pt * t[0], pn * n[1] + pt * t[1]];
    let [m1, m2] = impact.masses();
    let [i1, i2] = impact.inertias();
    let [r1, r2] = impact.lever_arms();
    let cross = |r: [f64; 2]| r[0] * p[1] - r[1] * p[0];
    let mut x = *x;
    x[0] += p[0] / m1;
    x[1] += p[1] / m1;
    x[2] += cross(r1) / i1;
    x[3] -= p[0] / m2;
    x[4] -= p[1] / m2;
    x[5] -= cross(r2) / i2;
    x
}

/// The sticking mode as a linear map of the contact state: `X = R x` with `vn' = -e vn` and
/// `vt' = et vt` (whatever the friction limit; the fit checks it as a condition of its own).
/// `None` when the collision matrix is singular.
pub fn stick_transfer(impact: &Impact, e: f64, et: f64) -> Option<Matrix6<f64>> {
    let k = collision_matrix(impact);
    let det = k[0][0] * k[1][1] - k[0][1] * k[1][0];
    if !(det.is_finite() && det.abs() > 1e-300) {
        return None;
    }
    let mut r = Matrix6::zeros();
    for j in 0..6 {
        let x = Vector6::ith(j, 1.0);
        let (vn, vt) = impact.relative_velocity(&Velocities::from_vector(&x));
        let (pn, pt) = stick_impulse(&k, e, et, vn, vt);
        r.set_column(j, &apply_impulse(impact, pn, pt, &x));
    }
    Some(r)
}

/// The sticking mode's transfer matrix as an affine map of its coefficients: the impulse that
/// gives `vn' = -e vn` and `vt' = et vt` is linear in `(1 + e) vn` and `(1 - et) vt`, so
/// `R(e, et) = I + (1 + e) A + (1 - et) B` for all e and et (built once per geometry, for
/// callers that need the transfer at many coefficients).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StickMaps {
    /// The part proportional to `1 + e`: `R(0, 1) - I`.
    pub a: Matrix6<f64>,
    /// The part proportional to `1 - et`: `R(0, 0) - R(0, 1)`.
    pub b: Matrix6<f64>,
}

impl StickMaps {
    /// The maps of an impact; `None` when its collision matrix is singular.
    ///
    /// ```
    /// # use pim_core::*;
    /// # let v = |mass, yaw_inertia, heading, d, phi| Vehicle { mass, yaw_inertia, heading, d, phi };
    /// # let impact = Impact::new(Collision {
    /// #     vehicle1: v(1036.0, 1348.0, 0.0, 1.4, 0.0),
    /// #     vehicle2: v(2189.0, 5287.0, 90.0, 1.6, -30.0),
    /// #     crush_angle: 0.0,
    /// # })?;
    /// let maps = StickMaps::new(&impact).unwrap();
    /// let direct = stick_transfer(&impact, 0.3, -0.4).unwrap();
    /// assert!((maps.transfer(0.3, -0.4) - direct).amax() < 1e-12);
    /// # Ok::<(), PimError>(())
    /// ```
    pub fn new(impact: &Impact) -> Option<StickMaps> {
        let r01 = stick_transfer(impact, 0.0, 1.0)?;
        let r00 = stick_transfer(impact, 0.0, 0.0)?;
        Some(StickMaps {
            a: r01 - Matrix6::identity(),
            b: r00 - r01,
        })
    }

    /// `R(e, et)`.
    pub fn transfer(&self, e: f64, et: f64) -> Matrix6<f64> {
        Matrix6::identity() + self.a * (1.0 + e) + self.b * (1.0 - et)
    }
}

/// Solves the tangential-restitution model forwards: the separation velocities from the
/// velocities at contact. Errors: coefficients outside their domains, invalid velocities,
/// vehicles that do not approach at C.
///
/// ```
/// use pim_core::*;
/// let v = |mass, yaw_inertia, heading, d, phi| Vehicle { mass, yaw_inertia, heading, d, phi };
/// let impact = Impact::new(Collision {
///     vehicle1: v(1036.0, 1348.0, 0.0, 1.4, 0.0),
///     vehicle2: v(2189.0, 5287.0, 90.0, 1.6, -30.0),
///     crush_angle: 0.0,
/// })?;
/// let initial = Velocities::from_vector(&nalgebra::Vector6::new(-9.48, 0.0, 0.0, 0.0, 9.48, 0.0));
/// let c = TangentialCoefficients { e: 0.1, et: 0.0, friction: 2.0 };
/// let r = solve_tangential(&impact, &c, &initial)?;
/// assert_eq!(r.mode, ContactMode::Stick);
/// let (vn, vt) = impact.relative_velocity(&r.report.separation);
/// assert!(vt.abs() < 1e-9 && (vn - 0.1 * 9.48).abs() < 1e-9);
/// # Ok::<(), PimError>(())
/// ```
pub fn solve_tangential(
    impact: &Impact,
    coefficients: &TangentialCoefficients,
    initial: &Velocities,
) -> Result<TangentialReport> {
    coefficients.validate()?;
    initial.validate()?;
    impact.check_approach(initial)?;
    let c = coefficients;
    let (vn, vt) = impact.relative_velocity(initial);
    let k = collision_matrix(impact);
    let [[knn, knt], _] = k;
    // The impulse that gives vn' = -e vn and vt' = et vt.
    let (pn_stick, pt_stick) = stick_impulse(&k, c.e, c.et, vn, vt);
    let dn = -(1.0 + c.e) * vn;
    let stick_ratio = pt_stick / pn_stick;
    // The one friction rule: the ratio lies between 0 and that of the sticking impulse, so a
    // binding limit puts it on the edge of the friction cone on the sticking impulse's side
    // (IMPC's rule), whatever the initial sliding direction.
    let side = CriticalImpulse {
        normal: pn_stick,
        tangential: pt_stick,
    }
    .direction();
    let tol = RATIO_TOL * (1.0 + c.friction);
    let (mode, ratio) = if stick_ratio.abs() <= c.friction + tol {
        (ContactMode::Stick, stick_ratio)
    } else {
        (ContactMode::Slide, c.friction * side.value())
    };
    let pn = match mode {
        ContactMode::Stick => pn_stick,
        ContactMode::Slide => dn / (knn + ratio * knt),
    };
    let pt = ratio * pn;
    let x = apply_impulse(impact, pn, pt, &initial.to_vector());
    let separation = Velocities::from_vector(&x);
    // PIM's equivalent: e, mu = the ratio in PIM's sign convention (relative to the sliding at
    // contact, or to PIM's no-slip impulse where there is none), em = 1; the no-slip form when
    // the model sticks with et = 0 (PIM's equation 5a).
    let pim_options = SolveOptions {
        moment_form: MomentForm::Corrected,
        tangential: TangentialCondition::Sliding,
    };
    let frictionless = Coefficients {
        e: c.e,
        mu: 0.0,
        em: 1.0,
    };
    let (sign, _) = crate::contact_friction(impact, &frictionless, initial, &pim_options);
    let mu = ratio * sign.value();
    let options = SolveOptions {
        moment_form: MomentForm::Corrected,
        tangential: if mode == ContactMode::Stick && c.et == 0.0 {
            TangentialCondition::NoSlip
        } else {
            TangentialCondition::Sliding
        },
    };
    let equivalent = Coefficients {
        e: c.e,
        mu,
        em: 1.0,
    };
    let mut report = crate::analyse(impact, &equivalent, &options, initial, &separation, sign)?;
    // The model's own tangential outcome, and its friction test by the same rule as PIM's: the
    // ratio between 0 and the sticking ratio (classify_friction), with a normal impulse that
    // pushes the vehicles apart.
    let verdict = classify_friction(ratio, Some(stick_ratio));
    report.tangential = match mode {
        ContactMode::Stick => TangentialOutcome::Sticking,
        ContactMode::Slide => TangentialOutcome::Sliding,
    };
    report.mu_ratio = verdict.ratio;
    report.admissibility.friction_ok = verdict.admissible && pn * vn <= 0.0;
    report.admissibility.admissible =
        report.admissibility.friction_ok && report.admissibility.energy_ok;
    Ok(TangentialReport {
        coefficients: *c,
        mode,
        impulse_ratio: ratio,
        stick_ratio,
        report,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::{solve_forward, Collision, Vehicle};

    pub(crate) fn impact() -> Impact {
        let v = |mass, yaw_inertia, heading, d, phi| Vehicle {
            mass,
            yaw_inertia,
            heading,
            d,
            phi,
        };
        Impact::new(Collision {
            vehicle1: v(1955.0, 4723.0, 0.0, 1.8, 0.0),
            vehicle2: v(1197.0, 2279.0, 60.0, 0.9, -140.0),
            crush_angle: -30.0,
        })
        .unwrap()
    }

    pub(crate) fn initial() -> Velocities {
        Velocities::from_vector(&nalgebra::Vector6::new(-13.01, 0.0, 0.0, 6.50, 11.27, 0.0))
    }

    #[test]
    fn domains_are_checked() {
        for (e, et, friction) in [(1.2, 0.0, 1.0), (0.1, -1.5, 1.0), (0.1, 0.0, -0.1)] {
            let c = TangentialCoefficients { e, et, friction };
            assert!(solve_tangential(&impact(), &c, &initial()).is_err());
        }
    }

    #[test]
    fn sticking_with_zero_tangential_restitution_is_pims_no_slip_form() {
        let c = TangentialCoefficients {
            e: 0.12,
            et: 0.0,
            friction: 10.0,
        };
        let r = solve_tangential(&impact(), &c, &initial()).unwrap();
        assert_eq!(r.mode, ContactMode::Stick);
        let pim = solve_forward(
            &impact(),
            &Coefficients {
                e: 0.12,
                mu: 0.5,
                em: 1.0,
            },
            &initial(),
            &SolveOptions {
                moment_form: MomentForm::Corrected,
                tangential: TangentialCondition::NoSlip,
            },
        )
        .unwrap();
        let (a, b) = (r.report.separation.to_vector(), pim.separation.to_vector());
        assert!((a - b).amax() < 1e-9, "{a} vs {b}");
        // The impulse ratio used is PIM's critical ratio mu_max.
        let mu_max = pim.mu_max.unwrap();
        assert!((r.report.coefficients.mu - mu_max).abs() < 1e-9);
    }

    #[test]
    fn a_binding_friction_limit_is_pims_sliding_form() {
        let c = TangentialCoefficients {
            e: 0.12,
            et: 0.0,
            friction: 0.3,
        };
        let r = solve_tangential(&impact(), &c, &initial()).unwrap();
        assert_eq!(r.mode, ContactMode::Slide);
        assert!(r.stick_ratio.abs() > 0.3);
        let pim = solve_forward(
            &impact(),
            &Coefficients {
                e: 0.12,
                mu: 0.3,
                em: 1.0,
            },
            &initial(),
            &SolveOptions::default(),
        )
        .unwrap();
        let (a, b) = (r.report.separation.to_vector(), pim.separation.to_vector());
        assert!((a - b).amax() < 1e-9, "{a} vs {b}");
        assert!(
            (r.report.impulse.tangential.abs() - 0.3 * r.report.impulse.normal.abs()).abs() < 1e-6
        );
        assert!(r.report.impulse.moment.abs() < 1e-6);
    }

    #[test]
    fn tangential_restitution_reverses_the_sliding_when_negative() {
        let c = TangentialCoefficients {
            e: 0.1,
            et: -0.3,
            friction: 10.0,
        };
        let r = solve_tangential(&impact(), &c, &initial()).unwrap();
        let (_, vt) = impact().relative_velocity(&initial());
        let (_, vt1) = impact().relative_velocity(&r.report.separation);
        assert!((vt1 + 0.3 * vt).abs() < 1e-9);
    }

    #[test]
    fn the_stick_transfer_is_the_sticking_solution() {
        for (e, et) in [(0.0, 0.0), (0.12, 0.4), (0.3, -0.7), (1.0, 1.0)] {
            let c = TangentialCoefficients {
                e,
                et,
                friction: 100.0,
            };
            let r = solve_tangential(&impact(), &c, &initial()).unwrap();
            assert_eq!(r.mode, ContactMode::Stick);
            let t = stick_transfer(&impact(), e, et).unwrap();
            let got = t * initial().to_vector();
            let want = r.report.separation.to_vector();
            assert!((got - want).amax() < 1e-9, "{got} vs {want}");
        }
    }
}
