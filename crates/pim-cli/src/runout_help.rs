//! The help text of `pim runout`, its source of separation velocities and its time arguments
//! (beside `args`, which holds every other command's arguments).

/// The text after `pim runout --help`'s options.
pub const RUNOUT_HELP: &str = "\
CASE FILE: any case (see `pim solve --help`) with a [runout] section, and for the separation
velocities [final], or [coefficients] with [initial], or --from fit, or scene evidence:
  [runout]
  friction = 0.7                   # road friction (default 0.7: dry asphalt, Fricke 1990)
  # friction_sigma = 0.05          # estimate the friction around it (scene estimates only)
  # time_limit = 60                # s
  # duration = 3.0                 # s: the state after it instead of to rest (exit 0)
  [runout.vehicle1]                # vehicle2 likewise; lengths in the case's length unit
  wheelbase = 2.8
  track = 1.55
  cg_to_front_axle = 1.25          # default half the wheelbase
  # cg_height = 0.55               # with it, load transfer
  wheels = \"locked\"               # \"locked\" (also a damaged wheel), \"rolling\", a braking
                                   # share 0-1, or per wheel: { front_left = \"locked\",
                                   # front_right = \"rolling\", rear_left = 0.3, rear_right = .. }
  # braking = 0.3                  # braking share of the wheels given as \"rolling\"
  # steer = 5.0                    # deg, both front wheels; or each wheel:
  #                                #   { front_left = 6.1, front_right = 4.4 }; or
  # steering_wheel = 90.0          #   deg, with steer_ratio = 16.0: the Ackermann angles
  #                                #   of 90/16 deg from the wheelbase and track
  # rolling_resistance = 0.015     # of the load (Gillespie 1992); 0: free rolling (PC-Crash's),
  #                                #   followed to [runout] time_limit, its end the state there
  # saturation_angle = 10.0        # deg: the linear tyre's lateral force reaches the
  #                                #   friction there; or cornering_stiffness (per deg), or
  # max_slip_angle = 10.0          #   PC-Crash's \"max. slip angle\": force min(alpha/10, mu),
  #                                #   saturating at mu x 10 deg (7.6 deg on a 0.76 road)
  # inputs = [                     # the driver after separation (PC-Crash's sequences):
  #   { at = 0.8, braking = 0.9, build_up = 0.25 },   # from 0.8 s, reached over 0.25 s
  #   { at = 1.0, braking = { front = 0.9, rear = 0.5 } },   # or per axle / per wheel
  #   { at = 1.5, steering_wheel = -90.0, build_up = 0.4 },  # or steer = 5.0 (deg)
  #   { distance = 12.0, braking = 0.0 },  # from 12 length units travelled since separation
  # ]                              # a value an input does not give keeps what it was
  [scene.vehicle1]                 # the evidence (positions in the case's frame: the impact
                                   # centre is the origin, or [impact] centre's frame)
  rest = { x = 14.2, y = 3.1, heading = 215.0 }
  rest_sigma = { x = 0.1, y = 0.1, heading = 2.0 }
  marks = [ { x = 6.0, y = 1.2, sigma = 0.15 } ]     # points the CG passed (tyre marks,
                                   # gouges), optionally with heading and heading_sigma
  # turns = 1                      # the count of full turns, when known

A MOTION CASE (no impact: a vehicle from a stated state, as PC-Crash runs one) has
[vehicle1] with mass and yaw_inertia (and length, width, cg_to_front for drawings), [runout]
and [runout.vehicle1] as above, and where and how it starts:
  [start.vehicle1]
  x = 0.0                          # CG, the case's length unit
  y = 0.0
  heading = 0.0                    # deg, where the nose points
  speed = 30.0                     # along the heading (or vx and vy in the fixed frame)
  omega = 0.0                      # yaw rate (default 0)
Two vehicles may start so, each on its own; there is no [impact] and no scene evidence.

WITHOUT separation velocities the scene estimates them: weighted least squares over vx, vy and
the yaw rate (and the friction with friction_sigma) through the run-out model, once per count of
full turns from -3 to 3 (a rest heading is known only modulo 360 deg). Every count's candidate is
listed with its cost; those that fit equally well are said to, never one picked by round-off.
The standard errors come from the linearised fit; directions the evidence leaves free are named.

THE MODEL: a planar rigid body on four wheels; locked wheels slide with Coulomb friction, rolling
wheels have rolling resistance and Steffan's linear tyre (SAE 960886) across, braked wheels a
share of the friction circle along; load transfer with cg_height; Dormand-Prince 5(4) to rest
(`cargo doc -p pim-runout` has the equations).

JSON (SI, natural frame, degrees): per vehicle separation, rest {x, y, heading}, distance, time,
rotation, turns, path [{t, x, y, heading, speed, yaw_rate}; with --wheels each wheel's load,
slip angle and tyre force], evidence (residuals) and, when
estimated, estimate {unknowns, candidates, undetermined}.

EXIT STATUS: 0 success; 2 bad input (file, line and field named); 3 a run-out that reaches its
time limit still moving, or no candidate reaching the scene evidence (the output says why);
4 an output file could not be written.";

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum RunoutSource {
    /// The case's [final].
    Final,
    /// The solve of [coefficients] and [initial].
    Solve,
    /// The fit of the case (its [estimates]; --cost as in `pim fit`).
    Fit,
    /// Estimated from [scene.vehicleN] through the run-out model.
    Scene,
}

/// Checks a time argument: between 1 ms and an hour.
pub fn positive_seconds(s: &str) -> Result<f64, String> {
    let x: f64 = s.parse().map_err(|_| format!("{s:?} is not a number"))?;
    if x.is_finite() && (0.001..=3600.0).contains(&x) {
        Ok(x)
    } else {
        Err(format!("{s}: must be between 0.001 and 3600 s"))
    }
}
