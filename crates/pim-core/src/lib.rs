//! # pim-core: Brach's Planar Impact Mechanics
//!
//! The forward (and backward) solver of the planar impact model of R. M. Brach (1983, 1984):
//! six linear impulse-momentum equations relate the velocities of two vehicles at the start of
//! contact to those at separation through three coefficients, restitution `e`, equivalent
//! friction `mu` and moment restitution `em`.
//!
//! ## Units and symbols
//! SI throughout: kg, kg m^2, m, m/s, rad/s. Angles in the input types ([`Vehicle`],
//! [`Collision`]) are in **degrees**. Vehicle 1 is the papers' vehicle A, vehicle 2 is B. Lower
//! case = contact (initial), upper case = separation (final).
//!
//! ### Two ways to give a heading
//! [`Vehicle::heading`] is the papers' theta: vehicle 2's nose points along theta2, but
//! vehicle 1's theta1 is the direction of its *tail* (its nose points along theta1 + 180 deg),
//! which is how Brach's tables and the RICSAC data are written. Scene diagrams and simulation
//! programs give both headings as the direction the nose points; [`Convention::Natural`]
//! converts such a heading with [`Convention::theta`], and [`impact_point_polar`] turns an
//! impact centre given in the vehicle's own frame (x forward, y to the left) into `(d, phi)`.
//! [`Impact::nose_heading`], [`Impact::forward_axis`] and [`Impact::to_body`] give each
//! vehicle's own axes whichever way the heading was given.
//!
//! Geometry (names of the 1983 BASIC listing):
//! ```text
//! D1 = d2 sin(theta2 + phi2)     D2 = d2 cos(theta2 + phi2)
//! D3 = d1 sin(theta1 + phi1)     D4 = d1 cos(theta1 + phi1)
//! ```
//! The impact centre C sits at `r1 = -(D4, D3)` from vehicle 1's CG and at `r2 = (D2, D1)` from
//! vehicle 2's (the papers' convention, in which the published RICSAC angles are written).
//! Velocities of the material points at C: vehicle 1 `(v1x + D3 w1, v1y - D4 w1)`, vehicle 2
//! `(v2x - D1 w2, v2y + D2 w2)`. The crush surface has normal `n = (cos G, sin G)` and tangent
//! `t = (-sin G, cos G)`; `vn`, `vt` are the relative velocity at C (vehicle 1 minus vehicle 2)
//! along n and t, `Vn`, `Vt` the same at separation.
//!
//! ## The six equations
//! ```text
//! (1) m1 (V1x - v1x) + m2 (V2x - v2x) = 0
//! (2) m1 (V1y - v1y) + m2 (V2y - v2y) = 0
//! (3) I1 (W1 - w1) + I2 (W2 - w2) + m1 (D2 + D4)(V1y - v1y) + m2 (D1 + D3)(V2x - v2x) = 0
//! (4) Vn = -e vn
//! (5) m1 (V1y - v1y)(cos G - mu' sin G) + m2 (V2x - v2x)(sin G + mu' cos G) = 0,
//!     mu' = mu s,  s = sgn(vn) sgn(vt)            (friction opposes the initial sliding)
//!     where vt = 0 at contact: s = sgn(Pt* Pn*) of the no-slip impulse (5a), the sliding the
//!     normal impulse itself causes (|vt| <= NO_SLIDING_TOL x the contact-point speeds is 0)
//! (5a) Vt = 0                                     (instead of 5: sliding ends before separation)
//! (6) (W2 - W1)(1 - em) = em B                    (corrected form, Brach 1984; the default)
//!     (W1 - W2)(1 - em) = em B                    (1983 listing, MomentForm::Brach1983)
//!     B = (W1 - w1) - m1 D3 (V1x - v1x)/I1 + m1 D4 (V1y - v1y)/I1
//!       - (W2 - w2) - m2 D1 (V2x - v2x)/I2 + m2 D2 (V2y - v2y)/I2
//! ```
//! `em = 1` means no moment impulse at C (M = 0), `em = 0` equal final yaw rates, `em = -1` a
//! perfectly elastic angular impact. All six are homogeneous and linear in the twelve velocity
//! components, `F X + G x = 0` ([`equations::assemble`]): forwards `X = -F^-1 G x`, backwards
//! `x = -G^-1 F X`.
//!
//! ## A fixed rigid barrier
//! Vehicle 2 may be a barrier ([`Vehicle::barrier`]: infinite mass and yaw inertia, at rest).
//! The equations are then their limits as `m2, I2` grow without bound: (1)-(3) divided by `m2`
//! (or `I2`) become `V2 - v2 = 0`; (5) is written with vehicle 1's impulse alone,
//! `m1 (V1y - v1y)(cos G - mu' sin G) - m1 (V1x - v1x)(sin G + mu' cos G) = 0` (the same
//! equation in the two-vehicle case, where (1) gives `m2 (V2x - v2x) = -m1 (V1x - v1x)`); the
//! vehicle-2 terms of `B` vanish; (4) is unchanged. Momentum is not conserved (the ground takes
//! it), kinetic energy is vehicle 1's, and vehicle 2's velocities must be 0
//! ([`Impact::check_barrier_state`]). The tangential-restitution model ([`tangential`]) is
//! written with `1/m2`, `1/I2` and needs no special form.
//!
//! ## Derived results ([`ImpactReport`])
//! - impulse on vehicle 1 `P = m1 (V1 - v1)`, `Pn = P.n`, `Pt = P.t`, moment impulse
//!   `M = I1 (W1 - w1) - r1 x P`;
//! - delta-V `|V - v|` and its direction per vehicle, and what a reconstruction reads
//!   ([`VehicleResult`]): speeds at contact and separation, delta-V along the vehicle's forward
//!   and left axes (an EDR's longitudinal and lateral channels), the principal direction of
//!   force (PDOF, degrees clockwise from the nose, SAE) and its clock direction, the yaw-rate
//!   change; kinetic energy
//!   `T = sum (m (vx^2 + vy^2) + I w^2) / 2` before and after and the loss in percent;
//! - the signed critical impulse ratio `mu_max`: the mu of equation 5 at which `Vt = 0`, i.e.
//!   `(Pt/Pn) sgn(vn) sgn(vt)` of the no-slip solution. It can be negative in near-collinear
//!   impacts (Brach 1984 Table 1B, tests 3 and 4);
//! - admissibility: mu between 0 and mu_max ([`classify_friction`]: mu = 0, or mu of the sign
//!   of mu_max and no larger in size), and no kinetic energy created ([`creates_energy`]).
//!   This is the friction rule below in PIM's form. Even
//!   inside the friction domain the equations can return more kinetic energy than they were
//!   given (mostly with `-1 < em < 0`), so the energy balance is always checked and reported.
//!   The no-slip impulse, and so mu_max, is a ratio of two linear forms of the contact state
//!   ([`reduction::Reduction::critical_rows`]); near a vanishing no-slip normal impulse mu_max
//!   jumps from plus to minus infinity, and there only the sign decides.
//!
//! ## The friction rule (every model, every fit)
//! The tangential impulse lies between zero and the impulse that sticking needs: the impulse
//! ratio `rho = Pt / Pn` between 0 and `rho_s` of the model's sticking impulse (PIM's no-slip
//! impulse of equation 5a; the tangential model's `vt' = et vt`). Derivation: at a fixed normal
//! impulse the final tangential velocity at C is affine in the tangential impulse,
//! `Vt = k Pt + c`; `rho_s` is where it reaches its sticking value, a ratio of the other sign
//! adds sliding, one beyond `rho_s` overshoots the sticking value and (in PIM) creates energy.
//! So friction acts on the side of the sticking impulse. In PIM's sign convention this is
//! "mu between 0 and mu_max": unchanged where the contact point slides at contact; where it
//! does not (`vt = 0`) the sign factor comes from the no-slip impulse ([`friction_direction`],
//! [`contact_friction`], [`FrictionBasis::NoSlipImpulse`]), so an eccentric impact into a
//! barrier face gets its tangential impulse and its yaw. In the tangential model a binding
//! friction limit puts the ratio on the edge of the friction cone on the sticking impulse's side
//! (IMPC's rule, [`TangentialCoefficients::impc`]). The point-mass solution has no coupling: its
//! no-slip ratio has the sign of the sliding, and without sliding only mu = 0 is admissible.
//! Details and the reduction to the former rule in the module docs of `friction`.
//!
//! ## Models as types ([`ImpactModel`])
//! A front end asks a model for its name, its coefficients and their domains, and its solve,
//! whichever model it is: [`PimModel`] (PIM with its solve options), [`TangentialCoefficients`]
//! (normal and tangential restitution with a friction limit) and [`Impc`] (Carpenter &
//! Welcher's model, the tangential model with `et = -e`, in a file of its own: a further model
//! is one such type and the line of the case reader that names it). Each returns PIM's
//! [`ImpactReport`] with its equivalent coefficients and its own admissibility, and, when it
//! decides between sticking and sliding, a [`ContactOutcome`].
//!
//! ## Reduction to three unknowns ([`reduction`])
//! Equations 1-3 fix the velocity change to a three-dimensional space `X - x = N p`; with one
//! state known the other follows from a 3x3 solve in p, along e both states are affine (in e,
//! or in 1 + 1/e when the separation state is known), and with neither known the same rows give
//! the transfer matrix of `X = R x`. The rows are those of [`equations`], evaluated once per
//! impact. The friction sign of equation 5 is the type [`FrictionSign`].
//!
//! ## Damped least squares ([`damped`])
//! The one Levenberg-Marquardt iteration of the workspace: a problem forms each damped step and
//! evaluates its trial point ([`damped::Damped`]); [`damped::minimise`] decides which point is
//! current, how Marquardt's `lambda` moves under rules checked once ([`damped::Rules`]), and
//! why the iteration ended ([`damped::Termination`]). The run-out inverse, the nonlinear impact
//! fit, a combination's refinement and the fit of the pose at contact are such problems.
//!
//! ## Example
//! ```
//! use pim_core::*;
//! let v = |mass, yaw_inertia, heading, d, phi| Vehicle { mass, yaw_inertia, heading, d, phi };
//! let impact = Impact::new(Collision {
//!     vehicle1: v(1955.0, 4723.0, 0.0, 1.8, 0.0),
//!     vehicle2: v(1197.0, 2279.0, 60.0, 0.9, -140.0),
//!     crush_angle: -30.0,
//! })?;
//! let initial = Velocities {
//!     vehicle1: VehicleVelocity { vx: -13.01, vy: 0.0, omega: 0.0 },
//!     vehicle2: VehicleVelocity { vx: 6.505, vy: 11.267, omega: 0.0 },
//! };
//! let c = Coefficients { e: 0.015, mu: 0.968, em: -0.774 };
//! let opts = SolveOptions { moment_form: MomentForm::Brach1983, ..Default::default() };
//! let r = solve_forward(&impact, &c, &initial, &opts)?;
//! // Brach 1983 Table 3: V1x = -7.33 m/s, energy loss 53.1 %
//! assert!((r.separation.vehicle1.vx + 7.33).abs() < 0.05);
//! assert!((r.energy.loss_percent - 53.1).abs() < 0.5);
//! # Ok::<(), PimError>(())
//! ```

