//! What a reconstruction is given: the impact's evidence, each vehicle's run-out and scene, the
//! pre-impact marks, and how the search runs.

use crate::error::{ReconstructError, Result};
use pim_core::VehicleId;
use pim_fit::{FitProblem, Knowledge, ValidSettings, Vector12};
use pim_runout::{Chassis, Evidence, Motion, Settings as RunoutSettings, GRAVITY};
use serde::Serialize;

/// One vehicle's run-out from separation to rest and what the scene shows of it.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneVehicle {
    /// Which vehicle.
    pub id: VehicleId,
    /// Its wheels and the road.
    pub chassis: Chassis,
    /// Its CG position and heading at separation (those at contact), natural frame; the
    /// velocities are not read.
    pub pose: Motion,
    /// The rest position, heading and marks (sigmas in metres and radians).
    pub evidence: Evidence,
}

/// A skid or yaw mark laid down before the impact: the vehicle braked over `distance` up to the
/// point of contact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Skid {
    /// Length of the braking before contact, m.
    pub distance: f64,
    /// Share of the road friction the braking used, 0 to 1 (1: all wheels locked).
    pub braking: f64,
    /// Road grade along the direction of travel, rad (positive uphill).
    pub grade: f64,
    /// Road friction, coefficient.
    pub friction: f64,
}

impl Skid {
    /// The deceleration while braking, m/s^2: `g (friction braking cos(grade) + sin(grade))`.
    pub fn deceleration(&self) -> f64 {
        GRAVITY * (self.friction * self.braking * self.grade.cos() + self.grade.sin())
    }

    /// The speed where the braking began from the speed at contact, m/s:
    /// `v0^2 = vc^2 + 2 a d` (constant deceleration a over the distance d).
    pub fn speed_before(&self, contact_speed: f64) -> f64 {
        (contact_speed * contact_speed + 2.0 * self.deceleration() * self.distance)
            .max(0.0)
            .sqrt()
    }

    /// Checks the numbers.
    ///
    /// # Errors
    /// [`ReconstructError::Input`] naming the field.
    pub fn check(&self) -> Result<()> {
        let bad = |field: &'static str, reason: &str| {
            Err(ReconstructError::Input {
                field,
                reason: reason.to_string(),
            })
        };
        if !(self.distance.is_finite() && self.distance >= 0.0 && self.distance <= 1000.0) {
            return bad("distance", "a braking distance from 0 to 1000 m");
        }
        if !(self.braking.is_finite() && (0.0..=1.0).contains(&self.braking)) {
            return bad("braking", "a share of the friction from 0 to 1");
        }
        if !(self.grade.is_finite() && self.grade.abs() <= 0.35) {
            return bad("grade", "a grade within 20 deg (35 %)");
        }
        if !(self.friction.is_finite() && self.friction > 0.0 && self.friction <= 1.5) {
            return bad("friction", "a road friction above 0 and at most 1.5");
        }
        Ok(())
    }
}

/// A piece of evidence that is a nonlinear function of the velocities `U = (contact state,
/// separation state)`: the crush energy of the damage against the energy PIM's impact takes
/// out, say. Its residual joins the chi-square as `(value / sigma)^2`; the search linearises
/// it at each point (forward differences over the free components of U) as it linearises the
/// scenes.
pub trait StateEvidence: Send + Sync + std::fmt::Debug {
    /// Its name in the evidence table (`crush energy`).
    fn name(&self) -> String;
    /// What its value measures, for display (`energy`).
    fn quantity(&self) -> &'static str;
    /// At `u`: fitted minus given and its standard deviation (both in the quantity's SI unit;
    /// the standard deviation may depend on `u`). `None` where it is not defined (no impulse):
    /// such a state is no answer.
    fn residual(&self, u: &Vector12) -> Option<(f64, f64)>;
}

/// The nonlinear evidence of a reconstruction ([`StateEvidence`]), shared: two are equal when
/// they are the same pieces.
#[derive(Debug, Clone, Default)]
pub struct NonlinearEvidence(pub Vec<std::sync::Arc<dyn StateEvidence>>);

impl PartialEq for NonlinearEvidence {
    fn eq(&self, other: &Self) -> bool {
        self.0.len() == other.0.len()
            && self
                .0
                .iter()
                .zip(&other.0)
                .all(|(a, b)| std::sync::Arc::ptr_eq(a, b))
    }
}

