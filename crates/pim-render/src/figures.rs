//! SVG figures of a batch run (plotters): cost per test and cost function, the coefficients, the
//! relative delta-V error per vehicle, and fitted against measured separation velocities.

use crate::{err, svg_figure, Figure};
use pim_studies::batch::BatchRecord;
use plotters::prelude::*;

const COLORS: [RGBColor; 3] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
];

/// One series of a grouped bar chart: its name and one value per test (`None`: no solution,
/// drawn as a cross on the axis; a value of 0 is a visible line).
struct Series {
    name: String,
    values: Vec<Option<f64>>,
    color: RGBColor,
}

/// Reads one value of a record.
type Getter = dyn Fn(&BatchRecord) -> Option<f64>;

pub(crate) type Area<'a> = DrawingArea<SVGBackend<'a>, plotters::coord::Shift>;

/// A horizontal reference line (a bound) with its label.
struct Bound {
    value: f64,
    label: String,
}

/// Width of the key strip on the right of every bar chart, px.
const KEY_WIDTH: u32 = 150;

fn grouped_bars(
    area: &Area,
    title: &str,
    y_label: &str,
    tests: &[u32],
    series: &[Series],
    bounds: &[Bound],
) -> Result<(), crate::RenderError> {
    let (w_px, _) = area.dim_in_pixel();
    let (plot, key) = area.split_horizontally(w_px.saturating_sub(KEY_WIDTH));
    let data: Vec<f64> = series
        .iter()
        .flat_map(|s| s.values.iter().flatten().copied())
        .collect();
    // A bound far from every value would only stretch the axis into empty space: it is
    // drawn when some value comes within a tenth of the values' span of it, and otherwise
    // named in the key as not reached.
    let span = data.iter().fold(0.0_f64, |m, v| m.max(v.abs())).max(1e-9);
    let reached = |b: &Bound| data.iter().any(|v| (v - b.value).abs() <= 0.1 * span);
    let vals: Vec<f64> = data
        .iter()
        .copied()
        .chain(bounds.iter().filter(|b| reached(b)).map(|b| b.value))
        .collect();
    let lo = vals.iter().copied().fold(0.0_f64, f64::min);
    let hi = vals.iter().copied().fold(0.0_f64, f64::max);
    let pad = 0.08 * (hi - lo).max(1e-9);
    let n = tests.len();
    let mut chart = ChartBuilder::on(&plot)
        .caption(title, ("sans-serif", 17))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.5f64..(n as f64 - 0.5), (lo - pad)..(hi + pad))
        .map_err(err)?;
    let labels: Vec<String> = tests.iter().map(|t| t.to_string()).collect();
    chart
        .configure_mesh()
        .x_desc("RICSAC test")
        .y_desc(y_label)
        .y_label_formatter(&|y| tick(*y))
        .max_light_lines(1)
        .x_labels(n)
        .x_label_formatter(&|x| {
            let i = x.round();
            if (x - i).abs() < 1e-6 && i >= 0.0 && (i as usize) < labels.len() {
                labels[i as usize].clone()
            } else {
                String::new()
            }
        })
        .disable_x_mesh()
        .draw()
        .map_err(err)?;
    let k = series.len().max(1) as f64;
    let w = 0.8 / k;
    let cross = 0.03 * (hi - lo + 2.0 * pad);
    for (j, s) in series.iter().enumerate() {
        let color = s.color;
        for (i, v) in s.values.iter().enumerate() {
            let x0 = i as f64 - 0.4 + j as f64 * w;
            let x1 = x0 + w * 0.9;
            match v {
                Some(v) => {
                    // A bar less than a pixel high has no area to draw (and an SVG rect of
                    // height 0 is invalid): the line on the axis below shows it.
                    let tall =
                        chart.backend_coord(&(x0, 0.0)).1 != chart.backend_coord(&(x0, *v)).1;
                    if tall {
                        chart
                            .draw_series(std::iter::once(Rectangle::new(
                                [(x0, 0.0), (x1, *v)],
                                color.filled(),
                            )))
                            .map_err(err)?;
                    }
                    // A zero (or tiny) value stays visible as a line on the axis.
                    chart
                        .draw_series(LineSeries::new(
                            [(x0, 0.0), (x1, 0.0)],
                            color.stroke_width(3),
                        ))
                        .map_err(err)?;
                }
                None => {
                    let xm = 0.5 * (x0 + x1);
                    let dx = 0.35 * (x1 - x0);
                    for (a, b) in [
                        ((xm - dx, -cross), (xm + dx, cross)),
                        ((xm - dx, cross), (xm + dx, -cross)),
                    ] {
                        chart
                            .draw_series(LineSeries::new([a, b], color.stroke_width(2)))
                            .map_err(err)?;
                    }
                }
            }
        }
    }
    for b in bounds.iter().filter(|b| reached(b)) {
        chart
            .draw_series(DashedLineSeries::new(
                [(-0.5, b.value), (n as f64 - 0.5, b.value)],
                6,
                4,
                BLACK.mix(0.6).stroke_width(1),
            ))
            .map_err(err)?;
    }
    // The key, beside the plot so that it never covers a bar.
    bars_key(&key, series, bounds, &reached)
}