mod coefficients;
pub mod damped;
pub mod equations;
mod error;
mod friction;
mod impact_model;
mod impc;
mod mirror;
pub use mirror::Mirror;
mod model;
mod names;
pub mod outline;
pub mod point_mass;
pub mod prediction;
pub mod reduction;
mod report;
mod sensitivity;
mod side;
mod solve;
pub mod tangential;

pub use coefficients::{Coefficients, MomentForm, SolveOptions, TangentialCondition, EM_ONE_TOL};
pub use error::{Equation, PimError, Result, VehicleId};
pub use friction::{
    classify_friction, creates_energy, friction_direction, CriticalImpulse, FrictionBasis,
    FrictionSign, FrictionVerdict, TangentialOutcome, REPORT_TOL,
};
pub use impact_model::{ContactOutcome, ImpactModel, ModelSolution, PimModel};
pub use impc::Impc;
pub use model::{
    impact_point_cartesian, impact_point_polar, wrap_degrees, Collision, Convention, Impact,
    SideBasis, Vehicle, VehicleVelocity, Velocities, MAX_ANGLE, MAX_DISTANCE, MAX_INERTIA,
    MAX_MASS, MAX_SPEED, MAX_YAW_RATE, NO_SLIDING_TOL,
};
pub use names::{parse_name, UnknownName};
pub use point_mass::{solve_point_mass, PointMassImpact, PointMassSolution};
pub use report::{
    pdof, residuals, vehicle_results, Admissibility, ContactPoints, DeltaV, Energy, ImpactReport,
    Impulse, RelativeVelocity, Residuals, VehicleResult,
};
pub use sensitivity::{
    sensitivity, CoefficientName, Level, LevelAverage, SensitivityCase, SensitivityStudy,
};
pub use solve::{
    analyse, contact_friction, critical_friction, separation_velocities, solve_backward,
    solve_backward_with_sign, solve_forward,
};
pub use tangential::{
    solve_tangential, stick_transfer, ContactMode, StickMaps, TangentialCoefficients,
    TangentialReport,
};

/// Implements `schemars::JsonSchema` for a type whose `Serialize` is written by hand (a number,
/// a word, a map of words): the schema is given inline, as `schemars::json_schema!` reads it.
#[macro_export]
macro_rules! json_schema_as {
    ($t:ty, $($schema:tt)+) => {
        impl ::schemars::JsonSchema for $t {
            fn schema_name() -> ::std::borrow::Cow<'static, str> {
                stringify!($t).into()
            }

            fn inline_schema() -> bool {
                true
            }

            fn json_schema(_: &mut ::schemars::SchemaGenerator) -> ::schemars::Schema {
                ::schemars::json_schema!($($schema)+)
            }
        }
    };
}
