//! The table of a reconstruction: the speeds of every phase, the impact's coefficients, every
//! piece of evidence against the fit, the counts of turns compared, and what is proven.

use crate::tables::num;
use crate::text::wrap;
use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_studies::reconstruct::ReconstructionOut;

/// The reconstruction's table in `units` and the case's `frame` (SAE: y to the right, headings
/// clockwise).
pub fn reconstruction_table(
    title: &str,
    d: &ReconstructionOut,
    units: UnitSystem,
    frame: Convention,
) -> String {
    let s = frame.sign();
    let spd = units.speed_label();
    let len = units.length_label();
    let v = |x: f64| num(units.speed(x), 2);
    let mut t = format!("Reconstruction (pre-impact, impact, run-out): {title}\n");
    if frame.mirrors() {
        t.push_str("frame: SAE (y to the right, headings and turns clockwise)\n");
    }
    let Some(b) = &d.best else {
        t.push_str(&format!(
            "\nno reconstruction: {}\n",
            d.reason.as_deref().unwrap_or("none found")
        ));
        if let Some(c) = &d.consistency {
            t.push_str(&consistency_lines(c, units));
        }
        return t;
    };
    if let Some(why) = &d.reason {
        for l in wrap(&format!("CONTRADICTED BY THE EVIDENCE: {why}"), 96) {
            t.push_str(&format!("{l}\n"));
        }
        t.push_str("(the best reconstruction found, for inspection:)\n");
    }
    t.push_str(&format!(
        "impact: e {:.4}, mu {:.4}, em {:.4} ({} branch), energy loss {:.1} %\n",
        b.e,
        b.mu,
        b.em,
        b.branch.name(),
        b.energy_loss_percent
    ));
    for l in wrap(
        &crate::statistics::chi_square_words(b.chi_square, b.degrees_of_freedom, b.p_value),
        96,
    ) {
        t.push_str(&format!("{l}\n"));
    }
    t.push_str(&format!(
        "\n{:<8} {:>16} {:>12} {:>14} {:>8} {:>7} {:>26}\n",
        "vehicle",
        "before braking",
        "at contact",
        "at separation",
        "at rest",
        "turns",
        "rest (x, y, heading)"
    ));
    for p in &b.vehicles {
        let rest = p.rest.map_or_else(
            || "-".to_string(),
            |r| {
                format!(
                    "{}, {} {len}, {:.1} deg",
                    num(units.length(r.x), 2),
                    num(units.length(s * r.y), 2),
                    s * r.heading
                )
            },
        );
        t.push_str(&format!(
            "{:<8} {:>16} {:>12} {:>14} {:>8} {:>7} {:>26}\n",
            p.vehicle,
            p.speed_before_braking.map_or_else(|| "-".into(), v),
            v(p.speed_at_contact),
            v(p.speed_at_separation),
            p.speed_at_rest.map_or_else(|| "-".into(), v),
            p.turns
                .map_or_else(|| "-".into(), |k| (s as i64 * k).to_string()),
            rest
        ));
    }
    t.push_str(&format!(
        "(speeds in {spd})\n{}",
        contact_pose_lines(b, units, s)
    ));
    t.push_str(&evidence_lines(b, units));
    t.push_str(&counts_lines(d, s));
    for (head, text) in [("how found", &d.method), ("proven", &d.proven)] {
        let lines = wrap(&format!("{head}: {text}"), 96);
        for l in lines {
            t.push_str(&format!("{l}\n"));
        }
    }
    for u in &d.undetermined {
        for (i, l) in wrap(&format!("not determined: {u}"), 96)
            .into_iter()
            .enumerate()
        {
            t.push_str(&format!("{}{l}\n", if i == 0 { "" } else { "  " }));
        }
    }
    if !b.converged {
        t.push_str("warning: the iterations reached their limit before their tolerance\n");
    }
    if let Some(c) = &d.consistency {
        t.push_str(&consistency_lines(c, units));
    }
    t
}

