//! `pim draw`: a to-scale plan view of a collision at contact (plotters, SVG).
//!
//! The fixed frame has the impact centre C at the origin. Drawn: both outlines (from the case's
//! `length`, `width`, `cg_to_front`, or a default by mass class, marked as such), the CGs and
//! noses, C, the crush surface with its normal n and tangent t, the CG velocities at contact
//! (and at separation when solved), the impulse on each vehicle at C, the PDOF arrows, a scale
//! bar and the axes; the thick edge of each outline is its front. A key on the right names every element and states the arrow scales.

use pim_core::{Impact, VehicleId, VehicleResult, Velocities};
use pim_data::case::VehicleSection;
use plotters::prelude::*;
use std::path::Path;

const VEHICLE_COLORS: [RGBColor; 2] = [RGBColor(31, 119, 180), RGBColor(214, 39, 40)];
const SEPARATION_COLORS: [RGBColor; 2] = [RGBColor(120, 170, 215), RGBColor(240, 140, 140)];
const IMPULSE_COLOR: RGBColor = RGBColor(40, 40, 40);
const SURFACE_COLOR: RGBColor = RGBColor(44, 160, 44);
const PDOF_COLOR: RGBColor = RGBColor(148, 103, 189);

/// A plan-view outline about the CG, m.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Outline {
    /// CG to the front face.
    pub front: f64,
    /// CG to the rear face.
    pub rear: f64,
    /// Overall width.
    pub width: f64,
    /// True when the dimensions are defaults for the mass class, not the case's.
    pub defaulted: bool,
}

/// Typical length and width of a passenger vehicle of this mass, m (small car, compact,
/// mid-size, full-size / light truck).
fn class_dimensions(mass: f64) -> (f64, f64) {
    match mass {
        m if m < 1100.0 => (3.9, 1.65),
        m if m < 1500.0 => (4.4, 1.75),
        m if m < 2000.0 => (4.85, 1.85),
        _ => (5.3, 2.0),
    }
}

impl Outline {
    /// The case's outline, or the default of its mass class enlarged (if needed) to reach the
    /// impact centre at `point` (body frame, m).
    pub fn of(v: &VehicleSection, point: [f64; 2]) -> Self {
        match (v.length, v.width) {
            (Some(length), Some(width)) => {
                let front = v.cg_to_front.unwrap_or(length / 2.0);
                Outline {
                    front,
                    rear: length - front,
                    width,
                    defaulted: false,
                }
            }
            (length, width) => {
                let (l, w) = class_dimensions(v.mass);
                let length = length.unwrap_or(l);
                let width = width.unwrap_or(w);
                let front = v.cg_to_front.unwrap_or(length / 2.0);
                Outline {
                    front: front.max(point[0]),
                    rear: (length - front).max(-point[0]),
                    width: width.max(2.0 * point[1].abs()),
                    defaulted: true,
                }
            }
        }
    }

    /// Corners in the body frame, counter-clockwise from front left.
    fn corners(&self) -> [[f64; 2]; 4] {
        let h = self.width / 2.0;
        [
            [self.front, h],
            [-self.rear, h],
            [-self.rear, -h],
            [self.front, -h],
        ]
    }

    /// Distance from the CG to the outline along the body-frame unit direction `w`.
    fn exit(&self, w: [f64; 2]) -> f64 {
        let mut t = f64::INFINITY;
        if w[0] > 1e-12 {
            t = t.min(self.front / w[0]);
        }
        if w[0] < -1e-12 {
            t = t.min(self.rear / -w[0]);
        }
        if w[1].abs() > 1e-12 {
            t = t.min(0.5 * self.width / w[1].abs());
        }
        t
    }

    /// Length, m.
    pub fn length(&self) -> f64 {
        self.front + self.rear
    }
}

