//! Assembly of the six linear impact equations.
//!
//! Every equation is homogeneous and linear in the twelve velocity components, so the system is
//! written `F X + G x = 0`, with `X = (V1x, V1y, W1, V2x, V2y, W2)` the separation state and
//! `x = (v1x, v1y, w1, v2x, v2y, w2)` the contact state. Each row function returns the pair
//! `(f, g)` of row vectors of one equation.

use crate::coefficients::{Coefficients, MomentForm, SolveOptions, TangentialCondition};
use crate::error::Equation;
use crate::friction::{CriticalImpulse, FrictionSign};
use crate::model::Impact;
use nalgebra::{Matrix6, RowVector6, Vector6};

/// One equation: coefficients of the separation state (`f`) and of the contact state (`g`).
pub type Row = (RowVector6<f64>, RowVector6<f64>);

/// The six equations `F X + G x = 0` and which equation sits in each row.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearSystem {
    /// Coefficients of the separation state X.
    pub f: Matrix6<f64>,
    /// Coefficients of the contact state x.
    pub g: Matrix6<f64>,
    /// The equation of each row.
    pub equations: [Equation; 6],
}

fn momentum(row: RowVector6<f64>) -> Row {
    (row, -row)
}

/// The limit row of equations 1-3 against a barrier: vehicle 2's component `k` does not change.
fn barrier_row(k: usize) -> Row {
    let mut row = RowVector6::zeros();
    row[k] = 1.0;
    momentum(row)
}

/// Equation 1: `m1 (V1x - v1x) + m2 (V2x - v2x) = 0` (barrier: `V2x - v2x = 0`).
pub fn momentum_x(impact: &Impact) -> Row {
    if impact.is_barrier() {
        return barrier_row(3);
    }
    let [m1, m2] = impact.masses();
    momentum(RowVector6::new(m1, 0.0, 0.0, m2, 0.0, 0.0))
}

/// Equation 2: `m1 (V1y - v1y) + m2 (V2y - v2y) = 0` (barrier: `V2y - v2y = 0`).
pub fn momentum_y(impact: &Impact) -> Row {
    if impact.is_barrier() {
        return barrier_row(4);
    }
    let [m1, m2] = impact.masses();
    momentum(RowVector6::new(0.0, m1, 0.0, 0.0, m2, 0.0))
}

/// Equation 3: `I1 (W1 - w1) + I2 (W2 - w2) + m1 (D2 + D4)(V1y - v1y) + m2 (D1 + D3)(V2x - v2x) = 0`
/// (barrier: `W2 - w2 = 0`).
pub fn angular_momentum(impact: &Impact) -> Row {
    if impact.is_barrier() {
        return barrier_row(5);
    }
    let [m1, m2] = impact.masses();
    let [i1, i2] = impact.inertias();
    let [d1, d2, d3, d4] = impact.levers();
    momentum(RowVector6::new(
        0.0,
        m1 * (d2 + d4),
        i1,
        m2 * (d1 + d3),
        0.0,
        i2,
    ))
}

/// The normal relative velocity at C as a row: `vn = row . x`.
pub fn normal_velocity_row(impact: &Impact) -> RowVector6<f64> {
    let [d1, d2, d3, d4] = impact.levers();
    let [c, s] = impact.normal();
    RowVector6::new(c, s, d3 * c - d4 * s, -c, -s, d1 * c - d2 * s)
}

/// The tangential relative velocity at C as a row: `vt = row . x`.
pub fn tangential_velocity_row(impact: &Impact) -> RowVector6<f64> {
    let [d1, d2, d3, d4] = impact.levers();
    let [ts, tc] = impact.tangent(); // (-sin G, cos G)
    RowVector6::new(ts, tc, ts * d3 - tc * d4, -ts, -tc, ts * d1 - tc * d2)
}

/// Equation 4: `Vn = -e vn`.
pub fn restitution(impact: &Impact, e: f64) -> Row {
    let row = normal_velocity_row(impact);
    (row, e * row)
}

/// Equation 5: `m1 (V1y - v1y)(cos G - mu' sin G) + m2 (V2x - v2x)(sin G + mu' cos G) = 0`, with
/// `mu' = mu * friction_sign` (the sign factor of the friction rule: the initial sliding
/// direction, or the no-slip impulse's side where there is none, [`crate::contact_friction`]). It says
/// `Pt = mu' Pn` for the impulse on vehicle 1; against a barrier it is written with that impulse
/// alone: `m1 (V1y - v1y)(cos G - mu' sin G) - m1 (V1x - v1x)(sin G + mu' cos G) = 0`.
pub fn friction(impact: &Impact, mu: f64, friction_sign: FrictionSign) -> Row {
    let [m1, m2] = impact.masses();
    let [c, s] = impact.normal();
    let mu_s = mu * friction_sign.value();
    if impact.is_barrier() {
        return momentum(RowVector6::new(
            -m1 * (s + mu_s * c),
            m1 * (c - mu_s * s),
            0.0,
            0.0,
            0.0,
            0.0,
        ));
    }
    momentum(RowVector6::new(
        0.0,
        m1 * (c - mu_s * s),
        0.0,
        m2 * (s + mu_s * c),
        0.0,
        0.0,
    ))
}

