//! `pim rectify`: a photo synthesised from a plan through a known perspective (a 40 m by 30 m
//! patch of road, grey, a red and a blue square among four control points given in the SAE
//! frame) is made into a plan-view image: the residuals are printed and near zero, the image has
//! the size asked for, the blue square lies on it where the plan has it (within a pixel), and
//! the printed [background] is one a case accepts. Three points are refused at the file.
use crate::common;
use common::*;
use image::{Rgba, RgbaImage};

/// Plan (natural: right, up; m) to photo pixels: `w = 1 + 0.06 y`, `u = 600 + 28 (x - 20) / w`,
/// `v = 760 - 60 y / w`.
fn camera(p: [f64; 2]) -> [f64; 2] {
    let w = 1.0 + 0.06 * p[1];
    [600.0 + 28.0 * (p[0] - 20.0) / w, 760.0 - 60.0 * p[1] / w]
}

/// Photo pixel to plan: the camera's inverse.
fn ground(q: [f64; 2]) -> [f64; 2] {
    // v = 760 - 60 y / (1 + 0.06 y)  =>  y = (760 - v) / (60 - 0.06 (760 - v)).
    let d = 760.0 - q[1];
    let y = d / (60.0 - 0.06 * d);
    [20.0 + (q[0] - 600.0) * (1.0 + 0.06 * y) / 28.0, y]
}

const BLUE: [f64; 2] = [26.0, 18.0];

fn photo() -> Vec<u8> {
    let img = RgbaImage::from_fn(1200, 800, |i, j| {
        let p = ground([f64::from(i) + 0.5, f64::from(j) + 0.5]);
        if (p[0] - BLUE[0]).abs() < 0.5 && (p[1] - BLUE[1]).abs() < 0.5 {
            Rgba([30, 30, 230, 255])
        } else if (0.0..40.0).contains(&p[0]) && (0.0..30.0).contains(&p[1]) && p[1] >= 0.0 {
            Rgba([130, 130, 130, 255])
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
fn a_photo_is_made_into_a_plan() {
    let dir = scratch_dir("rectify", "photo");
    std::fs::write(dir.join("photo.png"), photo()).unwrap();
    // Four corners of a 24 m by 16 m rectangle, written in the SAE frame (x up the plan, y to
    // its right): x is the plan's up, y its right.
    let mut csv = String::from("id,u,v,x,y\n");
    for (id, p) in [
        ("a", [8.0, 7.0]),
        ("b", [32.0, 7.0]),
        ("c", [32.0, 23.0]),
        ("d", [8.0, 23.0]),
    ] {
        let q = camera(p);
        csv.push_str(&format!("{id},{},{},{},{}\n", q[0], q[1], p[1], p[0]));
    }
    std::fs::write(dir.join("points.csv"), &csv).unwrap();
    let d = dir.to_str().unwrap();
    let out = pim_ok(&[
        "rectify",
        &format!("{d}/photo.png"),
        "--points",
        &format!("{d}/points.csv"),
        "--out",
        &format!("{d}/plan.png"),
        "--frame",
        "sae",
        "--per-pixel",
        "0.05",
    ]);
    let text = String::from_utf8_lossy(&out.stdout).to_string();
    println!("{text}");
    assert!(text.contains("960 by 640 pixels, 0.05 a pixel"), "{text}");
    for id in ["a", "b", "c", "d", "rms"] {
        let line = text
            .lines()
            .find(|l| l.trim_start().starts_with(id))
            .unwrap();
        assert!(line.trim_end().ends_with("0.000"), "{line}");
    }
    // The blue square's centroid on the image: where the plan has it, within a pixel.
    let img = image::open(dir.join("plan.png")).unwrap().to_rgba8();
    assert_eq!((img.width(), img.height()), (960, 640));
    let (mut n, mut si, mut sj) = (0.0, 0.0, 0.0);
    for (i, j, p) in img.enumerate_pixels() {
        if p.0[2] > 200 && p.0[0] < 60 && p.0[3] == 255 {
            n += 1.0;
            si += f64::from(i) + 0.5;
            sj += f64::from(j) + 0.5;
        }
    }
    // The image's top left corner: the points' extent (8..32 by 7..23) and half of it again.
    let at = [-4.0 + 0.05 * si / n, 31.0 - 0.05 * sj / n];
    println!("blue square at {at:?}, {n} pixels");
    assert!(
        (at[0] - BLUE[0]).abs() < 0.05 && (at[1] - BLUE[1]).abs() < 0.05,
        "{at:?}"
    );
    // The background printed: the top left corner in the SAE frame (x = 31, y = -4).
    assert!(
        text.contains("pixels = [ [0.0, 0.0], [960.0, 0.0] ]"),
        "{text}"
    );
    assert!(text.contains("distance = 48"), "{text}");
    assert!(text.contains("at = { x = 31, y = -4 }"), "{text}");
    // Three points are refused at the file.
    let three: String = csv.lines().take(4).map(|l| format!("{l}\n")).collect();
    std::fs::write(dir.join("three.csv"), three).unwrap();
    let bad = pim(&[
        "rectify",
        &format!("{d}/photo.png"),
        "--points",
        &format!("{d}/three.csv"),
        "--out",
        &format!("{d}/x.png"),
    ]);
    assert_eq!(bad.status.code(), Some(2));
    let e = String::from_utf8_lossy(&bad.stderr);
    assert!(e.contains("three.csv") && e.contains("3 points"), "{e}");
}
