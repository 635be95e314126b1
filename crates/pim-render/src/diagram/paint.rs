//! Painting a diagram into SVG: outlines, arrows, labels and the key.

use super::{Diagram, IMPULSE_COLOR, PDOF_COLOR, SEPARATION_COLORS, SURFACE_COLOR, VEHICLE_COLORS};
use plotters::prelude::*;

impl Diagram {
    pub(super) fn draw_into(&self, buf: &mut String) -> Result<(), crate::RenderError> {
        let err = |e: &dyn std::fmt::Display| crate::err(e);
        let (lo, hi) = self.extent();
        let units = self.units;
        let len = units.length_label();
        let pad = 0.08 * (hi[0] - lo[0]).max(hi[1] - lo[1]) + units.length(0.5);
        let (x0, x1) = (lo[0] - pad, hi[0] + pad);
        let (y0, y1) = (lo[1] - pad, hi[1] + pad);
        // Equal scale on both axes: the plot's pixel size follows the extent.
        let plot_w = 760.0;
        let px_per_m = plot_w / (x1 - x0);
        let plot_h = ((y1 - y0) * px_per_m).clamp(200.0, 1400.0);
        let (y0, y1) = {
            let mid = 0.5 * (y0 + y1);
            let half = 0.5 * plot_h / px_per_m;
            (mid - half, mid + half)
        };
        let margin_left = 60u32;
        let margin_bottom = 45u32;
        let key_w = 350u32;
        let width = plot_w as u32 + margin_left + 20 + key_w;
        // Tall enough for the key, whatever the plot's shape.
        let mut probe = Key { area: None, y: 30 };
        let (sv, si) = (self.velocity_scale(), self.impulse_scale());
        self.key(&mut probe, sv, si)?;
        let height = (plot_h as u32 + margin_bottom + 40)
            .max(560)
            .max(probe.y as u32 + 20);
        let root = SVGBackend::with_string(buf, (width, height)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&e))?;
        let (plot_area, key_area) = root.split_horizontally(width - key_w);
        let mut chart = ChartBuilder::on(&plot_area)
            .margin(10)
            .margin_top(30)
            .x_label_area_size(margin_bottom)
            .y_label_area_size(margin_left)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|e| err(&e))?;
        // Laid on the page as every figure of the case (SAE: x up, y to the right).
        let page = crate::plan::Page::of(self.frame);
        chart
            .configure_mesh()
            .x_desc(page.horizontal_label(len))
            .y_desc(page.vertical_label(len))
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(225, 225, 225))
            .draw()
            .map_err(|e| err(&e))?;
        let head = 0.035 * (x1 - x0);
        // Labels are placed at the end, clear of each other and of the arrowheads and marks.
        let mut heads: Vec<Head> = Vec::new();
        let mut labels: Vec<Label> = Vec::new();
        self.draw_outlines(&mut chart, &mut labels)?;
        self.draw_vehicle_arrows(&mut chart, (head, sv, si), (&mut heads, &mut labels))?;
        self.draw_surface(&mut chart, head, (&mut heads, &mut labels))?;
        let bar = scale_bar(&mut chart, [x0, x1, y0, y1], len)?;
        self.place_labels(&root, &chart, (&heads, &labels), bar)?;

        // The key, beside the plot.
        let mut key = Key {
            area: Some(&key_area),
            y: 30,
        };
        self.key(&mut key, sv, si)?;
        root.present().map_err(|e| err(&e))?;
        Ok(())
    }

    /// The outlines (filled lightly, the front face thick) and the CGs, each CG's label.
    fn draw_outlines(
        &self,
        chart: &mut Chart,
        labels: &mut Vec<Label>,
    ) -> Result<(), crate::RenderError> {
        let err = |e: &dyn std::fmt::Display| crate::err(e);
        let series: Vec<(Vec<(f64, f64)>, RGBColor)> = VEHICLE_COLORS
            .iter()
            .enumerate()
            .map(|(k, c)| (self.outline_points(k), *c))
            .collect();
        for (k, (pts, color)) in series.iter().enumerate() {
            let mut closed = pts.clone();
            closed.push(pts[0]);
            chart
                .draw_series(std::iter::once(Polygon::new(
                    pts.clone(),
                    color.mix(0.10).filled(),
                )))
                .map_err(|e| err(&e))?;
            chart
                .draw_series(LineSeries::new(
                    closed,
                    ShapeStyle::from(*color).stroke_width(2),
                ))
                .map_err(|e| err(&e))?;
            // The front face, thick: where the nose is.
            chart
                .draw_series(LineSeries::new(
                    vec![pts[0], pts[3]],
                    ShapeStyle::from(*color).stroke_width(6),
                ))
                .map_err(|e| err(&e))?;
            let v = &self.vehicles[k];
            if v.barrier {
                continue;
            }
            chart
                .draw_series(std::iter::once(Circle::new(
                    (v.cg[0], v.cg[1]),
                    5,
                    color.filled(),
                )))
                .map_err(|e| err(&e))?;
            labels.push((format!("CG{}", k + 1), v.cg, 14.0, *color));
        }
        Ok(())
    }

    /// Each vehicle's velocities at contact and separation (drawn `sv` per unit of speed from
    /// its CG), its impulse (`si` per unit from the impact centre), its yaw rate at separation
    /// and its PDOF; arrowheads `head` long, each head and label pushed.
    fn draw_vehicle_arrows(
        &self,
        chart: &mut Chart,
        (head, sv, si): (f64, f64, f64),
        (heads, labels): (&mut Vec<Head>, &mut Vec<Label>),
    ) -> Result<(), crate::RenderError> {
        let err = |e: &dyn std::fmt::Display| crate::err(e);
        let c0 = self.centre;
        let draw_arrow =
            |chart: &mut Chart, from: [f64; 2], to: [f64; 2], color: RGBColor, width: u32| {
                arrow(chart, head, from, to, color, width)
            };
        let l = self.longest();
        for (k, v) in self.vehicles.iter().enumerate() {
            let color = VEHICLE_COLORS[k];
            // The nose is marked by the thick front edge of the outline.
            if let Some(w) = v.contact {
                heads.push(draw_arrow(
                    chart,
                    v.cg,
                    [v.cg[0] + sv * w[0], v.cg[1] + sv * w[1]],
                    color,
                    3,
                )?);
            }
            if let Some(w) = v.separation {
                heads.push(draw_arrow(
                    chart,
                    v.cg,
                    [v.cg[0] + sv * w[0], v.cg[1] + sv * w[1]],
                    SEPARATION_COLORS[k],
                    3,
                )?);
            }
            if let Some(p) = v.impulse {
                // Each vehicle's impulse in its colour, labelled at its tip.
                let tip = [c0[0] + si * p[0], c0[1] + si * p[1]];
                heads.push(draw_arrow(chart, c0, tip, color, 2)?);
                labels.push((format!("on vehicle {}", k + 1), tip, 13.0, color));
            }
            // The yaw rate at separation: an arc about the CG in the sense of rotation, its
            // arrowhead at the end, the rate beside it (a rate below 0.01 rad/s is not drawn).
            if let Some(w) = v.yaw_separation.filter(|w| w.abs() >= 0.01) {
                let r = 0.11 * l;
                let sweep = 200f64.to_radians() * w.signum();
                let a0 = (v.heading + 90.0).to_radians();
                let pts: Vec<(f64, f64)> = (0..=24)
                    .map(|i| {
                        let a = a0 + sweep * i as f64 / 24.0;
                        (v.cg[0] + r * a.cos(), v.cg[1] + r * a.sin())
                    })
                    .collect();
                let n = pts.len();
                chart
                    .draw_series(std::iter::once(PathElement::new(
                        pts[..n - 1].to_vec(),
                        SEPARATION_COLORS[k].stroke_width(2),
                    )))
                    .map_err(|e| err(&e))?;
                let (p, q) = (pts[n - 3], pts[n - 1]);
                heads.push(arrow(
                    chart,
                    0.6 * head,
                    [p.0, p.1],
                    [q.0, q.1],
                    SEPARATION_COLORS[k],
                    2,
                )?);
                let shown = self.frame.sign() * w;
                let a = a0 + 0.5 * sweep;
                labels.push((
                    format!(
                        "{} {}",
                        crate::tables::num(self.units.yaw_rate(shown), 2),
                        self.units.yaw_rate_label()
                    ),
                    [v.cg[0] + r * a.cos(), v.cg[1] + r * a.sin()],
                    12.0,
                    SEPARATION_COLORS[k],
                ));
            }
            if let Some((from, to)) = self.pdof_arrow(k) {
                heads.push(draw_arrow(chart, from, to, PDOF_COLOR, 3)?);
                labels.push((format!("PDOF {}", k + 1), from, 13.0, PDOF_COLOR));
            }
        }
        Ok(())
    }

    /// The crush surface through the impact centre C, its normal n and tangent t.
    fn draw_surface(
        &self,
        chart: &mut Chart,
        head: f64,
        (heads, labels): (&mut Vec<Head>, &mut Vec<Label>),
    ) -> Result<(), crate::RenderError> {
        let err = |e: &dyn std::fmt::Display| crate::err(e);
        let (c0, l) = (self.centre, self.longest());
        let draw_arrow =
            |chart: &mut Chart, from: [f64; 2], to: [f64; 2], color: RGBColor, width: u32| {
                arrow(chart, head, from, to, color, width)
            };
        let n = self.normal;
        let t = [-n[1], n[0]];
        let half = 0.3 * l;
        chart
            .draw_series(LineSeries::new(
                vec![
                    (c0[0] - half * t[0], c0[1] - half * t[1]),
                    (c0[0] + half * t[0], c0[1] + half * t[1]),
                ],
                ShapeStyle::from(SURFACE_COLOR).stroke_width(3),
            ))
            .map_err(|e| err(&e))?;
        let at = |a: f64, d: [f64; 2]| [c0[0] + a * l * d[0], c0[1] + a * l * d[1]];
        heads.push(draw_arrow(chart, c0, at(0.2, n), SURFACE_COLOR, 1)?);
        heads.push(draw_arrow(chart, c0, at(0.12, t), SURFACE_COLOR, 1)?);
        labels.push(("n".into(), at(0.2, n), 14.0, SURFACE_COLOR));
        labels.push(("t".into(), at(0.12, t), 14.0, SURFACE_COLOR));
        chart
            .draw_series(std::iter::once(Cross::new(
                (c0[0], c0[1]),
                7,
                BLACK.stroke_width(2),
            )))
            .map_err(|e| err(&e))?;
        labels.push(("C".into(), c0, 14.0, BLACK));
        Ok(())
    }

    /// The labels, each placed clear of the others, the arrowheads `heads`, the marks (CGs,
    /// C) and the scale bar's label.
    fn place_labels(
        &self,
        root: &DrawingArea<SVGBackend, plotters::coord::Shift>,
        chart: &Chart,
        (heads, labels): (&[Head], &[Label]),
        (bar_at, bar_label): ((f64, f64), String),
    ) -> Result<(), crate::RenderError> {
        let err = |e: &dyn std::fmt::Display| crate::err(e);
        let c0 = self.centre;
        let px = |p: (f64, f64)| chart.backend_coord(&p);
        let mut obstacles: Vec<super::labels::PixelBox> = heads
            .iter()
            .filter(|h| !h.is_empty())
            .map(|h| {
                let pts: Vec<(i32, i32)> = h.iter().map(|p| px(*p)).collect();
                let xs = pts.iter().map(|p| f64::from(p.0));
                let ys = pts.iter().map(|p| f64::from(p.1));
                [
                    xs.clone().fold(f64::INFINITY, f64::min),
                    ys.clone().fold(f64::INFINITY, f64::min),
                    xs.fold(f64::NEG_INFINITY, f64::max),
                    ys.fold(f64::NEG_INFINITY, f64::max),
                ]
            })
            .collect();
        for p in self
            .vehicles
            .iter()
            .filter(|v| !v.barrier)
            .map(|v| (v.cg[0], v.cg[1]))
            .chain([(c0[0], c0[1])])
        {
            let (x, y) = px(p);
            let (x, y) = (f64::from(x), f64::from(y));
            obstacles.push([x - 7.0, y - 7.0, x + 7.0, y + 7.0]);
        }
        // The scale bar's label.
        {
            let (x, y) = px(bar_at);
            let w = super::labels::text_width(&bar_label, super::labels::svg_size(14.0));
            obstacles.push([
                f64::from(x),
                f64::from(y),
                f64::from(x) + w,
                f64::from(y) + 14.0,
            ]);
        }
        let (xr, yr) = chart.plotting_area().get_pixel_range();
        let area = [
            f64::from(xr.start),
            f64::from(yr.start),
            f64::from(xr.end),
            f64::from(yr.end),
        ];
        let to_place: Vec<super::labels::PlotLabel> = labels
            .iter()
            .map(|(text, at, size, color)| super::labels::PlotLabel {
                text: text.clone(),
                at: px((at[0], at[1])),
                size: *size,
                color: *color,
            })
            .collect();
        let spots = super::labels::place(&to_place, &obstacles, area);
        for (l, at) in to_place.iter().zip(spots) {
            root.draw(&Text::new(
                l.text.clone(),
                at,
                ("sans-serif", l.size).into_font().color(&l.color),
            ))
            .map_err(|e| err(&e))?;
        }

        Ok(())
    }

    /// Writes the key's lines (or, with a key without an area, only measures them).
    fn key(&self, key: &mut Key, sv: f64, si: f64) -> Result<(), crate::RenderError> {
        let mut line =
            |text: String, color: Option<RGBColor>, bold: bool| key.line(text, color, bold);
        for (i, part) in crate::text::wrap(&self.title, 36).into_iter().enumerate() {
            line(part, None, i == 0)?;
        }
        if let Some(sub) = &self.subtitle {
            for part in crate::text::wrap(sub, 40) {
                line(part, None, false)?;
            }
        }
        for note in &self.notes {
            for part in crate::text::wrap(note, 40) {
                line(part, Some(RGBColor(180, 0, 0)), false)?;
            }
        }
        line(String::new(), None, false)?;
        for (k, v) in self.vehicles.iter().enumerate() {
            self.vehicle_key(key, k, v)?;
        }
        self.key_legend(key, sv, si)
    }

    /// Vehicle `k`'s lines of the key: its size, where its nose points, its speeds, its yaw
    /// rate at separation and its PDOF.
    fn vehicle_key(
        &self,
        key: &mut Key,
        k: usize,
        v: &super::DrawnVehicle,
    ) -> Result<(), crate::RenderError> {
        let u = self.units;
        let len = u.length_label();
        let sae = self.frame.mirrors();
        let mut line =
            |text: String, color: Option<RGBColor>, bold: bool| key.line(text, color, bold);
        line(v.label.clone(), Some(VEHICLE_COLORS[k]), true)?;
        if v.barrier {
            line("  its face: the crush surface".into(), None, false)?;
            line("  it does not move".into(), None, false)?;
            line(String::new(), None, false)?;
            return Ok(());
        }
        let o = &v.outline;
        line(
            format!(
                "  {:.2} x {:.2} {len}{}",
                o.length(),
                o.width(),
                if o.defaulted {
                    " (typical for its mass)"
                } else {
                    ""
                }
            ),
            None,
            false,
        )?;
        line(
            if sae {
                format!(
                    "  nose towards {} deg clockwise",
                    crate::tables::num(pim_core::wrap_degrees(self.turned - v.heading), 1)
                )
            } else {
                format!(
                    "  nose towards {} deg",
                    crate::tables::num(pim_core::wrap_degrees(v.heading - self.turned), 1)
                )
            },
            None,
            false,
        )?;
        if let Some(w) = v.contact {
            line(
                format!(
                    "  contact {:.2} {}",
                    u.speed(w[0].hypot(w[1])),
                    u.speed_label()
                ),
                Some(VEHICLE_COLORS[k]),
                false,
            )?;
        }
        if let Some(w) = v.separation {
            line(
                format!(
                    "  separation {:.2} {}",
                    u.speed(w[0].hypot(w[1])),
                    u.speed_label()
                ),
                Some(SEPARATION_COLORS[k]),
                false,
            )?;
        }
        if let Some(w) = v.yaw_separation {
            let shown = self.frame.sign() * w;
            line(
                format!(
                    "  separation yaw {} {} (arc)",
                    crate::tables::num(u.yaw_rate(shown), 2),
                    u.yaw_rate_label()
                ),
                Some(SEPARATION_COLORS[k]),
                false,
            )?;
        }
        if let Some((_, pdof, clock)) = v.pdof {
            line(
                format!(
                    "  PDOF {} deg, {clock} o'clock",
                    crate::tables::num(pdof, 0)
                ),
                Some(PDOF_COLOR),
                false,
            )?;
        }
        line(String::new(), None, false)?;
        Ok(())
    }

    /// The key's legend: what the marks and lines show, the arrows' scales and the frame.
    fn key_legend(&self, key: &mut Key, sv: f64, si: f64) -> Result<(), crate::RenderError> {
        let u = self.units;
        let len = u.length_label();
        let sae = self.frame.mirrors();
        let mut line =
            |text: String, color: Option<RGBColor>, bold: bool| key.line(text, color, bold);
        line("thick edge: the front".into(), None, false)?;
        line("C impact centre (x)".into(), None, false)?;
        line("crush surface, n and t".into(), Some(SURFACE_COLOR), false)?;
        if si > 0.0 {
            line(
                "impulse at C, on vehicle 1 / on vehicle 2".into(),
                Some(IMPULSE_COLOR),
                false,
            )?;
        }
        line(String::new(), None, false)?;
        if sv > 0.0 {
            line(
                format!(
                    "velocity arrows: 1 {len} = {:.2} {}",
                    u.speed(1.0 / sv),
                    u.speed_label()
                ),
                None,
                false,
            )?;
        }
        if si > 0.0 {
            line(
                format!(
                    "impulse arrows: 1 {len} = {:.0} {}",
                    u.impulse(1.0 / si),
                    u.impulse_label()
                ),
                None,
                false,
            )?;
        }
        line(
            match (sae, self.centre[0].abs() + self.centre[1].abs() < 1e-12) {
                (true, true) => "SAE frame (x up, y right), C at the origin".into(),
                (true, false) => "SAE frame (x up, y right)".into(),
                (false, true) => "fixed frame, C at the origin".into(),
                (false, false) => "fixed frame of the scene".into(),
            },
            None,
            false,
        )?;
        line(
            format!("yaw rates {} +", self.frame.positive_sense()),
            None,
            false,
        )?;
        line("outlines undeformed: they overlap".into(), None, false)?;
        line("by about the crush at contact".into(), None, false)?;
        Ok(())
    }
}

