//! The plan view of run-outs to scale: each vehicle's path and outlines, the braking before the
//! impact, the scene's evidence and the key beside them.

use crate::tables::num;
use crate::text::wrap;
use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_runout::{Evidence, Motion};
use pim_studies::runout::{RunoutResult, Source};
use plotters::coord::Shift;
use plotters::prelude::*;

const COLORS: [RGBColor; 2] = [RGBColor(31, 119, 180), RGBColor(214, 39, 40)];
const LIGHT: [RGBColor; 2] = [RGBColor(160, 195, 225), RGBColor(240, 160, 160)];
const EVIDENCE: RGBColor = RGBColor(40, 40, 40);

/// The outline of a vehicle (length, width, CG to front) for drawing, m.
pub(crate) fn outline_of(r: &RunoutResult, k: usize) -> (f64, f64, f64) {
    let c = &r.inputs[k].chassis;
    let length = c.length.unwrap_or(c.wheelbase + 1.9);
    let width = c.width.unwrap_or(c.track + 0.25);
    let front = c
        .cg_to_front
        .unwrap_or(c.cg_to_front_axle + 0.5 * (length - c.wheelbase));
    (length, width, front)
}

pub(crate) fn corners(m: &Motion, (length, width, front): (f64, f64, f64)) -> Vec<(f64, f64)> {
    let body = [
        [front, width / 2.0],
        [front, -width / 2.0],
        [front - length, -width / 2.0],
        [front - length, width / 2.0],
        [front, width / 2.0],
    ];
    body.iter().map(|&p| m.point(p)).collect()
}

/// Vehicle `k`'s outline at separation (where the run-out starts: its pose at contact) as the
/// scene figure draws it: on the page of the case's `frame` ([`crate::plan::Page`]), in the
/// display length unit of `units`.
pub fn start_outline_on_page(
    r: &RunoutResult,
    k: usize,
    units: UnitSystem,
    frame: Convention,
) -> Vec<(f64, f64)> {
    outline_on_page(r, k, &r.runouts[k].start, units, frame)
}

/// Vehicle `k`'s outline in the pose `m` (natural frame, SI), on the page of `frame` in the
/// display length unit of `units`: the closed outline's five corners.
pub fn outline_on_page(
    r: &RunoutResult,
    k: usize,
    m: &Motion,
    units: UnitSystem,
    frame: Convention,
) -> Vec<(f64, f64)> {
    let page = crate::plan::Page::of(frame);
    corners(m, outline_of(r, k))
        .into_iter()
        .map(|(x, y)| page.xy((units.length(x), units.length(y))))
        .collect()
}

/// Braking marks before the impact, for the plan view of a reconstruction: the vehicle braked
/// over `length` metres straight up to its position at contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Approach {
    /// Which vehicle.
    pub vehicle: pim_core::VehicleId,
    /// Length of the marks up to contact, m.
    pub length: f64,
}

/// The path of each tyre that left one of `evidence`'s marks over the run-out `run` (one per
/// tyre, finely interpolated, m): a mark's residual is its distance from it.
pub fn tyre_traces(
    run: &pim_runout::Runout,
    evidence: Option<&pim_runout::Evidence>,
) -> Vec<Vec<(f64, f64)>> {
    let mut points: Vec<[f64; 2]> = Vec::new();
    for m in evidence.iter().flat_map(|e| &e.marks) {
        if m.point != [0.0, 0.0] && !points.contains(&m.point) {
            points.push(m.point);
        }
    }
    let n = 400;
    points
        .into_iter()
        .map(|p| {
            (0..=n)
                .map(|i| run.at(run.time * i as f64 / n as f64).point(p))
                .collect()
        })
        .collect()
}

/// The chart of the plan, in display units on the page.
type Chart<'a, 'b> = ChartContext<
    'a,
    SVGBackend<'b>,
    Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>,
>;

/// A point of the scene (m, the natural frame) on the page, in display units.
type ToPage<'a> = &'a dyn Fn((f64, f64)) -> (f64, f64);

/// Two tyre tracks of braking before the impact, each from the position at contact back.
type Tracks = Vec<[(f64, f64); 2]>;

