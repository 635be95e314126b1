//! A photo of the road made into a plan: a perspective photo rectified by four or more points
//! whose plan positions are known (a survey's, a diagram's), saved as a plan-view image to put
//! behind the scene (`[background]`).
//!
//! The ground is a plane, so a photo of it and the plan are related by a homography `H` (a
//! 3 x 3 matrix up to scale): a pixel `(u, v)` (right, down from the top left) lies on the plan
//! at
//! ```text
//! (x, y) = (h1 . p, h2 . p) / (h3 . p),    p = (u, v, 1)
//! ```
//! with `hk` the rows of `H` and `(x, y)` the plan's right and up. Each point gives two rows of
//! the direct linear transformation `A h = 0`; `h` (the nine entries) is the least-squares
//! solution of unit length: the eigenvector of `A^T A` of its smallest eigenvalue, the pixels
//! and the plan points first moved to their centroids and scaled to a mean distance of sqrt 2
//! (Hartley's normalisation, without which the fit is ill-conditioned in pixels). Four points
//! in general position (no three on a line) fix it exactly; more are fitted in the least-squares
//! sense, and the residual of each (its plan distance from where the fit puts its pixel) is
//! given, in the plan's unit, to be shown.
//!
//! The plan-view image covers the control points' extent with half of it again on every side
//! (or a given area): each of its pixels is looked up in the photo through `H^-1` and
//! interpolated bilinearly, transparent where it falls outside the photo or behind the camera.

use image::{ImageFormat, Rgba, RgbaImage};
use nalgebra::{DMatrix, Matrix3, Vector3};

/// A point of the ground seen on the photo: its pixel (right, down from the top left corner)
/// and its place on the plan (right, up; the plan's length unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Control {
    /// Pixel on the photo.
    pub pixel: [f64; 2],
    /// Where it lies on the plan.
    pub plan: [f64; 2],
}

/// Why a photo cannot be rectified.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum RectifyError {
    /// Fewer than four points, or points that do not fix a homography.
    #[error("{0}")]
    Points(String),
    /// The photo cannot be read or the plan written.
    #[error("{0}")]
    Image(String),
}

/// The fitted homography and how well it meets its points.
#[derive(Debug, Clone, PartialEq)]
pub struct Fitted {
    /// Photo pixel to plan (see the module docs), scaled to a unit Frobenius norm.
    pub homography: Matrix3<f64>,
    /// Each point's residual: the plan distance from where the fit puts its pixel to where it
    /// was given, the plan's length unit.
    pub residuals: Vec<f64>,
}

impl Fitted {
    /// Where the fit puts the photo pixel `p` on the plan (`None`: on or behind the horizon).
    pub fn to_plan(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        project(&self.homography, p)
    }

    /// The root mean square of the residuals, the plan's unit.
    pub fn rms(&self) -> f64 {
        let n = self.residuals.len().max(1) as f64;
        (self.residuals.iter().map(|r| r * r).sum::<f64>() / n).sqrt()
    }
}

/// `H p` as a point (`None` where its third coordinate is not positive: the horizon or behind).
fn project(h: &Matrix3<f64>, p: [f64; 2]) -> Option<[f64; 2]> {
    let q = h * Vector3::new(p[0], p[1], 1.0);
    (q[2] > 1e-12 * q.norm()).then(|| [q[0] / q[2], q[1] / q[2]])
}

/// The similarity that moves `points` to their centroid and scales their mean distance from
/// it to sqrt 2.
fn normaliser(points: impl Iterator<Item = [f64; 2]> + Clone) -> Matrix3<f64> {
    let n = points.clone().count().max(1) as f64;
    let c = points
        .clone()
        .fold([0.0, 0.0], |c, p| [c[0] + p[0] / n, c[1] + p[1] / n]);
    let mean = points
        .map(|p| (p[0] - c[0]).hypot(p[1] - c[1]))
        .sum::<f64>()
        / n;
    let s = if mean > 0.0 {
        std::f64::consts::SQRT_2 / mean
    } else {
        1.0
    };
    Matrix3::new(s, 0.0, -s * c[0], 0.0, s, -s * c[1], 0.0, 0.0, 1.0)
}