/// What is drawn for one vehicle.
#[derive(Debug, Clone)]
pub struct DrawnVehicle {
    /// Label, e.g. `vehicle 1 (striking car)`.
    pub label: String,
    /// Its outline.
    pub outline: Outline,
    /// Nose direction, degrees counter-clockwise from +x.
    pub heading: f64,
    /// CG position (C at the origin), m.
    pub cg: [f64; 2],
    /// CG velocity at contact, m/s.
    pub contact: Option<[f64; 2]>,
    /// CG velocity at separation, m/s.
    pub separation: Option<[f64; 2]>,
    /// Impulse on this vehicle, N s.
    pub impulse: Option<[f64; 2]>,
    /// Delta-V direction (fixed frame, unit) with PDOF and clock, when solved.
    pub pdof: Option<([f64; 2], f64, u8)>,
    /// A fixed barrier: drawn as a wall along the crush surface, its face through C.
    pub barrier: bool,
}

/// A whole diagram.
#[derive(Debug, Clone)]
pub struct Diagram {
    /// First line of the key.
    pub title: String,
    /// Both vehicles.
    pub vehicles: [DrawnVehicle; 2],
    /// Unit normal of the crush surface.
    pub normal: [f64; 2],
}

/// The states and results of a solved (or fitted) collision.
pub struct Solved<'a> {
    /// Contact velocities.
    pub initial: &'a Velocities,
    /// Separation velocities.
    pub separation: &'a Velocities,
    /// Impulse on vehicle 1 `(Px, Py)`, N s.
    pub impulse: [f64; 2],
    /// Per-vehicle results.
    pub vehicles: &'a [VehicleResult; 2],
}

impl<'a> Solved<'a> {
    /// The states and results of a solve.
    pub fn of_report(r: &'a pim_core::ImpactReport) -> Self {
        Solved {
            initial: &r.initial,
            separation: &r.separation,
            impulse: [r.impulse.px, r.impulse.py],
            vehicles: &r.vehicles,
        }
    }

    /// The states and results of a fitted branch.
    pub fn of_fit(s: &'a pim_fit::Solution) -> Self {
        Solved {
            initial: &s.initial,
            separation: &s.separation,
            impulse: [s.impulse.px, s.impulse.py],
            vehicles: &s.vehicles,
        }
    }
}

/// A barrier as a wall: its face on the crush surface through C, 0.3 m thick on the side away
/// from vehicle 1's CG, as long as 1.2 times vehicle 1.
fn barrier_wall(impact: &Impact, vehicle1: &DrawnVehicle) -> DrawnVehicle {
    let n = impact.normal();
    let cg1 = vehicle1.cg;
    // Unit normal towards vehicle 1's side.
    let towards = if cg1[0] * n[0] + cg1[1] * n[1] >= 0.0 {
        n
    } else {
        [-n[0], -n[1]]
    };
    let thick = 0.3;
    let length = 1.2 * vehicle1.outline.length();
    DrawnVehicle {
        label: "barrier (fixed, rigid)".to_string(),
        outline: Outline {
            front: thick / 2.0,
            rear: thick / 2.0,
            width: length,
            defaulted: false,
        },
        heading: towards[1].atan2(towards[0]).to_degrees(),
        cg: [-towards[0] * thick / 2.0, -towards[1] * thick / 2.0],
        contact: None,
        separation: None,
        impulse: None,
        pdof: None,
        barrier: true,
    }
}

fn rotate(p: [f64; 2], deg: f64) -> [f64; 2] {
    let (s, c) = deg.to_radians().sin_cos();
    [c * p[0] - s * p[1], s * p[0] + c * p[1]]
}

