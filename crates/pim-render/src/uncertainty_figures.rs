//! Figures of `pim uncertainty --out` (plotters, SVG): histograms of the impact speeds and
//! delta-V with their 90 % bands, speed 1 against speed 2, and a tornado chart of the inputs
//! that dominate each of them.

use crate::{err, svg_figure, Figure};
use pim_case::units::UnitSystem;
use pim_studies::uncertainty::{Study, QUANTITIES};
use plotters::prelude::*;

const BAR: RGBColor = RGBColor(31, 119, 180);
const BAND: RGBColor = RGBColor(255, 127, 14);

/// The four quantities drawn, with their labels (without the unit).
const SHOWN: [(&str, &str); 4] = [
    ("speed1", "vehicle 1 speed at contact"),
    ("speed2", "vehicle 2 speed at contact"),
    ("delta_v1", "vehicle 1 delta-V"),
    ("delta_v2", "vehicle 2 delta-V"),
];

/// The slot of a quantity both models share (the speeds, delta-V, the energy loss).
fn index(name: &str) -> usize {
    QUANTITIES.iter().position(|q| *q == name).unwrap_or(0)
}

/// The figures `histograms.svg`, `speeds.svg` and `tornado.svg`, speeds in the unit system
/// `u`.
pub fn figures(s: &Study, u: UnitSystem) -> Result<Vec<Figure>, crate::RenderError> {
    let speed = u.speed_label();
    let s = &s.in_speed_unit(u.speed(1.0));
    if s.samples.is_empty() || s.samples.iter().flatten().any(|x| !x.is_finite()) {
        return Err(crate::RenderError::Nothing(
            "no feasible draw, or a draw with a value that is not a number",
        ));
    }
    let mut figures = Vec::new();
    let figure = svg_figure("histograms.svg", (1000, 700), |root| {
        for (area, (name, label)) in root.split_evenly((2, 2)).iter().zip(SHOWN) {
            let q = index(name);
            let v: Vec<f64> = s.samples.iter().map(|d| d[q]).collect();
            let sum = &s.quantities[name];
            let ended = sum
                .reaches_bound
                .map(|h| format!(" (ended by the {} bound)", h.bound))
                .unwrap_or_default();
            let label = format!("{label} [{speed}]");
            histogram(
                area,
                &v,
                [sum.p05, sum.p95],
                s.nominal.get(name).copied(),
                &label,
                format!("{label}: 90 % {:.2} .. {:.2}{ended}", sum.p05, sum.p95),
            )?;
        }
        Ok(())
    })?;
    figures.push(figure);

    figures.push(speeds_figure(s, speed)?);

    let figure = svg_figure("tornado.svg", (1100, 700), |root| {
        for (area, (name, label)) in root.split_evenly((2, 2)).iter().zip(SHOWN) {
            let inputs: Vec<(String, f64)> = s
                .sensitivity
                .iter()
                .find(|x| x.quantity == name)
                .map(|x| x.inputs.iter().take(6).cloned().collect())
                .unwrap_or_default();
            let n = inputs.len().max(1);
            let (left, right) = area.split_horizontally(250);
            let mut chart = ChartBuilder::on(&right)
                .caption(format!("{label}: first-order index"), ("sans-serif", 14))
                .margin(8)
                .x_label_area_size(30)
                .y_label_area_size(5)
                .build_cartesian_2d(0.0..1.0f64, 0.0..n as f64)
                .map_err(err)?;
            chart
                .configure_mesh()
                .disable_y_mesh()
                .y_labels(0)
                .x_desc("share of the variance")
                .draw()
                .map_err(err)?;
            chart
                .draw_series(inputs.iter().enumerate().map(|(i, (_, v))| {
                    let y = (n - 1 - i) as f64;
                    Rectangle::new([(0.0, y + 0.15), (*v, y + 0.85)], BAR.filled())
                }))
                .map_err(err)?;
            // Input names beside their bars, in the left strip.
            let (_, h) = right.dim_in_pixel();
            let plot_top = 8 + 22;
            let plot_h = h as i32 - plot_top - 8 - 30;
            // Right-aligned against the bars, each on its bar's middle.
            let (strip_w, _) = left.dim_in_pixel();
            let style = TextStyle::from(("sans-serif", 12).into_font()).pos(
                plotters::style::text_anchor::Pos::new(
                    plotters::style::text_anchor::HPos::Right,
                    plotters::style::text_anchor::VPos::Center,
                ),
            );
            for (i, (input, v)) in inputs.iter().enumerate() {
                let y = plot_top + ((i as f64 + 0.5) / n as f64 * plot_h as f64) as i32;
                left.draw(&Text::new(
                    format!("{input} ({v:.2})"),
                    (strip_w as i32 - 2, y),
                    style.clone(),
                ))
                .map_err(err)?;
            }
            if inputs.is_empty() {
                left.draw(&Text::new(
                    "no input above 0.02",
                    (6, 40),
                    ("sans-serif", 12),
                ))
                .map_err(err)?;
            }
        }
        Ok(())
    })?;
    figures.push(figure);
    Ok(figures)
}