/// A reconstruction: the impact fit's own evidence (the contact state's estimates and
/// observations, e.g. EDR speeds, no lateral velocity), the scene of each vehicle that has one,
/// and the pre-impact marks.
#[derive(Debug, Clone, PartialEq)]
pub struct Reconstruction {
    /// The impact and its evidence. Its weights are `unit / sigma^2`; components of the
    /// separation state may carry estimates too (beside the scene).
    pub contact: FitProblem,
    /// The common unit of the contact problem's weights (`w = unit / sigma^2`); `None` when it
    /// has no estimates or observations.
    pub unit: Option<f64>,
    /// The vehicles whose run-out the scene shows (one or both).
    pub scene: Vec<SceneVehicle>,
    /// Braking before the impact, per vehicle.
    pub skids: [Option<Skid>; 2],
    /// Evidence on the velocities that is not linear in them (the crush energy).
    pub nonlinear: NonlinearEvidence,
    /// Road frictions fitted with the other unknowns (none: every vehicle's friction is held
    /// at its chassis's value).
    pub frictions: Vec<RoadFriction>,
}

/// A friction fitted with the velocities: its stated value and standard deviation (a datum of
/// the chi-square, `((mu - value) / sigma)^2`) and the scene vehicles that ran out on it. The
/// road's (one surface under both, or one each where they came to rest on different surfaces),
/// or a friction zone's ([`RoadFriction::zone`]: each wheel of every run-out on it where it
/// lies under the wheel).
#[derive(Debug, Clone, PartialEq)]
pub struct RoadFriction {
    /// Its name in the evidence table (`road friction`, `grass verge friction`).
    pub name: String,
    /// The friction zone it is (an index into each scene vehicle's
    /// [`Chassis::zones`](pim_runout::Chassis::zones), the same zones under both); `None`: the
    /// road's friction outside every zone ([`Chassis::friction`](pim_runout::Chassis::friction)).
    pub zone: Option<usize>,
    /// The stated value, coefficient.
    pub value: f64,
    /// Its standard deviation.
    pub sigma: f64,
    /// The vehicles on it: indices into [`Reconstruction::scene`].
    pub vehicles: Vec<usize>,
    /// The vehicles (0: vehicle 1, 1: vehicle 2) whose braking before the impact
    /// ([`Reconstruction::skids`]) was on it: their speed before braking takes the fitted value.
    pub skids: Vec<usize>,
}

/// Smallest and largest friction the search tries.
pub(crate) const FRICTION_RANGE: (f64, f64) = (0.05, pim_runout::MAX_FRICTION);

impl Reconstruction {
    /// Checks what the search needs.
    ///
    /// # Errors
    /// [`ReconstructError::Input`] for no scene, a vehicle twice, a barrier with a run-out,
    /// or a separation component held fixed (the scene decides the separation state).
    pub fn check(&self) -> Result<()> {
        if self.scene.is_empty() {
            return Err(ReconstructError::Input {
                field: "scene",
                reason: "no vehicle has scene evidence (a rest position or marks)".into(),
            });
        }
        for (i, v) in self.scene.iter().enumerate() {
            if self.scene[..i].iter().any(|w| w.id == v.id) {
                return Err(ReconstructError::Input {
                    field: "scene",
                    reason: format!("{} is given twice", v.id),
                });
            }
            if v.id == VehicleId::Two && self.contact.impact.is_barrier() {
                return Err(ReconstructError::Input {
                    field: "scene",
                    reason: "vehicle 2 is a fixed barrier: it has no run-out".into(),
                });
            }
            let base = 6 + 3 * v.id.index();
            if (base..base + 3)
                .any(|k| matches!(self.contact.components[k], Knowledge::Known { .. }))
            {
                return Err(ReconstructError::Input {
                    field: "final",
                    reason: format!(
                        "a separation velocity of {} is held fixed, but its scene decides it: \
                         give it as an estimate with a standard deviation, or leave it out",
                        v.id
                    ),
                });
            }
            v.chassis.check()?;
            v.pose.check()?;
            v.evidence.check()?;
        }
        if let Some(u) = self.unit {
            if !(u.is_finite() && u > 0.0) {
                return Err(ReconstructError::Input {
                    field: "unit",
                    reason: format!("{u}: the unit of the weights must be above 0"),
                });
            }
        }
        for s in self.skids.iter().flatten() {
            s.check()?;
        }
        for (g, f) in self.frictions.iter().enumerate() {
            let bad = |reason: String| {
                Err(ReconstructError::Input {
                    field: "friction",
                    reason,
                })
            };
            if !(f.value.is_finite() && f.value >= FRICTION_RANGE.0 && f.value <= FRICTION_RANGE.1)
            {
                return bad(format!(
                    "{}: a road friction from {} to {}",
                    f.value, FRICTION_RANGE.0, FRICTION_RANGE.1
                ));
            }
            if !(f.sigma.is_finite() && f.sigma > 0.0 && f.sigma <= 1.0) {
                return bad(format!(
                    "{}: the friction's standard deviation must be above 0 and at most 1",
                    f.sigma
                ));
            }
            // A vehicle runs out on one road friction, and each zone is fitted once.
            let taken = |v: usize| {
                self.frictions[..g]
                    .iter()
                    .any(|h| h.zone == f.zone && (f.zone.is_some() || h.vehicles.contains(&v)))
            };
            if f.vehicles.is_empty()
                || f.vehicles
                    .iter()
                    .any(|&v| v >= self.scene.len() || taken(v))
            {
                return bad(format!(
                    "{}: each fitted friction needs scene vehicles of its own",
                    f.name
                ));
            }
            if let Some(k) = f.zone {
                if f.vehicles
                    .iter()
                    .any(|&v| k >= self.scene[v].chassis.zones.len())
                {
                    return bad(format!(
                        "{}: zone {} is not under its vehicles",
                        f.name,
                        k + 1
                    ));
                }
            }
        }
        Ok(())
    }

