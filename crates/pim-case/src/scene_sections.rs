//! The `[runout]` and `[scene]` sections of a case file as written (read by [`crate::scene`]).

use serde::Deserialize;
use std::collections::BTreeMap;

/// `[runout]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunoutSection {
    /// Road friction under both vehicles (default 0.7).
    #[serde(default)]
    pub friction: Option<f64>,
    /// Standard deviation of the road friction: with it the friction is estimated from the
    /// scene around `friction` instead of taken as exact.
    #[serde(default)]
    pub friction_sigma: Option<f64>,
    /// The run-out is given up after this time, s (default 60).
    #[serde(default)]
    pub time_limit: Option<f64>,
    /// Follow each run-out for this long, s, and give the state then (PC-Crash's fixed window
    /// of motion), instead of to rest; a vehicle that stops before comes to rest as usual.
    #[serde(default)]
    pub duration: Option<f64>,
    /// Vehicle 1's wheels.
    #[serde(default)]
    pub vehicle1: Option<RunoutVehicleSection>,
    /// Vehicle 2's wheels.
    #[serde(default)]
    pub vehicle2: Option<RunoutVehicleSection>,
    /// Areas of the ground with a friction of their own (`[[runout.zones]]`).
    #[serde(default)]
    pub zones: Vec<ZoneSection>,
}

/// `[[runout.zones]]`: an area of the ground with a friction of its own.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ZoneSection {
    /// What it is, for the figures ("parking lot", "verge").
    #[serde(default)]
    pub name: Option<String>,
    /// Its friction coefficient.
    pub friction: f64,
    /// Its standard deviation: the fit then fits the zone's friction with the speeds (the
    /// stated value a prior of this deviation) and `pim uncertainty` draws the prior's centre
    /// by it; without it the friction is held as stated.
    #[serde(default)]
    pub friction_sigma: Option<f64>,
    /// The polygon's corners in order, `[x, y]` in the case's frame and length unit.
    pub corners: Vec<[f64; 2]>,
}

impl ZoneSection {
    /// Its name for the tables: its own, else `zone N` for the `k`-th zone (N from 1).
    pub fn display_name(&self, k: usize) -> String {
        self.name
            .clone()
            .unwrap_or_else(|| format!("zone {}", k + 1))
    }
}

/// What a wheel does, as written: `"locked"`, `"rolling"`, or a braking share.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum WheelWritten {
    /// `"locked"` (also `"damaged"`, `"sliding"`) or `"rolling"` (also `"free"`).
    Word(String),
    /// A braking share from 0 (rolling) to 1.
    Share(f64),
}

/// `wheels = ...`: one state for all four wheels, or each wheel by name.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum WheelsWritten {
    /// The same for all four.
    All(WheelWritten),
    /// `{ front_left = .., front_right = .., rear_left = .., rear_right = .. }`.
    Each(BTreeMap<String, WheelWritten>),
}

/// Other wheel states with their probability (`[runout.vehicleN] wheels_alternatives`).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WheelsAlternative {
    /// The wheels' states, written as `wheels` is.
    pub wheels: WheelsWritten,
    /// Its probability (above 0; with the others' below 1).
    pub weight: f64,
}

/// `steer = ...`: one angle for both front wheels, or each front wheel's angle, degrees.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(untagged)]
pub enum SteerWritten {
    /// The same angle on both front wheels.
    Both(f64),
    /// `{ front_left = .., front_right = .. }`.
    Each(FrontWheels),
}

/// An angle per front wheel, degrees.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrontWheels {
    /// The front left wheel.
    pub front_left: f64,
    /// The front right wheel.
    pub front_right: f64,
}

