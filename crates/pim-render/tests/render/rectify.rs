//! A photo made into a plan (`pim_render::rectify`): a photo synthesised from a known plan
//! through a known perspective is rectified back. The plan is a 40 m by 30 m patch of road at
//! 0.05 m a pixel, grey with a fine checker, and five coloured squares: four at the corners of
//! a 24 m by 16 m rectangle (the control points a survey gives) and one off it (a check). The
//! photo is that plan seen by a camera low over one edge (the far side about a third as wide
//! as the near), 1200 by 800 pixels, each pixel's colour looked up on the plan.
//!
//! Asserted: the fit meets its four points exactly (residuals below a micrometre); each square's
//! centre on the plan-view image (the centroid of its colour) lies within one of its pixels of
//! where the plan has it, the check square too; the distance between the two squares farthest
//! apart is the plan's within 1 %. Fewer than four points, and four with three on a line, are
//! refused with a message.
use image::{Rgba, RgbaImage};
use nalgebra::{Matrix3, Vector3};
use pim_render::rectify::{fit, rectify, Control, RectifyError};

/// Plan metres a plan pixel.
const PLAN_PX: f64 = 0.05;
/// The plan's extent, m (right, up from its bottom left corner at the origin).
const PLAN: [f64; 2] = [40.0, 30.0];
/// The squares' centres on the plan (m) and their colours: four controls, then the check.
const SQUARES: [([f64; 2], [u8; 3]); 5] = [
    ([8.0, 7.0], [230, 30, 30]),
    ([32.0, 7.0], [30, 200, 30]),
    ([32.0, 23.0], [30, 30, 230]),
    ([8.0, 23.0], [230, 200, 30]),
    ([20.0, 27.0], [200, 30, 200]),
];
/// A square's side, m.
const SIDE: f64 = 0.6;

/// The plan's colour at `p` (m).
fn plan_colour(p: [f64; 2]) -> Rgba<u8> {
    for (c, rgb) in SQUARES {
        if (p[0] - c[0]).abs() <= SIDE / 2.0 && (p[1] - c[1]).abs() <= SIDE / 2.0 {
            return Rgba([rgb[0], rgb[1], rgb[2], 255]);
        }
    }
    let checker = ((p[0] / 2.0).floor() + (p[1] / 2.0).floor()) as i64 % 2 == 0;
    let g = if checker { 120 } else { 140 };
    Rgba([g, g, g, 255])
}

/// The camera: plan metres to photo pixels (right, down), a perspective looking up the road
/// from below its bottom edge: `w = 1 + 0.06 y`, `u = 600 + 28 (x - 20) / w`,
/// `v = 760 - 60 y / w` (the near edge 28 pixels a metre, the far edge, y = 30, 2.8 times
/// smaller and near the top).
fn camera() -> Matrix3<f64> {
    let (s, c, t) = (28.0, 0.06, 60.0);
    Matrix3::new(
        s,
        600.0 * c,
        600.0 - 20.0 * s,
        0.0,
        760.0 * c - t,
        760.0,
        0.0,
        c,
        1.0,
    )
}

fn apply(h: &Matrix3<f64>, p: [f64; 2]) -> [f64; 2] {
    let q = h * Vector3::new(p[0], p[1], 1.0);
    [q[0] / q[2], q[1] / q[2]]
}

/// The photo: each pixel's centre looked up on the plan through the camera's inverse (grey
/// off the plan).
fn photo() -> Vec<u8> {
    let inverse = camera().try_inverse().unwrap();
    let img = RgbaImage::from_fn(1200, 800, |i, j| {
        let p = apply(&inverse, [f64::from(i) + 0.5, f64::from(j) + 0.5]);
        if (0.0..PLAN[0]).contains(&p[0]) && (0.0..PLAN[1]).contains(&p[1]) {
            plan_colour(p)
        } else {
            Rgba([200, 220, 240, 255])
        }
    });
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    png
}

#[test]
fn a_synthesised_photo_is_rectified_back_to_its_plan() {
    let cam = camera();
    // The controls: each square's centre, its pixel where the camera puts it.
    let controls: Vec<Control> = SQUARES[..4]
        .iter()
        .map(|(c, _)| Control {
            pixel: apply(&cam, *c),
            plan: *c,
        })
        .collect();
    let fitted = fit(&controls).unwrap();
    println!("residuals {:?} m", fitted.residuals);
    assert!(fitted.residuals.iter().all(|r| *r < 1e-6));
    let photo = photo();
    let out = rectify(&photo, &fitted, &controls, None, Some(PLAN_PX)).unwrap();
    let img = image::load_from_memory(&out.png).unwrap().to_rgba8();
    assert_eq!([img.width(), img.height()], out.size);
    // Each square's centroid on the plan-view image, against where the plan has it.
    let mut found = Vec::new();
    for (c, rgb) in SQUARES {
        let (mut n, mut si, mut sj) = (0.0, 0.0, 0.0);
        for (i, j, p) in img.enumerate_pixels() {
            let close = (0..3).all(|k| (i32::from(p.0[k]) - i32::from(rgb[k])).abs() < 40);
            if p.0[3] == 255 && close {
                n += 1.0;
                si += f64::from(i) + 0.5;
                sj += f64::from(j) + 0.5;
            }
        }
        assert!(n > 20.0, "square {c:?}: {n} pixels");
        let at = out.to_plan([si / n, sj / n]);
        let error = (at[0] - c[0]).hypot(at[1] - c[1]);
        println!(
            "square {c:?}: at {at:.3?}, {:.2} pixels off",
            error / out.per_pixel
        );
        assert!(error < out.per_pixel, "square {c:?} at {at:?}");
        found.push(at);
    }
    // The scale: the squares farthest apart (the first and the third, 28.8 m).
    let d = |a: [f64; 2], b: [f64; 2]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let (plan, image) = (d(SQUARES[0].0, SQUARES[2].0), d(found[0], found[2]));
    println!("{image:.3} m against {plan:.3} m");
    assert!((image / plan - 1.0).abs() < 0.01);
    // Refusals.
    assert!(matches!(fit(&controls[..3]), Err(RectifyError::Points(_))));
    let mut in_line = controls.clone();
    in_line[1].plan = [20.0, 7.0];
    in_line[1].pixel = apply(&cam, [20.0, 7.0]);
    in_line[3].plan = [14.0, 7.0];
    in_line[3].pixel = apply(&cam, [14.0, 7.0]);
    let e = fit(&in_line).unwrap_err().to_string();
    assert!(e.contains("no three in line"), "{e}");
}
