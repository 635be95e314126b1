//! Human-readable tables of `pim solve`, `pim sensitivity` and `pim fit`.

use pim_core::ImpactReport;
use pim_core::SensitivityStudy;
use std::fmt::Write as _;

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
