//! `pim rectify`: a photo of the road made into a plan-view image by points of known plan
//! position (`pim_render::rectify`), and the `[background]` section that puts it behind a case.

use crate::error::{Failure, EXIT_OK};
use crate::rectify_args::RectifyArgs;
use anyhow::Result;
use pim_render::rectify::{fit, rectify, Control};
use std::process::ExitCode;

/// A row of the points file.
#[derive(Debug, serde::Deserialize)]
struct Row {
    #[serde(default)]
    id: Option<String>,
    u: f64,
    v: f64,
    x: f64,
    y: f64,
}

/// The points of `a.points` on the plan (right, up): each row's id (or its number) and control.
fn points(a: &RectifyArgs) -> Result<Vec<(String, Control)>, Failure> {
    let file = a.points.display().to_string();
    let mut reader = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_path(&a.points)
        .map_err(|e| Failure::Input(format!("{file}: cannot read: {e}")))?;
    let sae = a.frame == "sae";
    let mut out = Vec::new();
    for (i, row) in reader.deserialize::<Row>().enumerate() {
        let line = i + 2;
        let r = row.map_err(|e| {
            Failure::Input(format!(
                "{file}: line {line}: {e} (columns: id (optional), u, v, x, y)"
            ))
        })?;
        let plan = if sae { [r.y, r.x] } else { [r.x, r.y] };
        out.push((
            r.id.unwrap_or_else(|| format!("point {}", i + 1)),
            Control {
                pixel: [r.u, r.v],
                plan,
            },
        ));
    }
    Ok(out)
}

/// Runs `pim rectify`.
pub fn run(a: &RectifyArgs) -> Result<ExitCode> {
    let named = points(a)?;
    let controls: Vec<Control> = named.iter().map(|(_, c)| *c).collect();
    let file = a.points.display().to_string();
    let fitted = fit(&controls).map_err(|e| Failure::Input(format!("{file}: {e}")))?;
    let photo = std::fs::read(&a.photo)
        .map_err(|e| Failure::Input(format!("{}: cannot read: {e}", a.photo.display())))?;
    let area = a.area.as_ref().map(|v| [v[0], v[1], v[2], v[3]]);
    let out = rectify(&photo, &fitted, &controls, area, a.per_pixel)
        .map_err(|e| Failure::Input(format!("{}: {e}", a.photo.display())))?;
    super::write_file_bytes(&a.out, &out.png)?;
    println!(
        "{}: {} by {} pixels, {} a pixel; the fit's residuals (the plan's unit):",
        a.out.display(),
        out.size[0],
        out.size[1],
        out.per_pixel
    );
    let width = named.iter().map(|(n, _)| n.len()).max().unwrap_or(5).max(5);
    for ((name, _), r) in named.iter().zip(&fitted.residuals) {
        println!("  {name:<width$}  {r:.3}");
    }
    println!("  {:<width$}  {:.3}\n", "rms", fitted.rms());
    // The top left corner in the case's frame, and the image's top edge as its scale.
    // Rounded to a nanometre's worth of the unit, so that 48 prints as 48.
    let tidy = |x: f64| (x * 1e9).round() / 1e9 + 0.0;
    let [h, v] = out.origin.map(tidy);
    let (x, y) = if a.frame == "sae" { (v, h) } else { (h, v) };
    let w = f64::from(out.size[0]);
    println!(
        "[background]\nimage = {:?}\npixels = [ [0.0, 0.0], [{w:.1}, 0.0] ]\ndistance = {}\nat = \
         {{ x = {x}, y = {y} }}",
        a.out.display().to_string(),
        tidy(w * out.per_pixel)
    );
    Ok(ExitCode::from(EXIT_OK))
}