/// `[runout.vehicleN]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RunoutVehicleSection {
    /// Front axle to rear axle (length unit).
    pub wheelbase: f64,
    /// Left to right wheel (length unit).
    pub track: f64,
    /// CG to the front axle (length unit; default half the wheelbase).
    #[serde(default)]
    pub cg_to_front_axle: Option<f64>,
    /// CG height (length unit): with it, load transfer.
    #[serde(default)]
    pub cg_height: Option<f64>,
    /// The wheels' states (default `"locked"`).
    #[serde(default)]
    pub wheels: Option<WheelsWritten>,
    /// Other wheel states the vehicle may have run out with, each with its probability: what
    /// `pim uncertainty` draws instead of `wheels` (which keeps the probability left). The
    /// reconstruction itself runs out with `wheels`.
    #[serde(default)]
    pub wheels_alternatives: Vec<WheelsAlternative>,
    /// Braking share of the wheels given as `"rolling"` (0 to 1, default 0).
    #[serde(default)]
    pub braking: Option<f64>,
    /// Steer angle of the front wheels, degrees: one for both, or `{ front_left, front_right }`.
    #[serde(default)]
    pub steer: Option<SteerWritten>,
    /// Steering-wheel angle, degrees (instead of `steer`, with `steer_ratio`): the front wheels
    /// then take the Ackermann angles of `steering_wheel / steer_ratio`.
    #[serde(default)]
    pub steering_wheel: Option<f64>,
    /// Steering-wheel degrees per degree of the front wheels (about 16 for a car).
    #[serde(default)]
    pub steer_ratio: Option<f64>,
    /// Road friction under this vehicle (instead of `[runout] friction`).
    #[serde(default)]
    pub friction: Option<f64>,
    /// Rolling resistance, a fraction of the load (default 0.015; 0 is free rolling, whose
    /// run-out is followed to the time limit).
    #[serde(default)]
    pub rolling_resistance: Option<f64>,
    /// Slip angle at which a rolling wheel's lateral force reaches the friction, degrees
    /// (default 10): the force per unit load is `friction x min(alpha / saturation_angle, 1)`.
    #[serde(default)]
    pub saturation_angle: Option<f64>,
    /// Cornering stiffness per unit load, per degree (instead of `saturation_angle`:
    /// saturation angle = friction / cornering_stiffness).
    #[serde(default)]
    pub cornering_stiffness: Option<f64>,
    /// PC-Crash's "maximum slip angle", degrees (instead of `saturation_angle`): PC-Crash's
    /// lateral force per unit load is `min(alpha / max_slip_angle, friction)`, so it saturates
    /// at `friction x max_slip_angle` (7.6 deg for PC-Crash's 10 deg on a 0.76 road); the
    /// cornering stiffness per unit load is `1 / max_slip_angle` whatever the friction.
    #[serde(default)]
    pub max_slip_angle: Option<f64>,
    /// The driver's inputs after separation, in time (PC-Crash's sequences).
    #[serde(default)]
    pub inputs: Option<Vec<InputWritten>>,
}

/// One driver input as written: from `at` seconds after separation, a braking share of the
/// wheels that are not locked and/or a steer (the wheels' angles, or a steering-wheel angle
/// with the vehicle's `steer_ratio`), reached over `build_up` seconds.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InputWritten {
    /// Seconds after separation (with `distance`: the earliest time; default 0 then).
    #[serde(default)]
    pub at: Option<f64>,
    /// Braking share, 0 to 1: one for every wheel, or per axle or wheel.
    #[serde(default)]
    pub braking: Option<BrakingWritten>,
    /// Front wheels' steer, degrees: one for both, or `{ front_left, front_right }`.
    #[serde(default)]
    pub steer: Option<SteerWritten>,
    /// Steering-wheel angle, degrees (with the vehicle's `steer_ratio`).
    #[serde(default)]
    pub steering_wheel: Option<f64>,
    /// Seconds to reach the values (default 0: at once).
    #[serde(default)]
    pub build_up: Option<f64>,
    /// The input starts once the CG has travelled this far since separation (length unit),
    /// and not before `at`.
    #[serde(default)]
    pub distance: Option<f64>,
}

/// An input's `braking = ...`: one share for every wheel, or shares by axle (`front`, `rear`)
/// or wheel (`front_left`, ...); a wheel not named keeps its share.
#[derive(Debug, Clone, Deserialize)]
#[serde(untagged)]
pub enum BrakingWritten {
    /// Every wheel that is not locked.
    All(f64),
    /// `{ front = .., rear = .. }`, `{ front_left = .., rear_right = .. }`, or both kinds.
    Each(BTreeMap<String, f64>),
}

