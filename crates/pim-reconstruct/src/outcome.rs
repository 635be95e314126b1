//! What a reconstruction answers: the best combination found, the speeds of every phase, and
//! every combination of counts of turns compared.

use crate::point::Point;
use crate::problem::{ContactTerm, Reconstruction, Skid, POOR_FIT_P};
use pim_core::VehicleId;
use pim_fit::{Certificate, Knowledge, MomentBranch, Solution};
use pim_runout::{Estimate, Residual, Runout};
use serde::Serialize;

/// Whether a reconstruction was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// The best combination found (see [`Outcome::tried`] for what was compared).
    Found,
    /// No admissible impact reaches the scene for any count of turns ([`Outcome::reason`]).
    NoSolution,
    /// The best reconstruction found contradicts the evidence: its chi-square is beyond
    /// chance ([`INCONSISTENT_P`], judged with [`pim_fit::judged_dof`]: with no degrees of
    /// freedom left as one degree of freedom). [`Outcome::reason`] names the largest terms;
    /// [`Outcome::best`] is kept for inspection.
    Inconsistent,
}

/// A chi-square whose probability under the stated sigmas is below this is a contradiction,
/// not a fit (with one degree of freedom: a chi-square above 23.9, a single residual beyond
/// 4.9 sigma).
pub const INCONSISTENT_P: f64 = 1e-6;

/// One vehicle's scene against the reconstruction.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct SceneFit {
    /// Which vehicle.
    pub vehicle: VehicleId,
    /// Full turns to rest beyond the nearest rest heading (none without a rest heading).
    pub turns: Option<i64>,
    /// The scene's share of the chi-square.
    pub chi_square: f64,
    /// Every piece of its evidence: fitted minus given, with its sigma.
    pub residuals: Vec<Residual>,
    /// The run-out from the reconstructed separation state, on [`SceneFit::friction`]: the
    /// one the residuals measure (what every figure draws).
    pub runout: Runout,
    /// The road friction the run-out ran on: the fitted one where the case fits its road's
    /// friction ([`Found::frictions`]), the stated one otherwise.
    pub friction: f64,
    /// The friction of each zone under it (the chassis's order): the fitted one where the case
    /// fits the zone's friction, the stated one otherwise.
    pub zones: Vec<f64>,
    /// The rolling resistance it ran with (at most half of each fitted friction, as the
    /// chassis's checks require).
    pub rolling_resistance: f64,
}

impl SceneFit {
    /// `chassis` (the vehicle's as the case gives it) on the ground the fitted run-out ran on:
    /// its road friction, its zones' frictions and its rolling resistance.
    pub fn ground(&self, chassis: &mut pim_runout::Chassis) {
        chassis.friction = self.friction;
        chassis.rolling_resistance = self.rolling_resistance;
        for (z, mu) in chassis.zones.iter_mut().zip(&self.zones) {
            z.friction = *mu;
        }
    }
}

/// A vehicle's speed in each phase.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Phases {
    /// Which vehicle.
    pub vehicle: VehicleId,
    /// Where the braking before the impact began, m/s (with a pre-impact skid).
    pub before_braking: Option<f64>,
    /// At contact, m/s.
    pub contact: f64,
    /// At separation, m/s.
    pub separation: f64,
    /// The run-out's distance to rest, m (with a scene).
    pub runout_distance: Option<f64>,
    /// The run-out's time to rest, s (with a scene).
    pub runout_time: Option<f64>,
}

/// The reconstruction found.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Found {
    /// The moment branch of the impact.
    pub branch: MomentBranch,
    /// The impact: coefficients, both states, impulses, energy (the impact fit with each scene
    /// linearised at the found separation state).
    pub solution: Solution,
    /// How the impact fit at the found separation state was established (its route and
    /// proof).
    pub certificate: Certificate,
    /// The whole cost: the contact evidence's chi-square plus every scene's.
    pub chi_square: f64,
    /// The contact evidence's share.
    pub contact_chi_square: f64,
    /// Each scene's share and residuals.
    pub scene: Vec<SceneFit>,
    /// Pieces of evidence minus unknowns (velocities, coefficients) plus the six equations.
    pub degrees_of_freedom: i64,
    /// Gauss-Newton iterations of the best combination.
    pub iterations: usize,
    /// The iterations ended by their tolerance (not by their limit).
    pub converged: bool,
    /// Per vehicle, its speeds before braking, at contact, at separation.
    pub phases: [Phases; 2],
    /// The fitted road frictions, one per [`Reconstruction::frictions`] (their stated values
    /// and standard deviations there; each is a datum of the chi-square).
    pub frictions: Vec<f64>,
}

