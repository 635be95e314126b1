//! Output records (JSON) and human-readable tables of `pim solve` and `pim sensitivity`.

use pim_core::{ImpactReport, SensitivityStudy, Velocities};
use serde::Serialize;
use std::fmt::Write as _;

/// One vehicle's velocity in the output.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct VelocityOut {
    /// m/s.
    pub vx: f64,
    /// m/s.
    pub vy: f64,
    /// rad/s.
    pub omega: f64,
}

/// Both vehicles' velocities.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct StateOut {
    /// Vehicle 1.
    pub vehicle1: VelocityOut,
    /// Vehicle 2.
    pub vehicle2: VelocityOut,
}

impl StateOut {
    /// `(v1x, v1y, w1, v2x, v2y, w2)`.
    pub fn to_array(&self) -> [f64; 6] {
        let (a, b) = (&self.vehicle1, &self.vehicle2);
        [a.vx, a.vy, a.omega, b.vx, b.vy, b.omega]
    }
}

impl From<&Velocities> for StateOut {
    fn from(v: &Velocities) -> Self {
        let f = |x: &pim_core::VehicleVelocity| VelocityOut {
            vx: x.vx,
            vy: x.vy,
            omega: x.omega,
        };
        StateOut {
            vehicle1: f(&v.vehicle1),
            vehicle2: f(&v.vehicle2),
        }
    }
}

/// Delta-V magnitudes, m/s.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct DeltaVOut {
    /// |V1 - v1|.
    pub vehicle1: f64,
    /// |V2 - v2|.
    pub vehicle2: f64,
}

/// Energy balance.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct EnergyOut {
    /// J.
    pub initial: f64,
    /// J.
    #[serde(rename = "final")]
    pub final_: f64,
    /// Percent.
    pub loss_percent: f64,
}

/// The JSON record of one forward or backward solve.
#[derive(Debug, Clone, Serialize)]
pub struct SolveOut {
    /// `forward` or `backward`.
    pub direction: &'static str,
    /// Coefficients used.
    pub coefficients: pim_core::Coefficients,
    /// Moment form and tangential condition.
    pub options: pim_core::SolveOptions,
    /// Velocities at contact.
    pub initial: StateOut,
    /// Velocities at separation.
    #[serde(rename = "final")]
    pub final_: StateOut,
    /// Delta-V magnitudes.
    pub delta_v: DeltaVOut,
    /// Delta-V components and directions per vehicle.
    pub delta_v_detail: [pim_core::DeltaV; 2],
    /// Energy balance.
    pub energy: EnergyOut,
    /// Impulses on vehicle 1.
    pub impulse: pim_core::Impulse,
    /// Relative velocities at C.
    pub relative_velocity: pim_core::RelativeVelocity,
    /// Material-point velocities at C.
    pub contact_points: pim_core::ContactPoints,
    /// Signed critical impulse ratio (null when undefined).
    pub mu_max: Option<f64>,
    /// mu / mu_max.
    pub mu_ratio: Option<f64>,
    /// sliding, sticking or reversed.
    pub tangential: pim_core::TangentialOutcome,
    /// Still sliding at separation.
    pub sliding: bool,
    /// Physically admissible.
    pub admissible: bool,
    /// Why not, when not admissible.
    pub reasons: Vec<String>,
    /// Largest relative equation residual.
    pub max_residual: f64,
}

impl SolveOut {
    /// Builds the record from a pim-core report.
    pub fn new(impact: &pim_core::Impact, r: &ImpactReport, forward: bool) -> Self {
        SolveOut {
            direction: if forward { "forward" } else { "backward" },
            coefficients: r.coefficients,
            options: r.options,
            initial: (&r.initial).into(),
            final_: (&r.separation).into(),
            delta_v: DeltaVOut {
                vehicle1: r.delta_v[0].magnitude,
                vehicle2: r.delta_v[1].magnitude,
            },
            delta_v_detail: r.delta_v,
            energy: EnergyOut {
                initial: r.energy.initial,
                final_: r.energy.final_,
                loss_percent: r.energy.loss_percent,
            },
            impulse: r.impulse,
            relative_velocity: r.relative,
            contact_points: r.contact_points,
            mu_max: r.mu_max,
            mu_ratio: r.mu_ratio,
            tangential: r.tangential,
            sliding: r.sliding,
            admissible: r.admissibility.admissible,
            reasons: r.inadmissibility_reasons(),
            max_residual: r.residuals(impact).max_relative(),
        }
    }
}

