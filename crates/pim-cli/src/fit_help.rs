//! The long help of `pim fit` and `pim uncertainty`: the case file's fit sections, the cost
//! functions, the models, the whole reconstruction and the uncertainty study.

/// After `pim fit --help`.
pub const FIT_HELP: &str = "\
CASE FILE: as for `pim solve` ([vehicle1], [vehicle2], [impact], optional [units] and
convention), without [coefficients], [initial], [final], plus:
  [estimates.initial]              # estimated velocities at contact (partial allowed)
  vehicle1 = { vx = -13.01, vy = 0.0, omega = 0.0 }
  vehicle2 = { vx = 6.50, vy = 11.27, omega = 0.0 }
  [estimates.final]                # estimated velocities at separation
  vehicle1 = { vx = -7.74, vy = 1.48, omega = -0.52 }
  vehicle2 = { vx = -2.22, vy = 8.64, omega = -3.35 }
  [weights.initial]                # optional, same shape, in (0, 1], default 1
  vehicle1 = { omega = 0.5 }
  [sigma.final]                    # or standard deviations (m/s, rad/s) instead of weights:
  vehicle1 = { vx = 0.5, vy = 0.5, omega = 0.2 }   # weights 1/sigma^2, the cost a chi-square
                                   # (printed with its degrees of freedom and p-value); every
                                   # estimate then needs a sigma
  [known.initial]                  # without --cost only: components held fixed
  vehicle1 = { omega = 0.0 }
  [bounds]                         # optional; these are the defaults
  e = [0.0, 1.0]                   # e's physical range (RICSAC refits state [0, 0.2])
  mu = [-1.2, 1.2]                 # and always between 0 and mu_max
  et = [-1.0, 1.0]                 # --model tangential: tangential restitution
  friction = [0.0, 1.2]            # --model tangential: friction limit of |Pt/Pn|
  velocity = 100.0                 # m/s, every linear component (RICSAC refits state 20)
  yaw_rate = 15.0                  # rad/s (RICSAC refits state 5)
  vehicle1 = { d = [1.6, 2.0], phi = [-10.0, 10.0] }   # optional: estimate the impact centre
  vehicle2 = { impact_point = { x = [-0.5, 0.5], y = [-0.9, -0.7] } }   # (either form)
  crush_angle = [-35.0, -25.0]     # and the crush-surface angle, degrees
                                   # (the case's values are the start; each branch then reports
                                   # its geometry with ranges; see the README, Unknown geometry)
  [[observations]]                 # optional, e.g. what an event data recorder gave
  name = \"EDR front\"              # optional: how messages and tables name it (else its number)
  kind = \"delta_v_longitudinal\"   # delta_v_lateral, speed_along_heading, lateral_velocity
  vehicle = 1
  value = -5.1                     # m/s, along the vehicle's own axes
  weight = 1.0                     # or sigma = 0.3 (m/s) with [sigma]

