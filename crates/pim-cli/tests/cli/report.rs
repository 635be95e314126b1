//! `pim report`: one document per crash. Its numbers are the JSON's (each residual row, the
//! chi-square, the ranges), its sections are all there, and, where Chromium is installed, the
//! page renders without any element wider than the page and prints to a PDF.

use crate::common;
use common::{pim_ok, scratch_dir};
use serde_json::Value;
use std::path::Path;

const SECTIONS: [&str; 8] = [
    "How to read this",
    "Answer",
    "What the data do not determine",
    "Warnings",
    "Figures",
    "Method",
    "Inputs as given",
    "Each value given against the fit",
];

/// Runs `pim report CASE --out DIR` (plus `args`) and reads report.html and result.json.
fn report(name: &str, case: &str, args: &[&str]) -> (std::path::PathBuf, String, Value) {
    let dir = scratch_dir("cli_report", name);
    let d = dir.display().to_string();
    let mut all = vec!["report", case, "--out", &d];
    all.extend_from_slice(args);
    pim_ok(&all);
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let json: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("result.json")).unwrap()).unwrap();
    (dir, html, json)
}

/// `x` to `prec` decimals as the report prints it (no minus sign on a rounded zero).
fn fixed(x: f64, prec: usize) -> String {
    let half = 0.5 * 10f64.powi(-(prec as i32));
    let x = if x.abs() < half { 0.0 } else { x };
    format!("{x:.prec$}")
}

fn best(json: &Value) -> &Value {
    let b = json["best"].as_str().expect("a best branch");
    json["branches"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["moment"] == b)
        .unwrap()
}

/// Every residual row of the HTML equals the JSON's, converted to the report's units (speed
/// factor `speed`, yaw-rate factor `yaw`) and frame (`sae` flips lateral values).
fn assert_residual_rows(html: &str, json: &Value, speed: f64, yaw: f64, sae: bool) -> usize {
    let rows = best(json)["residuals"].as_array().unwrap();
    assert!(!rows.is_empty());
    for r in rows {
        let is_yaw = r["unit"] == "rad/s";
        let sign = if sae && r["lateral"].as_bool().unwrap() {
            -1.0
        } else {
            1.0
        };
        let k = sign * if is_yaw { yaw } else { speed };
        let cell = |key: &str| fixed(k * r[key].as_f64().unwrap(), 3);
        let row = format!(
            "<td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td>",
            cell("given"),
            cell("fitted"),
            cell("residual")
        );
        assert!(
            html.contains(&row),
            "{}: row {row} not in the report",
            r["name"]
        );
    }
    rows.len()
}

#[test]
fn the_report_of_a_fitted_sae_crash_prints_the_jsons_numbers() {
    let (dir, html, json) = report(
        "tbone",
        "examples/cases/tbone_sae_us.toml",
        &["--cost", "q3", "--draws", "100"],
    );
    for s in SECTIONS {
        assert!(html.contains(&format!("<h2>{s}</h2>")), "section {s}");
    }
    // mph and deg/s, SAE's signs.
    let n = assert_residual_rows(
        &html,
        &json,
        1.0 / 0.44704,
        180.0 / std::f64::consts::PI,
        true,
    );
    assert_eq!(n, 12);
    let chi = &best(&json)["chi_square"];
    assert!(html.contains(&format!(
        "chi-square {} with {} degrees of freedom",
        fixed(chi["value"].as_f64().unwrap(), 3),
        chi["degrees_of_freedom"]
    )));
    // The ranges are uncertainty.json's, in mph.
    let study: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("uncertainty.json")).unwrap())
            .unwrap();
    let q = &study["quantities"]["speed1"];
    let mph = |key: &str| fixed(q[key].as_f64().unwrap() / 0.44704, 2);
    assert!(html.contains(&format!(
        "<td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td>",
        mph("p05"),
        mph("p50"),
        mph("p95")
    )));
    // Every figure inline, and beside the Markdown as a file.
    for f in [
        "diagram.svg",
        "momentum.svg",
        "histograms.svg",
        "tornado.svg",
    ] {
        assert!(dir.join(f).is_file(), "{f}");
    }
    assert_eq!(html.matches("<svg").count(), 5);
    let md = std::fs::read_to_string(dir.join("report.md")).unwrap();
    assert!(md.contains("](momentum.svg)"));
    // The inputs as given: the file itself.
    assert!(html.contains("crush_angle_from_vehicle1 = 0.0"));
    check_in_chromium(&dir.join("report.html"));
}