/// The combinations of counts of turns compared (each refined one's chi-square and state), the
/// counts in the frame of `s` (its sign).
fn counts_lines(d: &ReconstructionOut, s: f64) -> String {
    let mut t = String::new();
    t.push_str("\ncounts of turns compared (vehicle order: ");
    t.push_str(
        &d.scene_vehicles
            .iter()
            .map(|v| format!("vehicle {v}"))
            .collect::<Vec<_>>()
            .join(", "),
    );
    t.push_str(")\n");
    for c in d.counts.iter().filter(|c| c.chi_square.is_some()) {
        t.push_str(&format!(
            "  {:<14} chi-square {:>12}  ({})\n",
            format!(
                "{:?}",
                c.turns
                    .iter()
                    .map(|k| k.map_or_else(|| "-".to_string(), |k| (s as i64 * k).to_string()))
                    .collect::<Vec<_>>()
            )
            .replace('"', ""),
            num(c.chi_square.unwrap_or(f64::NAN), 3),
            c.state
        ));
    }
    let others = d.counts.iter().filter(|c| c.chi_square.is_none()).count();
    if others > 0 {
        t.push_str(&format!(
            "  {others} other combinations not refined (their bounds exclude them; see the JSON)\n"
        ));
    }
    t
}

/// The evidence table: each piece's residual and sigma in `units`, its z and share.
fn evidence_lines(b: &pim_studies::reconstruct::BestOut, units: UnitSystem) -> String {
    let mut t = String::new();
    t.push_str(&format!(
        "\n{:<56} {:>10} {:>10} {:>8} {:>8}\n",
        "evidence", "residual", "sigma", "z", "share %"
    ));
    for e in &b.evidence {
        let (scale, unit) = evidence_unit(e, units);
        t.push_str(&format!(
            "{:<56} {:>10} {:>10} {:>8.2} {:>8.1}\n",
            if unit.is_empty() {
                e.name.clone()
            } else {
                format!("{} ({unit})", e.name)
            },
            num(e.residual * scale, 3),
            num(e.sigma * scale, 3),
            e.z,
            e.share_percent
        ));
    }
    t
}

/// The pose at contact where the case fits it: each unknown stated and fitted, with its
/// standard deviation after the fit and its prior's (`s`: -1 mirrors y and angles for SAE).
fn contact_pose_lines(b: &pim_studies::reconstruct::BestOut, units: UnitSystem, s: f64) -> String {
    if b.contact_pose.is_empty() {
        return String::new();
    }
    let mut t = format!(
        "\n{:<28} {:>12} {:>12} {:>12} {:>12} {:>8}\n",
        "pose at contact", "stated", "fitted", "+- (fit)", "+- (prior)", "z"
    );
    for p in &b.contact_pose {
        let sign = if p.mirrored { s } else { 1.0 };
        let (scale, unit) = if p.quantity == "angle" {
            (1.0, "deg")
        } else {
            (units.length(1.0), units.length_label())
        };
        let x = |v: f64| num(v * scale, 2);
        t.push_str(&format!(
            "{:<28} {:>12} {:>12} {:>12} {:>12} {:>8.2}\n",
            format!("{} ({unit})", p.name),
            x(sign * p.stated),
            x(sign * p.fitted),
            x(p.sigma),
            x(p.prior_sigma),
            sign * p.z
        ));
    }
    t
}

/// The scale and label of a piece of evidence's unit in `units` (its `quantity`).
pub fn evidence_unit(
    e: &pim_studies::reconstruct::EvidenceOut,
    units: UnitSystem,
) -> (f64, &'static str) {
    match e.quantity {
        "angle" => (1.0, "deg"),
        "length" => (units.length(1.0), units.length_label()),
        "yaw_rate" => (units.yaw_rate(1.0), units.yaw_rate_label()),
        "energy" => (units.energy(1.0), units.energy_label()),
        // A coefficient: no unit.
        "friction" => (1.0, ""),
        _ => (units.speed(1.0), units.speed_label()),
    }
}

