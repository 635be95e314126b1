//! Human-readable tables of `pim solve`, `pim sensitivity` and `pim fit`.

use crate::geometry_lines::geometry_block;
use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_core::ImpactReport;
use pim_core::SensitivityStudy;
use std::fmt::Write as _;

/// `x` to `prec` decimals, without a minus sign on a value that rounds to zero.
pub fn num(x: f64, prec: usize) -> String {
    let half = 0.5 * 10f64.powi(-(prec as i32));
    let x = if x.abs() < half { 0.0 } else { x };
    format!("{x:.prec$}")
}

fn opt(x: Option<f64>, prec: usize) -> String {
    x.map_or_else(|| "undefined".to_string(), |v| format!("{v:.prec$}"))
}

/// Words for what happens along the crush surface in the model that was solved, and where
/// the direction of friction comes from when the contact point does not slide at contact.
/// `model` is the second model's record (tangential restitution with a friction limit, or
/// IMPC's), `None` for PIM.
pub fn tangential_words(
    r: &ImpactReport,
    model: Option<&pim_documents::records::ModelOut>,
) -> String {
    let tol = pim_core::REPORT_TOL;
    let rv = &r.relative;
    let scale = rv.normal_initial.abs().max(1.0);
    let slides_at_contact = rv.tangential_initial.abs() > tol * scale;
    let slides_at_separation = rv.tangential_final.abs() > tol * scale;
    if let Some(m) = model {
        let et = m.coefficients.get("et").copied().unwrap_or(0.0);
        return match m.mode {
            _ if !slides_at_contact && !slides_at_separation => {
                "no sliding at all: the contact point does not slide at contact, and the \
                 impulse makes it slide none by separation"
                    .to_string()
            }
            pim_core::ContactMode::Stick if et.abs() <= tol => {
                "sticks: the sliding at C ends by separation (Vt = et vt = 0, within the \
                 friction limit)"
                    .to_string()
            }
            pim_core::ContactMode::Stick => format!(
                "sticks at the tangential restitution: the sliding continues at et = {} times \
                 the initial tangential velocity (Vt = et vt), within the friction limit; it \
                 does not end",
                num(et, 3)
            ),
            pim_core::ContactMode::Slide => {
                "slides throughout: sticking would need more than the friction limit, so the \
                 impulse is at the limit (|Pt| = friction |Pn|) and the vehicles still slide at \
                 separation"
                    .to_string()
            }
        };
    }
    if r.options.tangential == pim_core::TangentialCondition::NoSlip {
        let no_coupling = r.mu_max.is_some_and(|m| m.abs() <= tol);
        return if !slides_at_contact && no_coupling {
            "no sliding at all: the contact point does not slide at contact and the normal \
             impulse causes none (no-slip condition 5a, mu_max = 0)"
                .to_string()
        } else {
            "the no-slip condition (5a) ends the sliding by separation (Vt = 0); the friction \
             that takes is mu_max"
                .to_string()
        };
    }
    let outcome = match r.tangential {
        pim_core::TangentialOutcome::Sliding => "still sliding at separation (|mu| < |mu_max|)",
        pim_core::TangentialOutcome::Sticking => "sliding ends by separation (mu = mu_max)",
        pim_core::TangentialOutcome::Reversed => {
            "sliding reversed (mu beyond mu_max: not physical)"
        }
    };
    let no_coupling = r.mu_max.is_some_and(|m| m.abs() <= tol);
    match r.friction_basis {
        pim_core::FrictionBasis::Sliding => outcome.to_string(),
        pim_core::FrictionBasis::NoSlipImpulse if no_coupling => {
            "no sliding at all: the contact point does not slide at contact (vt = 0) and the \
             normal impulse causes none (mu_max = 0): no tangential impulse is admissible"
                .to_string()
        }
        pim_core::FrictionBasis::NoSlipImpulse => format!(
            "{outcome}; no sliding at contact (vt = 0), so friction acts against the sliding \
             that the normal impulse causes (the side of the no-slip impulse)"
        ),
    }
}

/// The line that says which frame a table's signs are in.
pub fn frame_line(frame: Convention) -> &'static str {
    if frame.mirrors() {
        "frame: SAE J670 (x forward, y to the right, headings, angles and yaw rates clockwise)"
    } else {
        "frame: x, y with y to the left of x; headings, angles and yaw rates counter-clockwise"
    }
}