/// The plan view of [`runout_svg`](crate::runout::runout_svg) with the approach of each
/// vehicle that braked before the impact: its two tyre tracks over the braking distance up to
/// its position at contact.
pub fn scene_svg(
    title: &str,
    r: &RunoutResult,
    approach: &[Approach],
    units: UnitSystem,
    frame: Convention,
    every: f64,
) -> Result<String, crate::RenderError> {
    // Everything in display units, laid on the page as every figure of the case is (SAE: x up,
    // y to the right).
    let page = crate::plan::Page::of(frame);
    let to = |(x, y): (f64, f64)| page.xy((units.length(x), units.length(y)));
    let tracks: Vec<Tracks> = (0..r.runouts.len())
        .map(|k| approach_tracks(r, approach, k))
        .collect();
    let [x0, x1, mut y0, mut y1] = extent(r, &tracks, &to, units)?;
    let plot_w = 760.0;
    let px = plot_w / (x1 - x0);
    let plot_h = ((y1 - y0) * px).clamp(240.0, 1400.0);
    let mid = 0.5 * (y0 + y1);
    let half = 0.5 * plot_h / px;
    (y0, y1) = (mid - half, mid + half);
    let key_w = 330u32;
    let width = plot_w as u32 + 80 + key_w;
    let height = (plot_h as u32 + 90).max(420);
    let mut buf = String::new();
    {
        let root = SVGBackend::with_string(&mut buf, (width, height)).into_drawing_area();
        let e = |e: &dyn std::fmt::Display| crate::err(e);
        root.fill(&WHITE).map_err(|x| e(&x))?;
        let (plot, key) = root.split_horizontally(width - key_w);
        let len = units.length_label();
        let mut chart = ChartBuilder::on(&plot)
            .margin(10)
            .margin_top(30)
            .x_label_area_size(45)
            .y_label_area_size(60)
            .build_cartesian_2d(x0..x1, y0..y1)
            .map_err(|x| e(&x))?;
        chart
            .configure_mesh()
            .x_desc(page.horizontal_label(len))
            .y_desc(page.vertical_label(len))
            .light_line_style(RGBColor(240, 240, 240))
            .bold_line_style(RGBColor(225, 225, 225))
            .draw()
            .map_err(|x| e(&x))?;
        let zones = r.inputs.first().map_or(&[][..], |v| &v.chassis.zones[..]);
        crate::ground::draw_zones(&mut chart, zones, to, [x0, x1, y0, y1]).map_err(|x| e(&x))?;
        for (k, marks) in tracks.iter().enumerate() {
            draw_vehicle(&mut chart, (r, k), marks, (&to, units, frame, every))?;
            if let Some(ev) = &r.inputs[k].evidence {
                draw_evidence(&mut chart, (r, k), ev, (&to, units))?;
            }
        }
        draw_key(&key, title, (r, approach), (units, frame, every))?;
        root.present().map_err(|x| e(&x))?;
    }
    Ok(buf)
}

/// Vehicle `k`'s braking before the impact (where `approach` gives it): its two tyre tracks,
/// each from its position at contact back over the braking distance, m.
fn approach_tracks(r: &RunoutResult, approach: &[Approach], k: usize) -> Tracks {
    let v = &r.inputs[k];
    let Some(a) = approach.iter().find(|a| a.vehicle == v.id) else {
        return Vec::new();
    };
    let s = &r.runouts[k].start;
    let (f, n) = (
        (s.heading.cos(), s.heading.sin()),
        (-s.heading.sin(), s.heading.cos()),
    );
    [-0.5, 0.5]
        .iter()
        .map(|side| {
            let o = side * v.chassis.track;
            let front = (s.x + o * n.0, s.y + o * n.1);
            [front, (front.0 - a.length * f.0, front.1 - a.length * f.1)]
        })
        .collect()
}

