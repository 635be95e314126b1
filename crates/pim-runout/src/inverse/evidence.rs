//! What the estimate takes and gives: the evidence, the settings, the candidates.

use crate::chassis::Motion;
use crate::error::{Result, RunoutError};
use crate::simulate::{Runout, Settings};
use serde::{Deserialize, Serialize};

/// Farthest a rest position or mark may lie from the frame's origin, and largest standard
/// deviation of a position, m (a scene diagram's origin is at the impact).
pub const MAX_SCENE_DISTANCE: f64 = 10_000.0;

/// Farthest a mark's point of the vehicle may lie from its CG, m (the longest road vehicle's
/// half length, with room).
pub const MAX_POINT: f64 = 15.0;

/// Largest heading (and heading standard deviation) accepted, rad: one turn either way.
pub const MAX_HEADING: f64 = std::f64::consts::TAU;

/// Most full turns a stated count may give, either way.
pub const MAX_TURNS: i64 = 20;

/// Fastest separation state a search tries: a CG speed beyond this (m/s) or a yaw rate beyond
/// [`MAX_SEARCH_YAW_RATE`] (rad/s) is no separation state of a road crash.
pub const MAX_SEARCH_SPEED: f64 = 100.0;

/// See [`MAX_SEARCH_SPEED`].
pub const MAX_SEARCH_YAW_RATE: f64 = 30.0;

/// Candidates whose costs differ by less than this (in units of chi-square) are equally
/// consistent with the evidence.
pub const CONSISTENT_COST: f64 = 1e-6;

/// Candidates within this cost of the best (a likelihood ratio above e^-2, two standard
/// deviations of one parameter) are not excluded by the evidence: it favours the best without
/// deciding against them.
pub const PLAUSIBLE_COST: f64 = 4.0;

/// The rest position (and heading) of the vehicle, with standard deviations.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Rest {
    /// CG position, m.
    pub x: f64,
    /// CG position, m.
    pub y: f64,
    /// Heading at rest, rad (modulo a full turn), when known.
    pub heading: Option<f64>,
    /// Standard deviations of x and y, m.
    pub sigma_xy: [f64; 2],
    /// Standard deviation of the heading, rad.
    pub sigma_heading: f64,
    /// The point of the vehicle whose rest position `x`, `y` is, in the vehicle's frame:
    /// metres ahead of the CG and to its left (`[0, 0]`: the CG; the centroid of tyre contact
    /// points measured at rest, with the heading they give).
    #[serde(default)]
    pub point: [f64; 2],
}

impl Rest {
    /// Where the CG rests if the vehicle rests as given: `(x, y)` less the point's offset
    /// turned by the rest heading (by none without one).
    pub fn cg(&self) -> (f64, f64) {
        let (s, c) = self.heading.unwrap_or(0.0).sin_cos();
        let [a, b] = self.point;
        (self.x - (c * a - s * b), self.y - (s * a + c * b))
    }
}

/// A point a point of the vehicle passed: a tyre mark left by one wheel (its contact point,
/// [`Mark::point`] the wheel's place on the vehicle), or a point of the CG's path (`point`
/// `[0, 0]`), with a standard deviation, optionally with the vehicle's heading there. Its
/// residual is the distance of the mark from the path that point of the vehicle traced.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Mark {
    /// Position, m.
    pub x: f64,
    /// Position, m.
    pub y: f64,
    /// Standard deviation of the distance from the path, m.
    pub sigma: f64,
    /// Heading of the vehicle there (rad, modulo a full turn) and its standard deviation (rad).
    pub heading: Option<(f64, f64)>,
    /// The point of the vehicle that left the mark, in the vehicle's frame: metres ahead of the
    /// CG and to its left (a wheel's [`crate::Chassis::wheel_position`]; `[0, 0]` the CG).
    #[serde(default)]
    pub point: [f64; 2],
}

/// The evidence of one vehicle's run-out.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Evidence {
    /// The rest position and heading.
    pub rest: Option<Rest>,
    /// Points the CG passed, in any order.
    pub marks: Vec<Mark>,
    /// The count of full turns to rest, when the case states it (only that candidate is
    /// searched).
    pub turns: Option<i64>,
    /// Standard deviation of the road friction: with it the friction is estimated (its value in
    /// the chassis is the estimate's centre), without it the friction is taken as exact.
    pub friction_sigma: Option<f64>,
}