/// The key of [`grouped_bars`]: each series' colour, the mark of no solution, each bound
/// (drawn where `reached`, else named as not reached).
fn bars_key(
    key: &Area,
    series: &[Series],
    bounds: &[Bound],
    reached: &dyn Fn(&Bound) -> bool,
) -> Result<(), crate::RenderError> {
    let mut y = 40;
    for s in series {
        let color = s.color;
        key.draw(&Rectangle::new([(6, y), (20, y + 12)], color.filled()))
            .map_err(err)?;
        key.draw(&Text::new(s.name.clone(), (26, y), ("sans-serif", 14)))
            .map_err(err)?;
        y += 20;
    }
    key.draw(&Text::new("x  no solution", (6, y), ("sans-serif", 13)))
        .map_err(err)?;
    y += 18;
    key.draw(&Text::new("(infeasible)", (6, y), ("sans-serif", 13)))
        .map_err(err)?;
    y += 24;
    for b in bounds {
        if reached(b) {
            key.draw(&PathElement::new(
                [(6, y + 6), (20, y + 6)],
                BLACK.mix(0.6).stroke_width(1),
            ))
            .map_err(err)?;
            key.draw(&Text::new(b.label.clone(), (26, y), ("sans-serif", 13)))
                .map_err(err)?;
        } else {
            // Two lines, so that the key stays inside its strip.
            for line in [b.label.as_str(), "  (not reached)"] {
                key.draw(&Text::new(line, (6, y), ("sans-serif", 13)))
                    .map_err(err)?;
                y += 16;
            }
            y += 4;
            continue;
        }
        y += 18;
    }
    Ok(())
}

fn best_per_cost(
    records: &[BatchRecord],
    test: u32,
    cost: pim_fit::CostPreset,
) -> Option<&BatchRecord> {
    records
        .iter()
        .find(|r| r.test == test && r.cost_function == cost && r.best && r.solved())
}

/// The lighter shade of a cost function's colour, for the tangential model beside PIM.
fn light(c: RGBColor) -> RGBColor {
    let mix = |v: u8| (v as f64 + 0.55 * (255.0 - v as f64)).round() as u8;
    RGBColor(mix(c.0), mix(c.1), mix(c.2))
}