/// The page's extent `[x0, x1, y0, y1]` (display units): every outline of every run-out, the
/// evidence and the braking tracks, padded.
fn extent(
    r: &RunoutResult,
    tracks: &[Tracks],
    to: ToPage,
    units: UnitSystem,
) -> Result<[f64; 4], crate::RenderError> {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    let mut grow = |p: (f64, f64)| {
        lo = [lo[0].min(p.0), lo[1].min(p.1)];
        hi = [hi[0].max(p.0), hi[1].max(p.1)];
    };
    for (k, run) in r.runouts.iter().enumerate() {
        let dims = outline_of(r, k);
        for s in &run.steps {
            corners(&s.motion, dims)
                .into_iter()
                .map(to)
                .for_each(&mut grow);
        }
        if let Some(ev) = &r.inputs[k].evidence {
            if let Some(rest) = &ev.rest {
                grow(to(rest.cg()));
            }
            for m in &ev.marks {
                grow(to((m.x, m.y)));
            }
        }
    }
    for t in tracks.iter().flatten() {
        t.iter().copied().map(to).for_each(&mut grow);
    }
    if !lo.iter().chain(&hi).all(|x| x.is_finite()) {
        return Err(crate::RenderError::NotFinite("a position of the run-out"));
    }
    let pad = 0.06 * (hi[0] - lo[0]).max(hi[1] - lo[1]) + units.length(1.0);
    Ok([lo[0] - pad, hi[0] + pad, lo[1] - pad, hi[1] + pad])
}

/// Vehicle `k`'s run-out: its outlines every `every` seconds, its CG path, its braking marks
/// before the impact, its outline at separation (bold) and at rest (filled).
fn draw_vehicle(
    chart: &mut Chart,
    (r, k): (&RunoutResult, usize),
    marks: &[[(f64, f64); 2]],
    (to, units, frame, every): (ToPage, UnitSystem, Convention, f64),
) -> Result<(), crate::RenderError> {
    let e = |e: &dyn std::fmt::Display| crate::err(e);
    let run = &r.runouts[k];
    let color = COLORS[(r.inputs[k].id.index()).min(1)];
    let light = LIGHT[(r.inputs[k].id.index()).min(1)];
    let dims = outline_of(r, k);
    // Outlines at regular times.
    if every > 0.0 {
        for (t, m) in run.sample(every) {
            if t > 0.0 && t < run.time {
                let pts: Vec<_> = corners(&m, dims).into_iter().map(to).collect();
                stroke(chart, pts, light.stroke_width(1))?;
            }
        }
    }
    // The CG path, finely interpolated.
    let n = 400;
    let cg: Vec<(f64, f64)> = (0..=n)
        .map(|i| {
            let m = run.at(run.time * i as f64 / n as f64);
            to((m.x, m.y))
        })
        .collect();
    stroke(chart, cg, color.stroke_width(2))?;
    // Braking marks before the impact, up to the position at contact.
    for t in marks {
        stroke(
            chart,
            vec![to(t[0]), to(t[1])],
            EVIDENCE.mix(0.7).stroke_width(3),
        )?;
    }
    if let Some(t) = marks.first() {
        let length = (t[1].0 - t[0].0).hypot(t[1].1 - t[0].1);
        chart
            .draw_series(std::iter::once(Text::new(
                format!(
                    "braking {} {}",
                    num(units.length(length), 1),
                    units.length_label()
                ),
                to(t[1]),
                ("sans-serif", 13).into_font().color(&EVIDENCE),
            )))
            .map_err(|x| e(&x))?;
    }
    // At separation: bold outline, the nose edge thicker.
    let start = start_outline_on_page(r, k, units, frame);
    stroke(chart, start.clone(), color.stroke_width(2))?;
    stroke(chart, vec![start[0], start[1]], color.stroke_width(5))?;
    // At rest: filled.
    let rest: Vec<_> = corners(&run.rest, dims).into_iter().map(to).collect();
    chart
        .draw_series(std::iter::once(Polygon::new(
            rest.clone(),
            color.mix(0.35).filled(),
        )))
        .map_err(|x| e(&x))?;
    chart
        .draw_series(std::iter::once(PathElement::new(
            vec![rest[0], rest[1]],
            color.stroke_width(5),
        )))
        .map_err(|x| e(&x))?;
    Ok(())
}