/// How the separation velocities are searched.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct EstimateSettings {
    /// The counts of full turns tried, from the first to the second inclusive.
    pub turns: (i64, i64),
    /// Iterations of the least-squares search per candidate.
    pub max_iterations: usize,
    /// How each run-out is integrated.
    pub runout: Settings,
    /// Explore the counts also from a scatter of separation states over the yaw rates of road
    /// crashes (see the module docs): about 800 to 1,500 more run-outs per vehicle and a dozen
    /// more searches, for a search that must not stop at the first basin that fits the scene.
    #[serde(default)]
    pub scatter: bool,
    /// Explore each count only from its first guess (and, with marks, through the rest alone)
    /// and from the answers of the neighbouring counts, no further starts around the first
    /// guess, and polish each candidate until a step gains less than 1e-6 in chi-square, not
    /// to the run-outs' precision. A first look that gives starting points, for a search that
    /// refines them and looks again more thoroughly where its answer does not fit (the whole
    /// reconstruction's first search).
    #[serde(default)]
    pub quick: bool,
    /// Separation states found elsewhere (an impact's answer: the whole reconstruction's
    /// earlier search), each with the count of turns it was found for: each count within one
    /// turn of it is also explored from it (its yaw rate scaled to that count's rotation), as
    /// the scatter's states are, whatever the other starts found. A scene whose states reaching
    /// the rest form several basins for one count keeps the basin the impact leads to among
    /// its [`Candidate::alternatives`]. Those ends are kept apart: alternatives beyond
    /// [`MAX_ALTERNATIVES`], never the candidate and never in place of the scene's own
    /// alternatives (mixed with them, they crowded out the basin of a crash's truth).
    #[serde(default)]
    pub starts: Vec<(Option<i64>, [f64; 3])>,
    /// With the scatter: its grid of CG velocities mapped at every quarter of a rad/s of yaw
    /// rate instead of every whole one (four times the grid's 4,032 run-outs). A branch of the
    /// rest curve that is a closed loop between two whole yaw rates (a steered car turned
    /// once around by its wheels, reaching its rest only between -1 and 0 rad/s) crosses no
    /// whole one: the finer grid finds it. For a last look before a refusal.
    #[serde(default)]
    pub fine: bool,
}

impl Default for EstimateSettings {
    /// Turns -3 to 3, 100 iterations, the default run-out settings, no scatter, every start,
    /// the scatter's grid at whole yaw rates.
    fn default() -> Self {
        EstimateSettings {
            turns: (-3, 3),
            max_iterations: 100,
            runout: Settings::default(),
            scatter: false,
            quick: false,
            starts: Vec::new(),
            fine: false,
        }
    }
}

/// What a residual of a run-out's evidence measures: its identity, which every table, figure
/// and reader tells residuals apart by ([`Quantity::name`] is only for display).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Quantity {
    /// The rest position along x, m.
    RestX,
    /// The rest position along y, m.
    RestY,
    /// The rest heading, rad.
    RestHeading,
    /// A mark's distance from the path of the vehicle's point that left it, m; `index` counts
    /// the evidence's marks from 0.
    Mark {
        /// Which mark of [`Evidence::marks`].
        index: usize,
    },
    /// The vehicle's heading where it passed a mark, rad.
    MarkHeading {
        /// Which mark of [`Evidence::marks`].
        index: usize,
    },
    /// The road friction against its stated value (when estimated), coefficient.
    Friction,
}

impl Quantity {
    /// Its display name: `rest.x`, `rest.y`, `rest.heading`, `mark 1`, `mark 1 heading`,
    /// `friction` (marks counted from 1).
    pub fn name(self) -> String {
        match self {
            Quantity::RestX => "rest.x".into(),
            Quantity::RestY => "rest.y".into(),
            Quantity::RestHeading => "rest.heading".into(),
            Quantity::Mark { index } => format!("mark {}", index + 1),
            Quantity::MarkHeading { index } => format!("mark {} heading", index + 1),
            Quantity::Friction => "friction".into(),
        }
    }

    /// Whether it is an angle (rad; shown in degrees).
    pub fn is_angle(self) -> bool {
        matches!(self, Quantity::RestHeading | Quantity::MarkHeading { .. })
    }

    /// Whether it is a rest position or heading, or a mark (what a scene figure draws), not
    /// the friction.
    pub fn is_scene(self) -> bool {
        !matches!(self, Quantity::Friction)
    }
}

