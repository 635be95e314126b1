//! Every plan view reads at a glance: parsed from its SVG, no two text boxes overlap, no text
//! box covers an arrowhead, and every text and shape lies inside the canvas. Checked on the
//! README's crash, every example case (drawn, solved and fitted) and every RICSAC test fitted.
//!
//! Text boxes are estimated from the font size and the characters (DejaVu Sans advance widths
//! by class of character), placed by `text-anchor` and the baseline shift `dy` that plotters
//! writes, and rotated with the text.

use pim_data::case::Case;
use pim_data::documents;
use std::path::Path;

/// The repository root.
fn repo() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// An axis-aligned box: x0, y0, x1, y1 in pixels.
type Box4 = [f64; 4];

/// The advance width of `text` at `size` px (DejaVu Sans, by class of character).
fn width(text: &str, size: f64) -> f64 {
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

fn overlap(a: &Box4, b: &Box4, slack: f64) -> bool {
    a[0] + slack < b[2] && b[0] + slack < a[2] && a[1] + slack < b[3] && b[1] + slack < a[3]
}

/// The text boxes, arrowhead boxes and canvas size of an SVG.
struct Layout {
    texts: Vec<(String, Box4)>,
    heads: Vec<Box4>,
    points: Vec<[f64; 2]>,
    size: [f64; 2],
}

fn num(node: &roxmltree::Node, name: &str) -> f64 {
    node.attribute(name)
        .and_then(|v| v.trim_end_matches("px").parse().ok())
        .unwrap_or(0.0)
}

fn layout(svg: &str) -> Layout {
    let doc = roxmltree::Document::parse(svg).expect("the SVG parses");
    let root = doc.root_element();
    let size = [num(&root, "width"), num(&root, "height")];
    let mut out = Layout {
        texts: Vec::new(),
        heads: Vec::new(),
        points: Vec::new(),
        size,
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
fn defects(name: &str, svg: &str) -> Vec<String> {
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
    for p in &l.points {
        if p[0] < -0.5 || p[1] < -0.5 || p[0] > l.size[0] + 0.5 || p[1] > l.size[1] + 0.5 {
            bad.push(format!("{name}: a shape leaves the canvas at {p:?}"));
            break;
        }
    }
    bad
}

fn load(path: &Path) -> Case {
    let text = std::fs::read_to_string(path).unwrap();
    Case::from_text(&path.display().to_string(), &text).unwrap()
}

/// The diagrams of a case: drawn, solved (when it can be) and fitted (when it can be).
fn diagrams(case: &Case) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let options = pim_core::SolveOptions::default();
    let d = pim_render::diagram::case_diagram(case, &options).unwrap();
    out.push((format!("{} (draw)", case.file), d.svg().unwrap()));
    if let Ok(s) = documents::solve(case, &options) {
        let d = pim_render::diagram::of_solve(case, &s);
        out.push((format!("{} (solve)", case.file), d.svg().unwrap()));
    }
    let cost = if case.content.known.is_some() || !case.content.observations.is_empty() {
        None
    } else {
        Some(pim_fit::CostPreset::Q3)
    };
    let fit = documents::fit(
        case,
        cost,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        pim_fit::MomentBranch::ALL.to_vec(),
    );
    if let Ok(f) = fit {
        let d = pim_render::diagram::of_fit(case, &f, "q3").unwrap();
        out.push((format!("{} (fit)", case.file), d.svg().unwrap()));
    }
    out
}

#[test]
fn no_diagram_has_overlapping_labels_or_leaves_its_canvas() {
    let mut cases = Vec::new();
    let mut files: Vec<_> = std::fs::read_dir(repo().join("examples/cases"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    assert!(files.len() >= 12);
    for f in &files {
        cases.push(load(f));
    }
    let data = std::fs::read_to_string(repo().join("data/ricsac.csv")).unwrap();
    let tests = pim_data::ricsac::parse("data/ricsac.csv", &data).unwrap();
    assert_eq!(tests.len(), 11);
    for t in &tests {
        cases.push(t.case(&format!("RICSAC test {}", t.test)).unwrap());
    }
    let mut bad = Vec::new();
    let mut drawn = 0;
    for c in &cases {
        for (name, svg) in diagrams(c) {
            drawn += 1;
            bad.extend(defects(&name, &svg));
        }
    }
    assert!(drawn >= 40, "{drawn} diagrams");
    assert!(bad.is_empty(), "{} defects:\n{}", bad.len(), bad.join("\n"));
}

#[test]
fn the_checker_sees_an_overlap_and_a_label_off_the_canvas() {
    let svg = r#"<svg width="100" height="50" xmlns="http://www.w3.org/2000/svg">
<text x="10" y="10" dy="0.76em" font-size="10">hello</text>
<text x="20" y="12" dy="0.76em" font-size="10">world</text>
<text x="90" y="30" dy="0.76em" font-size="10">outside</text>
<polygon points="12,12 14,18 16,12"/>
</svg>"#;
    let d = defects("probe", svg);
    assert!(d.iter().any(|x| x.contains("overlap")), "{d:?}");
    assert!(d.iter().any(|x| x.contains("leaves the canvas")), "{d:?}");
    assert!(d.iter().any(|x| x.contains("arrowhead")), "{d:?}");
}