COST FUNCTIONS (--cost):
  q1  separation velocities known exactly, contact velocities estimated
  q2  contact velocities known exactly, separation velocities estimated (Brach's fits)
  q3  all twelve estimated
  (none) [known] held fixed, [estimates] estimated, everything else unknown

MODELS (--model):
  pim         e, mu, em; both moment branches (default)
  tangential  e, et and the friction limit (normal and tangential restitution, Routh's
              friction limit, no moment impulse; one branch). Searched per contact mode:
              sticking over (e, et), any friction limit at least the impulse ratio giving the
              same answer; sliding over (e, friction), where et only decides that sticking
              would need more than the limit. The output says which mode, et, and the
              friction limits that give the answer; the ranges say what the data leave open.

THE WHOLE RECONSTRUCTION: a case whose [scene] gives a rest position or marks (with [runout];
see `pim runout --help`) is fitted, without --cost, through all three phases at once: the
separation velocities are those whose run-outs end at the scene, one chi-square holds every
piece of evidence ([sigma] then required for estimates and observations), and every count of
full turns to rest is compared. Before the impact, per vehicle:
  [pre_impact.vehicle1]
  skid = 42.0                      # braking marks up to the point of contact (length unit)
  braking = 1.0                    # share of the road friction used (default 1: locked)
  grade = 0.0                      # percent along the travel, positive uphill (default 0)
  friction = 0.7                   # default [runout] friction
  edr = [ { speed = 27.5, time = 0.5, deceleration = 0.0, sigma = 1.5 } ]
                                   # a recorded speed (speed unit) `time` s before contact with
                                   # a mean deceleration (g) between: evidence on the speed along
                                   # the heading at contact, speed - deceleration g time
Where the pose at contact is uncertain, [contact_sigma] fits it: each value given a standard
deviation (the case's length unit, degrees) is an unknown held near the case's by that prior:
  [contact_sigma]
  vehicle1 = { heading = 3.0, position = { x = 1.0, y = 1.0 } }   # CG moved, turned about it
  vehicle2 = { heading = 3.0, impact_point = { x = 0.8 } }        # struck where, on the vehicle
  centre = { x = 1.0, y = 1.0 }    # the impact centre in the scene
  crush_angle = 5.0
The table then gives each value stated and fitted with its deviation (example:
examples/cases/reconstruction_pose_us.toml).
The output: per vehicle the speed before braking (v0^2 = vc^2 + 2 a d), at contact, at
separation and at rest; e, mu, em; every piece of evidence (residual, sigma, share of the
chi-square); every combination of counts of turns with its cost or why it was not refined;
what is proven and what the evidence leaves open. Evidence that none of the searched impacts
and run-outs reaches (chi-square beyond p = 1e-6, with zero degrees of freedom judged as one)
is refused with its largest residuals and the evidence consistency table (exit 3); a fit with
p below 0.05 is warned and shows the table too. The refinements end on a budget of work, so
the answer is the same on every machine. --out writes
result.json, the table, report.html, the scene to scale (scene.svg) and the same plan for CAD
(scene.dxf: a DXF drawing with a layer per kind of thing).
Example: examples/cases/reconstruction_us.toml

THE DAMAGE: a case with [damage] (see `pim solve --help`, DAMAGE) is fitted as above, then the
crush is set beside the best answer (crush energies, expected and PIM's energy loss, CRASH3's
delta-V against PIM's) and, when the crush energy has a standard deviation (from a_sigma,
b_sigma, depth_sigma, width_sigma; or [damage] evidence = true), the fit is repeated with the
crush energy as one more piece of evidence: its residual (expected loss - PIM's loss) / sigma
squared joins the cost, with the PDOF factors and the sigma evaluated at the answer being
fitted. It is fitted by Gauss-Newton steps with the exact fit inside (PIM's equations and
every admissibility condition hold at each step), from each branch's optimum without it, and
when that end is not proven from the optimum within each of five slices of the e range. The
output says whether the answer is proven optimal (its cost meets the certified optimum without
the energy) or the best found, with that lower bound. Without [sigma] the weighted velocity
residuals count beside the energy's as if their sigma were 1 m/s. [damage] evidence = false
compares without fitting. Example: examples/cases/ricsac7_damage.toml";

/// After `pim uncertainty --help`.
pub const UNCERTAINTY_HELP: &str = "\
CASE FILE: a fit case (see `pim fit --help`) with standard deviations of the estimates,
  [sigma.initial] / [sigma.final] (m/s, rad/s, or the case's [units]), and optionally
  [uncertainty]                      # inputs the fit takes as exact
  vehicle1 = { mass = 50.0, d = 0.2, phi = 5.0 }        # normal standard deviations
  vehicle2 = { heading = { uniform = [58.0, 62.0] } }   # or uniform between two values
  impact = { crush_angle = 5.0 }
  (also yaw_inertia, and impact_point = { x = sd, y = sd } instead of d / phi)
  [damage.vehicle1]                  # the damage's a_sigma, b_sigma, width_sigma and
  depth_sigma = 2.0                  # depth_sigma (each depth drawn on its own) are drawn too;
                                     # with the crush energy as evidence every draw refits with it

OUTPUT: the nominal fit; per quantity p05, p50, p95, mean, sd over the feasible draws, flagged
`not_determined` when the nominal fit leaves it open (then the interval is not a confidence
statement); the share of draws per branch; per quantity the inputs with a first-order index
(correlation ratio) above 0.02.

A CASE WITH SCENE EVIDENCE (see `pim fit --help`, THE WHOLE RECONSTRUCTION), without --cost:
every draw also perturbs each rest position, heading and mark by its sigma, each EDR speed by
its sigma and the road friction by [runout] friction_sigma, and refits all three phases (from
where the nominal reconstruction ended, for each count of turns within a chi-square of 4 of
its best). Per vehicle: speed before braking, at contact, at separation; e, mu, em, the energy
loss; the inputs that dominate each. --out DIR writes the nominal reconstruction, the study and
the scene to scale (report.html, report.md, scene.svg, scene.dxf, result.json,
uncertainty.json).";
