//! The momentum diagram, as reconstructionists draw it: each vehicle's momentum (mass times the
//! velocity of its centre of gravity) at contact and at separation, to one scale, placed head
//! to tail. Both chains start at the origin and, because the impact conserves momentum, end
//! at the same point, the total momentum; the difference of a vehicle's two arrows is the
//! impulse on it. Against a barrier only vehicle 1 is drawn (the wall takes the impulse).
//!
//! Drawn in the case's frame (SAE's y axis points to the right of x, so its plot is the
//! natural one mirrored) and impulse unit.

use crate::{err, svg_figure, Figure, RenderError};
use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_core::Velocities;
use plotters::prelude::*;

const COLORS: [RGBColor; 2] = [RGBColor(31, 119, 180), RGBColor(214, 39, 40)];
const LIGHT: [RGBColor; 2] = [RGBColor(120, 170, 215), RGBColor(240, 140, 140)];

/// One arrow of the diagram: from, to, colour, dashed, its label in the key.
struct Arrow {
    from: [f64; 2],
    to: [f64; 2],
    color: RGBColor,
    dashed: bool,
    label: String,
}

/// What a momentum diagram that is not finite holds.
const NOT_FINITE: &str = "a velocity or mass of the momentum diagram";

/// The momentum diagram of the states `initial` and `separation` (natural frame, SI) of `case`,
/// named `name`.
pub fn figure(
    case: &Case,
    initial: &Velocities,
    separation: &Velocities,
    name: &str,
) -> Result<Figure, RenderError> {
    let u = UnitSystem::of(&case.written_units);
    let sae = case.written.mirrors();
    let barrier = case.is_barrier();
    let arrows = arrows_of(case, [initial, separation], u);
    let pts: Vec<[f64; 2]> = arrows.iter().flat_map(|a| [a.from, a.to]).collect();
    if !pts.iter().flatten().all(|x| x.is_finite()) {
        return Err(RenderError::NotFinite(NOT_FINITE));
    }
    let (mut lo, mut hi) = ([0.0f64; 2], [0.0f64; 2]);
    for q in &pts {
        for d in 0..2 {
            lo[d] = lo[d].min(q[d]);
            hi[d] = hi[d].max(q[d]);
        }
    }
    // One scale on both axes: a square box around the arrows.
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1.0) * 1.12;
    let mid = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
    let xr = (mid[0] - span / 2.0)..(mid[0] + span / 2.0);
    let yr = (mid[1] - span / 2.0)..(mid[1] + span / 2.0);
    // Plot area 520 x 520 px: 600 wide with the y labels, 580 high with the caption and x labels.
    let (plot_w, key_w, height) = (600u32, 330u32, 600u32);
    svg_figure(name, (plot_w + key_w, height), |root| {
        let (left, right) = root.split_horizontally(plot_w);
        let unit = u.impulse_label();
        let mut chart = ChartBuilder::on(&left)
            .caption(
                "Momentum at contact and at separation, to scale",
                ("sans-serif", 16),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(64)
            .build_cartesian_2d(xr.clone(), yr.clone())
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(format!("x [{unit}]"))
            .y_desc(format!(
                "y [{unit}]{}",
                if sae { ", SAE: to the right of x" } else { "" }
            ))
            .x_label_formatter(&|v| crate::figures::tick(*v))
            .y_label_formatter(&|v| crate::figures::tick(if sae { -*v } else { *v }))
            .light_line_style(WHITE.mix(0.0))
            .draw()
            .map_err(err)?;
        // Arrowheads sized to the plot, not to the momenta.
        let head = span * 0.025;
        for a in &arrows {
            let style = a.color.stroke_width(if a.dashed { 2 } else { 3 });
            let line = [(a.from[0], a.from[1]), (a.to[0], a.to[1])];
            if a.dashed {
                chart
                    .draw_series(DashedLineSeries::new(line, 8, 5, style))
                    .map_err(err)?;
            } else {
                chart
                    .draw_series(LineSeries::new(line, style))
                    .map_err(err)?;
            }
            let d = [a.to[0] - a.from[0], a.to[1] - a.from[1]];
            let len = d[0].hypot(d[1]);
            if len > 2.0 * head {
                let (ux, uy) = (d[0] / len, d[1] / len);
                let base = (a.to[0] - head * ux, a.to[1] - head * uy);
                let w = head * 0.45;
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        vec![
                            (a.to[0], a.to[1]),
                            (base.0 - w * uy, base.1 + w * ux),
                            (base.0 + w * uy, base.1 - w * ux),
                        ],
                        a.color.filled(),
                    )))
                    .map_err(err)?;
            }
        }
        chart
            .draw_series(std::iter::once(Circle::new((0.0, 0.0), 3, BLACK.filled())))
            .map_err(err)?;
        draw_key(&right, &arrows, barrier)?;
        Ok(())
    })
}