impl Found {
    /// Its counts of turns, one per scene vehicle (none without a rest heading), as
    /// [`TriedCounts::counts`] lists them.
    pub fn counts(&self) -> Vec<Option<i64>> {
        self.scene.iter().map(|s| s.turns).collect()
    }

    /// Whether the evidence contradicts this answer: its chi-square's probability lies below
    /// [`INCONSISTENT_P`] (as a refusal judges it).
    pub fn refused(&self) -> bool {
        self.p_below(INCONSISTENT_P)
    }

    /// Whether it fits poorly: its chi-square's probability lies below [`POOR_FIT_P`].
    pub fn fits_poorly(&self) -> bool {
        self.p_below(POOR_FIT_P)
    }

    /// Whether its chi-square's probability lies below `p`.
    fn p_below(&self, p: f64) -> bool {
        pim_fit::ChiSquare::p_value_of(self.degrees_of_freedom, self.chi_square)
            .is_some_and(|q| q < p)
    }

    pub(crate) fn new(r: &Reconstruction, p: Point, iterations: usize, converged: bool) -> Found {
        let scene = scene_fits(r, &p);
        let s = &p.solution;
        let phases = [VehicleId::One, VehicleId::Two].map(|id| {
            let k = id.index();
            let (c, sep) = if k == 0 {
                (s.initial.vehicle1, s.separation.vehicle1)
            } else {
                (s.initial.vehicle2, s.separation.vehicle2)
            };
            // As every report of the impact measures a speed (pim_core::VehicleVelocity::speed).
            let contact = c.speed();
            let run = scene.iter().find(|f| f.vehicle == id).map(|f| &f.runout);
            Phases {
                vehicle: id,
                before_braking: r.skids[k].map(|sk| {
                    // On a fitted road, at its fitted friction.
                    let fitted = r
                        .frictions
                        .iter()
                        .zip(&p.mus)
                        .find(|(f, _)| f.skids.contains(&k))
                        .map(|(_, m)| *m);
                    Skid {
                        friction: fitted.unwrap_or(sk.friction),
                        ..sk
                    }
                    .speed_before(contact)
                }),
                contact,
                separation: sep.speed(),
                runout_distance: run.map(|x| x.distance),
                runout_time: run.map(|x| x.time),
            }
        });
        // Each fitted friction is a datum (its stated value) and an unknown: the degrees of
        // freedom do not change with it.
        let data = r.contact_data() + scene.iter().map(|f| f.residuals.len()).sum::<usize>();
        let free = r
            .contact
            .components
            .iter()
            .filter(|k| !matches!(k, Knowledge::Known { .. }))
            .count();
        let coefficients = match p.branch {
            MomentBranch::Free => 3,
            MomentBranch::Zero => 2,
        };
        Found {
            branch: p.branch,
            certificate: p.certificate,
            chi_square: p.total,
            contact_chi_square: p.contact,
            degrees_of_freedom: data as i64 - (free as i64 + coefficients - 6),
            iterations,
            converged,
            phases,
            solution: p.solution,
            scene,
            frictions: p.mus,
        }
    }
}

/// What became of one combination of counts of turns.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum Tried {
    /// Refined to a (local) minimum of the whole cost.
    Refined {
        /// The chi-square reached.
        cost: f64,
        /// Gauss-Newton iterations.
        iterations: usize,
        /// Ended by the tolerance.
        converged: bool,
        /// Stopped while still more than [`Settings::refine_margin`](crate::Settings) above the
        /// best found and no longer closing the gap (after 8 iterations, or gaining less than
        /// 1 % of the gap in one).
        abandoned: bool,
    },
    /// Compared by its linearised fit only.
    NotRefined {
        /// Why not refined.
        reason: String,
    },
    /// No admissible impact reaches its run-outs.
    NoImpact {
        /// The fit's reason.
        reason: String,
    },
}

/// One combination of counts of turns (one per scene vehicle, in the order of
/// [`Reconstruction::scene`]).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct TriedCounts {
    /// The counts (none for a scene without a rest heading).
    pub counts: Vec<Option<i64>>,
    /// The chi-square of the scenes alone at the best separation states their search found
    /// for these counts: a lower bound of the combination's cost where that search found each
    /// count's minimum (it searches from many starts; it is not a proof).
    pub scene_alone: f64,
    /// The chi-square of the problem with each scene linearised at its own best separation
    /// state and only the momentum balance as constraints (a lower bound of that linearised
    /// fit; the combinations are refined in the order of these bounds).
    pub momentum_bound: Option<f64>,
    /// What became of it.
    pub state: Tried,
    /// Where its refinement ended (a start for the same combination with perturbed evidence).
    #[serde(skip)]
    pub end: Option<End>,
}

