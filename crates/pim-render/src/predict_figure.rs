//! The figure of `pim predict-dv --out` (as Brach 1984 Fig. 3): L of eq. 16 against the speed
//! ratio for several mass ratios, and predicted against measured delta-V.

use crate::{err, svg_figure, Figure};
use pim_core::prediction::l_factor;
use pim_studies::predict::TestPrediction;
use plotters::coord::Shift;
use plotters::prelude::*;

const COLORS: [RGBColor; 5] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
];

/// The figure `predict_dv.svg`.
pub fn figure(rows: &[TestPrediction]) -> Result<Figure, crate::RenderError> {
    svg_figure("predict_dv.svg", (1100, 520), |root| draw(rows, root))
}

fn draw(
    rows: &[TestPrediction],
    root: &DrawingArea<SVGBackend<'_>, Shift>,
) -> Result<(), crate::RenderError> {
    let (left, right) = root.split_horizontally(550);
    let mut chart = ChartBuilder::on(&left)
        .caption(
            "L of eq. 16 against the speed ratio R = v2 / v1",
            ("sans-serif", 16),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..3.0f64, 0.5..0.95f64)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("R = v2 / v1")
        .y_desc("L")
        .draw()
        .map_err(err)?;
    for (k, alpha) in [0.5, 0.75, 1.0, 1.5, 2.0].into_iter().enumerate() {
        let c = COLORS[k];
        chart
            .draw_series(LineSeries::new(
                (0..=300).map(|i| {
                    let r = i as f64 / 100.0;
                    (r, l_factor(alpha, r))
                }),
                c.stroke_width(2),
            ))
            .map_err(err)?
            .label(format!("m1 / m2 = {alpha}"))
            .legend(move |(x, y)| PathElement::new([(x, y), (x + 16, y)], c.stroke_width(2)));
    }
    chart
        .draw_series(
            rows.iter()
                .map(|r| Circle::new((r.speed_ratio.min(3.0), r.l), 4, BLACK.filled())),
        )
        .map_err(err)?
        .label("the tests (their own m1 / m2)")
        .legend(|(x, y)| Circle::new((x + 6, y), 4, BLACK.filled()));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;

    let max = rows
        .iter()
        .flat_map(|r| {
            [r.delta_v1, r.delta_v2]
                .into_iter()
                .flat_map(|d| [d.measured, d.eq14, d.eq14_two_thirds, d.eq17])
        })
        .fold(1.0f64, f64::max)
        * 1.08;
    let mut chart = ChartBuilder::on(&right)
        .caption("Predicted against measured delta-V", ("sans-serif", 16))
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(0.0..max, 0.0..max)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("measured delta-V [m/s]")
        .y_desc("predicted delta-V [m/s]")
        .draw()
        .map_err(err)?;
    chart
        .draw_series(LineSeries::new([(0.0, 0.0), (max, max)], BLACK.mix(0.4)))
        .map_err(err)?;
    type Pick = fn(&pim_studies::predict::DeltaVPrediction) -> f64;
    let sets: [(&str, Pick); 3] = [
        ("eq. 14, L of eq. 16", |d| d.eq14),
        ("eq. 14, L = 2/3", |d| d.eq14_two_thirds),
        ("eq. 17, point mass", |d| d.eq17),
    ];
    for (k, (name, pick)) in sets.into_iter().enumerate() {
        let c = COLORS[k];
        chart
            .draw_series(rows.iter().flat_map(|r| {
                [r.delta_v1, r.delta_v2]
                    .into_iter()
                    .map(move |d| Circle::new((d.measured, pick(&d)), 4, c.filled()))
            }))
            .map_err(err)?
            .label(name)
            .legend(move |(x, y)| Circle::new((x + 6, y), 4, c.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}