/// The comparison of the models (`pim batch --model pim,tangential`): per test, the minimum
/// cost, the relative delta-V error of each vehicle and the energy loss of the best fit of each
/// model and cost function (PIM in the cost function's colour, the tangential model lighter).
/// The figure `models.svg`.
pub fn models(
    records: &[BatchRecord],
    costs: &[pim_fit::CostPreset],
    models: &[pim_fit::FitModel],
) -> Result<Figure, crate::RenderError> {
    let mut tests: Vec<u32> = records.iter().map(|r| r.test).collect();
    tests.dedup();
    let series = |f: &Getter| -> Vec<Series> {
        let mut out = Vec::new();
        for (j, &c) in costs.iter().enumerate() {
            for &m in models {
                let base = COLORS[j % COLORS.len()];
                out.push(Series {
                    name: format!("{} {}", c.name().to_uppercase(), m.name()),
                    values: tests
                        .iter()
                        .map(|&t| {
                            records
                                .iter()
                                .find(|r| {
                                    r.test == t
                                        && r.cost_function == c
                                        && r.model == m
                                        && r.best
                                        && r.solved()
                                })
                                .and_then(f)
                        })
                        .collect(),
                    color: match m {
                        pim_fit::FitModel::Pim => base,
                        pim_fit::FitModel::Tangential => light(base),
                    },
                });
            }
        }
        out
    };
    let figure = svg_figure("models.svg", (1000, 1400), |root| {
        let panels = root.split_evenly((4, 1));
        let getters: [(&str, &str, &Getter); 4] = [
            (
                "Minimum cost per test: PIM (best branch) and the tangential model",
                "cost [(m/s)^2]",
                &|r| r.branch.as_ref().and_then(|b| b.cost),
            ),
            (
                "Relative delta-V error of vehicle 1 ((fitted - measured) / measured)",
                "relative error [%]",
                &|r| r.delta_v_relative_error.map(|e| 100.0 * e[0]),
            ),
            (
                "Relative delta-V error of vehicle 2 ((fitted - measured) / measured)",
                "relative error [%]",
                &|r| r.delta_v_relative_error.map(|e| 100.0 * e[1]),
            ),
            ("Kinetic energy loss", "loss [%]", &|r| {
                r.branch.as_ref().and_then(|b| b.energy_loss_percent)
            }),
        ];
        for (panel, (title, label, f)) in panels.iter().zip(getters) {
            grouped_bars(panel, title, label, &tests, &series(f), &[])?;
        }
        Ok(())
    })?;
    Ok(figure)
}