/// Where a combination's refinement ended: the state a refinement of the same counts starts
/// from again.
#[derive(Debug, Clone, PartialEq)]
pub struct End {
    /// Each scene vehicle's separation velocity `(vx, vy, yaw_rate)`.
    pub velocities: Vec<[f64; 3]>,
    /// The frictions its run-outs ran on, one per [`Reconstruction::frictions`] (the fitted
    /// ones: a long run-out started again on the stated friction ends far from where it did).
    pub frictions: Vec<f64>,
    /// The twelve velocities (contact, then separation): where the nonlinear contact evidence
    /// is linearised again.
    pub state: pim_fit::Vector12,
}

impl End {
    pub(crate) fn of(p: &Point) -> End {
        End {
            velocities: p.scene.iter().map(|l| l.at).collect(),
            frictions: p.mus.clone(),
            state: pim_fit::state_vector(&p.solution.initial, &p.solution.separation),
        }
    }

    /// Each scene linearised at this end for `counts` (a count of 0 without a rest heading).
    pub(crate) fn linearised(
        &self,
        r: &Reconstruction,
        settings: &crate::problem::Settings,
        counts: &[Option<i64>],
    ) -> crate::error::Result<Vec<crate::point::Lin>> {
        self.velocities
            .iter()
            .enumerate()
            .map(|(v, at)| {
                crate::point::linearised(
                    r,
                    settings,
                    v,
                    counts[v].unwrap_or(0),
                    *at,
                    true,
                    &self.frictions,
                )
            })
            .collect()
    }
}

/// A reconstruction's answer.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Outcome {
    /// Found or not.
    pub status: Status,
    /// Why there is no answer.
    pub reason: Option<String>,
    /// With [`Status::Inconsistent`]: what is contradicted and the largest residuals (what
    /// [`Outcome::reason`] says in words).
    pub contradiction: Option<Contradiction>,
    /// The best combination found.
    pub best: Option<Found>,
    /// Every combination of counts, in the order of the candidates.
    pub tried: Vec<TriedCounts>,
    /// Each scene vehicle's separation velocities from its scene alone, per count of turns.
    pub estimates: Vec<Estimate>,
    /// Run-outs simulated.
    pub runouts: usize,
    /// Impact fits solved.
    pub fits: usize,
    /// The refinements' work ([`crate::Settings::refine_work`]): run-out right-hand side
    /// evaluations and the impact fits' equivalents.
    pub work: u64,
    /// The scenes were searched a second time, each count also from a scatter of separation
    /// states ([`pim_runout::EstimateSettings::scatter`]), because the first search's answer
    /// fit worse than the median of its chi-square or was refused; the better answer is kept.
    pub scattered: bool,
    /// The work of the first search alone ([`Outcome::work`] without the second's).
    pub first_work: u64,
}

impl Outcome {
    /// The index in [`Outcome::tried`] of the best combination: the one entry of its counts
    /// of turns (never told apart by comparing costs).
    pub fn best_index(&self) -> Option<usize> {
        let counts = self.best.as_ref()?.counts();
        self.tried.iter().position(|t| t.counts == counts)
    }

    /// The combinations refined to a cost within `margin` of the best (the best among them):
    /// with more than one, the evidence does not decide between their counts of turns.
    pub fn within(&self, margin: f64) -> Vec<&TriedCounts> {
        let Some(best) = &self.best else {
            return Vec::new();
        };
        self.tried
            .iter()
            .filter(|t| matches!(t.state, Tried::Refined { cost, .. } if cost <= best.chi_square + margin))
            .collect()
    }
}

/// A piece of evidence against a reconstruction: the contact problem's, or a scene's.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum EvidenceTerm {
    /// A piece of the contact problem's evidence.
    Contact(ContactTerm),
    /// A residual of a vehicle's scene (`rest.x`, `mark 1`, ...).
    Scene {
        /// Whose.
        vehicle: VehicleId,
        /// Its name.
        name: String,
    },
    /// A fitted road friction against its stated value (index into
    /// [`Reconstruction::frictions`]).
    Friction(usize),
}

