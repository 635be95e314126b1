//! The ground under the plan views: the friction zones of a case, shaded and labelled.

use crate::tables::num;
use plotters::coord::types::RangedCoordf64;
use plotters::prelude::*;

/// The colour of a friction zone.
const ZONE: RGBColor = RGBColor(120, 160, 60);

/// The friction `zones` (SI, the natural frame) on the chart, laid on the page by `to`: each a
/// light polygon clipped to the plotted area `[x0, x1, y0, y1]` (page units), labelled with its
/// friction in the middle of what is seen of it.
pub(crate) fn draw_zones<DB: DrawingBackend>(
    chart: &mut ChartContext<'_, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>,
    zones: &[pim_runout::Zone],
    to: impl Fn((f64, f64)) -> (f64, f64),
    area: [f64; 4],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    for z in zones {
        let on_page: Vec<(f64, f64)> = z.corners.iter().map(|c| to((c[0], c[1]))).collect();
        let seen = clipped(&on_page, area);
        if seen.len() < 3 {
            continue;
        }
        chart.draw_series(std::iter::once(Polygon::new(
            seen.clone(),
            ZONE.mix(0.15).filled(),
        )))?;
        let mut edge = seen.clone();
        edge.push(seen[0]);
        chart.draw_series(std::iter::once(PathElement::new(
            edge,
            ZONE.stroke_width(1),
        )))?;
        let n = seen.len() as f64;
        let mid = seen
            .iter()
            .fold((0.0, 0.0), |a, p| (a.0 + p.0 / n, a.1 + p.1 / n));
        chart.draw_series(std::iter::once(Text::new(
            format!("friction {}", num(z.friction, 2)),
            mid,
            ("sans-serif", 13).into_font().color(&ZONE),
        )))?;
    }
    Ok(())
}

/// The polygon `p` clipped to the rectangle `[x0, x1, y0, y1]` (Sutherland and Hodgman: one
/// side of the rectangle after the other).
fn clipped(p: &[(f64, f64)], [x0, x1, y0, y1]: [f64; 4]) -> Vec<(f64, f64)> {
    // Each side as (axis, bound, keep the side above it).
    let sides = [(0, x0, true), (0, x1, false), (1, y0, true), (1, y1, false)];
    let coord = |q: (f64, f64), axis: usize| if axis == 0 { q.0 } else { q.1 };
    let mut out = p.to_vec();
    for (axis, bound, above) in sides {
        let inside = |q: (f64, f64)| (coord(q, axis) >= bound) == above;
        let input = std::mem::take(&mut out);
        for (i, &b) in input.iter().enumerate() {
            let a = input[(i + input.len() - 1) % input.len()];
            if inside(b) != inside(a) {
                let t = (bound - coord(a, axis)) / (coord(b, axis) - coord(a, axis));
                out.push((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1)));
            }
            if inside(b) {
                out.push(b);
            }
        }
        if out.is_empty() {
            break;
        }
    }
    out
}