/// One residual of a candidate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Residual {
    /// What it measures.
    pub what: Quantity,
    /// Its display name ([`Quantity::name`]).
    pub name: String,
    /// Fitted minus given, in its unit (m, rad, or the friction coefficient).
    pub value: f64,
    /// Its standard deviation, in the same unit.
    pub sigma: f64,
}

/// The best separation state for one count of turns.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Candidate {
    /// Full turns beyond the rotation to the nearest rest heading (none when the rest heading
    /// is not given).
    pub turns: Option<i64>,
    /// The motion at separation (position and heading as given, velocities estimated).
    pub separation: Motion,
    /// The friction (estimated or as given).
    pub friction: f64,
    /// Sum of the squared residuals in units of their sigmas.
    pub cost: f64,
    /// Every piece of evidence against the fit.
    pub residuals: Vec<Residual>,
    /// Standard errors of the unknowns (`vx`, `vy`, `yaw_rate` and `friction` when estimated,
    /// in the order of [`Estimate::unknowns`]); `None` for an unknown the evidence leaves free.
    pub sigma: Vec<Option<f64>>,
    /// Directions in the unknowns (unit vectors, same order) that the scene's evidence does not
    /// determine (with the friction estimated: the evidence without the friction's own standard
    /// deviation, which then decides along them).
    pub free: Vec<Vec<f64>>,
    /// Equally consistent with the best candidate (cost within [`CONSISTENT_COST`]).
    pub consistent: bool,
    /// Not excluded by the evidence (cost within [`PLAUSIBLE_COST`] of the best).
    pub plausible: bool,
    /// The search converged (step or cost change below its tolerance).
    pub converged: bool,
    /// Least-squares iterations.
    pub iterations: usize,
    /// Run-outs simulated for this candidate.
    pub runouts: usize,
    /// Why this candidate does not reach the evidence, when it does not (a residual beyond
    /// 3 sigma, or a run-out that reaches its time limit).
    pub reason: Option<String>,
    /// The run-out from the estimated separation state.
    pub runout: Runout,
    /// Other local minima of this count's cost that the search passed through (distinct
    /// separation states within [`ALTERNATIVE_COST`] of this candidate's cost, the lowest first,
    /// at most [`MAX_ALTERNATIVES`] beyond those whose cost is no larger than the count of
    /// residuals, which are all kept; found on the exploring run-outs, not polished). The scene
    /// alone prefers the candidate; evidence beyond the scene (the impact) may prefer one of
    /// these.
    #[serde(skip)]
    #[schemars(skip)]
    pub alternatives: Vec<Alternative>,
}

/// Another local minimum of a candidate's cost ([`Candidate::alternatives`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Alternative {
    /// The separation velocities `(vx, vy, yaw_rate)`, m/s and rad/s.
    pub velocity: [f64; 3],
    /// The friction there (estimated or as given).
    pub friction: f64,
    /// Its cost (sum of the squared weighted residuals) on the exploring run-outs.
    pub cost: f64,
}

/// Alternatives are kept up to this cost above their candidate's (a misfit of five standard
/// deviations in one residual: beyond it, no other evidence of an ordinary case brings them
/// back).
pub const ALTERNATIVE_COST: f64 = 25.0;

/// Most alternatives kept per candidate beyond those that meet the scene as well as its data
/// expect (a cost no larger than its count of residuals: the scene cannot tell them from the
/// candidate, and all are kept).
pub const MAX_ALTERNATIVES: usize = 3;

/// The separation velocities of one vehicle estimated from its run-out evidence.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Estimate {
    /// The names of the unknowns, in the order of [`Candidate::sigma`].
    pub unknowns: Vec<String>,
    /// One candidate per count of turns, the lowest cost first.
    pub candidates: Vec<Candidate>,
}

impl Estimate {
    /// The candidates equally consistent with the evidence (the lowest cost and those within
    /// [`CONSISTENT_COST`] of it).
    pub fn consistent(&self) -> impl Iterator<Item = &Candidate> {
        self.candidates.iter().filter(|c| c.consistent)
    }

    /// The lowest-cost candidate (one of the consistent ones; check [`Estimate::consistent`]
    /// before calling it *the* answer).
    pub fn best(&self) -> Option<&Candidate> {
        self.candidates.first()
    }
}