impl Diagram {
    /// Builds the diagram of a collision, with contact velocities only (`contact`) or a solved
    /// state (`solved`).
    pub fn new(
        title: &str,
        impact: &Impact,
        sections: [&VehicleSection; 2],
        contact: Option<&Velocities>,
        solved: Option<Solved>,
    ) -> Self {
        let cgs = impact.cg_positions();
        let arms = impact.lever_arms();
        let vehicle = |k: usize| {
            let id = VehicleId::from_index(k);
            let point = impact.to_body(id, arms[k]);
            let sec = sections[k];
            let label = match &sec.description {
                Some(d) => format!("vehicle {} ({d})", k + 1),
                None => format!("vehicle {}", k + 1),
            };
            let v = |s: &Velocities| {
                let x = s.vehicle(id);
                [x.vx, x.vy]
            };
            let sign = if k == 0 { 1.0 } else { -1.0 };
            DrawnVehicle {
                label,
                outline: Outline::of(sec, point),
                heading: impact.nose_heading(id),
                cg: cgs[k],
                contact: solved.as_ref().map(|s| v(s.initial)).or(contact.map(&v)),
                separation: solved.as_ref().map(|s| v(s.separation)),
                impulse: solved
                    .as_ref()
                    .map(|s| [sign * s.impulse[0], sign * s.impulse[1]]),
                pdof: solved.as_ref().and_then(|s| {
                    let r = &s.vehicles[k];
                    let a = s.initial.vehicle(id);
                    let b = s.separation.vehicle(id);
                    let d = [b.vx - a.vx, b.vy - a.vy];
                    let n = d[0].hypot(d[1]);
                    (n > 0.0).then(|| ([d[0] / n, d[1] / n], r.pdof, r.clock))
                }),
                barrier: false,
            }
        };
        Diagram {
            title: title.to_string(),
            vehicles: {
                let first = vehicle(0);
                let second = if impact.is_barrier() {
                    barrier_wall(impact, &first)
                } else {
                    vehicle(1)
                };
                [first, second]
            },
            normal: impact.normal(),
        }
    }

    /// The PDOF arrow of vehicle `k`: along the force, from outside the outline to its edge,
    /// aimed at the CG.
    fn pdof_arrow(&self, k: usize) -> Option<([f64; 2], [f64; 2])> {
        let v = &self.vehicles[k];
        let (u, _, _) = v.pdof?;
        let back = rotate([-u[0], -u[1]], -v.heading);
        let edge = v.outline.exit(back) + 0.05 * self.longest();
        let len = 0.35 * self.longest();
        // Beside the line through the CG, where the velocity arrows often lie.
        let off = 0.06 * self.longest();
        let side = [-u[1] * off, u[0] * off];
        let end = [
            v.cg[0] - edge * u[0] + side[0],
            v.cg[1] - edge * u[1] + side[1],
        ];
        let start = [end[0] - len * u[0], end[1] - len * u[1]];
        Some((start, end))
    }

    fn outline_points(&self, k: usize) -> Vec<(f64, f64)> {
        let v = &self.vehicles[k];
        v.outline
            .corners()
            .iter()
            .map(|c| {
                let p = rotate(*c, v.heading);
                (v.cg[0] + p[0], v.cg[1] + p[1])
            })
            .collect()
    }

    /// Metres of arrow per m/s, so that the longest velocity arrow is 0.6 of the longer vehicle.
    fn velocity_scale(&self) -> f64 {
        let max = self
            .vehicles
            .iter()
            .flat_map(|v| [v.contact, v.separation])
            .flatten()
            .map(|u| u[0].hypot(u[1]))
            .fold(0.0, f64::max);
        if max > 0.0 {
            0.6 * self.longest() / max
        } else {
            0.0
        }
    }

    /// Metres of arrow per N s: the impulse arrow is 0.5 of the longer vehicle.
    fn impulse_scale(&self) -> f64 {
        let max = self
            .vehicles
            .iter()
            .filter_map(|v| v.impulse)
            .map(|u| u[0].hypot(u[1]))
            .fold(0.0, f64::max);
        if max > 0.0 {
            0.5 * self.longest() / max
        } else {
            0.0
        }
    }

    fn longest(&self) -> f64 {
        self.vehicles
            .iter()
            .map(|v| v.outline.length())
            .fold(0.0, f64::max)
    }

    /// Every segment drawn (for the extent of the view).
    fn extent(&self) -> ([f64; 2], [f64; 2]) {
        let mut pts: Vec<[f64; 2]> = vec![[0.0, 0.0]];
        let sv = self.velocity_scale();
        let si = self.impulse_scale();
        for (k, v) in self.vehicles.iter().enumerate() {
            pts.extend(self.outline_points(k).iter().map(|p| [p.0, p.1]));
            for u in [v.contact, v.separation].into_iter().flatten() {
                pts.push([v.cg[0] + sv * u[0], v.cg[1] + sv * u[1]]);
            }
            if let Some(p) = v.impulse {
                pts.push([si * p[0], si * p[1]]);
            }
            if let Some((a, _)) = self.pdof_arrow(k) {
                pts.push(a);
            }
        }
        let lo = pts
            .iter()
            .fold([f64::INFINITY; 2], |a, p| [a[0].min(p[0]), a[1].min(p[1])]);
        let hi = pts.iter().fold([f64::NEG_INFINITY; 2], |a, p| {
            [a[0].max(p[0]), a[1].max(p[1])]
        });
        (lo, hi)
    }