    /// The fitted road friction the scene vehicle `v` runs out on (outside every zone), if
    /// any.
    pub fn friction_of(&self, v: usize) -> Option<usize> {
        self.frictions
            .iter()
            .position(|f| f.zone.is_none() && f.vehicles.contains(&v))
    }

    /// The fitted zone frictions under the scene vehicle `v`: each one's index in
    /// [`Reconstruction::frictions`] and its zone.
    pub fn zone_frictions_of(&self, v: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        self.frictions
            .iter()
            .enumerate()
            .filter_map(move |(g, f)| f.zone.filter(|_| f.vehicles.contains(&v)).map(|k| (g, k)))
    }

    /// The frictions' residuals at `mus` (one per [`Reconstruction::frictions`]) in standard
    /// deviations.
    pub fn friction_z(&self, mus: &[f64]) -> Vec<f64> {
        self.frictions
            .iter()
            .zip(mus)
            .map(|(f, m)| (m - f.value) / f.sigma)
            .collect()
    }

    /// Every piece of the contact problem's evidence at `u`, in the order of the problem
    /// (estimated components, observations, combinations): fitted minus given and its weight.
    pub fn contact_residuals(&self, u: &Vector12) -> Vec<ContactResidual> {
        let p = &self.contact;
        let components = p
            .components
            .iter()
            .enumerate()
            .filter_map(|(k, c)| match *c {
                Knowledge::Estimated { value, weight } => Some(ContactResidual {
                    term: ContactTerm::Component(k),
                    residual: u[k] - value,
                    weight,
                }),
                _ => None,
            });
        let observations = p
            .observations
            .iter()
            .enumerate()
            .map(|(i, o)| ContactResidual {
                term: ContactTerm::Observation(i),
                residual: o.row(&p.impact).dot(u) - o.value,
                weight: o.weight,
            });
        let combinations = p
            .combinations
            .iter()
            .enumerate()
            .map(|(i, c)| ContactResidual {
                term: ContactTerm::Combination(i),
                residual: c.row.dot(u) - c.value,
                weight: c.weight,
            });
        let unit = self.unit.unwrap_or(1.0);
        let nonlinear = self.nonlinear.0.iter().enumerate().filter_map(|(i, t)| {
            let (value, sigma) = t.residual(u)?;
            Some(ContactResidual {
                term: ContactTerm::Nonlinear(i),
                residual: value,
                weight: unit / (sigma * sigma),
            })
        });
        components
            .chain(observations)
            .chain(combinations)
            .chain(nonlinear)
            .collect()
    }

    /// Whether every piece of nonlinear evidence is defined at `u`.
    pub fn nonlinear_defined(&self, u: &Vector12) -> bool {
        self.nonlinear.0.iter().all(|t| {
            t.residual(u)
                .is_some_and(|(v, s)| v.is_finite() && s.is_finite() && s > 0.0)
        })
    }

    /// The standard deviation of a contact residual: `sqrt(unit / weight)`.
    pub fn sigma_of(&self, r: &ContactResidual) -> f64 {
        (self.unit.unwrap_or(1.0) / r.weight).sqrt()
    }

    /// The chi-square of the contact problem's evidence at `u` (`sum w r^2 / unit`).
    pub fn contact_chi_square(&self, u: &Vector12) -> f64 {
        let sum: f64 = self
            .contact_residuals(u)
            .iter()
            .map(|r| r.weight * r.residual.powi(2))
            .sum();
        sum / self.unit.unwrap_or(1.0)
    }

    /// The count of pieces of evidence of the contact problem (estimated components,
    /// observations, combinations).
    pub fn contact_data(&self) -> usize {
        self.contact
            .components
            .iter()
            .filter(|k| matches!(k, Knowledge::Estimated { .. }))
            .count()
            + self.contact.observations.len()
            + self.contact.combinations.len()
            + self.nonlinear.0.len()
    }
}