/// The arrows of the diagram, in the impulse unit of `u`: each vehicle's momentum at contact
/// (solid) and at separation (dashed), head to tail from the origin, then the total (not against
/// a barrier).
fn arrows_of(case: &Case, [initial, separation]: [&Velocities; 2], u: UnitSystem) -> Vec<Arrow> {
    let barrier = case.is_barrier();
    let masses = case.vehicles().map(|v| v.mass);
    let k = u.impulse(1.0);
    // Drawn in the natural frame (the picture of the plan view); an SAE case's y ticks read
    // SAE's y, which points the other way.
    let p = |m: f64, vx: f64, vy: f64| [k * m * vx, k * m * vy];
    let count = if barrier { 1 } else { 2 };
    let mut arrows = Vec::new();
    for (state, dashed, when) in [
        (initial, false, "contact"),
        (separation, true, "separation"),
    ] {
        let mut at = [0.0, 0.0];
        for (i, v) in [&state.vehicle1, &state.vehicle2]
            .iter()
            .enumerate()
            .take(count)
        {
            let m = p(masses[i], v.vx, v.vy);
            let to = [at[0] + m[0], at[1] + m[1]];
            arrows.push(Arrow {
                from: at,
                to,
                color: if dashed { LIGHT[i] } else { COLORS[i] },
                dashed,
                label: format!(
                    "vehicle {} at {when}: {} {}",
                    i + 1,
                    crate::tables::num(m[0].hypot(m[1]), 0),
                    u.impulse_label()
                ),
            });
            at = to;
        }
    }
    let total = arrows[count - 1].to;
    if !barrier {
        arrows.push(Arrow {
            from: [0.0, 0.0],
            to: total,
            color: RGBColor(40, 40, 40),
            dashed: false,
            label: format!(
                "total momentum: {} {}",
                crate::tables::num(total[0].hypot(total[1]), 0),
                u.impulse_label()
            ),
        });
    }
    arrows
}

/// The key beside the plot: one line per arrow, then how to read the diagram.
fn draw_key(
    right: &crate::figures::Area,
    arrows: &[Arrow],
    barrier: bool,
) -> Result<(), RenderError> {
    let font = ("sans-serif", 13).into_font();
    right
        .draw(&Text::new(
            "Key",
            (10, 40),
            font.clone().style(FontStyle::Bold),
        ))
        .map_err(err)?;
    for (i, a) in arrows.iter().enumerate() {
        let y = 66 + 24 * i as i32;
        let style = a.color.stroke_width(if a.dashed { 2 } else { 3 });
        if a.dashed {
            right
                .draw(&PathElement::new(vec![(10, y), (18, y)], style))
                .map_err(err)?;
            right
                .draw(&PathElement::new(vec![(24, y), (34, y)], style))
                .map_err(err)?;
        } else {
            right
                .draw(&PathElement::new(vec![(10, y), (34, y)], style))
                .map_err(err)?;
        }
        right
            .draw(&Text::new(a.label.clone(), (42, y - 7), font.clone()))
            .map_err(err)?;
    }
    let notes = [
        "Head to tail from the origin (dot):".to_string(),
        "solid at contact, dashed at separation.".to_string(),
        if barrier {
            "Vehicle 2 is a fixed barrier.".to_string()
        } else {
            "Both chains end at the total momentum.".to_string()
        },
        "A vehicle's impulse = its separation".to_string(),
        "arrow minus its contact arrow.".to_string(),
    ];
    for (i, n) in notes.iter().enumerate() {
        let y = 90 + 24 * arrows.len() as i32 + 18 * i as i32;
        right
            .draw(&Text::new(n.clone(), (10, y), font.clone()))
            .map_err(err)?;
    }
    Ok(())
}