/// The homography of `points` (see the module docs).
///
/// # Errors
/// [`RectifyError::Points`]: fewer than four points, a coordinate that is not finite, or points
/// that fix no homography (three or more on a line among four, all on one line).
pub fn fit(points: &[Control]) -> Result<Fitted, RectifyError> {
    if points.len() < 4 {
        return Err(RectifyError::Points(format!(
            "{} points: a photo is rectified by four or more points of known plan position",
            points.len()
        )));
    }
    if let Some(p) = points
        .iter()
        .find(|p| !p.pixel.iter().chain(&p.plan).all(|x| x.is_finite()))
    {
        return Err(RectifyError::Points(format!("{p:?}: not a finite point")));
    }
    let t1 = normaliser(points.iter().map(|p| p.pixel));
    let t2 = normaliser(points.iter().map(|p| p.plan));
    let mut a = DMatrix::zeros(2 * points.len(), 9);
    for (i, c) in points.iter().enumerate() {
        let p = t1 * Vector3::new(c.pixel[0], c.pixel[1], 1.0);
        let q = t2 * Vector3::new(c.plan[0], c.plan[1], 1.0);
        for k in 0..3 {
            a[(2 * i, 3 + k)] = -p[k];
            a[(2 * i, 6 + k)] = q[1] * p[k];
            a[(2 * i + 1, k)] = p[k];
            a[(2 * i + 1, 6 + k)] = -q[0] * p[k];
        }
    }
    let ata = a.transpose() * &a;
    let eig = ata
        .try_symmetric_eigen(f64::EPSILON, 10_000)
        .ok_or_else(|| RectifyError::Points("the points' equations did not solve".into()))?;
    let mut order: Vec<usize> = (0..9).collect();
    order.sort_by(|&i, &j| eig.eigenvalues[i].total_cmp(&eig.eigenvalues[j]));
    // A second (near) null direction: the points do not fix one homography.
    let scale = eig.eigenvalues[order[8]].abs().max(f64::MIN_POSITIVE);
    if eig.eigenvalues[order[1]].abs() < 1e-10 * scale {
        return Err(RectifyError::Points(
            "the points do not fix the photo's perspective (three of them on a line, or all on \
             one): take four or more spread over the ground, no three in line"
                .into(),
        ));
    }
    let h = eig.eigenvectors.column(order[0]);
    let hn = Matrix3::new(h[0], h[1], h[2], h[3], h[4], h[5], h[6], h[7], h[8]);
    let t2_inv = t2
        .try_inverse()
        .ok_or_else(|| RectifyError::Points("the plan points coincide".into()))?;
    let mut homography = t2_inv * hn * t1;
    // The sign that puts the points in front of the camera, then a unit norm.
    let w: f64 = points
        .iter()
        .map(|c| (homography * Vector3::new(c.pixel[0], c.pixel[1], 1.0))[2])
        .sum();
    if w < 0.0 {
        homography = -homography;
    }
    homography /= homography.norm();
    let residuals = points
        .iter()
        .map(|c| {
            project(&homography, c.pixel).map_or(f64::INFINITY, |q| {
                (q[0] - c.plan[0]).hypot(q[1] - c.plan[1])
            })
        })
        .collect();
    Ok(Fitted {
        homography,
        residuals,
    })
}

/// A plan-view image made from a photo.
#[derive(Debug, Clone, PartialEq)]
pub struct Rectified {
    /// The image, PNG.
    pub png: Vec<u8>,
    /// Its size in pixels (width, height).
    pub size: [u32; 2],
    /// Where its top left corner lies on the plan (right, up; the plan's unit).
    pub origin: [f64; 2],
    /// The plan length of one of its pixels (square).
    pub per_pixel: f64,
}

impl Rectified {
    /// Where the pixel `p` of the plan-view image (right, down from its top left) lies on the
    /// plan.
    pub fn to_plan(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.origin[0] + p[0] * self.per_pixel,
            self.origin[1] - p[1] * self.per_pixel,
        ]
    }
}

/// Most pixels along a side of the plan-view image.
pub const MAX_SIDE: u32 = 4000;

