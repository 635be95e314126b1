//! # pim-fit: certified least-squares estimation of the PIM coefficients
//!
//! Finds the impact coefficients `(e, mu, e_m)` and the twelve velocity components
//! `U = (v1x, v1y, w1, v2x, v2y, w2, V1x, V1y, W1, V2x, V2y, W2)` (m/s, rad/s) that satisfy the six
//! Planar Impact Mechanics equations of [`pim_core`] and come closest to what is measured or
//! estimated:
//!
//! ```text
//! minimise    Q(U) = sum_k w_k (U_k - U_k_est)^2 + sum_j w_j (a_j . U - t_j)^2
//! subject to  F(e, mu, em, s) X + G(e, mu, em, s) x = 0        (equations 1-6)
//!             U_k = value            for components known exactly
//!             e_min <= e <= e_max,   em in [-1, 0] (branch "free") or em = 1 (branch "zero")
//!             mu between 0 and mu_max(x) (signed), mu_min <= mu <= mu_max_bound
//!             |v| <= v_bound, |w| <= w_bound
//!             the vehicles approach at C at contact, s = sgn(vn) sgn(vt)
//!             T(X) <= T(x)                                       (no kinetic energy created)
//! ```
//!
//! ## Modules, and the path of one fit through them
//! ```text
//! fit (run.rs) ── per moment branch (FitModel::family().branches), side by side ──> search::search_branch   (the route)
//!   │                                                   │
//!   │                 ┌── convex::bnb::solve ─ Verdict::Optimal / Infeasible ─┐
//!   │                 │     (sign patterns, dual active-set QPs,               │
//!   │                 │      branch-and-bound over e_m)                        │
//!   │                 └── Verdict::Search(Fallback) ──> grid over the box      │
//!   │                        (search::space, refine, scan; every point by      │
//!   │                         inner::Inner::evaluate: known.rs / general.rs,   │
//!   │                         profile.rs along e, constraints.rs, qp.rs)       │
//!   │                                                   ▼                      ▼
//!   └──> branch::report: pim-core's analyse/solve_tangential check, status,
//!        ranges, Certificate { method: Method { route, fallback, description } }
//! geometry (fit_geometry): fit() at every geometry point of a box, then the proof over the box
//! (geometry/certify: PIM's convex pieces as rows with polynomial entries in the geometry,
//! bounded by weak duality and interval arithmetic, branch-and-bound); its estimate types in
//! geometry/types.rs. report.rs and certificate.rs hold the public result types; settings.rs
//! every tolerance with its default; problem.rs the data and cost presets.
//! ```
//! Every equation row, the reduction to three unknowns, the impulse projection and the
//! friction rule come from pim-core. What differs between models (a moment impulse or none,
//! equivalent friction or a friction limit, how sticking maps a contact state, whether the
//! convex route is written for it) is asked of the model's `family` (one file per model,
//! registered in [`FitModel`]); no other module names a model. The linear conditions (bounds,
//! approach, sliding direction) are written once in `inner/constraints.rs` as rows over the
//! twelve components, which the QPs read over the contact state and the convex route over
//! its own variables.
//!
//! ## Which route a problem takes
//! `search::search_branch` decides, once per branch, and the certificate says which route ran and, when
//! the grid search decided, why ([`Method`], [`Fallback`]):
//! - **convex decomposition** (exact): PIM with every component estimated with a positive
//!   weight (Q3, custom costs that weigh each component) and problems with components known
//!   exactly (Q1, Q2, `[known]`), both moment branches, no barrier; and the same problems of
//!   the tangential model (its sticking and sliding modes, the friction rule on the sticking
//!   impulse at some et of the range written over the same variables). The cost is strictly
//!   convex over the contact state and the impulse, on the affine subspace the known
//!   components leave, and every condition but the energy is linear once a few signs are
//!   fixed.
//! - **grid search** (certified by lower bounds and refinements), otherwise: a component
//!   neither known nor weighted ([`Fallback::NotStrictlyConvex`]), a barrier, a degenerate geometry, or where the convex route cannot
//!   certify its answer (its best point creates energy, a QP fails its KKT check, the equations
//!   are singular or so ill-conditioned there that its coefficients do not reproduce its
//!   velocities, the branch-and-bound runs out of intervals), and where the convex route proves
//!   a branch infeasible but the data alone do not say why (the grid search's statistics of
//!   the violated conditions explain it; [`Fallback::NoPatternFeasible`]).
//!
//! The observation rows `a_j` cover EDR-style data: delta-V along and across a vehicle's axis,
//! the speed along its heading ([`ObservationKind`]). Presets Q1, Q2, Q3 ([`CostPreset`]) are the
//! cost functions of Vossou & Koulocheris (2018): Q1 holds the separation velocities fixed and
//! estimates the contact ones, Q2 the reverse (Brach's fits), Q3 estimates all twelve.
//!
//! ## How the global optimum is found
//! For fixed coefficients, friction sign and tangential mode the best U is a convex quadratic
//! program in the six contact components (`X = R x`); it is solved in closed form when no
//! inequality is active and by clarabel otherwise, and the non-convex energy condition is
//! enforced exactly through its Lagrangian (see the `inner` module). mu_max is the ratio of the
//! no-slip impulse of the contact state, whose normal and tangential parts are linear in x
//! (pim-core's `reduction::Reduction::critical_rows`), so "mu between 0 and mu_max" is exactly
//! the union of two polyhedra in x, one for each sign of the no-slip normal impulse; each is
//! searched, and every candidate is decided by pim-core's own `classify_friction`. The
//! boundary mu = mu_max is also the sticking mode (equation 5a), searched on its own. Before a
//! branch is reported optimal, pim-core checks its answer (equations, friction, energy). The coefficients live in a small box, searched by a grid
//! whose points are solved exactly wherever their lower bound could beat the best value, then
//! refined by Nelder-Mead (argmin) from the best grid points of distinct cells and polished by a
//! compass search. When one whole state is known (Q1, Q2) the six equations reduce to a 3x3
//! system in the impulse, both states are affine in e (or in 1 + 1/e) at fixed `(mu, e_m)`, and
//! e is minimised exactly at every point of the search (a quadratic over at most two intervals),
//! which removes one dimension from the box. The [`Certificate`] of each branch records that
//! search. Infeasible data are an
//! [`Status::Infeasible`] outcome with the reason in words, never a solution that violates the
//! equations.
//!
//! When every component is estimated with a positive weight (Q3, and custom costs that weigh
//! each component) PIM fits take another, exact route (`convex`): over the contact state x and
//! the velocity change `d = X - x`, which equations 1-3 confine to a three-dimensional space
//! (two-dimensional with no moment impulse), restitution, moment restitution, the mu bounds and
//! "mu between 0 and mu_max" are all linear once a handful of signs are fixed (of the friction,
//! of the normal and tangential impulse, of the frictionless and no-slip normal impulses, of
//! the final tangential velocity and of the yaw rate the linear impulse alone would leave).
//! Each sign pattern is then a strictly convex QP, solved to its verified KKT point by a dual
//! active-set method; the zero branch is the minimum over its patterns, the free branch a
//! branch-and-bound over e_m intervals on which the two ratios that depend on e_m are relaxed
//! to their range. The best point must pass the same constraint set as the grid search's
//! answers; where it does not (its optimum creates energy, whose condition is not convex over
//! these variables, or the six equations are singular there) the grid search decides. On the
//! RICSAC data the two agree on every Q3 problem, and the convex route is 10 to 200 times
//! faster.
//!
//! ## The second model
//! With [`FitSettings::model`] = [`FitModel::Tangential`] the fit estimates pim-core's
//! tangential-restitution model (normal restitution e, tangential restitution et, a friction
//! limit on `|Pt / Pn|`, no moment impulse) with the same cost, observations and routes. Its
//! velocity changes are those of PIM's zero branch (one impulse at C), so over the contact state
//! and the impulse its modes are convex pieces once a few signs are fixed (the `convex`
//! module's `tangential` file):
//! - sticking: `Vn = -e vn` with e in its range, `Vt = et vt` with et in its range (linear for
//!   the sign of `vt`), and the impulse ratio within the largest friction limit,
//!   `|Pt| <= friction_max |Pn|`, with the normal impulse pushing the vehicles apart;
//! - sliding on the side s: `s Pt / Pn` within the friction range, and the friction rule's
//!   condition that sticking at some et of the range would need at least that ratio on that
//!   side. Along the line of impulses of a fixed contact state the ratio is monotone on each
//!   side of its pole, so the condition is an order of the sticking impulse and the actual one
//!   (or the sticking impulse beyond the pole, on the side where the ratio there exceeds every
//!   admissible friction), linear in z and `w = et vt`; w is eliminated exactly
//!   (Fourier-Motzkin). The answer does not depend on et; et only witnesses the condition.
//!
//! Each piece is a strictly convex QP, the best one's point is checked by the constraint set of
//! the grid search, which stays as the fallback: sticking over `(e, et)` through pim-core's
//! sticking transfer (an affine map of `(e, et)`, `StickMaps`) and sliding over
//! `(e, friction, et)` with the condition written as `Pn / (s Pt)` of the sticking impulse
//! within `[0, 1 / friction]`. The sign of the sliding mode is the side of the sticking
//! impulse, not the sliding direction, so neither mode carries a sliding-direction row.
//!
//! The report's [`Solution::tangential`] says which mode acted, et and the friction limits
//! that give the answer; e, mu and e_m of the solution are then PIM's equivalent (mu the
//! impulse ratio relative to the sliding direction, e_m = 1). pim-core's forward solve from the
//! fitted contact state must reproduce the fitted separation state, or the branch is reported
//! as [`Status::CheckFailed`].
//!
//! ```
//! use pim_core::*;
//! use pim_fit::*;
//! let v = |mass, yaw_inertia, heading, d, phi| Vehicle { mass, yaw_inertia, heading, d, phi };
//! let impact = Impact::new(Collision {
//!     vehicle1: v(1036.0, 1348.0, 0.0, 1.4, 0.0),
//!     vehicle2: v(2189.0, 5287.0, 90.0, 1.6, -30.0),
//!     crush_angle: 0.0,
//! })?;
//! // Synthetic data from known coefficients: the fit must find them again.
//! let initial = Velocities::from_vector(&nalgebra::Vector6::new(-9.48, 0.0, 0.0, 0.0, 9.48, 0.0));
//! let truth = Coefficients { e: 0.1, mu: 0.3, em: 1.0 };
//! let sep = solve_forward(&impact, &truth, &initial, &SolveOptions::default())?.separation;
//! let problem = FitProblem::from_preset(impact, CostPreset::Q2, &initial, &sep, None);
//! let report = fit(&problem, &FitSettings::default().check()?)?;
//! let zero = report.branches.iter().find(|b| b.moment == MomentBranch::Zero).unwrap();
//! let s = zero.solution.as_ref().unwrap();
//! assert!(s.cost < 1e-8 && (s.e - 0.1).abs() < 1e-3 && (s.mu - 0.3).abs() < 1e-3);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod bounds;
mod branch;
mod certificate;
mod convex;
mod error;
mod family;
mod geometry;
mod inner;
mod nonlinear;
mod problem;
mod report;
mod run;
mod search;
mod settings;

pub use bounds::SearchBound;
pub use certificate::{Certificate, Fallback, Method, Route};
pub use error::{FitError, Result};
pub use geometry::{
    fit_geometry, impact_at, CentreEstimate, GeometryBound, GeometryEstimate, GeometryInput,
    GeometryProof, GeometryRange, GeometrySearch, ProofStatus,
};
pub use nonlinear::{
    fit_nonlinear, linear_cost, NonlinearFit, NonlinearTerm, E_SLICES, PROVEN_GAP,
};
pub use problem::{
    forward_axis, state_vector, Combination, Component, CostPreset, FitProblem, Knowledge,
    MomentBranch, Observation, ObservationKind, Vector12, COMPONENT_NAMES,
};
pub use report::{
    judged_dof, ActiveConstraint, BranchReport, ChiSquare, FitReport, Identifiability, Limits,
    Quantity, Reason, Solution, Status, TangentialFit, Violation,
};
pub use run::fit;
pub use settings::{FitModel, FitSettings, SearchSettings, ValidSettings, DEFAULT_E_RANGE};