#[test]
fn the_report_of_a_ricsac_fit_and_of_the_readme_crash() {
    let (dir, html, json) = report(
        "ricsac7",
        "examples/cases/ricsac7_fit.toml",
        &["--cost", "q2"],
    );
    assert_residual_rows(&html, &json, 1.0, 1.0, false);
    // Q2 holds the contact state: only the six separation components are residuals.
    assert_eq!(best(&json)["residuals"].as_array().unwrap().len(), 6);
    assert!(html.contains("no moment impulse (best)"));
    check_in_chromium(&dir.join("report.html"));

    // The README's crash is a solve: no residuals, the answer and the figures.
    let (dir, html, _) = report("side", "examples/cases/side_impact.toml", &[]);
    assert!(!html.contains("Each value given against the fit"));
    assert!(
        html.contains("<td class=\"n\">6.75</td>"),
        "separation speed 6.75 m/s"
    );
    assert!(html.contains("lost (49.50 %)"));
    check_in_chromium(&dir.join("report.html"));
}

#[test]
fn a_report_goes_to_stdout_or_to_one_file() {
    let out = pim_ok(&["report", "examples/cases/side_impact.toml"]);
    let html = String::from_utf8(out.stdout).unwrap();
    assert!(html.starts_with("<!DOCTYPE html>"));
    let dir = scratch_dir("cli_report", "one_file");
    let file = dir.join("side.html");
    pim_ok(&[
        "report",
        "examples/cases/side_impact.toml",
        "-o",
        &file.display().to_string(),
    ]);
    assert_eq!(std::fs::read_to_string(&file).unwrap(), html);
}

/// Chromium, if installed (`PIM_CHROMIUM` names it, else `chromium` / `chromium-browser` on the
/// PATH).
fn chromium() -> Option<String> {
    if let Ok(c) = std::env::var("PIM_CHROMIUM") {
        return Some(c);
    }
    ["chromium", "chromium-browser"].into_iter().find_map(|c| {
        std::process::Command::new(c)
            .arg("--version")
            .output()
            .ok()
            .filter(|o| o.status.success())
            .map(|_| c.to_string())
    })
}

/// Renders the report in headless Chromium at a print page's width (A4 less its margins,
/// 700 px) and a screen's (1280 px): no element may reach beyond the page's width (measured
/// from the DOM by a script added to a copy of the page); then prints it to a PDF, which must
/// have pages. Skipped, with a message, without Chromium.
fn check_in_chromium(page: &Path) {
    let Some(browser) = chromium() else {
        eprintln!(
            "skipped: Chromium is not installed (install Debian's `chromium` to run the DOM check)"
        );
        return;
    };
    let html = std::fs::read_to_string(page).unwrap();
    let probe = "<script>\n\
        const W = document.documentElement.clientWidth; const bad = [];\n\
        for (const el of document.querySelectorAll('body *')) {\n\
          const r = el.getBoundingClientRect();\n\
          if (r.width > 0 && (r.right > W + 0.5 || r.left < -0.5))\n\
            bad.push(el.tagName + ':' + Math.round(r.left) + '..' + Math.round(r.right));\n\
        }\n\
        document.body.setAttribute('data-probe', 'width ' + W + ' scroll ' +\n\
          document.documentElement.scrollWidth + ' bad ' + bad.length + ' ' + bad.slice(0, 8).join(' '));\n\
        </script>\n</body>";
    let probed = page.with_file_name("probed.html");
    std::fs::write(&probed, html.replace("</body>", probe)).unwrap();
    let url = format!(
        "file://{}",
        std::fs::canonicalize(&probed).unwrap().display()
    );
    let base = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
    ];
    for width in [700, 1280] {
        let out = std::process::Command::new(&browser)
            .args(base)
            .arg(format!("--window-size={width},1200"))
            .args(["--virtual-time-budget=2000", "--dump-dom", &url])
            .output()
            .expect("run chromium");
        let dom = String::from_utf8_lossy(&out.stdout);
        let at = dom.find("data-probe=\"").unwrap_or_else(|| {
            panic!(
                "the probe did not run: {}",
                String::from_utf8_lossy(&out.stderr)
            )
        });
        let probe = &dom[at + 12..];
        let probe = &probe[..probe.find('"').unwrap()];
        let words: Vec<&str> = probe.split_whitespace().collect();
        assert_eq!(
            words[3], words[1],
            "{page:?} at {width} px: the page scrolls sideways: {probe}"
        );
        assert_eq!(
            words[5], "0",
            "{page:?} at {width} px: elements overflow: {probe}"
        );
    }
    let pdf = page.with_extension("pdf");
    let out = std::process::Command::new(&browser)
        .args(base)
        .args(["--no-pdf-header-footer"])
        .arg(format!("--print-to-pdf={}", pdf.display()))
        .arg(format!(
            "file://{}",
            std::fs::canonicalize(page).unwrap().display()
        ))
        .output()
        .expect("run chromium");
    let bytes = std::fs::read(&pdf)
        .unwrap_or_else(|_| panic!("no PDF: {}", String::from_utf8_lossy(&out.stderr)));
    assert!(bytes.starts_with(b"%PDF"));
    assert!(
        bytes.len() > 20_000,
        "the PDF is nearly empty ({} bytes)",
        bytes.len()
    );
}