/// Which piece of the contact problem's evidence.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ContactTerm {
    /// The estimate of component `k` of U.
    Component(usize),
    /// Observation `i` of the problem.
    Observation(usize),
    /// Combination `i` of the problem.
    Combination(usize),
    /// Nonlinear evidence `i` of the reconstruction ([`Reconstruction::nonlinear`]).
    Nonlinear(usize),
}

impl ContactTerm {
    /// Its name without the case's labels: the component's name, or `observation N (kind of
    /// vehicleN)`, or `combination N`.
    pub fn name(self, problem: &FitProblem) -> String {
        match self {
            ContactTerm::Component(k) => pim_fit::COMPONENT_NAMES[k].to_string(),
            ContactTerm::Observation(i) => {
                let o = &problem.observations[i];
                format!("observation {} ({:?} of {})", i + 1, o.kind, o.vehicle)
            }
            ContactTerm::Combination(i) => format!("combination {}", i + 1),
            ContactTerm::Nonlinear(i) => format!("nonlinear evidence {}", i + 1),
        }
    }
}

/// One piece of the contact problem's evidence at a state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactResidual {
    /// Which.
    pub term: ContactTerm,
    /// Fitted minus given (m/s or rad/s).
    pub residual: f64,
    /// Its weight in the problem (`unit / sigma^2`).
    pub weight: f64,
}

/// The default [`Settings::refine_work`]: run-out right-hand side evaluations (and their
/// equivalents for the impact fits) the refinements may spend. The refinements of the example
/// `reconstruction_us.toml` spend 0.27 million of its 12 million, the example without its
/// contact estimates and with its EDR moved 8 mph 3.2 million; a budget, not a time, so that
/// the answer is the same on a slow and a fast machine (a unit takes 0.4 to 1.3 us on one
/// core: the budget bounds a reconstruction to about 10 s).
pub const REFINE_WORK: u64 = 12_000_000;

/// Below this probability a found reconstruction fits poorly (its evidence is looked at piece
/// by piece: the consistency table).
pub const POOR_FIT_P: f64 = 0.05;

/// The chi-square's probability below which a first search's answer is searched again from a
/// scatter: where it fits poorly ([`POOR_FIT_P`]). See the crate docs (*What is proven and what
/// is the best found*).
pub const SCATTER_BELOW_P: f64 = POOR_FIT_P;

/// How a reconstruction searches.
#[derive(Debug, Clone)]
pub struct Settings {
    /// The impact fit's settings (bounds, coefficient ranges, branches, model).
    pub fit: ValidSettings,
    /// How each run-out is integrated.
    pub runout: RunoutSettings,
    /// The counts of full turns to rest each vehicle's scene is searched over.
    pub turns: (i64, i64),
    /// Gauss-Newton iterations per combination of counts.
    pub max_iterations: usize,
    /// Combinations of counts whose first linearised fit lies more than this (chi-square
    /// units) above the best cost found are not refined.
    pub refine_margin: f64,
    /// At most this many combinations of counts are refined (the lowest bound first) whose
    /// refinement ended within [`Settings::refine_margin`] of its bound; one that ended
    /// farther (its linearisation, hence its bound, did not hold) does not count.
    pub max_refined: usize,
    /// The work after which the refinements stop (the one in progress after its current step,
    /// with at least one point) and the combinations not yet refined are left, each with that
    /// reason: run-out right-hand side evaluations, an impact fit counted by its quadratic
    /// programs and grid points. Counted, not timed: the same answer on every machine, and a
    /// bound of the time spent on evidence whose impact fits or run-outs are very slow.
    pub refine_work: u64,
    /// An answer whose chi-square's probability lies below this is searched again from a
    /// scatter of separation states ([`SCATTER_BELOW_P`]; 0: never; above 1: always).
    pub scatter_below_p: f64,
}

impl Settings {
    /// Default search settings around the given fit settings: turns -3 to 3, 160 iterations (a
    /// refinement crawling along a curved valley of a scene still gains; the budget of work
    /// bounds it), a margin of 25 (a 5-sigma misfit), at most 6 refined combinations,
    /// [`REFINE_WORK`]. The impact fits inside
    /// the search skip the identifiability scans ([`pim_fit::FitSettings::ranges`]): the
    /// search needs each fit's optimum, not its ranges.
    pub fn new(fit: ValidSettings) -> Self {
        Settings {
            fit: fit.without_ranges(),
            runout: RunoutSettings::default(),
            turns: (-3, 3),
            max_iterations: 160,
            refine_margin: 25.0,
            max_refined: 6,
            refine_work: REFINE_WORK,
            scatter_below_p: SCATTER_BELOW_P,
        }
    }
}