    /// Writes the SVG.
    pub fn write_svg(&self, path: &Path) -> Result<(), String> {
        let svg = self.svg()?;
        std::fs::write(path, svg).map_err(|e| format!("{}: {e}", path.display()))
    }

    /// The diagram as SVG text.
    pub fn svg(&self) -> Result<String, String> {
        let mut buf = String::new();
        self.draw_into(&mut buf)?;
        Ok(buf)
    }

    fn draw_into(&self, buf: &mut String) -> Result<(), String> {
        let err = |e: &dyn std::fmt::Display| e.to_string();
        let (lo, hi) = self.extent();
        let pad = 0.08 * (hi[0] - lo[0]).max(hi[1] - lo[1]) + 0.5;
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
        let height = (plot_h as u32 + margin_bottom + 40).max(560);
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
        chart
            .configure_mesh()
            .x_desc("x [m]")
            .y_desc("y [m]")
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(225, 225, 225))
            .draw()
            .map_err(|e| err(&e))?;
        let head = 0.035 * (x1 - x0);
        let span_m = x1 - x0;
        let draw_arrow =
            |chart: &mut Chart, from: [f64; 2], to: [f64; 2], color: RGBColor, width: u32| {
                arrow(chart, head, from, to, color, width)
            };
        // Outlines, noses and CGs.
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
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("CG{}", k + 1),
                    (v.cg[0] + 0.02 * span_m, v.cg[1] + 0.045 * span_m),
                    ("sans-serif", 14).into_font().color(color),
                )))
                .map_err(|e| err(&e))?;
        }
        let sv = self.velocity_scale();
        let si = self.impulse_scale();
        let l = self.longest();
        for (k, v) in self.vehicles.iter().enumerate() {
            let color = VEHICLE_COLORS[k];
            // The nose is marked by the thick front edge of the outline.
            if let Some(u) = v.contact {
                draw_arrow(
                    &mut chart,
                    v.cg,
                    [v.cg[0] + sv * u[0], v.cg[1] + sv * u[1]],
                    color,
                    3,
                )?;
            }
            if let Some(u) = v.separation {
                draw_arrow(
                    &mut chart,
                    v.cg,
                    [v.cg[0] + sv * u[0], v.cg[1] + sv * u[1]],
                    SEPARATION_COLORS[k],
                    3,
                )?;
            }
            if let Some(p) = v.impulse {
                draw_arrow(
                    &mut chart,
                    [0.0, 0.0],
                    [si * p[0], si * p[1]],
                    IMPULSE_COLOR,
                    2,
                )?;
            }
            if let Some((from, to)) = self.pdof_arrow(k) {
                draw_arrow(&mut chart, from, to, PDOF_COLOR, 3)?;
                chart
                    .draw_series(std::iter::once(Text::new(
                        format!("PDOF {}", k + 1),
                        (from[0], from[1]),
                        ("sans-serif", 13).into_font().color(&PDOF_COLOR),
                    )))
                    .map_err(|e| err(&e))?;
            }
        }
        // Crush surface through C, n and t.
        let n = self.normal;
        let t = [-n[1], n[0]];
        let half = 0.3 * l;
        chart
            .draw_series(LineSeries::new(
                vec![(-half * t[0], -half * t[1]), (half * t[0], half * t[1])],
                ShapeStyle::from(SURFACE_COLOR).stroke_width(3),
            ))
            .map_err(|e| err(&e))?;
        draw_arrow(
            &mut chart,
            [0.0; 2],
            [0.2 * l * n[0], 0.2 * l * n[1]],
            SURFACE_COLOR,
            1,
        )?;
        draw_arrow(
            &mut chart,
            [0.0; 2],
            [0.12 * l * t[0], 0.12 * l * t[1]],
            SURFACE_COLOR,
            1,
        )?;
        let label = |text: &str, at: [f64; 2], color: RGBColor| {
            Text::new(
                text.to_string(),
                (at[0], at[1]),
                ("sans-serif", 14).into_font().color(&color),
            )
        };
        chart
            .draw_series([
                label("n", [0.22 * l * n[0], 0.22 * l * n[1]], SURFACE_COLOR),
                label("t", [0.14 * l * t[0], 0.14 * l * t[1]], SURFACE_COLOR),
            ])
            .map_err(|e| err(&e))?;
        chart
            .draw_series(std::iter::once(Cross::new(
                (0.0, 0.0),
                7,
                BLACK.stroke_width(2),
            )))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(std::iter::once(label("C", [0.03 * l, -0.07 * l], BLACK)))
            .map_err(|e| err(&e))?;
        // Scale bar: 1, 2 or 5 m, about a fifth of the width, bottom left.
        let span = x1 - x0;
        let bar = [1.0, 2.0, 5.0, 10.0]
            .into_iter()
            .find(|b| *b >= 0.15 * span)
            .unwrap_or(20.0);
        let bx = x0 + 0.04 * span;
        let by = y0 + 0.05 * (y1 - y0);
        chart
            .draw_series(LineSeries::new(
                vec![(bx, by), (bx + bar, by)],
                BLACK.stroke_width(4),
            ))
            .map_err(|e| err(&e))?;
        chart
            .draw_series(std::iter::once(label(
                &format!("{bar} m"),
                [bx, by + 0.03 * (y1 - y0)],
                BLACK,
            )))
            .map_err(|e| err(&e))?;

        // The key.
        let mut key = Key {
            area: &key_area,
            y: 30,
        };
        let mut line =
            |text: String, color: Option<RGBColor>, bold: bool| key.line(text, color, bold);
        for (i, part) in wrap(&self.title, 36).into_iter().enumerate() {
            line(part, None, i == 0)?;
        }
        line(String::new(), None, false)?;
        for (k, v) in self.vehicles.iter().enumerate() {
            line(v.label.clone(), Some(VEHICLE_COLORS[k]), true)?;
            if v.barrier {
                line("  its face: the crush surface".into(), None, false)?;
                line("  it does not move".into(), None, false)?;
                line(String::new(), None, false)?;
                continue;
            }
            let o = &v.outline;
            line(
                format!(
                    "  {:.2} x {:.2} m{}",
                    o.length(),
                    o.width,
                    if o.defaulted {
                        " (typical for its mass)"
                    } else {
                        ""
                    }
                ),
                None,
                false,
            )?;
            line(format!("  nose towards {:.1} deg", v.heading), None, false)?;
            if let Some(u) = v.contact {
                line(
                    format!("  contact {:.2} m/s", u[0].hypot(u[1])),
                    Some(VEHICLE_COLORS[k]),
                    false,
                )?;
            }
            if let Some(u) = v.separation {
                line(
                    format!("  separation {:.2} m/s", u[0].hypot(u[1])),
                    Some(SEPARATION_COLORS[k]),
                    false,
                )?;
            }
            if let Some((_, pdof, clock)) = v.pdof {
                line(
                    format!("  PDOF {pdof:.0} deg, {clock} o'clock"),
                    Some(PDOF_COLOR),
                    false,
                )?;
            }
            line(String::new(), None, false)?;
        }
        line("thick edge: the front".into(), None, false)?;
        line("C impact centre (x)".into(), None, false)?;
        line("crush surface, n and t".into(), Some(SURFACE_COLOR), false)?;
        if si > 0.0 {
            line(
                "impulse on each vehicle at C".into(),
                Some(IMPULSE_COLOR),
                false,
            )?;
        }
        line(String::new(), None, false)?;
        if sv > 0.0 {
            line(
                format!("velocity arrows: 1 m = {:.2} m/s", 1.0 / sv),
                None,
                false,
            )?;
        }
        if si > 0.0 {
            line(
                format!("impulse arrows: 1 m = {:.0} N s", 1.0 / si),
                None,
                false,
            )?;
        }
        line("fixed frame, C at the origin".into(), None, false)?;
        line("outlines undeformed: they overlap".into(), None, false)?;
        line("by about the crush at contact".into(), None, false)?;
        root.present().map_err(|e| err(&e))?;
        Ok(())
    }
}

