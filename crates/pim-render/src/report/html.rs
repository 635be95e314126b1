//! The HTML rendering of a report: one page, its style and figures inline, nothing fetched.

use super::doc::{Block, Document};
use std::fmt::Write as _;

/// The page's style: readable on a screen, A4 pages when printed, nothing wider than the page
/// (tables wrap their cells, figures scale down, the case file wraps its long lines).
const STYLE: &str = "
:root { color-scheme: light; }
* { box-sizing: border-box; }
body { font-family: 'DejaVu Sans', 'Helvetica Neue', Arial, sans-serif; font-size: 10.5pt;
  line-height: 1.45; color: #1a1a1a; margin: 0; background: #fff; }
main { max-width: 52rem; margin: 0 auto; padding: 1.5rem 1.25rem 3rem; }
h1 { font-size: 1.55rem; margin: 0 0 .3rem; line-height: 1.25; overflow-wrap: anywhere; }
h2 { font-size: 1.15rem; margin: 1.8rem 0 .6rem; padding-bottom: .2rem;
  border-bottom: 1px solid #ccc; }
p.sub { margin: .1rem 0; color: #444; overflow-wrap: anywhere; }
p, li { overflow-wrap: anywhere; }
table { border-collapse: collapse; width: 100%; margin: .4rem 0 .8rem; font-size: 9.5pt; }
th, td { border-bottom: 1px solid #ddd; padding: .2rem .4rem; vertical-align: top;
  overflow-wrap: break-word; }
th { text-align: left; background: #f3f3f3; font-weight: 600; }
td.n, th.n { text-align: right; font-variant-numeric: tabular-nums; white-space: nowrap; }
ul.warn { border-left: 4px solid #d62728; background: #fff4f4; padding: .5rem .5rem .5rem 1.8rem;
  margin: .4rem 0; }
figure { margin: .8rem 0; break-inside: avoid; page-break-inside: avoid; }
figure svg { display: block; max-width: 100%; height: auto; margin: 0 auto; }
figcaption { font-size: 9pt; color: #444; margin-top: .3rem; }
pre { white-space: pre-wrap; overflow-wrap: anywhere; background: #f7f7f7; border: 1px solid #ddd;
  padding: .6rem; font-size: 8.5pt; line-height: 1.35; }
@page { size: A4; margin: 14mm 12mm; }
@media print { main { max-width: none; padding: 0; } h2 { break-after: avoid; }
  table { break-inside: auto; } tr { break-inside: avoid; } }
";

/// Text made safe for HTML.
pub(crate) fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            _ => out.push(c),
        }
    }
    out
}

/// An SVG document made ready to sit inline: without its XML declaration, and with a
/// `viewBox` (from its width and height) so that it scales to the page.
fn inline_svg(svg: &str) -> String {
    let body = match svg.find("<svg") {
        Some(at) => &svg[at..],
        None => return String::new(),
    };
    let end = body.find('>').unwrap_or(body.len());
    let open = &body[..end];
    if open.contains("viewBox") {
        return body.to_string();
    }
    let attr = |name: &str| -> Option<f64> {
        let at = open.find(&format!(" {name}=\""))? + name.len() + 3;
        let rest = &open[at..];
        rest[..rest.find('"')?].trim_end_matches("px").parse().ok()
    };
    match (attr("width"), attr("height")) {
        (Some(w), Some(h)) => format!("<svg viewBox=\"0 0 {w} {h}\"{}", &body[4..]),
        _ => body.to_string(),
    }
}

impl Document {
    /// The document as one self-contained HTML page.
    pub fn html(&self) -> String {
        page(self)
    }
}

/// The whole page.
fn page(d: &Document) -> String {
    let mut s = String::new();
    let _ = write!(
        s,
        "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n\
         <meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n\
         <meta name=\"generator\" content=\"pim {}\">\n<title>{}</title>\n<style>{STYLE}</style>\n\
         </head>\n<body>\n<main>\n<h1>{}</h1>\n",
        env!("CARGO_PKG_VERSION"),
        escape(&d.title),
        escape(&d.title)
    );
    for line in &d.subtitle {
        let _ = writeln!(s, "<p class=\"sub\">{}</p>", escape(line));
    }
    for sec in &d.sections {
        let _ = writeln!(s, "<section>\n<h2>{}</h2>", escape(&sec.heading));
        for b in &sec.blocks {
            block(&mut s, b);
        }
        s.push_str("</section>\n");
    }
    s.push_str("</main>\n</body>\n</html>\n");
    s
}

fn block(s: &mut String, b: &Block) {
    match b {
        Block::Text(t) => {
            let _ = writeln!(s, "<p>{}</p>", escape(t));
        }
        Block::List(items) | Block::Warnings(items) => {
            let class = if matches!(b, Block::Warnings(_)) {
                " class=\"warn\""
            } else {
                ""
            };
            let _ = writeln!(s, "<ul{class}>");
            for i in items {
                let _ = writeln!(s, "<li>{}</li>", escape(i));
            }
            s.push_str("</ul>\n");
        }
        Block::Table(t) => {
            let class = |k: usize| if t.numeric[k] { " class=\"n\"" } else { "" };
            s.push_str("<table>\n<thead><tr>");
            for (k, h) in t.head.iter().enumerate() {
                let _ = write!(s, "<th{}>{}</th>", class(k), escape(h));
            }
            s.push_str("</tr></thead>\n<tbody>\n");
            for r in &t.rows {
                s.push_str("<tr>");
                for (k, c) in r.iter().enumerate() {
                    let _ = write!(s, "<td{}>{}</td>", class(k), escape(c));
                }
                s.push_str("</tr>\n");
            }
            s.push_str("</tbody>\n</table>\n");
        }
        Block::Figure(f, caption) => {
            let _ = writeln!(
                s,
                "<figure>\n{}\n<figcaption>{}</figcaption>\n</figure>",
                inline_svg(&f.svg),
                escape(caption)
            );
        }
        Block::Source(name, text) => {
            let _ = writeln!(
                s,
                "<p><code>{}</code>:</p>\n<pre>{}</pre>",
                escape(name),
                escape(text.trim_end())
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_svg_gets_a_view_box_from_its_size() {
        let svg = "<?xml version=\"1.0\"?>\n<svg width=\"640\" height=\"480\" \
                   xmlns=\"http://www.w3.org/2000/svg\"><rect/></svg>";
        assert_eq!(
            inline_svg(svg),
            "<svg viewBox=\"0 0 640 480\" width=\"640\" height=\"480\" \
             xmlns=\"http://www.w3.org/2000/svg\"><rect/></svg>"
        );
        let kept = "<svg viewBox=\"0 0 1 1\" width=\"1\"></svg>";
        assert_eq!(inline_svg(kept), kept);
    }

    #[test]
    fn text_is_escaped() {
        assert_eq!(escape("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
    }
}