#[test]
fn uncertainty_out_writes_the_report_with_its_ranges() {
    let dir = scratch_dir("cli_report", "uncertainty");
    let d = dir.display().to_string();
    pim_ok(&[
        "uncertainty",
        "examples/cases/ricsac7_uncertainty.toml",
        "--cost",
        "q2",
        "--draws",
        "40",
        "--out",
        &d,
    ]);
    let html = std::fs::read_to_string(dir.join("report.html")).unwrap();
    let study: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("uncertainty.json")).unwrap())
            .unwrap();
    let q = &study["quantities"]["delta_v1"];
    let cell = |key: &str| fixed(q[key].as_f64().unwrap(), 2);
    assert!(html.contains(&format!(
        "<td class=\"n\">{}</td><td class=\"n\">{}</td><td class=\"n\">{}</td>",
        cell("p05"),
        cell("p50"),
        cell("p95")
    )));
    for f in ["diagram.svg", "momentum.svg", "histograms.svg", "report.md"] {
        assert!(dir.join(f).is_file(), "{f}");
    }
}

/// A fit with the impact geometry among the unknowns: the report gives each estimated input
/// (the JSON's value, its range and bounds) and says what is proven, as the table output does.
#[test]
fn the_report_of_a_geometry_fit_names_the_geometry_and_what_is_proven() {
    let case = "examples/cases/ricsac6_geometry.toml";
    let (dir, html, json) = report("geometry", case, &["--cost", "q2"]);
    let ranges = best(&json)["geometry"]["ranges"].as_array().unwrap();
    assert_eq!(ranges.len(), 5);
    for r in ranges {
        let name = r["input"].as_str().unwrap();
        let value = r["value"].as_f64().unwrap();
        let shown = if name.ends_with(".d") {
            format!("{} m", fixed(value, 3))
        } else {
            format!("{} deg", fixed(value, 2))
        };
        assert!(
            html.contains(&format!("<td>{name}</td><td class=\"n\">{shown}</td>")),
            "{name} {shown}"
        );
    }
    // RICSAC 6 under Q2: the optimum over the geometry box is proven (the JSON's proof, the
    // report's words and the table's).
    let proof = &best(&json)["geometry"]["search"]["proof"];
    assert_eq!(proof["status"], "proven");
    let lower = proof["lower"].as_f64().unwrap();
    let cost = best(&json)["cost"].as_f64().unwrap();
    assert!(
        lower <= cost && cost - lower <= 1e-4 * cost,
        "{lower} {cost}"
    );
    let proven = "the geometry is proven optimal over its bounds to a relative 1e-4 of the cost";
    assert!(html.contains(&format!(
        "What is proven: the coefficients are optimal at the reported geometry; {proven}"
    )));
    assert!(!html.contains("not proven"));
    check_in_chromium(&dir.join("report.html"));
    let table = String::from_utf8(pim_ok(&["fit", case, "--cost", "q2"]).stdout).unwrap();
    assert!(table.contains(proven), "{table}");
}
