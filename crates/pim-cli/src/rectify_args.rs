//! The arguments of `pim rectify` and its help.

use std::path::PathBuf;

/// What `pim rectify` does, with an example.
pub const RECTIFY_HELP: &str =
    "THE POINTS: a CSV file with a header and a row per point of the ground seen on the photo:
  id,u,v,x,y
  hydrant,412.5,633.0,0.0,0.0
  kerb NE,1507.0,598.5,36.2,2.1
  ...
u and v are its pixel on the photo (right and down from the top left corner, as an image
viewer shows them); x and y its place on the scene in the case's frame and length unit (a
survey's, a diagram's measurements); id is optional. Four points fix the photo's perspective
exactly, no three on a line; more are fitted by least squares and each one's residual (how far
the fit puts its pixel from where it was given) is printed: a residual far above the others is
a point misread or mistyped.

THE PLAN: the ground is a plane, so the photo is related to the plan by a homography (the
direct linear transformation with Hartley's normalisation). The plan-view image covers the
points' extent with half of it again on every side (--area to choose), the longer side 2,000
pixels (--per-pixel to choose), transparent where the photo does not see the ground. With
--frame sae (x ahead, y to the right, as an SAE case writes positions) the plan's right is y and
its up is x; the natural frame's right is x and up is y.

THE BACKGROUND: the [background] section that puts the image behind the case at its scale and
place is printed; paste it into the case (or set it with `pim set`), with the image's path (as
given to --out) made relative to the case's folder.

EXAMPLE:
  pim rectify photo.jpg --points photo_points.csv --out photo_plan.png --frame sae

EXIT STATUS:
  0  written   2  bad input (too few points, three on a line, a photo that cannot be read)
  4  the image cannot be written";

/// `pim rectify`.
#[derive(clap::Args, Debug)]
pub struct RectifyArgs {
    /// The photo (PNG or JPEG).
    pub photo: PathBuf,
    /// The points: CSV with columns u, v (pixels) and x, y (the case's frame and unit), and
    /// optionally id.
    #[arg(long, value_name = "CSV")]
    pub points: PathBuf,
    /// The plan-view image to write (PNG).
    #[arg(long, value_name = "PNG")]
    pub out: PathBuf,
    /// The frame x and y are written in: natural (x right, y up on the plan) or sae (x up, y
    /// right).
    #[arg(long, default_value = "natural", value_parser = ["natural", "sae"])]
    pub frame: String,
    /// The plan length of one pixel of the image, the case's unit (default: 2,000 pixels
    /// along the longer side).
    #[arg(long, value_name = "LENGTH")]
    pub per_pixel: Option<f64>,
    /// The area of the plan to cover: LEFT,BOTTOM,RIGHT,TOP as the plan shows it (right and up),
    /// the case's unit.
    #[arg(long, value_name = "L,B,R,T", value_delimiter = ',', num_args = 4)]
    pub area: Option<Vec<f64>>,
}