/// One row of the evidence consistency table as the text table and the report show it: what
/// was left out, chi-square, dof, p, consistent, each vehicle's speed at contact in `units`,
/// and the largest remaining residual.
pub fn consistency_cells(r: &pim_studies::consistency::LeftOut, units: UnitSystem) -> [String; 8] {
    let speed = |k: usize| {
        r.speed_at_contact[k].map_or_else(|| "-".to_string(), |v| num(units.speed(v), 2))
    };
    [
        if r.left_out.is_empty() {
            "(nothing: all the evidence)".to_string()
        } else {
            r.left_out.join(" + ")
        },
        r.chi_square.map_or_else(|| "-".to_string(), |x| num(x, 2)),
        r.degrees_of_freedom
            .map_or_else(|| "-".to_string(), |x| x.to_string()),
        r.p_value
            .map_or_else(|| "-".to_string(), crate::statistics::format_p),
        if r.consistent { "yes" } else { "no" }.to_string(),
        speed(0),
        speed(1),
        match (&r.largest, &r.error) {
            (_, Some(e)) => format!("cannot reconstruct: {e}"),
            (Some((n, z)), None) => format!("{n} ({z:+.1})"),
            (None, None) => "-".to_string(),
        },
    ]
}

/// The evidence consistency table as text, speeds in `units`.
pub fn consistency_lines(c: &pim_studies::consistency::Consistency, units: UnitSystem) -> String {
    let mut t = String::from(
        "\nevidence consistency: the reconstruction with each piece of evidence left out in turn\n",
    );
    let spd = units.speed_label();
    t.push_str(&format!(
        "{:<44} {:>10} {:>4} {:>8} {:>10} {:>9} {:>9}  {}\n",
        "left out",
        "chi-square",
        "dof",
        "p",
        "consistent",
        format!("v1 {spd}"),
        format!("v2 {spd}"),
        "largest remaining residual (z)"
    ));
    for r in std::iter::once(&c.all).chain(&c.rows) {
        let [name, chi, dof, p, consistent, v1, v2, largest] = consistency_cells(r, units);
        t.push_str(&format!(
            "{name:<44} {chi:>10} {dof:>4} {p:>8} {consistent:>10} {v1:>9} {v2:>9}  {largest}\n"
        ));
    }
    t.push_str("(v1, v2: speeds at contact)\n");
    for l in wrap(&c.summary, 96) {
        t.push_str(&format!("{l}\n"));
    }
    t
}

/// The reconstruction's report as one HTML page: the table, the scene to scale and, when
/// given, the speeds before contact beside the EDR's (`speeds`, an SVG).
pub fn reconstruction_html(title: &str, table: &str, svg: &str, speeds: Option<&str>) -> String {
    let esc = |t: &str| {
        t.replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
    };
    // An SVG document inline: without its XML declaration.
    let inline = |svg: &'_ str| -> String {
        svg.trim_start_matches(|c| c != '<')
            .split_once("?>")
            .map_or(svg, |(_, rest)| rest)
            .to_string()
    };
    let speeds = speeds.map_or(String::new(), |s| {
        format!(
            "<h2>The speeds before contact: the answer and the EDR</h2>\n{}\n",
            inline(s)
        )
    });
    let first = title.lines().next().unwrap_or("");
    format!(
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>Reconstruction: \
         {}</title>\n<style>body{{font-family:sans-serif;max-width:60rem;margin:2rem auto;}}\
         pre{{font-size:0.72rem;line-height:1.25;}} svg{{max-width:100%;height:auto;}}\
         </style></head><body>\n<h1>Reconstruction</h1>\n<h2>The speeds, the evidence, what is \
         proven</h2>\n<pre>{}</pre>\n<h2>The scene to scale</h2>\n{}\n{speeds}</body></html>\n",
        esc(first),
        esc(table),
        inline(svg)
    )
}
