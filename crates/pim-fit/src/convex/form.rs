//! Linear forms over the variables `z = (x, q)` of the convex route.

use super::dual::N;

/// A linear form over `z = (x, q)`.
pub(super) type Form = [f64; N];

pub(super) fn add(a: &Form, b: &Form, s: f64) -> Form {
    let mut out = *a;
    for (o, v) in out.iter_mut().zip(b) {
        *o += s * v;
    }
    out
}

pub(super) fn scaled(a: &Form, s: f64) -> Form {
    a.map(|v| v * s)
}

pub(super) fn dot(a: &Form, z: &[f64; N]) -> f64 {
    a.iter().zip(z).map(|(x, y)| x * y).sum()
}