/// One combination of a sensitivity study.
#[derive(Debug, Clone, Serialize)]
pub struct SensitivityCaseOut {
    /// Levels of e, mu, em (`low`, `high`, `nominal`).
    pub levels: [pim_core::Level; 3],
    /// The full solve record (its `coefficients` are this combination's).
    #[serde(flatten)]
    pub solve: SolveOut,
}

/// The JSON of `pim sensitivity`.
#[derive(Debug, Clone, Serialize)]
pub struct SensitivityOut {
    /// p, percent.
    pub percent: f64,
    /// The nominal solve.
    pub nominal: SolveOut,
    /// Every combination.
    pub combinations: Vec<SensitivityCaseOut>,
    /// Averages per coefficient level.
    pub averages: Vec<pim_core::LevelAverage>,
}

impl SensitivityOut {
    /// Builds the record.
    pub fn new(impact: &pim_core::Impact, s: &SensitivityStudy) -> Self {
        SensitivityOut {
            percent: s.percent,
            nominal: SolveOut::new(impact, &s.nominal, true),
            combinations: s
                .cases
                .iter()
                .map(|c| SensitivityCaseOut {
                    levels: c.levels,
                    solve: SolveOut::new(impact, &c.report, true),
                })
                .collect(),
            averages: s.averages.clone(),
        }
    }
}

fn opt(x: Option<f64>, prec: usize) -> String {
    x.map_or_else(|| "undefined".to_string(), |v| format!("{v:.prec$}"))
}

/// The human-readable table of one solve.
pub fn solve_table(
    title: &str,
    impact: &pim_core::Impact,
    r: &ImpactReport,
    forward: bool,
) -> String {
    let mut s = String::new();
    let c = &r.coefficients;
    let _ = writeln!(s, "{title}");
    let _ = writeln!(
        s,
        "solved {}: e = {}, mu = {}, em = {}; moment equation {:?}, tangential condition {:?}",
        if forward { "forwards" } else { "backwards" },
        c.e,
        c.mu,
        c.em,
        r.options.moment_form,
        r.options.tangential
    );
    let _ = writeln!(s);
    let _ = writeln!(
        s,
        "                     vx [m/s]   vy [m/s]  omega [rad/s]   |dV| [m/s]  dir [deg]"
    );
    for (k, name) in ["vehicle1", "vehicle2"].iter().enumerate() {
        let i = r.initial.vehicle(pim_core::VehicleId::from_index(k));
        let f = r.separation.vehicle(pim_core::VehicleId::from_index(k));
        let dv = &r.delta_v[k];
        let _ = writeln!(
            s,
            "{name}  initial  {:>9.3}  {:>9.3}  {:>13.3}",
            i.vx, i.vy, i.omega
        );
        let _ = writeln!(
            s,
            "{name}  final    {:>9.3}  {:>9.3}  {:>13.3}   {:>10.3}  {:>9.1}",
            f.vx, f.vy, f.omega, dv.magnitude, dv.direction
        );
    }
    let _ = writeln!(s);
    let e = &r.energy;
    let _ = writeln!(
        s,
        "kinetic energy      {:.0} J at contact, {:.0} J at separation: loss {:.2} %",
        e.initial, e.final_, e.loss_percent
    );
    let p = &r.impulse;
    let _ = writeln!(
        s,
        "impulse on veh. 1   Px {:.1}, Py {:.1}, Pn {:.1}, Pt {:.1} N s; moment M {:.1} N m s",
        p.px, p.py, p.normal, p.tangential, p.moment
    );
    let rv = &r.relative;
    let _ = writeln!(
        s,
        "relative vel. at C  vn {:.3} -> Vn {:.3} m/s, vt {:.3} -> Vt {:.3} m/s",
        rv.normal_initial, rv.normal_final, rv.tangential_initial, rv.tangential_final
    );
    let _ = writeln!(
        s,
        "friction            mu_max {} (signed), mu/mu_max {}, {:?}",
        opt(r.mu_max, 4),
        opt(r.mu_ratio, 4),
        r.tangential
    );
    let _ = writeln!(
        s,
        "equation residual   {:.1e} (largest, relative to the size of its terms)",
        r.residuals(impact).max_relative()
    );
    if r.admissibility.admissible {
        let _ = writeln!(s, "admissible          yes");
    } else {
        let _ = writeln!(s, "admissible          NO");
        for reason in &r.inadmissibility_reasons() {
            let _ = writeln!(s, "  - {reason}");
        }
    }
    s
}