/// The scale bar (1, 2, 5 ... length units, about a fifth of the width, bottom left of the
/// extent `[x0, x1, y0, y1]`): where its label is and the label.
fn scale_bar(
    chart: &mut Chart,
    [x0, x1, y0, y1]: [f64; 4],
    len: &str,
) -> Result<((f64, f64), String), crate::RenderError> {
    let err = |e: &dyn std::fmt::Display| crate::err(e);
    let span = x1 - x0;
    let bar = [1.0, 2.0, 5.0, 10.0, 20.0, 50.0]
        .into_iter()
        .find(|b| *b >= 0.15 * span)
        .unwrap_or(100.0);
    let bx = x0 + 0.04 * span;
    let by = y0 + 0.05 * (y1 - y0);
    chart
        .draw_series(LineSeries::new(
            vec![(bx, by), (bx + bar, by)],
            BLACK.stroke_width(4),
        ))
        .map_err(|e| err(&e))?;
    let bar_label = format!("{bar} {len}");
    chart
        .draw_series(std::iter::once(Text::new(
            bar_label.clone(),
            (bx, by + 0.03 * (y1 - y0)),
            ("sans-serif", 14).into_font().color(&BLACK),
        )))
        .map_err(|e| err(&e))?;
    Ok(((bx, by + 0.03 * (y1 - y0)), bar_label))
}