/// Vehicle `k`'s evidence `ev`: the rest given (dashed outline, a cross at its CG), the path of
/// each tyre that left a mark, the tyres measured at rest and the marks with their sd.
fn draw_evidence(
    chart: &mut Chart,
    (r, k): (&RunoutResult, usize),
    ev: &Evidence,
    (to, units): (ToPage, UnitSystem),
) -> Result<(), crate::RenderError> {
    let e = |e: &dyn std::fmt::Display| crate::err(e);
    let u = |x: f64| units.length(x);
    let run = &r.runouts[k];
    let color = COLORS[(r.inputs[k].id.index()).min(1)];
    if let Some(g) = &ev.rest {
        // The CG's rest as measured (a tyres' rest is of their centroid).
        let heading = g.heading.unwrap_or(run.rest.heading);
        let (gx, gy) = g.cg();
        let given = Motion {
            x: gx,
            y: gy,
            heading,
            ..Motion::default()
        };
        let pts: Vec<_> = corners(&given, outline_of(r, k))
            .into_iter()
            .map(to)
            .collect();
        for w in pts.windows(2) {
            dashed(chart, w[0], w[1], EVIDENCE)?;
        }
        let c = to((gx, gy));
        let a = u(0.25);
        for (p, q) in [
            ((c.0 - a, c.1 - a), (c.0 + a, c.1 + a)),
            ((c.0 - a, c.1 + a), (c.0 + a, c.1 - a)),
        ] {
            chart
                .draw_series(std::iter::once(PathElement::new(
                    vec![p, q],
                    EVIDENCE.stroke_width(2),
                )))
                .map_err(|x| e(&x))?;
        }
    }
    // The path of each tyre that left a mark: the residual's distance is from it.
    for trace in tyre_traces(run, Some(ev)) {
        let trace: Vec<_> = trace.into_iter().map(to).collect();
        chart
            .draw_series(std::iter::once(PathElement::new(
                trace,
                color.mix(0.6).stroke_width(1),
            )))
            .map_err(|x| e(&x))?;
    }
    // The tyres measured at rest: small squares.
    for t in &r.inputs[k].rest_tyres {
        let c = to((t[0], t[1]));
        let a = u(0.12);
        chart
            .draw_series(std::iter::once(Rectangle::new(
                [(c.0 - a, c.1 - a), (c.0 + a, c.1 + a)],
                EVIDENCE.filled(),
            )))
            .map_err(|x| e(&x))?;
    }
    for (i, m) in ev.marks.iter().enumerate() {
        let c = to((m.x, m.y));
        let rad = u(m.sigma).max(u(0.05));
        let circle: Vec<(f64, f64)> = (0..=48)
            .map(|j| {
                let a = std::f64::consts::TAU * j as f64 / 48.0;
                (c.0 + rad * a.cos(), c.1 + rad * a.sin())
            })
            .collect();
        chart
            .draw_series(std::iter::once(PathElement::new(
                circle,
                EVIDENCE.stroke_width(1),
            )))
            .map_err(|x| e(&x))?;
        chart
            .draw_series(std::iter::once(Circle::new(c, 3, EVIDENCE.filled())))
            .map_err(|x| e(&x))?;
        chart
            .draw_series(std::iter::once(Text::new(
                format!("mark {}", i + 1),
                (c.0 + rad, c.1 + rad),
                ("sans-serif", 13).into_font().color(&EVIDENCE),
            )))
            .map_err(|x| e(&x))?;
    }
    Ok(())
}