/// The reconstructionist's rows per vehicle, in the unit system `u` and the frame `frame`
/// (the values already in it, see `ImpactReport::mirrored`): label and the two vehicles'
/// values (speeds, delta-V in the vehicle's axes, PDOF, yaw-rate change).
pub fn vehicle_rows(
    v: &[pim_core::VehicleResult; 2],
    u: UnitSystem,
    frame: Convention,
) -> Vec<(String, [String; 2])> {
    let (sp, yr) = (u.speed_label(), u.yaw_rate_label());
    let (heading, lateral) = if frame.mirrors() {
        ("heading of the nose [deg, clockwise]", "right")
    } else {
        ("heading of the nose [deg]", "left")
    };
    type Cell<'a> = &'a dyn Fn(&pim_core::VehicleResult) -> String;
    let rows: [(String, Cell); 9] = [
        (heading.into(), &|r| num(r.heading, 1)),
        (format!("speed at contact [{sp}]"), &|r| {
            num(u.speed(r.speed_initial), 2)
        }),
        (format!("speed at separation [{sp}]"), &|r| {
            num(u.speed(r.speed_final), 2)
        }),
        (format!("delta-V [{sp}]"), &|r| num(u.speed(r.delta_v), 2)),
        (format!("  longitudinal, forward + [{sp}]"), &|r| {
            num(u.speed(r.delta_v_longitudinal), 2)
        }),
        (format!("  lateral, {lateral} + [{sp}]"), &|r| {
            num(u.speed(r.delta_v_lateral), 2)
        }),
        ("PDOF, clockwise from nose [deg]".into(), &|r| {
            num(r.pdof, 0)
        }),
        ("PDOF as a clock direction".into(), &|r| {
            format!("{} o'clock", r.clock)
        }),
        (format!("yaw-rate change [{yr}]"), &|r| {
            num(u.yaw_rate(r.yaw_rate_change), 3)
        }),
    ];
    rows.into_iter()
        .map(|(label, f)| (label, [f(&v[0]), f(&v[1])]))
        .collect()
}

/// The reconstructionist's block of a table (see [`vehicle_rows`]).
pub fn vehicle_block(
    s: &mut String,
    v: &[pim_core::VehicleResult; 2],
    u: UnitSystem,
    frame: Convention,
) {
    let _ = writeln!(s, "{:<34} {:>12} {:>12}", "", "vehicle1", "vehicle2");
    for (label, [a, b]) in vehicle_rows(v, u, frame) {
        let _ = writeln!(s, "{label:<34} {a:>12} {b:>12}");
    }
}