pub(crate) fn input(field: &'static str, reason: String) -> RunoutError {
    RunoutError::Input { field, reason }
}

/// Smallest standard deviation of a position (rest or mark) in the softened cost, m.
const SOFT_POSITION: f64 = 1.0;
/// Smallest standard deviation of a heading in the softened cost, rad (10 deg).
const SOFT_HEADING: f64 = 0.175;

impl Evidence {
    /// The evidence with its standard deviations raised to `factor` times [`SOFT_POSITION`] and
    /// [`SOFT_HEADING`]:
    /// a smoother cost of the same minimum for noise-free evidence. With marks of a few centimetres
    /// the cost of a state a metre off is dominated by which part of the path passes nearest each
    /// mark, and ranks the scatter by chance; softened, it ranks by how close the run-out comes to
    /// the whole scene, and a search on it first (then on the evidence as given) is drawn into the
    /// right basin from farther off.
    pub(crate) fn softened(&self, factor: f64) -> Evidence {
        let (position, heading) = (factor * SOFT_POSITION, factor * SOFT_HEADING);
        let mut e = self.clone();
        if let Some(r) = e.rest.as_mut() {
            r.sigma_xy = r.sigma_xy.map(|s| s.max(position));
            r.sigma_heading = r.sigma_heading.max(heading);
        }
        for m in &mut e.marks {
            m.sigma = m.sigma.max(position);
            if let Some((_, s)) = m.heading.as_mut() {
                *s = s.max(heading);
            }
        }
        e
    }

    /// Checks the evidence: finite numbers, sigmas above 0, something to fit.
    pub fn check(&self) -> Result<()> {
        let within = |field: &'static str, x: f64, lo: f64, hi: f64, unit: &str| {
            if x.is_finite() && x >= lo && x <= hi {
                Ok(())
            } else {
                Err(input(
                    field,
                    format!("{x}: must be a number from {lo} to {hi} {unit}"),
                ))
            }
        };
        let positive = |field: &'static str, s: f64, hi: f64, unit: &str| {
            if s.is_finite() && s > 0.0 && s <= hi {
                Ok(())
            } else {
                Err(input(
                    field,
                    format!("{s}: a standard deviation must be above 0 and at most {hi} {unit}"),
                ))
            }
        };
        let (p, h) = (MAX_SCENE_DISTANCE, MAX_HEADING);
        if let Some(r) = &self.rest {
            within("rest.x", r.x, -p, p, "m")?;
            within("rest.y", r.y, -p, p, "m")?;
            within("rest.point", r.point[0], -MAX_POINT, MAX_POINT, "m")?;
            within("rest.point", r.point[1], -MAX_POINT, MAX_POINT, "m")?;
            positive("rest_sigma.x", r.sigma_xy[0], p, "m")?;
            positive("rest_sigma.y", r.sigma_xy[1], p, "m")?;
            if let Some(a) = r.heading {
                within("rest.heading", a, -h, h, "rad")?;
                positive("rest_sigma.heading", r.sigma_heading, h, "rad")?;
            }
        }
        for m in &self.marks {
            within("marks.x", m.x, -p, p, "m")?;
            within("marks.y", m.y, -p, p, "m")?;
            within("marks.point", m.point[0], -MAX_POINT, MAX_POINT, "m")?;
            within("marks.point", m.point[1], -MAX_POINT, MAX_POINT, "m")?;
            positive("marks.sigma", m.sigma, p, "m")?;
            if let Some((a, s)) = m.heading {
                within("marks.heading", a, -h, h, "rad")?;
                positive("marks.heading_sigma", s, h, "rad")?;
            }
        }
        if let Some(k) = self.turns {
            if k.abs() > MAX_TURNS {
                return Err(input(
                    "turns",
                    format!("{k}: at most {MAX_TURNS} full turns either way"),
                ));
            }
        }
        if let Some(s) = self.friction_sigma {
            positive("friction_sigma", s, 1.0, "")?;
        }
        if self.rest.is_none() && self.marks.is_empty() {
            return Err(input(
                "rest",
                "no evidence: give the rest position (and heading) or marks the CG passed".into(),
            ));
        }
        if self.turns.is_some() && self.rest.and_then(|r| r.heading).is_none() {
            return Err(input(
                "turns",
                "a count of turns needs the rest heading it counts to".into(),
            ));
        }
        Ok(())
    }
}