type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// Draws an arrow from `from` to `to` (m) with a filled head of length `head` (m).
fn arrow(
    chart: &mut Chart,
    head: f64,
    from: [f64; 2],
    to: [f64; 2],
    color: RGBColor,
    width: u32,
) -> Result<(), String> {
    let d = [to[0] - from[0], to[1] - from[1]];
    let len = d[0].hypot(d[1]);
    if len <= 0.0 {
        return Ok(());
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
        .map_err(|e| e.to_string())?;
    chart
        .draw_series(std::iter::once(Polygon::new(
            vec![
                (to[0], to[1]),
                (base[0] + side[0], base[1] + side[1]),
                (base[0] - side[0], base[1] - side[1]),
            ],
            color.filled(),
        )))
        .map_err(|e| e.to_string())?;
    Ok(())
}

/// The key beside the plot: one line per element, with its colour.
struct Key<'a, 'b> {
    area: &'a DrawingArea<SVGBackend<'b>, plotters::coord::Shift>,
    y: i32,
}

impl Key<'_, '_> {
    fn line(&mut self, text: String, color: Option<RGBColor>, bold: bool) -> Result<(), String> {
        let x = 12i32;
        let y = self.y;
        if text.is_empty() {
            self.y += 8;
            return Ok(());
        }
        if let Some(c) = color {
            self.area
                .draw(&PathElement::new(
                    vec![(x, y + 7), (x + 26, y + 7)],
                    c.stroke_width(3),
                ))
                .map_err(|e| e.to_string())?;
        }
        let f = if bold {
            ("sans-serif", 15).into_font().style(FontStyle::Bold)
        } else {
            ("sans-serif", 14).into_font()
        };
        self.area
            .draw(&Text::new(text, (x + 34, y), f))
            .map_err(|e| e.to_string())?;
        self.y += 20;
        Ok(())
    }
}

/// Splits text into lines of at most `width` characters at spaces.
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut out = Vec::new();
    for para in text.lines() {
        let mut cur = String::new();
        for word in para.split_whitespace() {
            if !cur.is_empty() && cur.len() + 1 + word.len() > width {
                out.push(std::mem::take(&mut cur));
            }
            if !cur.is_empty() {
                cur.push(' ');
            }
            cur.push_str(word);
        }
        if !cur.is_empty() {
            out.push(cur);
        }
    }
    out
}

