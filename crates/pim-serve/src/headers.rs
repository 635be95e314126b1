//! The headers of every answer: its type as given (`nosniff`), a content policy (the page's, or
//! an image's sandbox), and the type of an image by its bytes.

use axum::http::header;
use axum::response::Response;

/// Every response: its type is the one it says (`nosniff`), and a policy (the page's, unless
/// the route set its own, as images do).
pub(crate) fn secured(mut res: Response) -> Response {
    let h = res.headers_mut();
    h.insert(
        header::X_CONTENT_TYPE_OPTIONS,
        header::HeaderValue::from_static("nosniff"),
    );
    if !h.contains_key(header::CONTENT_SECURITY_POLICY) {
        h.insert(
            header::CONTENT_SECURITY_POLICY,
            header::HeaderValue::from_static(PAGE_POLICY),
        );
    }
    h.insert(
        header::REFERRER_POLICY,
        header::HeaderValue::from_static("no-referrer"),
    );
    res
}

/// The largest image served, bytes (a scanned scene diagram or an aerial photo).
pub const MAX_IMAGE_BYTES: u64 = 64 << 20;

/// The policy of every image served: sandboxed (no script, its own origin), nothing loaded.
pub(crate) const IMAGE_POLICY: &str =
    "sandbox; default-src 'none'; style-src 'unsafe-inline'; img-src data:";

/// The policy of the page and every other answer: scripts and everything else only from the
/// server itself (inline styles allowed: the plan sizes its labels with them); no frames, no
/// plugins, no forms sent elsewhere.
const PAGE_POLICY: &str = "default-src 'self'; script-src 'self'; style-src 'self' \
     'unsafe-inline'; img-src 'self' data: blob:; connect-src 'self'; object-src 'none'; \
     base-uri 'none'; frame-ancestors 'none'; form-action 'self'";

/// The type of an image by its first bytes: PNG and JPEG by their signatures, SVG by its root
/// element (after an XML declaration, comments, a doctype and white space).
pub fn image_kind(bytes: &[u8]) -> Option<&'static str> {
    if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
        return Some("image/png");
    }
    if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
        return Some("image/jpeg");
    }
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(4096)]);
    let mut rest = head.trim_start_matches('\u{feff}').trim_start();
    loop {
        if let Some(r) = rest.strip_prefix("<?") {
            rest = r.split_once("?>")?.1.trim_start();
        } else if let Some(r) = rest.strip_prefix("<!--") {
            rest = r.split_once("-->")?.1.trim_start();
        } else if let Some(r) = rest.strip_prefix("<!") {
            rest = r.split_once('>')?.1.trim_start();
        } else {
            break;
        }
    }
    let svg = rest.strip_prefix("<svg")?;
    svg.starts_with(|c: char| c.is_whitespace() || c == '>' || c == '/')
        .then_some("image/svg+xml")
}