/// The key: the title, where the separation came from, each vehicle's run-out and evidence,
/// and what each line of the plan shows.
fn draw_key(
    key: &DrawingArea<SVGBackend, Shift>,
    title: &str,
    (r, approach): (&RunoutResult, &[Approach]),
    (units, frame, every): (UnitSystem, Convention, f64),
) -> Result<(), crate::RenderError> {
    let sae = frame.mirrors();
    let mut y = 30;
    let mut line = |text: String, color: RGBColor, size: u32| -> Result<(), crate::RenderError> {
        key.draw(&Text::new(
            text,
            (10, y),
            ("sans-serif", size).into_font().color(&color),
        ))
        .map_err(|x| crate::err(&x))?;
        y += size as i32 + 6;
        Ok(())
    };
    for (i, part) in title.lines().enumerate() {
        for piece in wrap(part, if i == 0 { 40 } else { 48 }) {
            line(piece, BLACK, if i == 0 { 15 } else { 12 })?;
        }
    }
    let source = match r.document.source {
        Source::Scene => "separation: estimated from the scene".to_string(),
        Source::Start => format!("start: {}", Source::Start.describe()),
        s => format!("separation: {}", s.describe()),
    };
    for piece in wrap(&source, 48) {
        line(piece, BLACK, 12)?;
    }
    line(String::new(), BLACK, 0)?;
    for (k, v) in r.document.vehicles.iter().enumerate() {
        let color = COLORS[(r.inputs[k].id.index()).min(1)];
        line(format!("vehicle {}", v.vehicle), color, 14)?;
        line(
            format!(
                "  {} {} to rest in {:.2} s",
                num(units.length(v.distance), 1),
                units.length_label(),
                v.time
            ),
            color,
            12,
        )?;
        line(
            format!(
                "  rotation {:.0} deg ({} full turns)",
                if sae { -v.rotation } else { v.rotation },
                if sae { -v.turns } else { v.turns }
            ),
            color,
            12,
        )?;
        line(format!("  road friction {:.3}", v.friction), color, 12)?;
        for ev in v.evidence.iter().filter(|e| e.what.is_scene()) {
            let shown = if ev.what.is_angle() {
                format!("{} deg", num(ev.value, 1))
            } else {
                format!(
                    "{} {}",
                    num(units.length(ev.value), 2),
                    units.length_label()
                )
            };
            line(
                format!("  {}: {shown} (z {})", ev.name, num(ev.z, 1)),
                color,
                12,
            )?;
        }
    }
    line(String::new(), BLACK, 0)?;
    let motion = r.document.source == Source::Start;
    line(
        format!(
            "bold outline: at {} (thick edge: nose)",
            if motion { "the start" } else { "separation" }
        ),
        BLACK,
        12,
    )?;
    line(format!("light outlines: every {every} s"), BLACK, 12)?;
    line(
        if motion && r.duration.is_some() {
            "filled outline: the end of the stated duration"
        } else {
            "filled outline: the run-out's rest"
        }
        .into(),
        BLACK,
        12,
    )?;
    if !motion {
        line("dashed outline, cross: rest given".into(), EVIDENCE, 12)?;
        line("circle: a mark and its sd".into(), EVIDENCE, 12)?;
        if r.inputs.iter().any(|v| !v.rest_tyres.is_empty()) {
            line("square: a tyre measured at rest".into(), EVIDENCE, 12)?;
        }
        if r.inputs
            .iter()
            .filter_map(|v| v.evidence.as_ref())
            .any(|ev| ev.marks.iter().any(|m| m.point != [0.0, 0.0]))
        {
            line(
                "thin line: the path of a tyre that left a mark".into(),
                BLACK,
                12,
            )?;
        }
    }
    if !approach.is_empty() {
        line(
            "grey tracks: braking before the impact, up to contact".into(),
            EVIDENCE,
            12,
        )?;
    }
    Ok(())
}

/// A line through `pts` on the chart.
fn stroke(
    chart: &mut Chart,
    pts: Vec<(f64, f64)>,
    style: ShapeStyle,
) -> Result<(), crate::RenderError> {
    chart
        .draw_series(std::iter::once(PathElement::new(pts, style)))
        .map_err(crate::err)?;
    Ok(())
}

/// A dashed line from `a` to `b` on the chart.
fn dashed(
    chart: &mut Chart,
    a: (f64, f64),
    b: (f64, f64),
    color: RGBColor,
) -> Result<(), crate::RenderError> {
    let n = 8;
    for i in (0..n).step_by(2) {
        let f = |t: f64| (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t);
        let (p, q) = (f(i as f64 / n as f64), f((i + 1) as f64 / n as f64));
        chart
            .draw_series(std::iter::once(PathElement::new(
                vec![p, q],
                color.stroke_width(2),
            )))
            .map_err(crate::err)?;
    }
    Ok(())
}
