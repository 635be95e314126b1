//! # pim-runout: the motion of a vehicle from separation to rest
//!
//! After an impact each vehicle slides, rolls and spins to its rest position. This crate
//! simulates that run-out with a planar four-wheel model ([`simulate()`]) and goes back from the
//! evidence of the scene (the rest position and heading, points of tyre marks or gouges the CG
//! passed) to the velocities at separation ([`estimate`]). It needs nothing of the impact: the
//! start is a position, a heading and three velocities.
//!
//! ## Units and frames
//! SI throughout: kg, kg m^2, m, s, m/s, rad/s; angles in **radians**. The fixed (road) frame is
//! right-handed with angles counter-clockwise seen from above; a vehicle's heading is where its
//! nose points. The body frame has x forward and y to the left, its origin at the CG.
//!
//! ## The model
//! A rigid body of mass `m` and yaw inertia `I` moves in the plane, with state
//! `(x, y, psi, vx, vy, r)` (CG position, heading, CG velocity in the fixed frame, yaw rate):
//! ```text
//! m (dvx/dt, dvy/dt) = R(psi) sum_i F_i          I dr/dt = sum_i (p_i x F_i)
//! ```
//! where `R(psi)` turns the body frame into the fixed one and `F_i` is the force of wheel `i`
//! in the body frame. The wheels sit at `p_i = (a, +-T/2)` (front) and `(a - L, +-T/2)` (rear)
//! for wheelbase `L`, CG-to-front-axle `a` and track `T`. The contact patch of wheel `i` moves
//! at `u_i = v_body + r (-p_iy, p_ix)`.
//!
//! **Normal loads.** Statically `Fz = m g (L - a) / (2 L)` on each front wheel and
//! `m g a / (2 L)` on each rear wheel (g = 9.80665 m/s^2). With a CG height `h`, the CG
//! acceleration `(ax, ay)` in the body frame moves `m ax h / L` between the axles and
//! `m ay h / T` between the sides (shared by the axles in their static proportion):
//! ```text
//! Fz_i = Fz_i,static + sx_i m h ax / (2 L) + sy_i m h ay / T * share_i
//! ```
//! with `sx = -1` front, `+1` rear, `sy = -1` left, `+1` right. Every force below is its load
//! times a function of the kinematics, so the acceleration and the loads solve a 2 x 2 linear
//! system; a wheel whose load would be negative lifts (load 0).
//!
//! **Tyre forces**, per unit load, with `mu` the friction under the wheel (the road's, or a
//! friction zone's where the wheel runs on one: [`zones`]):
//! - *locked or sliding* (and a wheel the impact damaged): `F = -mu Fz u / |u|`, Coulomb
//!   friction against the sliding of the patch;
//! - *free-rolling*: along the wheel the rolling resistance `-f_r Fz sgn(u_l)`; across it the
//!   linear tyre of Steffan (SAE 960886, as PC-Crash and pycrash use it),
//!   `-F_s min(alpha / alpha_s, 1) sgn(u_s)` with the slip angle `alpha = atan(|u_s| / |u_l|)`,
//!   saturation angle `alpha_s` (default 10 deg; the cornering stiffness per unit load is
//!   `mu / alpha_s`; PC-Crash's "maximum slip angle" `alpha_m` is the same tyre with
//!   `alpha_s = mu alpha_m`, its force `min(alpha / alpha_m, mu)`) and `F_s = sqrt(mu^2 - f_r^2) Fz`, so that the force never leaves the
//!   friction circle `mu Fz`;
//! - *braked* with a share `b`: as rolling with `b mu` (at least `f_r`) along the wheel and
//!   `sqrt(1 - b^2) mu Fz` available across it;
//! - *steered*: each front wheel's axis turned by its own steer angle (one angle for both, an
//!   angle per wheel, or the Ackermann angles of [`ackermann`]).
//!
//! `u_l`, `u_s` are the patch velocity along and across the wheel. Below a sliding speed of
//! [`SLIDING_DEADBAND`] (1 cm/s) each `sgn` and `u / |u|` is replaced by its linear
//! continuation (`u / 1 cm/s`), so that a patch passing through zero sliding neither chatters
//! nor stalls the integrator.
//!
//! **Energy.** Every force opposes the sliding of its patch, so the power of the tyre forces,
//! `P = -sum F_i . u_i`, is never negative and `dK/dt = -P` for the kinetic energy
//! `K = (m v^2 + I r^2) / 2`. The integration carries the work `W = int P dt` as a state:
//! `K + W` stays the initial kinetic energy (to the integration tolerance).
//!
//! **Integration and the stop.** Dormand-Prince 5(4) with adaptive steps (Hairer and Wanner's
//! DOPRI5 step control, as the `ode_solvers` crate implements it, to the last bit; see
//! `dopri.rs` for why it is the crate's own), tolerances 1e-10. The stop is an event checked at every accepted step: once every
//! contact patch is slower than the rest speed (2 cm/s, twice the band above), the last
//! millimetres are taken at the current deceleration in closed form: the kinetic energy `K`
//! goes at the power `P`, so a uniform deceleration ends after `tau = 2 K / P` having covered
//! half of `v tau` (exact for a sliding translation: four locked wheels from `v` stop at
//! `v^2 / (2 mu g)`). A motion still going at the time limit (60 s) ends there and says so
//! ([`End::TimeLimit`]).
//!
//! ## From the scene back to separation
//! [`estimate`] finds the separation velocities `(vx, vy, r)` (and the friction when the case
//! gives it a standard deviation) whose run-out ends at the rest position and heading and
//! passes the marks, by weighted least squares through the run-out model (see [`inverse`]).
//! A rest heading is known modulo a full turn: each count of turns is a separate candidate.

pub mod chassis;
mod dopri;
pub mod error;
mod forces;
pub mod inverse;
pub mod simulate;
pub mod zones;

pub use chassis::{
    ackermann, Chassis, Input, Motion, WheelState, DEFAULT_FRICTION, DEFAULT_ROLLING_RESISTANCE,
    DEFAULT_SATURATION_ANGLE, GRAVITY, MAX_FRICTION, WHEEL_NAMES,
};
pub use error::{Result, RunoutError};
pub use forces::{wheels_at, WheelAt, SLIDING_DEADBAND};
pub use inverse::{
    differentiate, differentiate_zones, estimate, linearise, linearise_with_friction, Alternative,
    Candidate, Estimate, EstimateSettings, Evidence, Linearised, Mark, Quantity, Residual, Rest,
    ALTERNATIVE_COST, CONSISTENT_COST, MAX_ALTERNATIVES, PLAUSIBLE_COST,
};
pub use simulate::{full_turns, simulate, End, Runout, Settings, Step};
pub use zones::{friction_at, Zone};