/// The plan-view image of `photo` (PNG or JPEG bytes) through the fit `fitted` of `points`:
/// the area `[left, bottom, right, top]` on the plan (`None`: the points' extent and half of it
/// again on every side) at `per_pixel` plan units a pixel (`None`: the longer side 2,000
/// pixels; at most [`MAX_SIDE`] either way).
///
/// # Errors
/// [`RectifyError::Image`] for a photo that cannot be read or an empty area.
pub fn rectify(
    photo: &[u8],
    fitted: &Fitted,
    points: &[Control],
    area: Option<[f64; 4]>,
    per_pixel: Option<f64>,
) -> Result<Rectified, RectifyError> {
    let bad = |e: &dyn std::fmt::Display| RectifyError::Image(e.to_string());
    let photo = image::load_from_memory(photo)
        .map_err(|e| bad(&format!("the photo cannot be read: {e}")))?
        .to_rgba8();
    let [left, bottom, right, top] = area.unwrap_or_else(|| {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for c in points {
            for k in 0..2 {
                lo[k] = lo[k].min(c.plan[k]);
                hi[k] = hi[k].max(c.plan[k]);
            }
        }
        let m = [0.5 * (hi[0] - lo[0]), 0.5 * (hi[1] - lo[1])];
        [lo[0] - m[0], lo[1] - m[1], hi[0] + m[0], hi[1] + m[1]]
    });
    let (w, h) = (right - left, top - bottom);
    if !(w.is_finite() && h.is_finite() && w > 0.0 && h > 0.0) {
        return Err(bad(&format!(
            "the area {left}..{right} by {bottom}..{top} on the plan is empty"
        )));
    }
    let per_pixel = per_pixel
        .filter(|p| p.is_finite() && *p > 0.0)
        .unwrap_or(w.max(h) / 2000.0)
        .max(w.max(h) / f64::from(MAX_SIDE));
    // Whole pixels covering the area (a side that is a whole number of pixels to rounding
    // takes no extra one).
    let pixels = |side: f64| ((side / per_pixel - 1e-9).ceil() as u32).max(1);
    let size = [pixels(w), pixels(h)];
    let inverse = fitted
        .homography
        .try_inverse()
        .ok_or_else(|| bad(&"the fit is singular"))?;
    let out = RgbaImage::from_fn(size[0], size[1], |i, j| {
        let at = [
            left + (f64::from(i) + 0.5) * per_pixel,
            top - (f64::from(j) + 0.5) * per_pixel,
        ];
        project(&inverse, at).map_or(Rgba([0, 0, 0, 0]), |p| bilinear(&photo, p))
    });
    let mut png = Vec::new();
    out.write_to(&mut std::io::Cursor::new(&mut png), ImageFormat::Png)
        .map_err(|e| bad(&e))?;
    Ok(Rectified {
        png,
        size,
        origin: [left, top],
        per_pixel,
    })
}

/// The photo's colour at the pixel point `p` (pixel centres at half-integers), interpolated
/// between its four nearest pixels; transparent outside it.
fn bilinear(photo: &RgbaImage, p: [f64; 2]) -> Rgba<u8> {
    let (x, y) = (p[0] - 0.5, p[1] - 0.5);
    let (w, h) = (f64::from(photo.width()), f64::from(photo.height()));
    if !(x >= -0.5 && y >= -0.5 && x <= w - 0.5 && y <= h - 0.5) {
        return Rgba([0, 0, 0, 0]);
    }
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: f64, j: f64| {
        let i = i.clamp(0.0, w - 1.0) as u32;
        let j = j.clamp(0.0, h - 1.0) as u32;
        photo.get_pixel(i, j).0
    };
    let (a, b, c, d) = (
        at(x0, y0),
        at(x0 + 1.0, y0),
        at(x0, y0 + 1.0),
        at(x0 + 1.0, y0 + 1.0),
    );
    let mut out = [0u8; 4];
    for k in 0..4 {
        let top = f64::from(a[k]) * (1.0 - fx) + f64::from(b[k]) * fx;
        let bottom = f64::from(c[k]) * (1.0 - fx) + f64::from(d[k]) * fx;
        out[k] = (top * (1.0 - fy) + bottom * fy).round().clamp(0.0, 255.0) as u8;
    }
    Rgba(out)
}