/// The human-readable table of a sensitivity study (as Brach 1983 Tables 4-6).
pub fn sensitivity_table(title: &str, st: &SensitivityStudy) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "{title}\nsensitivity: each coefficient x (1 -/+ {}%); em = 1 is not varied\n",
        st.percent
    );
    let _ = writeln!(
        s,
        "      e       mu       em |  V1x     V1y     W1   |dV1| |  V2x     V2y     W2   |dV2| | loss % | adm."
    );
    for c in &st.cases {
        let r = &c.report;
        let a = &r.separation.vehicle1;
        let b = &r.separation.vehicle2;
        let _ = writeln!(
            s,
            "{:>7.4} {:>8.4} {:>8.4} | {:>6.2} {:>6.2} {:>6.2} {:>6.2} | {:>6.2} {:>6.2} {:>6.2} {:>6.2} | {:>6.2} | {}",
            c.coefficients.e,
            c.coefficients.mu,
            c.coefficients.em,
            a.vx,
            a.vy,
            a.omega,
            r.delta_v[0].magnitude,
            b.vx,
            b.vy,
            b.omega,
            r.delta_v[1].magnitude,
            r.energy.loss_percent,
            if r.admissibility.admissible { "yes" } else { "NO" }
        );
    }
    let _ = writeln!(s, "\naverage effect of each coefficient level");
    let _ = writeln!(
        s,
        "coef  level      value | |dV1| m/s |dV2| m/s |dW1| rad/s |dW2| rad/s | loss %"
    );
    for a in &st.averages {
        let _ = writeln!(
            s,
            "{:<5} {:<6} {:>9.4} | {:>9.3} {:>9.3} {:>11.3} {:>11.3} | {:>6.2}",
            format!("{:?}", a.coefficient).to_lowercase(),
            format!("{:?}", a.level).to_lowercase(),
            a.value,
            a.delta_v1,
            a.delta_v2,
            a.delta_omega1,
            a.delta_omega2,
            a.energy_loss_percent
        );
    }
    s
}

/// One fitted branch as a flat record (the JSON of `pim fit` and of `pim batch`).
#[derive(Debug, Clone, Serialize)]
pub struct BranchRecord {
    /// `free` (em in [-1, 0]) or `zero` (em = 1).
    pub moment: pim_fit::MomentBranch,
    /// `optimal`, `infeasible` or `limit_reached`.
    pub status: pim_fit::Status,
    /// Words: why not optimal, or a caveat.
    pub reason: Option<pim_fit::Reason>,
    /// Restitution.
    pub e: Option<f64>,
    /// Friction ratio of equation 5 (mu_max when sticking).
    pub mu: Option<f64>,
    /// Moment restitution.
    pub em: Option<f64>,
    /// Weighted sum of squares.
    pub cost: Option<f64>,
    /// Fitted contact velocities.
    pub initial: Option<StateOut>,
    /// Fitted separation velocities.
    #[serde(rename = "final")]
    pub final_: Option<StateOut>,
    /// Largest relative residual of the six equations.
    pub max_residual: Option<f64>,
    /// Kinetic energy loss, percent.
    pub energy_loss_percent: Option<f64>,
    /// Signed critical friction of the fitted contact state.
    pub mu_max: Option<f64>,
    /// mu / mu_max.
    pub mu_ratio: Option<f64>,
    /// True when the vehicles stick (mu = mu_max).
    pub sticking: Option<bool>,
    /// Delta-V magnitudes, m/s.
    pub delta_v: Option<DeltaVOut>,
    /// Impulses on vehicle 1.
    pub impulse: Option<pim_core::Impulse>,
    /// Constraints active at the optimum.
    pub active_constraints: Vec<pim_fit::ActiveConstraint>,
    /// Velocity components the data leave undetermined.
    pub undetermined: Vec<pim_fit::Component>,
    /// Physically admissible (pim-core's own check).
    pub admissible: Option<bool>,
    /// Identifiability ranges.
    pub identifiability: Vec<pim_fit::Identifiability>,
    /// How the optimum was established.
    pub certificate: pim_fit::Certificate,
}

