//! The run-out table of `pim runout` (the text beside its plan view in [`crate::runout`]).

use crate::tables::num;
use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_runout::{Quantity, WheelState};
use pim_studies::runout::{RunoutResult, Source};

/// The wheels in a line: `all rolling`, or each wheel by name.
fn wheels_text(w: &[WheelState; 4]) -> String {
    let one = |s: &WheelState| match s {
        WheelState::Locked => "locked".to_string(),
        WheelState::Rolling => "rolling".to_string(),
        WheelState::Braked(b) => format!("braked {b:.2}"),
    };
    if w.iter().all(|s| s == &w[0]) {
        format!("all {}", one(&w[0]))
    } else {
        pim_runout::WHEEL_NAMES
            .iter()
            .zip(w)
            .map(|(n, s)| format!("{n} {}", one(s)))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// The driver's inputs in a line: `from 0.80 s: braking 0.90 over 0.25 s; from 12.00 m: ...`
/// (steer angles in the frame's sense `s`, degrees; distances in `units`).
fn inputs_text(inputs: &[pim_runout::Input], s: f64, units: UnitSystem) -> String {
    inputs
        .iter()
        .map(|i| {
            let mut parts = Vec::new();
            if i.braking.iter().all(|b| b.is_some() && *b == i.braking[0]) {
                parts.push(format!("braking {:.2}", i.braking[0].unwrap_or(0.0)));
            } else {
                for (b, name) in i.braking.iter().zip(pim_runout::WHEEL_NAMES) {
                    if let Some(b) = b {
                        parts.push(format!("{name} braking {b:.2}"));
                    }
                }
            }
            if let Some([l, r]) = i.steer {
                parts.push(format!(
                    "steer {:.1} / {:.1} deg",
                    s * l.to_degrees(),
                    s * r.to_degrees()
                ));
            }
            let over = if i.build_up > 0.0 {
                format!(" over {:.2} s", i.build_up)
            } else {
                String::new()
            };
            let from = match i.distance {
                Some(d) if i.at > 0.0 => format!(
                    "from {} {} (not before {:.2} s)",
                    num(units.length(d), 2),
                    units.length_label(),
                    i.at
                ),
                Some(d) => format!("from {} {}", num(units.length(d), 2), units.length_label()),
                None => format!("from {:.2} s", i.at),
            };
            format!("{from}: {}{over}", parts.join(", "))
        })
        .collect::<Vec<_>>()
        .join("; ")
}

/// The run-out table in `units` and the case's `frame` (an SAE case: y to the right, angles
/// and yaw rates clockwise).
pub fn runout_table(title: &str, r: &RunoutResult, units: UnitSystem, frame: Convention) -> String {
    let d = &r.document;
    let s = frame.sign();
    let (len, spd, rate) = (
        units.length_label(),
        units.speed_label(),
        units.yaw_rate_label(),
    );
    let l = |x: f64| num(units.length(x), 2);
    let mut t = format!("Run-out: {title}\n");
    if frame.mirrors() {
        t.push_str("frame: SAE (y to the right, headings and yaw rates clockwise)\n");
    }
    // A motion case starts from a stated state, not from a separation.
    let start = if d.source == Source::Start {
        t.push_str(&format!("start: {}\n", d.source.describe()));
        "start     "
    } else {
        t.push_str(&format!("separation velocities: {}\n", d.source.describe()));
        "separation"
    };
    for v in &d.vehicles {
        let sep = &v.separation;
        t.push_str(&format!(
            "\nvehicle {} (friction {:.3}; wheels: {})\n",
            v.vehicle,
            v.friction,
            wheels_text(&v.wheels)
        ));
        t.push_str(&format!(
            "  {start}  x {} {len}, y {} {len}, heading {:.1} deg; vx {} {spd}, vy {} {spd}, \
             yaw rate {} {rate}\n",
            l(sep.x),
            l(s * sep.y),
            s * sep.heading,
            num(units.speed(sep.vx), 3),
            num(units.speed(s * sep.vy), 3),
            num(units.yaw_rate(s * sep.yaw_rate), 3),
        ));
        if let Some(input) = r
            .inputs
            .iter()
            .find(|i| i.id.index() + 1 == v.vehicle as usize)
        {
            if !input.chassis.inputs.is_empty() {
                t.push_str(&format!(
                    "  inputs      {}\n",
                    inputs_text(&input.chassis.inputs, s, units)
                ));
            }
        }
        let ended = match v.end {
            pim_runout::End::Rest => "rest",
            pim_runout::End::TimeLimit if r.duration.is_some() => "after (still moving)",
            pim_runout::End::TimeLimit => "TIME LIMIT (still moving)",
        };
        t.push_str(&format!(
            "  {ended:<10}  x {} {len}, y {} {len}, heading {:.1} deg ({:.1} deg modulo 360)\n",
            l(v.rest.x),
            l(s * v.rest.y),
            s * v.rest.heading,
            (s * v.rest.heading).rem_euclid(360.0),
        ));
        t.push_str(&format!(
            "  run-out     {:.2} s, {} {len} along the path, rotation {:.1} deg (the shortest \
             {:.1} deg and {} full turns), energy {:.1} kJ taken by the tyres\n",
            v.time,
            l(v.distance),
            s * v.rotation,
            pim_core::wrap_degrees(s * v.rotation),
            s as i64 * v.turns,
            v.tyre_work / 1000.0,
        ));
        t.push_str(&evidence_lines(&v.evidence, s, units));
        if let Some(est) = &v.estimate {
            t.push_str(&candidate_lines(est, s, units));
        }
    }
    // A note already printed as a vehicle's NOT DETERMINED line is not printed again.
    let printed: Vec<&String> = d
        .vehicles
        .iter()
        .filter_map(|v| v.estimate.as_ref())
        .flat_map(|e| &e.undetermined)
        .collect();
    for n in d.notes.iter().filter(|n| !printed.contains(n)) {
        t.push_str(&format!("note: {n}\n"));
    }
    t
}

/// The lines of a vehicle's evidence, fitted less given (with the sign `s` of the frame).
fn evidence_lines(
    evidence: &[pim_documents::runout::ResidualOut],
    s: f64,
    units: UnitSystem,
) -> String {
    let len = units.length_label();
    let mut t = String::new();
    if evidence.is_empty() {
        return t;
    }
    t.push_str("  evidence    fitted - given (sd, z):\n");
    for e in evidence {
        let (value, sigma, unit) = if e.what.is_angle() {
            (num(s * e.value, 2), format!("{:.2}", e.sigma), "deg")
        } else if e.what == Quantity::Friction {
            (format!("{:.4}", e.value), format!("{:.4}", e.sigma), "")
        } else if e.what == Quantity::RestY {
            (
                num(units.length(s * e.value), 3),
                num(units.length(e.sigma), 3),
                len,
            )
        } else {
            (
                num(units.length(e.value), 3),
                num(units.length(e.sigma), 3),
                len,
            )
        };
        t.push_str(&format!(
            "    {:<16} {value:>9} {unit} (sd {sigma}, z {})\n",
            e.name,
            num(e.z, 2)
        ));
    }
    t
}

/// The lines of a scene's estimate: its candidates, the first one's standard errors and what
/// the evidence leaves undetermined.
fn candidate_lines(est: &pim_documents::runout::EstimateOut, s: f64, units: UnitSystem) -> String {
    let (spd, rate) = (units.speed_label(), units.yaw_rate_label());
    let mut t = String::new();
    t.push_str(&format!(
        "  candidates  ({} run-outs simulated; cost = sum of squared z)\n",
        est.runouts
    ));
    t.push_str("    turns: full turns added to the shortest rotation to the rest heading\n");
    t.push_str(&format!(
        "    {:>5} {:>11} {:>9} {:>9} {:>9} {:>8}  \n",
        "turns",
        "cost",
        format!("vx {spd}"),
        format!("vy {spd}"),
        format!("yaw {rate}"),
        "friction"
    ));
    for c in &est.candidates {
        let turns = c.turns.map_or("-".into(), |k| (s as i64 * k).to_string());
        t.push_str(&format!(
            "    {turns:>5} {:>11.3e} {:>9} {:>9} {:>9} {:>8.3}  {}{}\n",
            c.cost,
            num(units.speed(c.separation.vx), 3),
            num(units.speed(s * c.separation.vy), 3),
            num(units.yaw_rate(s * c.separation.yaw_rate), 3),
            c.friction,
            if c.consistent {
                "consistent"
            } else if c.plausible {
                "not excluded"
            } else {
                ""
            },
            c.reason
                .as_ref()
                .map_or(String::new(), |r| format!(" ({r})"))
        ));
    }
    if let Some(best) = est.candidates.first() {
        let sd: Vec<String> = est
            .unknowns
            .iter()
            .zip(&best.sigma)
            .map(|(n, x)| {
                let shown = match (n.as_str(), x) {
                    (_, None) => "not determined".to_string(),
                    ("vx", Some(x)) | ("vy", Some(x)) => {
                        format!("{} {spd}", num(units.speed(*x), 3))
                    }
                    ("yaw_rate", Some(x)) => {
                        format!("{} {rate}", num(units.yaw_rate(*x), 3))
                    }
                    (_, Some(x)) => format!("{x:.4}"),
                };
                format!("{n} {shown}")
            })
            .collect();
        t.push_str(&format!(
            "  standard errors of the first candidate (linearised): {}\n",
            sd.join(", ")
        ));
    }
    for u in &est.undetermined {
        t.push_str(&format!("  NOT DETERMINED: {u}\n"));
    }
    t
}