/// The human-readable table of one solve, in the unit system `u` and the frame `frame` (`r`
/// already in it).
pub fn solve_table(
    title: &str,
    impact: &pim_core::Impact,
    r: &ImpactReport,
    model: Option<&pim_documents::records::ModelOut>,
    forward: bool,
    u: UnitSystem,
    frame: Convention,
) -> String {
    let mut s = String::new();
    let c = &r.coefficients;
    let _ = writeln!(s, "{title}");
    let _ = writeln!(
        s,
        "solved {}: e = {}, mu = {}, em = {} ({} moment equation, {})",
        if forward { "forwards" } else { "backwards" },
        c.e,
        c.mu,
        c.em,
        match r.options.moment_form {
            pim_core::MomentForm::Corrected => "corrected",
            pim_core::MomentForm::Brach1983 => "1983",
        },
        match r.options.tangential {
            pim_core::TangentialCondition::Sliding => "friction ratio mu (equation 5)",
            pim_core::TangentialCondition::NoSlip => "no slip at separation (equation 5a)",
        }
    );
    if impact.is_barrier() {
        let _ = writeln!(
            s,
            "vehicle 2 is a fixed rigid barrier: it does not move, takes the momentum, and the \
             energy is vehicle 1's"
        );
    }
    let _ = writeln!(s, "{}", frame_line(frame));
    let _ = writeln!(s);
    velocity_rows(&mut s, r, u);
    let sp = u.speed_label();
    let _ = writeln!(s);
    vehicle_block(&mut s, &r.vehicles, u, frame);
    let _ = writeln!(s);
    let e = &r.energy;
    let el = u.energy_label();
    let _ = writeln!(
        s,
        "kinetic energy      {:.0} {el} at contact, {:.0} {el} at separation: loss {:.0} {el} \
         ({:.2} %)",
        u.energy(e.initial),
        u.energy(e.final_),
        u.energy(e.loss),
        e.loss_percent
    );
    let p = &r.impulse;
    let (pl, ll) = (u.impulse_label(), u.length_label());
    let _ = writeln!(
        s,
        "impulse on veh. 1   Px {}, Py {}, Pn {}, Pt {} {pl}; moment M {} {pl} {ll}",
        num(u.impulse(p.px), 1),
        num(u.impulse(p.py), 1),
        num(u.impulse(p.normal), 1),
        num(u.impulse(p.tangential), 1),
        num(u.length(u.impulse(p.moment)), 1)
    );
    let rv = &r.relative;
    let _ = writeln!(
        s,
        "relative vel. at C  vn {} -> Vn {} {sp}, vt {} -> Vt {} {sp}",
        num(u.speed(rv.normal_initial), 3),
        num(u.speed(rv.normal_final), 3),
        num(u.speed(rv.tangential_initial), 3),
        num(u.speed(rv.tangential_final), 3)
    );
    let _ = writeln!(
        s,
        "friction            mu_max {} (signed), mu/mu_max {}: {}",
        opt(r.mu_max, 4),
        opt(r.mu_ratio, 4),
        tangential_words(r, model)
    );
    let _ = writeln!(
        s,
        "equation residual   {:.1e} (largest, relative to the size of its terms)",
        // The residual of the solution as solved (mirroring twice is the identity).
        frame.shown(r).residuals(impact).max_relative()
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

/// The velocities at contact and at separation, a row per vehicle and phase.
fn velocity_rows(s: &mut String, r: &ImpactReport, u: UnitSystem) {
    let (sp, yr) = (u.speed_label(), u.yaw_rate_label());
    let _ = writeln!(
        s,
        "{:<21}{:>10}  {:>9}  {:>13}",
        "",
        format!("vx [{sp}]"),
        format!("vy [{sp}]"),
        format!("omega [{yr}]")
    );
    for (k, name) in ["vehicle1", "vehicle2"].iter().enumerate() {
        let id = pim_core::VehicleId::from_index(k);
        for (when, v) in [
            ("contact   ", r.initial.vehicle(id)),
            ("separation", r.separation.vehicle(id)),
        ] {
            let _ = writeln!(
                s,
                "{name}  {when} {:>9}  {:>9}  {:>13}",
                num(u.speed(v.vx), 3),
                num(u.speed(v.vy), 3),
                num(u.yaw_rate(v.omega), 3)
            );
        }
    }
}

/// The human-readable table of a sensitivity study (as Brach 1983 Tables 4-6).
pub fn sensitivity_table(
    title: &str,
    st: &SensitivityStudy,
    u: UnitSystem,
    frame: Convention,
) -> String {
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
    let (v, w) = (|x: f64| u.speed(x), |x: f64| u.yaw_rate(x));
    for c in &st.cases {
        let r = &frame.shown(&c.report);
        let a = &r.separation.vehicle1;
        let b = &r.separation.vehicle2;
        let _ = writeln!(
            s,
            "{:>7.4} {:>8.4} {:>8.4} | {:>6.2} {:>6.2} {:>6.2} {:>6.2} | {:>6.2} {:>6.2} {:>6.2} {:>6.2} | {:>6.2} | {}",
            c.coefficients.e,
            c.coefficients.mu,
            c.coefficients.em,
            v(a.vx),
            v(a.vy),
            w(a.omega),
            v(r.delta_v[0].magnitude),
            v(b.vx),
            v(b.vy),
            w(b.omega),
            v(r.delta_v[1].magnitude),
            r.energy.loss_percent,
            if r.admissibility.admissible { "yes" } else { "NO" }
        );
    }
    if u != UnitSystem::Si || frame.mirrors() {
        let _ = writeln!(
            s,
            "(separation velocities V in {}, yaw rates W in {}; {})",
            u.speed_label(),
            u.yaw_rate_label(),
            frame_line(frame)
        );
    }
    let _ = writeln!(s, "\naverage effect of each coefficient level");
    let _ = writeln!(
        s,
        "coef  level      value | {:>9} {:>9} {:>11} {:>11} | loss %",
        format!("|dV1| {}", u.speed_label()),
        format!("|dV2| {}", u.speed_label()),
        format!("|dW1| {}", u.yaw_rate_label()),
        format!("|dW2| {}", u.yaw_rate_label()),
    );
    for a in &st.averages {
        let _ = writeln!(
            s,
            "{:<5} {:<6} {:>9.4} | {:>9.3} {:>9.3} {:>11.3} {:>11.3} | {:>6.2}",
            format!("{:?}", a.coefficient).to_lowercase(),
            format!("{:?}", a.level).to_lowercase(),
            a.value,
            v(a.delta_v1),
            v(a.delta_v2),
            w(a.delta_omega1),
            w(a.delta_omega2),
            a.energy_loss_percent
        );
    }
    s
}

fn opt3(x: Option<f64>) -> String {
    x.map_or_else(|| "-".to_string(), |v| format!("{v:.3}"))
}

/// The human-readable table of a fit.
pub fn fit_table(
    title: &str,
    cost: &str,
    r: &pim_fit::FitReport,
    u: UnitSystem,
    frame: Convention,
) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "{title}\nfit with cost function {cost}\n");
    for b in &r.branches {
        let tangential = r.model == pim_fit::FitModel::Tangential;
        let _ = writeln!(
            s,
            "{}: {:?}{}",
            if tangential {
                "tangential model (normal and tangential restitution, friction limit, no moment \
                 impulse)"
                    .to_string()
            } else {
                branch_words(b.moment)
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
            if let Some(t) = &sol.tangential {
                tangential_lines(&mut s, sol.e, t);
            } else {
                let _ = writeln!(
                    s,
                    "  e = {:.4}   mu = {:+.4}   em = {:+.4}   mu/mu_max = {}   {}",
                    sol.e,
                    sol.mu,
                    sol.em,
                    opt3(sol.mu_ratio),
                    if sol.sticking { "sticking" } else { "sliding" }
                );
            }
            let _ = writeln!(
                s,
                "  cost {:.5}   energy loss {:.0} {} ({:.2} %)   residual {:.1e}",
                sol.cost,
                u.energy(sol.energy_loss),
                u.energy_label(),
                sol.energy_loss_percent,
                sol.max_residual
            );
            let (initial, separation, vehicles) = in_frame(sol, frame);
            let (sp, yr) = (u.speed_label(), u.yaw_rate_label());
            let _ = writeln!(
                s,
                "{:<19}{:>10}  {:>9}  {:>13}",
                "",
                format!("vx [{sp}]"),
                format!("vy [{sp}]"),
                format!("omega [{yr}]")
            );
            for (name, st) in [("contact", &initial), ("separation", &separation)] {
                for (k, v) in [&st.vehicle1, &st.vehicle2].iter().enumerate() {
                    let _ = writeln!(
                        s,
                        "  {name:<10} veh{} {:>9}  {:>9}  {:>13}",
                        k + 1,
                        num(u.speed(v.vx), 3),
                        num(u.speed(v.vy), 3),
                        num(u.yaw_rate(v.omega), 3)
                    );
                }
            }
            let mut block = String::new();
            vehicle_block(&mut block, &vehicles, u, frame);
            for line in block.lines() {
                let _ = writeln!(s, "  {line}");
            }
            if !sol.active_constraints.is_empty() {
                let active: Vec<String> = sol
                    .active_constraints
                    .iter()
                    .map(|a| a.to_string())
                    .collect();
                let _ = writeln!(s, "  at the end of its range: {}", active.join("; "));
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
        if let Some(g) = &b.geometry {
            geometry_block(&mut s, g, u, b.solution.as_ref().map(|x| x.cost));
        }
        let _ = writeln!(s, "  {}\n", how_found(&b.certificate));
    }
    for n in &r.notes {
        let _ = writeln!(s, "note: {n}");
    }
    let _ = writeln!(s, "{}", frame_line(frame));
    s
}

/// A moment branch in words: `moment impulse free (em in [-1, 0])` or `no moment impulse (em
/// = 1)`, with the name the JSON and `--branch` use.
pub fn branch_words(b: pim_fit::MomentBranch) -> String {
    let em = match b {
        pim_fit::MomentBranch::Free => "em in [-1, 0]",
        pim_fit::MomentBranch::Zero => "em = 1",
    };
    format!("{} ({em}; branch {:?})", branch_short(b), b.name())
}

/// A moment branch in two or three words: `moment impulse free`, `no moment impulse`.
pub fn branch_short(b: pim_fit::MomentBranch) -> &'static str {
    match b {
        pim_fit::MomentBranch::Free => "moment impulse free",
        pim_fit::MomentBranch::Zero => "no moment impulse",
    }
}

/// How a branch's optimum was found, in a sentence a reader can follow.
pub fn how_found(c: &pim_fit::Certificate) -> String {
    let mut s = format!(
        "how found: {}; {} fits of the velocities ({} exact, {} by quadratic programming)",
        c.method.description, c.evaluations, c.exact_solves, c.qp_solves
    );
    if c.grid_points > 0 {
        let _ = write!(s, " over a grid of {} coefficient points", c.grid_points);
    }
    if c.refinements > 0 {
        let _ = write!(
            s,
            "; {} of {} local searches from the best grid points end at the same optimum",
            c.refinements_agreeing, c.refinements
        );
    }
    s
}

/// A fitted solution's velocities and per-vehicle results in the frame `frame` (the fit runs
/// in the natural one; an SAE case reads them mirrored).
pub fn in_frame(
    sol: &pim_fit::Solution,
    frame: Convention,
) -> (
    pim_core::Velocities,
    pim_core::Velocities,
    [pim_core::VehicleResult; 2],
) {
    (
        frame.shown(&sol.initial),
        frame.shown(&sol.separation),
        frame.shown(&sol.vehicles),
    )
}

/// The tangential model's coefficients of a fitted solution, in words.
fn tangential_lines(s: &mut String, e: f64, t: &pim_fit::TangentialFit) {
    match t.mode {
        pim_core::ContactMode::Stick => {
            let _ = writeln!(
                s,
                "  e = {e:.4}   et = {:+.4}   sticking: impulse ratio {:+.4}, so any friction \
                 limit from {:.4} to {:.4} (its bound) gives this answer",
                t.et, t.impulse_ratio, t.friction, t.friction_max
            );
        }
        pim_core::ContactMode::Slide => {
            let _ = writeln!(
                s,
                "  e = {e:.4}   friction = {:.4}   sliding (Routh): sticking would need the \
                 impulse ratio {:+.4}; et is any value that needs more than the limit \
                 (e.g. {:+.4})",
                t.friction, t.stick_ratio, t.et
            );
        }
    }
}

/// The line that names a model other than PIM and says what it did, before PIM's equivalent
/// of its solution.
pub fn model_line(m: &pim_documents::records::ModelOut) -> String {
    let friction = m.coefficients.get("friction").copied().unwrap_or(f64::NAN);
    let how = match m.mode {
        pim_core::ContactMode::Stick => format!(
            "sticks: the restitution is reached within the friction limit (|Pt/Pn| = {:.3} <= \
             {friction})",
            m.stick_ratio.abs(),
        ),
        pim_core::ContactMode::Slide => format!(
            "slides: sticking would need Pt/Pn = {:+.3}, beyond the friction limit {friction}, \
             so Pt/Pn = {:+} (the limit on the sticking impulse's side)",
            m.stick_ratio, m.impulse_ratio
        ),
    };
    let coefficients: Vec<String> = m
        .coefficients
        .iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect();
    format!(
        "model: {} ({}); it {how}; as PIM with the equivalent coefficients:\n",
        m.description,
        coefficients.join(", ")
    )
}

/// One line per search bound a fitted branch rests on, in `u`'s units, saying who set it: the
/// reader learns that the bound, not the data, decides that part of the answer (empty when
/// none).
pub fn bounds_lines(
    records: &[pim_documents::records::BranchRecord],
    best: Option<pim_fit::MomentBranch>,
    u: UnitSystem,
) -> String {
    use pim_documents::records::BoundSource;
    let mut s = String::new();
    for r in records.iter().filter(|r| !r.bounds_reached.is_empty()) {
        let items: Vec<String> = r
            .bounds_reached
            .iter()
            .map(|b| {
                let limit = match b.bound.as_str() {
                    "velocity" => format!("{} {}", num(u.speed(b.limit), 2), u.speed_label()),
                    "yaw_rate" => format!("{} {}", num(u.yaw_rate(b.limit), 2), u.yaw_rate_label()),
                    g if pim_fit::GeometryInput::name_is_length(g) => {
                        format!("{} {}", num(u.length(b.limit), 3), u.length_label())
                    }
                    g if g.ends_with(".phi") || g == "crush_angle" => {
                        format!("{} deg", num(b.limit, 2))
                    }
                    _ => num(b.limit, 3),
                };
                let who = match b.source {
                    BoundSource::Case => "set in [bounds]",
                    BoundSource::Default => "the default, not set for this crash",
                };
                if b.at == b.bound {
                    format!("{} = {limit} ({who})", b.bound)
                } else {
                    format!("{} at [bounds] {} = {limit} ({who})", b.at, b.bound)
                }
            })
            .collect();
        let _ = writeln!(
            s,
            "{}{} rests on a bound (the bound, not the data, ends it): {}",
            branch_short(r.moment),
            if Some(r.moment) == best {
                " (best)"
            } else {
                ""
            },
            items.join("; ")
        );
    }
    s
}