/// The normal and tangential impulse on vehicle 1 as rows over the velocity change
/// `D = X - x`: `Pn = pn . D`, `Pt = pt . D`, with `P = m1 (V1 - v1)` (vehicle 2 receives `-P`).
/// Every projection of the impulse onto the crush surface goes through these rows.
pub fn impulse_rows(impact: &Impact) -> (RowVector6<f64>, RowVector6<f64>) {
    let [m1, _] = impact.masses();
    let [nx, ny] = impact.normal();
    let [tx, ty] = impact.tangent();
    (
        RowVector6::new(m1 * nx, m1 * ny, 0.0, 0.0, 0.0, 0.0),
        RowVector6::new(m1 * tx, m1 * ty, 0.0, 0.0, 0.0, 0.0),
    )
}

/// The normal and tangential impulse on vehicle 1 of a velocity change `D = X - x`, through
/// [`impulse_rows`].
pub fn impulse_of(impact: &Impact, change: &Vector6<f64>) -> CriticalImpulse {
    let (pn, pt) = impulse_rows(impact);
    CriticalImpulse {
        normal: (pn * change)[0],
        tangential: (pt * change)[0],
    }
}

/// Equation 5a: `Vt = 0`.
pub fn no_slip(impact: &Impact) -> Row {
    (tangential_velocity_row(impact), RowVector6::zeros())
}

/// The relative-yaw-rate change caused by the moment impulse alone, as a row:
/// `B = b . (X - x)`, `b = (-m1 D3/I1, m1 D4/I1, 1, -m2 D1/I2, m2 D2/I2, -1)` (barrier: the
/// vehicle-2 terms are 0, as vehicle 2 does not move).
pub fn moment_b_row(impact: &Impact) -> RowVector6<f64> {
    let [m1, m2] = impact.masses();
    let [i1, i2] = impact.inertias();
    let [d1, d2, d3, d4] = impact.levers();
    if impact.is_barrier() {
        return RowVector6::new(-m1 * d3 / i1, m1 * d4 / i1, 1.0, 0.0, 0.0, 0.0);
    }
    RowVector6::new(
        -m1 * d3 / i1,
        m1 * d4 / i1,
        1.0,
        -m2 * d1 / i2,
        m2 * d2 / i2,
        -1.0,
    )
}

/// The relative yaw rate of equation 6 over the separation state: `W2 - W1` in the corrected
/// form (1984), `W1 - W2` in the 1983 listing.
pub fn relative_yaw_row(form: MomentForm) -> RowVector6<f64> {
    let sign = match form {
        MomentForm::Corrected => 1.0,
        MomentForm::Brach1983 => -1.0,
    };
    RowVector6::new(0.0, 0.0, -sign, 0.0, 0.0, sign)
}

/// Equation 6. Corrected (1984): `(W2 - W1)(1 - em) = em B`; 1983 listing: `(W1 - W2)(1 - em) = em B`.
pub fn moment_restitution(impact: &Impact, em: f64, form: MomentForm) -> Row {
    let b = moment_b_row(impact);
    let w = relative_yaw_row(form) * (1.0 - em);
    (w - b * em, b * em)
}

/// Assembles the six equations for given coefficients, friction sign and options.
///
/// `friction_sign` is the sign factor of equation 5 (see [`crate::contact_friction`]);
/// it is ignored under [`TangentialCondition::NoSlip`].
pub fn assemble(
    impact: &Impact,
    coefficients: &Coefficients,
    friction_sign: FrictionSign,
    options: &SolveOptions,
) -> LinearSystem {
    let (tangential, eq5) = match options.tangential {
        TangentialCondition::Sliding => (
            friction(impact, coefficients.mu, friction_sign),
            Equation::Friction,
        ),
        TangentialCondition::NoSlip => (no_slip(impact), Equation::NoSlip),
    };
    let rows = [
        momentum_x(impact),
        momentum_y(impact),
        angular_momentum(impact),
        restitution(impact, coefficients.e),
        tangential,
        moment_restitution(impact, coefficients.em, options.moment_form),
    ];
    let mut f = Matrix6::zeros();
    let mut g = Matrix6::zeros();
    for (i, (fr, gr)) in rows.iter().enumerate() {
        f.set_row(i, fr);
        g.set_row(i, gr);
    }
    LinearSystem {
        f,
        g,
        equations: [
            Equation::MomentumX,
            Equation::MomentumY,
            Equation::AngularMomentum,
            Equation::Restitution,
            eq5,
            Equation::MomentRestitution,
        ],
    }
}