/// The scatter of the draws' impact speeds (`speed`: the unit's label), the nominal fit marked.
fn speeds_figure(s: &Study, speed: &str) -> Result<Figure, crate::RenderError> {
    svg_figure("speeds.svg", (620, 560), |root| {
        let (a, b) = (index("speed1"), index("speed2"));
        let pts: Vec<(f64, f64)> = s.samples.iter().map(|d| (d[a], d[b])).collect();
        let range = |k: usize| {
            let lo = pts
                .iter()
                .map(|p| if k == 0 { p.0 } else { p.1 })
                .fold(f64::INFINITY, f64::min);
            let hi = pts
                .iter()
                .map(|p| if k == 0 { p.0 } else { p.1 })
                .fold(f64::NEG_INFINITY, f64::max);
            let pad = 0.05 * (hi - lo).max(0.1);
            (lo - pad)..(hi + pad)
        };
        let mut chart = ChartBuilder::on(root)
            .caption(
                "Impact speeds of the draws (black: nominal fit)",
                ("sans-serif", 16),
            )
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(50)
            .build_cartesian_2d(range(0), range(1))
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc(format!("vehicle 1 speed at contact [{speed}]"))
            .y_desc(format!("vehicle 2 speed at contact [{speed}]"))
            .draw()
            .map_err(err)?;
        chart
            .draw_series(
                pts.iter()
                    .map(|p| Circle::new(*p, 2, BAR.mix(0.6).filled())),
            )
            .map_err(err)?;
        if let (Some(x), Some(y)) = (s.nominal.get("speed1"), s.nominal.get("speed2")) {
            chart
                .draw_series(std::iter::once(Cross::new(
                    (*x, *y),
                    7,
                    BLACK.stroke_width(2),
                )))
                .map_err(err)?;
        }
        Ok(())
    })
}

/// One histogram panel of a study's draws: 25 bars of `v`, its 90 % interval `band` shaded and
/// the nominal answer as a black line; `label` names the axis, `caption` heads the panel.
pub(crate) fn histogram(
    area: &plotters::drawing::DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    v: &[f64],
    band: [f64; 2],
    nominal: Option<f64>,
    label: &str,
    caption: String,
) -> Result<(), crate::RenderError> {
    let lo = v.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !(lo.is_finite() && hi.is_finite()) {
        return Ok(());
    }
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, hi + 0.5)
    };
    let bins = 25usize;
    let w = (hi - lo) / bins as f64;
    let mut counts = vec![0usize; bins];
    for x in v {
        counts[(((x - lo) / w) as usize).min(bins - 1)] += 1;
    }
    let top = counts.iter().copied().max().unwrap_or(1) as f64 * 1.1;
    let mut chart = ChartBuilder::on(area)
        .caption(caption, ("sans-serif", 15))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(45)
        .build_cartesian_2d(lo..hi, 0.0..top)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(label)
        .y_desc("draws")
        .draw()
        .map_err(err)?;
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(band[0], 0.0), (band[1], top)],
            BAND.mix(0.15).filled(),
        )))
        .map_err(err)?;
    chart
        .draw_series(
            counts
                .iter()
                .enumerate()
                .filter(|(_, c)| **c > 0)
                .map(|(i, c)| {
                    let x0 = lo + i as f64 * w;
                    Rectangle::new([(x0, 0.0), (x0 + 0.92 * w, *c as f64)], BAR.filled())
                }),
        )
        .map_err(err)?;
    if let Some(n) = nominal {
        chart
            .draw_series(LineSeries::new([(n, 0.0), (n, top)], BLACK.stroke_width(2)))
            .map_err(err)?;
    }
    Ok(())
}
