//! The layout of an SVG as plotters writes it, read back for the layout tests: text boxes
//! estimated from the font size and the characters (DejaVu Sans advance widths by class of
//! character), placed by `text-anchor` and the baseline shift `dy`, and rotated with the text;
//! arrowheads (triangles) and the points of every polygon and polyline.

/// An axis-aligned box: x0, y0, x1, y1 in pixels.
pub type Box4 = [f64; 4];

/// The advance width of `text` at `size` px (DejaVu Sans, by class of character).
pub fn width(text: &str, size: f64) -> f64 {
    text.chars()
        .map(|c| match c {
            ' ' => 0.32,
            '.' | ',' | ':' | ';' | '\'' | '!' | '|' | 'i' | 'j' | 'l' => 0.3,
            '(' | ')' | '[' | ']' | '-' | 'f' | 't' | 'r' | '/' => 0.4,
            c if c.is_ascii_digit() => 0.64,
            'm' | 'w' => 0.92,
            'M' | 'W' => 0.95,
            c if c.is_uppercase() => 0.72,
            _ => 0.6,
        })
        .sum::<f64>()
        * size
}

pub fn overlap(a: &Box4, b: &Box4, slack: f64) -> bool {
    a[0] + slack < b[2] && b[0] + slack < a[2] && a[1] + slack < b[3] && b[1] + slack < a[3]
}

/// The text boxes, arrowhead boxes and canvas size of an SVG.
pub struct Layout {
    pub texts: Vec<(String, Box4)>,
    pub heads: Vec<Box4>,
    pub points: Vec<[f64; 2]>,
    pub size: [f64; 2],
    /// Rectangles with no area (height or width 0), which an SVG renderer rejects.
    pub empty_rects: usize,
}

pub fn num(node: &roxmltree::Node, name: &str) -> f64 {
    node.attribute(name)
        .and_then(|v| v.trim_end_matches("px").parse().ok())
        .unwrap_or(0.0)
}

pub fn layout(svg: &str) -> Layout {
    let doc = roxmltree::Document::parse(svg).expect("the SVG parses");
    let root = doc.root_element();
    let size = [num(&root, "width"), num(&root, "height")];
    let mut out = Layout {
        texts: Vec::new(),
        heads: Vec::new(),
        points: Vec::new(),
        size,
        empty_rects: 0,
    };
    for n in doc.descendants() {
        match n.tag_name().name() {
            "text" => {
                let text: String = n
                    .descendants()
                    .filter(|d| d.is_text())
                    .filter_map(|d| d.text())
                    .collect::<String>()
                    .trim()
                    .to_string();
                if text.is_empty() {
                    continue;
                }
                let (x, y, s) = (num(&n, "x"), num(&n, "y"), num(&n, "font-size"));
                let w = width(&text, s);
                let dy = match n.attribute("dy") {
                    Some(d) if d.ends_with("em") => {
                        d.trim_end_matches("em").parse::<f64>().unwrap() * s
                    }
                    Some(d) if d.ends_with("ex") => {
                        d.trim_end_matches("ex").parse::<f64>().unwrap() * 0.55 * s
                    }
                    _ => 0.0,
                };
                let base = y + dy;
                let x0 = match n.attribute("text-anchor") {
                    Some("middle") => x - w / 2.0,
                    Some("end") => x - w,
                    _ => x,
                };
                let mut b = [x0, base - 0.76 * s, x0 + w, base + 0.24 * s];
                if let Some(t) = n.attribute("transform") {
                    // rotate(270, cx, cy): (x, y) -> (cx + (y - cy), cy - (x - cx)).
                    let v: Vec<f64> = t
                        .trim_start_matches("rotate(")
                        .trim_end_matches(')')
                        .split(',')
                        .map(|p| p.trim().parse().unwrap())
                        .collect();
                    assert!(
                        (v[0] - 270.0).abs() < 1e-9,
                        "only the y axis title is rotated"
                    );
                    let (cx, cy) = (v[1], v[2]);
                    let r = |px: f64, py: f64| [cx + (py - cy), cy - (px - cx)];
                    let (p, q) = (r(b[0], b[1]), r(b[2], b[3]));
                    b = [
                        p[0].min(q[0]),
                        p[1].min(q[1]),
                        p[0].max(q[0]),
                        p[1].max(q[1]),
                    ];
                }
                out.texts.push((text, b));
            }
            "rect" if num(&n, "width") <= 0.0 || num(&n, "height") <= 0.0 => {
                out.empty_rects += 1;
            }
            "polygon" | "polyline" => {
                let pts: Vec<[f64; 2]> = n
                    .attribute("points")
                    .unwrap_or("")
                    .split_whitespace()
                    .map(|p| {
                        let (a, b) = p.split_once(',').unwrap();
                        [a.parse().unwrap(), b.parse().unwrap()]
                    })
                    .collect();
                if n.tag_name().name() == "polygon" && pts.len() == 3 {
                    let xs = pts.iter().map(|p| p[0]);
                    let ys = pts.iter().map(|p| p[1]);
                    out.heads.push([
                        xs.clone().fold(f64::INFINITY, f64::min),
                        ys.clone().fold(f64::INFINITY, f64::min),
                        xs.fold(f64::NEG_INFINITY, f64::max),
                        ys.fold(f64::NEG_INFINITY, f64::max),
                    ]);
                }
                out.points.extend(pts);
            }
            _ => {}
        }
    }
    out
}

/// The defects of one drawing, as lines.
pub fn defects(name: &str, svg: &str) -> Vec<String> {
    let l = layout(svg);
    let mut bad = Vec::new();
    for (i, (a, ba)) in l.texts.iter().enumerate() {
        if ba[0] < -0.5 || ba[1] < -0.5 || ba[2] > l.size[0] + 0.5 || ba[3] > l.size[1] + 0.5 {
            bad.push(format!("{name}: text {a:?} leaves the canvas: {ba:?}"));
        }
        for (b, bb) in &l.texts[i + 1..] {
            if overlap(ba, bb, 1.0) {
                bad.push(format!("{name}: texts {a:?} and {b:?} overlap"));
            }
        }
        for h in &l.heads {
            if overlap(ba, h, 1.0) {
                bad.push(format!("{name}: text {a:?} covers an arrowhead at {h:?}"));
            }
        }
    }
    if l.empty_rects > 0 {
        bad.push(format!("{name}: {} rectangles of no area", l.empty_rects));
    }
    for p in &l.points {
        if p[0] < -0.5 || p[1] < -0.5 || p[0] > l.size[0] + 0.5 || p[1] > l.size[1] + 0.5 {
            bad.push(format!("{name}: a shape leaves the canvas at {p:?}"));
            break;
        }
    }
    bad
}