/// Why the best reconstruction found contradicts the evidence.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Contradiction {
    /// What is contradicted, in words.
    pub statement: String,
    /// The three largest residuals, in sigmas, the largest first.
    pub largest: Vec<(EvidenceTerm, f64)>,
}

impl Contradiction {
    /// The statement and the largest residuals, each named by `name`.
    pub fn describe(&self, name: impl Fn(&EvidenceTerm) -> String) -> String {
        let list: Vec<String> = self
            .largest
            .iter()
            .map(|(t, z)| format!("{} {z:+.1} sigma", name(t)))
            .collect();
        format!(
            "{}; the largest residuals: {}",
            self.statement,
            list.join(", ")
        )
    }

    /// Names without the case's labels ([`ContactTerm::name`], `vehicleN rest.x`).
    pub fn default_name(r: &Reconstruction, t: &EvidenceTerm) -> String {
        match t {
            EvidenceTerm::Contact(crate::ContactTerm::Nonlinear(i)) => r
                .nonlinear
                .0
                .get(*i)
                .map_or_else(|| format!("nonlinear evidence {}", i + 1), |t| t.name()),
            EvidenceTerm::Contact(c) => c.name(&r.contact),
            EvidenceTerm::Scene { vehicle, name } => format!("{vehicle} {name}"),
            EvidenceTerm::Friction(g) => r
                .frictions
                .get(*g)
                .map_or_else(|| format!("friction {}", g + 1), |f| f.name.clone()),
        }
    }
}

/// Every piece of evidence against a found reconstruction and its residual in standard
/// deviations, in a fixed order: the contact evidence, the fitted frictions, each scene's
/// residuals. Their squares sum to its chi-square.
pub(crate) fn evidence_z(r: &Reconstruction, f: &Found) -> Vec<(EvidenceTerm, f64)> {
    let u = pim_fit::state_vector(&f.solution.initial, &f.solution.separation);
    let mut terms: Vec<(EvidenceTerm, f64)> = r
        .contact_residuals(&u)
        .iter()
        .map(|c| (EvidenceTerm::Contact(c.term), c.residual / r.sigma_of(c)))
        .collect();
    for (g, z) in r.friction_z(&f.frictions).into_iter().enumerate() {
        terms.push((EvidenceTerm::Friction(g), z));
    }
    for s in &f.scene {
        for x in &s.residuals {
            terms.push((
                EvidenceTerm::Scene {
                    vehicle: s.vehicle,
                    name: x.name.clone(),
                },
                x.value / x.sigma,
            ));
        }
    }
    terms
}

/// Why the found reconstruction contradicts the evidence, if it does: the chi-square's
/// probability, or the largest residual with no degrees of freedom left, and the largest terms.
pub(crate) fn contradiction(r: &Reconstruction, f: &Found) -> Option<Contradiction> {
    let mut terms = evidence_z(r, f);
    terms.sort_by(|a, b| b.1.abs().total_cmp(&a.1.abs()));
    let p = pim_fit::ChiSquare::p_value_of(f.degrees_of_freedom, f.chi_square)?;
    if p >= INCONSISTENT_P {
        return None;
    }
    let judged = if f.degrees_of_freedom > 0 {
        String::new()
    } else {
        " (no degrees of freedom left: judged as one)".to_string()
    };
    let statement = format!(
        "the best reconstruction found has a chi-square of {:.1} with {} degrees of \
         freedom{judged}, p {}: none of the impacts and run-outs searched reaches this \
         evidence within its standard deviations",
        f.chi_square,
        f.degrees_of_freedom,
        if p < 1e-300 {
            "below 1e-300".to_string()
        } else {
            format!("= {p:.1e}")
        }
    );
    terms.truncate(3);
    Some(Contradiction {
        statement,
        largest: terms,
    })
}

/// The scene fit of a point, for the outcome.
fn scene_fits(r: &Reconstruction, p: &Point) -> Vec<SceneFit> {
    p.scene
        .iter()
        .map(|l| SceneFit {
            vehicle: r.scene[l.vehicle].id,
            turns: r.scene[l.vehicle]
                .evidence
                .rest
                .and_then(|x| x.heading)
                .map(|_| l.turns),
            chi_square: l.lin.cost,
            residuals: l.lin.residuals.clone(),
            runout: l.lin.runout.clone(),
            friction: l.mu,
            zones: l.zone_mus.clone(),
            rolling_resistance: l.rolling_resistance,
        })
        .collect()
}