/// A point as written: `{ x, y }` with an optional heading.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseWritten {
    /// x (length unit).
    pub x: f64,
    /// y (length unit).
    pub y: f64,
    /// Heading, degrees.
    #[serde(default)]
    pub heading: Option<f64>,
    /// The survey point it was placed on (`[survey]`'s id), if any: kept with it, and checked
    /// to lie there.
    #[serde(default)]
    pub point: Option<String>,
}

/// `rest_sigma = { x, y, heading }`.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PoseSigmaWritten {
    /// sd of x (length unit).
    pub x: f64,
    /// sd of y (length unit).
    pub y: f64,
    /// sd of the heading, degrees.
    #[serde(default)]
    pub heading: Option<f64>,
}

/// The point of a vehicle that left a mark: one of its wheels, or its CG.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum MarkPoint {
    /// The CG's path (a mark carried to the CG by hand, as before wheels could be named).
    Cg,
    /// The front left tyre.
    FrontLeft,
    /// The front right tyre.
    FrontRight,
    /// The rear left tyre.
    RearLeft,
    /// The rear right tyre.
    RearRight,
}

impl MarkPoint {
    /// The wheel's index in [`pim_runout::WHEEL_NAMES`] (none for the CG).
    pub fn wheel(self) -> Option<usize> {
        match self {
            MarkPoint::Cg => None,
            MarkPoint::FrontLeft => Some(0),
            MarkPoint::FrontRight => Some(1),
            MarkPoint::RearLeft => Some(2),
            MarkPoint::RearRight => Some(3),
        }
    }
}

/// One mark: a point a tyre (`wheel`) or the CG passed.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MarkWritten {
    /// x (length unit).
    pub x: f64,
    /// y (length unit).
    pub y: f64,
    /// sd of the path's distance from it (length unit).
    pub sigma: f64,
    /// The heading there, degrees.
    #[serde(default)]
    pub heading: Option<f64>,
    /// sd of that heading, degrees.
    #[serde(default)]
    pub heading_sigma: Option<f64>,
    /// The tyre that left the mark (`front_left`, `front_right`, `rear_left`, `rear_right`),
    /// or `cg` (the default): the mark is measured against that point's path.
    #[serde(default)]
    pub wheel: Option<MarkPoint>,
    /// The survey point it was placed on (`[survey]`'s id), if any: kept with it, and checked
    /// to lie there.
    #[serde(default)]
    pub point: Option<String>,
}

/// A mark surveyed along its length (a yaw mark, a scuff): its points, in order, each a point
/// the wheel's contact point passed.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TraceWritten {
    /// The tyre that left it (`front_left`, ...), or `cg` (the default).
    #[serde(default)]
    pub wheel: Option<MarkPoint>,
    /// Its points `[x, y]` (length unit), two or more.
    pub points: Vec<[f64; 2]>,
    /// sd of the path's distance from each point (length unit).
    pub sigma: f64,
}

/// A point of the vehicle measured at rest: a tyre's contact point, or a corner of its
/// outline.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TyreWritten {
    /// Which tyre (`front_left`, `front_right`, `rear_left`, `rear_right`).
    #[serde(default)]
    pub wheel: Option<MarkPoint>,
    /// Or which corner of the outline (the same names; the outline from `[vehicleN]` length,
    /// width and cg_to_front).
    #[serde(default)]
    pub corner: Option<MarkPoint>,
    /// x (length unit).
    pub x: f64,
    /// y (length unit).
    pub y: f64,
    /// sd of each coordinate (length unit).
    pub sigma: f64,
    /// The survey point it was placed on (`[survey]`'s id), if any: kept with it, and checked
    /// to lie there.
    #[serde(default)]
    pub point: Option<String>,
}

/// `[scene.vehicleN]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneVehicleSection {
    /// Rest position and heading.
    #[serde(default)]
    pub rest: Option<PoseWritten>,
    /// Their standard deviations.
    #[serde(default)]
    pub rest_sigma: Option<PoseSigmaWritten>,
    /// Points the CG passed.
    #[serde(default)]
    pub marks: Vec<MarkWritten>,
    /// The rest as measured: tyre contact points (two or more wheels), instead of `rest` and
    /// `rest_sigma`.
    #[serde(default)]
    pub rest_tyres: Vec<TyreWritten>,
    /// Marks traced as polylines (a yaw mark surveyed at several points): each point a mark
    /// of the trace's wheel.
    #[serde(default)]
    pub traces: Vec<TraceWritten>,
    /// The count of full turns to rest, when known.
    #[serde(default)]
    pub turns: Option<i64>,
}