/// The estimated contact velocities of a fit case, when all six are given.
pub fn estimated_contact(case: &pim_data::case::Case) -> Option<Velocities> {
    let est = case.content.estimates?.initial?.components();
    let v: Option<Vec<f64>> = est.iter().copied().collect();
    v.map(|v| Velocities::from_vector(&nalgebra::Vector6::new(v[0], v[1], v[2], v[3], v[4], v[5])))
}

/// The diagram of a case, solved or not.
pub fn diagram(
    case: &pim_data::case::Case,
    impact: &Impact,
    contact: Option<&Velocities>,
    solved: Option<Solved>,
) -> Diagram {
    let title = match &case.content.title {
        Some(t) => t.clone(),
        None => case.file.clone(),
    };
    Diagram::new(
        &title,
        impact,
        [&case.content.vehicle1, &case.content.vehicle2],
        contact,
        solved,
    )
}

/// The diagram of `pim draw`: the case at contact, solved with `options` when it has
/// `[coefficients]` and a state, with the estimated contact velocities when it is a fit case.
pub fn case_diagram(
    case: &pim_data::case::Case,
    options: &pim_core::SolveOptions,
) -> Result<Diagram, pim_data::documents::DocumentError> {
    let impact = case.impact()?;
    let c = &case.content;
    let solved = if c.coefficients.is_some() && (c.initial.is_some() || c.final_.is_some()) {
        Some(pim_data::documents::solve(case, options)?.report)
    } else {
        None
    };
    let contact = estimated_contact(case);
    Ok(diagram(
        case,
        &impact,
        contact.as_ref(),
        solved.as_ref().map(Solved::of_report),
    ))
}
