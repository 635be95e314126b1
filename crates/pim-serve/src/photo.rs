//! A photo of the folder made into a plan-view image from the page
//! ([`pim_render::rectify`]): the points clicked on it and their places on the plan, the image
//! written beside the photo under a name of its own (never over a file), and the case's
//! `[background]` set to it.

use crate::AnswerError;
use pim_case::units::UnitSystem;
use pim_render::rectify::{fit, rectify, Control};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;

/// A point clicked on the photo and where it lies on the plan.
#[derive(Debug, Clone, Copy, Deserialize)]
pub struct PhotoPoint {
    /// Its pixel on the photo (right, down from the top left).
    pub pixel: [f64; 2],
    /// Where it lies in the scene: x and y in the case's own frame (the display length unit).
    pub at: [f64; 2],
}

/// What the page is given back.
#[derive(Debug, Serialize)]
pub struct PhotoPlan {
    /// The case text with `[background]` set to the plan-view image (not saved).
    pub text: String,
    /// The image written, relative to the folder served.
    pub image: String,
    /// Each point's residual, the display length unit.
    pub residuals: Vec<f64>,
    /// The image's size in pixels.
    pub size: [u32; 2],
}

/// The plan-view image of the photo `photo` (a path inside `root`, already checked to be an
/// image there) through `points`, written beside it as `NAME_plan.png` (`NAME_plan_2.png` ...
/// when that is taken: no file is ever overwritten), and the case `file`'s `text` with its
/// `[background]` set to it, locked, in the display units `units`.
///
/// # Errors
/// Too few points or points that fix no perspective, a photo that cannot be read, or an image
/// that cannot be written (the system's message).
pub fn photo_plan(
    root: &Path,
    (file, text): (&str, &str),
    (photo, bytes): (&str, &[u8]),
    points: &[PhotoPoint],
    units: Option<UnitSystem>,
) -> Result<PhotoPlan, AnswerError> {
    let (sketch, _) = crate::plan::Sketch::read(file, text)?;
    let controls: Vec<Control> = points
        .iter()
        .map(|p| Control {
            pixel: p.pixel,
            plan: sketch.convention.page_of_written(p.at),
        })
        .collect();
    let bad = |e: &dyn std::fmt::Display| AnswerError::Input(format!("{photo}: {e}"));
    let fitted = fit(&controls).map_err(|e| bad(&e))?;
    let out = rectify(bytes, &fitted, &controls, None, None).map_err(|e| bad(&e))?;
    let image = write_beside(root, photo, &out.png)?;
    // The image relative to the case's folder.
    let case_dir = Path::new(file).parent().unwrap_or(Path::new(""));
    let relative = Path::new(&image)
        .strip_prefix(case_dir)
        .map_or_else(|_| image.clone(), |p| p.display().to_string());
    let w = f64::from(out.size[0]);
    let change = crate::BackgroundChange {
        image: Some(relative),
        pixels: Some([[0.0, 0.0], [w, 0.0]]),
        distance: Some(w * out.per_pixel),
        at: Some(out.origin),
        rotation: Some(0.0),
        locked: Some(true),
    };
    let text = crate::set_background(file, text, &change, units)?;
    Ok(PhotoPlan {
        text,
        image,
        residuals: fitted.residuals,
        size: out.size,
    })
}

/// `png` written beside `photo` (inside `root`) under the first free name of `NAME_plan.png`,
/// `NAME_plan_2.png` ...: the path written, relative to `root`.
fn write_beside(root: &Path, photo: &str, png: &[u8]) -> Result<String, AnswerError> {
    let failed = |e: &dyn std::fmt::Display| {
        AnswerError::Input(format!(
            "{photo}: the plan-view image cannot be written: {e}"
        ))
    };
    let rel = Path::new(photo);
    let stem = rel.file_stem().and_then(|s| s.to_str()).unwrap_or("photo");
    let folder = rel.parent().unwrap_or(Path::new(""));
    let dir = root.join(folder);
    let mut tmp = tempfile::NamedTempFile::new_in(&dir).map_err(|e| failed(&e))?;
    tmp.write_all(png).map_err(|e| failed(&e))?;
    tmp.as_file().sync_all().map_err(|e| failed(&e))?;
    for n in 1..1000 {
        let name = if n == 1 {
            format!("{stem}_plan.png")
        } else {
            format!("{stem}_plan_{n}.png")
        };
        match tmp.persist_noclobber(dir.join(&name)) {
            Ok(_) => return Ok(folder.join(&name).display().to_string()),
            Err(e) if e.error.kind() == std::io::ErrorKind::AlreadyExists => tmp = e.file,
            Err(e) => return Err(failed(&e.error)),
        }
    }
    Err(failed(&"a thousand plan-view images of it already"))
}