/// A label of the plot: its text, where (m), its size and colour.
type Label = (String, [f64; 2], f64, RGBColor);
/// An arrowhead's corners (m).
type Head = Vec<(f64, f64)>;

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draws an arrow from `from` to `to` (m) with a filled head of length `head` (m); returns the
/// head's corners (none for an arrow of no length).
fn arrow(
    chart: &mut Chart,
    head: f64,
    from: [f64; 2],
    to: [f64; 2],
    color: RGBColor,
    width: u32,
) -> Result<Vec<(f64, f64)>, crate::RenderError> {
    let d = [to[0] - from[0], to[1] - from[1]];
    let len = d[0].hypot(d[1]);
    if len <= 0.0 {
        return Ok(Vec::new());
    }
    let u = [d[0] / len, d[1] / len];
    let h = head.min(0.5 * len);
    let base = [to[0] - h * u[0], to[1] - h * u[1]];
    let side = [-u[1] * 0.45 * h, u[0] * 0.45 * h];
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![(from[0], from[1]), (base[0], base[1])],
            color.stroke_width(width),
        )))
        .map_err(crate::err)?;
    let triangle = vec![
        (to[0], to[1]),
        (base[0] + side[0], base[1] + side[1]),
        (base[0] - side[0], base[1] - side[1]),
    ];
    chart
        .draw_series(std::iter::once(Polygon::new(
            triangle.clone(),
            color.filled(),
        )))
        .map_err(crate::err)?;
    Ok(triangle)
}

/// The key beside the plot: one line per element, with its colour.
struct Key<'a, 'b> {
    /// Where to draw; `None` measures only.
    area: Option<&'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>>,
    y: i32,
}

impl Key<'_, '_> {
    fn line(
        &mut self,
        text: String,
        color: Option<RGBColor>,
        bold: bool,
    ) -> Result<(), crate::RenderError> {
        let x = 12i32;
        let y = self.y;
        if text.is_empty() {
            self.y += 8;
            return Ok(());
        }
        let Some(area) = self.area else {
            self.y += 20;
            return Ok(());
        };
        if let Some(c) = color {
            area.draw(&PathElement::new(
                vec![(x, y + 7), (x + 26, y + 7)],
                c.stroke_width(3),
            ))
            .map_err(crate::err)?;
        }
        let f = if bold {
            ("sans-serif", 15).into_font().style(FontStyle::Bold)
        } else {
            ("sans-serif", 14).into_font()
        };
        area.draw(&Text::new(text, (x + 34, y), f))
            .map_err(crate::err)?;
        self.y += 20;
        Ok(())
    }
}