/// `[scene]`.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSection {
    /// Vehicle 1's evidence.
    #[serde(default)]
    pub vehicle1: Option<SceneVehicleSection>,
    /// Vehicle 2's evidence.
    #[serde(default)]
    pub vehicle2: Option<SceneVehicleSection>,
}

/// One speed an event data recorder stored before the impact.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdrWritten {
    /// The recorded speed along the heading (speed unit).
    pub speed: f64,
    /// How long before contact it was recorded, s (0: at contact).
    #[serde(default)]
    pub time: f64,
    /// The mean deceleration between that time and contact, in g (0: constant speed).
    #[serde(default)]
    pub deceleration: f64,
    /// Standard deviation of the speed at contact this gives (speed unit).
    pub sigma: f64,
}

/// One row of an event data recorder's pre-crash table, as it was recorded. The rows are not
/// evidence themselves (the `edr` records are, see pim_case's `edr` module); they are drawn
/// beside the answer's speed history.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EdrRow {
    /// How long before contact it was recorded, s (the report's -2.5 s is 2.5).
    pub time: f64,
    /// The recorded speed (speed unit).
    pub speed: f64,
    /// The service brake: on or off.
    #[serde(default)]
    pub brake: Option<bool>,
    /// The accelerator pedal, percent of full.
    #[serde(default)]
    pub accelerator: Option<f64>,
}

/// `[pre_impact.vehicleN]`: braking before the impact and EDR speeds.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreImpactVehicleSection {
    /// Length of the skid or yaw marks up to the point of contact (length unit).
    #[serde(default)]
    pub skid: Option<f64>,
    /// Share of the road friction the braking used along them, 0 to 1 (default 1: locked).
    #[serde(default)]
    pub braking: Option<f64>,
    /// Road grade along the direction of travel, percent (positive uphill; default 0).
    #[serde(default)]
    pub grade: Option<f64>,
    /// Road friction under the marks (default `[runout] friction`, else 0.7).
    #[serde(default)]
    pub friction: Option<f64>,
    /// Speeds the EDR recorded before contact, as evidence on the speed at contact.
    #[serde(default)]
    pub edr: Vec<EdrWritten>,
    /// The EDR's pre-crash table as recorded, oldest row first (drawn, not evidence).
    #[serde(default)]
    pub edr_history: Vec<EdrRow>,
}

/// `[pre_impact]`.
#[derive(Debug, Clone, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PreImpactSection {
    /// Vehicle 1.
    #[serde(default)]
    pub vehicle1: Option<PreImpactVehicleSection>,
    /// Vehicle 2.
    #[serde(default)]
    pub vehicle2: Option<PreImpactVehicleSection>,
}

/// `[start]`: where and how each vehicle starts.
#[derive(Debug, Clone, Copy, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartSection {
    /// Vehicle 1.
    #[serde(default)]
    pub vehicle1: Option<StartWritten>,
    /// Vehicle 2.
    #[serde(default)]
    pub vehicle2: Option<StartWritten>,
}

/// `[start.vehicleN]` as written, in the case's units and frame.
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StartWritten {
    /// CG position (length unit).
    pub x: f64,
    /// CG position (length unit).
    pub y: f64,
    /// Where the nose points, degrees.
    pub heading: f64,
    /// Speed along the heading (speed unit), instead of `vx` and `vy`.
    #[serde(default)]
    pub speed: Option<f64>,
    /// CG velocity along the fixed x axis (speed unit).
    #[serde(default)]
    pub vx: Option<f64>,
    /// CG velocity along the fixed y axis (speed unit).
    #[serde(default)]
    pub vy: Option<f64>,
    /// Yaw rate (yaw-rate unit; default 0).
    #[serde(default)]
    pub omega: Option<f64>,
}

