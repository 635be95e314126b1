//! Placing the labels of the plan view so that none covers another or an arrowhead: each label
//! is tried at growing distances and in sixteen directions around its anchor, and takes the
//! first place that is free and inside the plot (else the least covered one).

/// A label to place: its text, the pixel it belongs to, its font size (as plotters takes it)
/// and colour.
pub(super) struct PlotLabel {
    /// The text.
    pub text: String,
    /// The pixel the label names (its anchor).
    pub at: (i32, i32),
    /// Font size as given to plotters (its SVG writes it 1 / 1.24 as large).
    pub size: f64,
    /// Colour.
    pub color: plotters::style::RGBColor,
}

/// An axis-aligned box in pixels: x0, y0, x1, y1.
pub(super) type PixelBox = [f64; 4];

/// The SVG font size of a plotters font size.
pub(super) fn svg_size(size: f64) -> f64 {
    size / 1.24
}

/// A generous estimate of the width of `text` at `px` pixels (DejaVu Sans advance widths by
/// class of character, plus 8 %).
pub(super) fn text_width(text: &str, px: f64) -> f64 {
    1.08 * px
        * text
            .chars()
            .map(|c| match c {
                ' ' => 0.32,
                '.' | ',' | ':' | ';' | '\'' | '!' | '|' | 'i' | 'j' | 'l' => 0.3,
                '(' | ')' | '[' | ']' | '-' | 'f' | 't' | 'r' | '/' => 0.4,
                c if c.is_ascii_digit() => 0.64,
                'm' | 'w' | 'M' | 'W' => 0.95,
                c if c.is_uppercase() => 0.72,
                _ => 0.6,
            })
            .sum::<f64>()
}

fn overlap(a: &PixelBox, b: &PixelBox) -> f64 {
    let w = a[2].min(b[2]) - a[0].max(b[0]);
    let h = a[3].min(b[3]) - a[1].max(b[1]);
    if w > 0.0 && h > 0.0 {
        w * h
    } else {
        0.0
    }
}

/// The top-left corner of each label, in order: clear of the labels placed before it and of
/// `obstacles`, inside `area` when it can be.
pub(super) fn place(
    labels: &[PlotLabel],
    obstacles: &[PixelBox],
    area: PixelBox,
) -> Vec<(i32, i32)> {
    const PAD: f64 = 2.0;
    let mut taken: Vec<PixelBox> = obstacles
        .iter()
        .map(|b| [b[0] - PAD, b[1] - PAD, b[2] + PAD, b[3] + PAD])
        .collect();
    let mut out = Vec::with_capacity(labels.len());
    for l in labels {
        let px = svg_size(l.size);
        let (w, h) = (text_width(&l.text, px), 1.05 * px);
        let (ax, ay) = (f64::from(l.at.0), f64::from(l.at.1));
        let mut best: Option<(f64, PixelBox)> = None;
        'search: for r in [3.0, 8.0, 14.0, 22.0, 32.0, 46.0, 64.0, 90.0] {
            for k in 0..16 {
                // Up and to the right first, then round.
                let a = std::f64::consts::PI * (0.25 - k as f64 / 8.0);
                let (c, s) = (a.cos(), -a.sin());
                let cx = ax + c * (r + w / 2.0);
                let cy = ay + s * (r + h / 2.0);
                let b = [cx - w / 2.0, cy - h / 2.0, cx + w / 2.0, cy + h / 2.0];
                let outside = (area[0] - b[0]).max(0.0)
                    + (b[2] - area[2]).max(0.0)
                    + (area[1] - b[1]).max(0.0)
                    + (b[3] - area[3]).max(0.0);
                let covered: f64 = taken.iter().map(|t| overlap(&b, t)).sum();
                let score = covered + 1e3 * outside + r * 1e-3;
                if best.is_none_or(|(s, _)| score < s) {
                    best = Some((score, b));
                }
                if covered == 0.0 && outside == 0.0 {
                    break 'search;
                }
            }
        }
        let b = best.map_or([ax, ay, ax + w, ay + h], |(_, b)| b);
        taken.push([b[0] - PAD, b[1] - PAD, b[2] + PAD, b[3] + PAD]);
        // Plotters' text is anchored at its top left (its SVG sets dy = 0.76 em).
        out.push((b[0].round() as i32, (b[1] + 0.02 * px).round() as i32));
    }
    out
}