impl BranchRecord {
    /// Flattens a branch report.
    pub fn new(b: &pim_fit::BranchReport) -> Self {
        let s = b.solution.as_ref();
        BranchRecord {
            moment: b.moment,
            status: b.status,
            reason: b.reason.clone(),
            e: s.map(|s| s.e),
            mu: s.map(|s| s.mu),
            em: s.map(|s| s.em),
            cost: s.map(|s| s.cost),
            initial: s.map(|s| (&s.initial).into()),
            final_: s.map(|s| (&s.separation).into()),
            max_residual: s.map(|s| s.max_residual),
            energy_loss_percent: s.map(|s| s.energy_loss_percent),
            mu_max: s.and_then(|s| s.mu_max),
            mu_ratio: s.and_then(|s| s.mu_ratio),
            sticking: s.map(|s| s.sticking),
            delta_v: s.map(|s| DeltaVOut {
                vehicle1: s.delta_v[0].magnitude,
                vehicle2: s.delta_v[1].magnitude,
            }),
            impulse: s.map(|s| s.impulse),
            active_constraints: s.map_or_else(Vec::new, |s| s.active_constraints.clone()),
            undetermined: s.map_or_else(Vec::new, |s| s.undetermined.clone()),
            admissible: s.map(|s| s.admissible),
            identifiability: b.identifiability.clone(),
            certificate: b.certificate.clone(),
        }
    }
}

/// The JSON of `pim fit`.
#[derive(Debug, Clone, Serialize)]
pub struct FitOut {
    /// `q1`, `q2`, `q3` or `custom`.
    pub cost_function: String,
    /// One record per branch.
    pub branches: Vec<BranchRecord>,
    /// The optimal branch with the lower cost.
    pub best: Option<pim_fit::MomentBranch>,
    /// Remarks on the whole fit.
    pub notes: Vec<String>,
}

fn opt3(x: Option<f64>) -> String {
    x.map_or_else(|| "-".to_string(), |v| format!("{v:.3}"))
}

/// The human-readable table of a fit.
pub fn fit_table(title: &str, cost: &str, r: &pim_fit::FitReport) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{title}\nfit with cost function {cost}\n");
    for b in &r.branches {
        let _ = writeln!(
            s,
            "branch {:<4} ({}): {:?}{}",
            b.moment.name(),
            if b.moment == pim_fit::MomentBranch::Zero {
                "em = 1"
            } else {
                "em in [-1, 0]"
            },
            b.status,
            if Some(b.moment) == r.best {
                "   <- best"
            } else {
                ""
            }
        );
        if let Some(reason) = &b.reason {
            let _ = writeln!(s, "  {reason}");
        }
        if let Some(sol) = &b.solution {
            let _ = writeln!(
                s,
                "  e = {:.4}   mu = {:+.4}   em = {:+.4}   mu/mu_max = {}   {}",
                sol.e,
                sol.mu,
                sol.em,
                opt3(sol.mu_ratio),
                if sol.sticking { "sticking" } else { "sliding" }
            );
            let _ = writeln!(
                s,
                "  cost {:.5}   energy loss {:.2} %   |dV| {:.3} / {:.3} m/s   residual {:.1e}",
                sol.cost,
                sol.energy_loss_percent,
                sol.delta_v[0].magnitude,
                sol.delta_v[1].magnitude,
                sol.max_residual
            );
            let _ = writeln!(s, "                 vx [m/s]   vy [m/s]  omega [rad/s]");
            for (name, st) in [("initial", &sol.initial), ("final", &sol.separation)] {
                for (k, v) in [&st.vehicle1, &st.vehicle2].iter().enumerate() {
                    let _ = writeln!(
                        s,
                        "  {name:<7} veh{} {:>9.3}  {:>9.3}  {:>13.3}",
                        k + 1,
                        v.vx,
                        v.vy,
                        v.omega
                    );
                }
            }
            if !sol.active_constraints.is_empty() {
                let active: Vec<String> = sol
                    .active_constraints
                    .iter()
                    .map(|a| a.to_string())
                    .collect();
                let _ = writeln!(s, "  active: {}", active.join("; "));
            }
            for i in &b.identifiability {
                if !i.identifiable {
                    let _ = writeln!(
                        s,
                        "  not pinned down: {} within {:.0} % of the optimum for {:.3} .. {:.3}{}",
                        i.coefficient,
                        i.tolerance * 100.0,
                        i.low,
                        i.high,
                        if i.open_ended { " and beyond" } else { "" }
                    );
                }
            }
        }
        let c = &b.certificate;
        let _ = writeln!(
            s,
            "  search: {} grid points, {} inner solves ({} exact, {} by QP), {}/{} refinements agree\n",
            c.grid_points, c.evaluations, c.exact_solves, c.qp_solves, c.refinements_agreeing, c.refinements
        );
    }
    for n in &r.notes {
        let _ = writeln!(s, "note: {n}");
    }
    s
}