/// True when the TOML text has a top-level `start` table: a motion case.
pub fn is_motion(text: &str) -> bool {
    text.parse::<toml::Table>()
        .is_ok_and(|t| t.get("start").is_some_and(toml::Value::is_table))
}

/// `[background]`: a scene diagram or an aerial photo behind the plan, set to scale by two
/// points on it and their distance, placed by where the first point lies and turned on the
/// plan (`pim serve` draws it and writes it; no answer reads it).
///
/// ```toml
/// [background]
/// image = "intersection.png"                    # beside the case file
/// pixels = [[120.0, 400.0], [720.0, 400.0]]     # two points on it, pixels from its top left
/// distance = 60.0                               # their distance, the case's length unit
/// at = { x = -30.0, y = 0.0 }                   # where the first lies, the case's frame
/// rotation = 0.0                                # deg, turned counter-clockwise on the plan
/// locked = true                                 # not moved by dragging
/// ```
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BackgroundSection {
    /// The image (PNG, JPEG or SVG), a path relative to the case file's folder.
    pub image: String,
    /// Two points on the image, pixels from its top left corner (right, down).
    pub pixels: [[f64; 2]; 2],
    /// Their distance on the scene, the case's length unit.
    pub distance: f64,
    /// Where the first point lies in the case's frame (length unit; default the origin).
    #[serde(default)]
    pub at: Option<crate::sections::PointSection>,
    /// Degrees the image is turned, counter-clockwise as seen on the plan (default 0).
    #[serde(default)]
    pub rotation: f64,
    /// Not moved by dragging (default false).
    #[serde(default)]
    pub locked: bool,
}

impl BackgroundSection {
    /// The image's kinds.
    pub const KINDS: [&'static str; 4] = ["png", "jpg", "jpeg", "svg"];

    /// Checks the section; the error names the key and says why.
    pub fn check(&self) -> std::result::Result<(), (&'static str, String)> {
        let path = std::path::Path::new(&self.image);
        let kind = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !kind.is_some_and(|k| Self::KINDS.contains(&k.as_str())) {
            return Err((
                "image",
                format!(
                    "{:?}: give a PNG, JPEG or SVG image ({})",
                    self.image,
                    Self::KINDS.join(", ")
                ),
            ));
        }
        if !path
            .components()
            .all(|c| matches!(c, std::path::Component::Normal(_)))
        {
            return Err((
                "image",
                format!(
                    "{:?}: give a path inside the case's folder (no .., not absolute)",
                    self.image
                ),
            ));
        }
        let [a, b] = self.pixels;
        if !a.iter().chain(&b).all(|x| x.is_finite()) || (a[0] - b[0]).hypot(a[1] - b[1]) < 1.0 {
            return Err((
                "pixels",
                "two distinct points on the image (at least a pixel apart), pixels from its top \
                 left"
                    .to_string(),
            ));
        }
        if !(self.distance.is_finite() && self.distance > 0.0) {
            return Err((
                "distance",
                format!(
                    "{}: must be above 0 (the case's length unit)",
                    self.distance
                ),
            ));
        }
        if let Some(at) = &self.at {
            if !(at.x.is_finite() && at.y.is_finite()) {
                return Err(("at", "must be a finite position".to_string()));
            }
        }
        if !self.rotation.is_finite() {
            return Err(("rotation", "must be a finite angle, degrees".to_string()));
        }
        Ok(())
    }
}

/// `[survey]`: the scene's surveyed points (see [`crate::survey`]).
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurveySection {
    /// Where the points came from (a file name; not read).
    #[serde(default)]
    pub source: Option<String>,
    /// The points, in the case's frame and length unit.
    pub points: Vec<SurveyPoint>,
}

/// One surveyed point.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SurveyPoint {
    /// The surveyor's id of the point (unique in the survey).
    pub id: String,
    /// x (the case's length unit and frame).
    pub x: f64,
    /// y.
    pub y: f64,
    /// The surveyor's code (`LF`, `HYD`, `SKID`), if any.
    #[serde(default)]
    pub code: Option<String>,
    /// What the point is, if said.
    #[serde(default)]
    pub description: Option<String>,
}
