//! The case's background image as the page changes it: chosen, set to scale by two points and
//! their distance, moved, turned and locked, each written into `[background]` of the case's
//! text with every other byte kept.

use crate::AnswerError;
use pim_case::edit::{CaseEdit, NewValue, Quantity};
use pim_case::units::UnitSystem;
use serde::Deserialize;

/// What the page changes of `[background]`: each value given is written, the others kept.
/// Lengths and the page point `at` are in the page's display length unit (`units`, default the
/// case's own); the image's points in pixels.
#[derive(Debug, Clone, Default, Deserialize)]
pub struct BackgroundChange {
    /// The image, a path relative to the case file's folder.
    #[serde(default)]
    pub image: Option<String>,
    /// Two points on the image, pixels from its top left.
    #[serde(default)]
    pub pixels: Option<[[f64; 2]; 2]>,
    /// Their distance on the scene.
    #[serde(default)]
    pub distance: Option<f64>,
    /// Where the first point lies on the page.
    #[serde(default)]
    pub at: Option<[f64; 2]>,
    /// Degrees turned counter-clockwise on the page.
    #[serde(default)]
    pub rotation: Option<f64>,
    /// Not moved by dragging.
    #[serde(default)]
    pub locked: Option<bool>,
}

/// The case text with `change` written into its `[background]` (the section added at the end
/// when the case has none: then the image, its points and their distance are needed).
///
/// # Errors
/// Text that is not a valid case, a change that makes it invalid (the message of `pim`), or a
/// new section without its image, points and distance.
pub fn set_background(
    file: &str,
    text: &str,
    change: &BackgroundChange,
    units: Option<UnitSystem>,
) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let (case, was_case) = crate::plan::Sketch::read(file, text)?;
    let units = units.unwrap_or_else(|| UnitSystem::of(&case.units));
    // Display length unit to the file's.
    let per_unit = units.length(1.0).recip() / case.units.length.to_si();
    let mut text = text.to_string();
    if case.background.is_none() {
        let (Some(image), Some([p, q]), Some(d)) = (&change.image, change.pixels, change.distance)
        else {
            return Err(AnswerError::Input(format!(
                "{file}: a new [background] needs its image, two points on it and their distance"
            )));
        };
        let image = toml_edit::Value::from(image.as_str()).to_string();
        if !text.ends_with('\n') {
            text.push('\n');
        }
        text.push_str(&format!(
            "\n[background]\nimage = {}\npixels = [[{}, {}], [{}, {}]]\ndistance = {}\nat = {{ x \
             = 0.0, y = 0.0 }}\nrotation = 0.0\nlocked = false\n",
            image.trim(),
            float(p[0]),
            float(p[1]),
            float(q[0]),
            float(q[1]),
            float(d * per_unit)
        ));
    }
    let mut edit = CaseEdit::new(file, &text).map_err(|e| input(&e))?;
    let set = |edit: &mut CaseEdit, path: &str, v: NewValue| {
        edit.set(path, v)
            .map_err(|e| AnswerError::Input(e.to_string()))
    };
    if let Some(image) = &change.image {
        set(&mut edit, "background.image", NewValue::Text(image.clone()))?;
    }
    if let Some(px) = change.pixels {
        for (i, p) in px.iter().enumerate() {
            for (j, x) in p.iter().enumerate() {
                let rounded = (x * 10.0).round() / 10.0;
                set(
                    &mut edit,
                    &format!("background.pixels.{i}.{j}"),
                    NewValue::Written(rounded),
                )?;
            }
        }
    }
    if let Some(d) = change.distance {
        set(
            &mut edit,
            "background.distance",
            NewValue::Written(round(d * per_unit)),
        )?;
    }
    if let Some(at) = change.at {
        // The page is the written frame turned: natural (h, v) = (x, y); SAE (h, v) = (y, x).
        let [x, y] = case.convention.from_page(at);
        let si = Quantity::Length.si_per_unit(&edit.units().map_err(|e| input(&e))?);
        let display = units.length(1.0).recip();
        for (key, value) in [("x", x), ("y", y)] {
            set(
                &mut edit,
                &format!("background.at.{key}"),
                NewValue::Written(round(value * display / si)),
            )?;
        }
    }
    if let Some(r) = change.rotation {
        set(
            &mut edit,
            "background.rotation",
            NewValue::Written(round(r)),
        )?;
    }
    if let Some(l) = change.locked {
        set(&mut edit, "background.locked", NewValue::Bool(l))?;
    }
    let text = edit.text();
    crate::plan::Sketch::check_edited(file, &text, was_case)?;
    Ok(text)
}

/// To a thousandth, as a scene is measured.
fn round(x: f64) -> f64 {
    (x * 1000.0).round() / 1000.0
}

/// A float as TOML writes it (always with a point).
fn float(x: f64) -> String {
    let x = round(x);
    if x.fract() == 0.0 {
        format!("{x:.1}")
    } else {
        format!("{x}")
    }
}