/// One panel of separation.svg: the separation components `comps` (of the twelve velocities)
/// fitted against measured, per cost function (those that hold them fixed said in the key).
fn separation_panel(
    panel: &Area,
    (title, unit, comps): (&str, &str, &[usize]),
    records: &[BatchRecord],
    costs: &[pim_fit::CostPreset],
    tests: &[u32],
) -> Result<(), crate::RenderError> {
    let mut pts: Vec<(usize, f64, f64)> = Vec::new();
    for (j, &c) in costs.iter().enumerate() {
        // A cost function that holds the separation state fixed (Q1) reproduces it
        // exactly: its points say nothing and are left out.
        if comps.iter().all(|&k| c.holds_fixed(k)) {
            continue;
        }
        for &t in tests {
            if let Some(r) = best_per_cost(records, t, c) {
                if let (Some(e), Some(b)) = (r.velocity_error, r.branch.as_ref()) {
                    let f = b.final_.as_ref().map(|s| s.to_array());
                    if let Some(f) = f {
                        for &k in comps {
                            let fitted = f[k - 6];
                            pts.push((j, fitted - e[k], fitted));
                        }
                    }
                }
            }
        }
    }
    let lim = pts
        .iter()
        .flat_map(|p| [p.1.abs(), p.2.abs()])
        .fold(1.0_f64, f64::max)
        * 1.1;
    let mut chart = ChartBuilder::on(panel)
        .caption(title, ("sans-serif", 16))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(50)
        .build_cartesian_2d(-lim..lim, -lim..lim)
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc(format!("measured [{unit}]"))
        .y_desc(format!("fitted [{unit}]"))
        .x_label_formatter(&|x| tick(*x))
        .y_label_formatter(&|y| tick(*y))
        .max_light_lines(1)
        .draw()
        .map_err(err)?;
    chart
        .draw_series(LineSeries::new([(-lim, -lim), (lim, lim)], BLACK.mix(0.4)))
        .map_err(err)?
        .label("fitted = measured")
        .legend(|(x, y)| PathElement::new([(x, y), (x + 12, y)], BLACK.mix(0.4)));
    for (j, &c) in costs.iter().enumerate() {
        if comps.iter().all(|&k| c.holds_fixed(k)) {
            // Said in the key: the cost function reproduces these exactly.
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(err)?
                .label(format!(
                    "{}: held fixed, not shown",
                    c.name().to_uppercase()
                ))
                .legend(|(x, y)| PathElement::new([(x, y), (x, y)], WHITE));
            continue;
        }
        let color = COLORS[j % COLORS.len()];
        chart
            .draw_series(
                pts.iter()
                    .filter(|p| p.0 == j)
                    .map(|p| Circle::new((p.1, p.2), 3, color.filled())),
            )
            .map_err(err)?
            .label(c.name().to_uppercase())
            .legend(move |(x, y)| Circle::new((x + 5, y), 3, color.filled()));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    Ok(())
}

/// The four figures of a batch: `cost.svg`, `coefficients.svg`, `delta_v.svg` and
/// `separation.svg` (the separation state fitted against measured).
pub fn all(
    records: &[BatchRecord],
    costs: &[pim_fit::CostPreset],
    settings: &pim_fit::FitSettings,
) -> Result<Vec<Figure>, crate::RenderError> {
    let mut tests: Vec<u32> = records.iter().map(|r| r.test).collect();
    tests.dedup();
    let per_cost = |f: &dyn Fn(&BatchRecord) -> Option<f64>| -> Vec<Series> {
        costs
            .iter()
            .enumerate()
            .map(|(j, &c)| Series {
                name: c.name().to_uppercase(),
                values: tests
                    .iter()
                    .map(|&t| best_per_cost(records, t, c).and_then(f))
                    .collect(),
                color: COLORS[j % COLORS.len()],
            })
            .collect()
    };
    let mut figures = Vec::new();

    let figure = svg_figure("cost.svg", (900, 500), |root| {
        grouped_bars(
            root,
            "Minimum cost per test and cost function (best branch)",
            "weighted sum of squares [(m/s)^2]",
            &tests,
            &per_cost(&|r| r.branch.as_ref().and_then(|b| b.cost)),
            &[],
        )?;
        Ok(())
    })?;
    figures.push(figure);

    let figure = svg_figure("coefficients.svg", (900, 1100), |root| {
        let panels = root.split_evenly((3, 1));
        let [elo, ehi] = settings.e;
        let [mlo, mhi] = settings.mu;
        let bound = |value: f64, label: String| Bound { value, label };
        let getters: [(&str, &str, &Getter, Vec<Bound>); 3] = [
            (
                "Restitution e per test (best branch)",
                "e [-]",
                &|r| r.branch.as_ref().and_then(|b| b.e),
                vec![bound(ehi, format!("e = {ehi} bound"))]
                    .into_iter()
                    .chain((elo > 0.0).then(|| bound(elo, format!("e = {elo} bound"))))
                    .collect(),
            ),
            (
                "Moment restitution em per test (best branch)",
                "em [-]",
                &|r| r.branch.as_ref().and_then(|b| b.em),
                vec![
                    bound(-1.0, "em = -1 bound".into()),
                    bound(1.0, "em = 1 (zero)".into()),
                ],
            ),
            (
                "Equivalent friction mu per test (best branch)",
                "mu [-]",
                &|r| r.branch.as_ref().and_then(|b| b.mu),
                vec![
                    bound(mlo, format!("mu = {mlo} bound")),
                    bound(mhi, format!("mu = {mhi} bound")),
                ],
            ),
        ];
        for (panel, (title, label, f, bounds)) in panels.iter().zip(getters) {
            grouped_bars(panel, title, label, &tests, &per_cost(f), &bounds)?;
        }
        Ok(())
    })?;
    figures.push(figure);

    let figure = svg_figure("delta_v.svg", (900, 800), |root| {
        let panels = root.split_evenly((2, 1));
        for (v, panel) in panels.iter().enumerate() {
            grouped_bars(
                panel,
                &format!(
                    "Relative delta-V error of vehicle {} ((fitted - measured) / measured)",
                    v + 1
                ),
                "relative error [%]",
                &tests,
                &per_cost(&|r| r.delta_v_relative_error.map(|e| 100.0 * e[v])),
                &[],
            )?;
        }
        Ok(())
    })?;
    figures.push(figure);

    let figure = svg_figure("separation.svg", (1000, 500), |root| {
        let panels = root.split_evenly((1, 2));
        for (panel, (title, unit, comps)) in panels.iter().zip([
            (
                "Separation velocities: fitted against measured",
                "m/s",
                [6usize, 7, 9, 10].as_slice(),
            ),
            (
                "Separation yaw rates: fitted against measured",
                "rad/s",
                [8usize, 11].as_slice(),
            ),
        ]) {
            separation_panel(panel, (title, unit, comps), records, costs, &tests)?;
        }
        Ok(())
    })?;
    figures.push(figure);
    Ok(figures)
}

/// An axis tick as a person writes it: at most four decimals, no trailing zeros, and never
/// "-0" (a tick at -1e-17 is 0).
pub(crate) fn tick(y: f64) -> String {
    let s = format!("{y:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" || s.is_empty() {
        "0".to_string()
    } else {
        s.to_string()
    }
}
