//! `pim uncertainty` of a case with scene evidence: intervals through all three phases.

use super::{json, print_out, title_of};
use crate::args::{Format, UncertaintyArgs};
use crate::error::Failure;
use anyhow::Result;
use pim_case::case::Case;
use pim_case::units::UnitSystem;
use pim_studies::reconstruct_study::{self, ReconstructionStudy};
use std::fmt::Write as _;
use std::process::ExitCode;

/// The scale and sign of a quantity of the study as the table shows it in `u` and `frame`:
/// speeds in the speed unit; the pose at contact (`contact ...`) in the length unit and
/// degrees, y coordinates and angles mirrored in an SAE frame.
fn shown(name: &str, u: UnitSystem, frame: pim_core::Convention) -> (f64, f64) {
    if let Some(pose) = name.strip_prefix("contact ") {
        let angle = pose.ends_with("heading") || pose == "crush_angle";
        let mirrored = angle || pose.ends_with(".y");
        let sign = if mirrored { frame.sign() } else { 1.0 };
        (if angle { 1.0 } else { u.length(1.0) }, sign)
    } else if name.contains("speed") {
        (u.speed(1.0), 1.0)
    } else {
        (1.0, 1.0)
    }
}

/// The study's table, speeds in `u`, the pose at contact in `u` and `frame`.
pub fn table(
    title: &str,
    s: &ReconstructionStudy,
    u: UnitSystem,
    frame: pim_core::Convention,
) -> String {
    let mut t = String::new();
    let _ = writeln!(
        t,
        "{title}\nreconstruction, parametric bootstrap through all three phases: {} draws (seed \
         {}), {} with an admissible reconstruction\n",
        s.draws, s.seed, s.feasible_draws
    );
    let _ = writeln!(
        t,
        "{:<34} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "quantity", "nominal", "p05", "p50", "p95", "sd"
    );
    let order = |n: &str| (n.starts_with("vehicle"), n.to_string());
    let mut names: Vec<&String> = s.quantities.keys().collect();
    names.sort_by_key(|n| order(n));
    for name in names {
        let q = &s.quantities[name];
        let (k, sign) = shown(name, u, frame);
        let nominal = s.nominal.get(name).map_or(f64::NAN, |v| v * k * sign);
        // Mirrored, the 5th percentile is the 95th's image.
        let (lo, hi) = if sign < 0.0 {
            (-q.p95, -q.p05)
        } else {
            (q.p05, q.p95)
        };
        let _ = writeln!(
            t,
            "{name:<34} {nominal:>10.3} {:>10.3} {:>10.3} {:>10.3} {:>10.3}",
            lo * k,
            sign * q.p50 * k,
            hi * k,
            q.sd * k
        );
    }
    let _ = writeln!(
        t,
        "(speeds in {}, energy loss in %{}; the draws' 90 % interval is p05 to p95)\n",
        u.speed_label(),
        if s.quantities.keys().any(|n| n.starts_with("contact ")) {
            format!(
                ", the pose at contact in {} and degrees{}",
                u.length_label(),
                if frame.mirrors() { ", SAE frame" } else { "" }
            )
        } else {
            String::new()
        }
    );
    for q in &s.nominal_outside {
        let _ = writeln!(
            t,
            "note: the nominal {q} lies outside its own 90 % interval: the draws' answers are \
             skewed away from it (a nonlinear or bounded answer); read the interval\n"
        );
    }
    if !s.intervals.is_empty() {
        let _ = writeln!(
            t,
            "the speeds at contact, 90 % intervals: the draws' (p05 to p95), the profile's (where \
             the best reconstruction's chi-square has risen {:.2} above the answer's: the \
             evidence's alone) and the one reported (on each side the wider of the two)",
            pim_reconstruct::profile_rise(pim_reconstruct::PROFILE_LEVEL)
        );
        let _ = writeln!(
            t,
            "{:<34} {:>21} {:>21} {:>21}",
            "quantity", "draws", "profile", "reported"
        );
        let pair = |a: f64, b: f64| format!("{:.3} .. {:.3}", u.speed(a), u.speed(b));
        for (name, [lo, hi]) in &s.intervals {
            let draws = s
                .quantities
                .get(name)
                .map_or_else(|| "-".into(), |q| pair(q.p05, q.p95));
            let profile = s.profiles.get(name).map_or_else(
                || "-".into(),
                |p| {
                    let end = |e: &pim_reconstruct::ProfileEnd, beyond: &str| {
                        let v = format!("{:.3}", u.speed(e.speed));
                        if e.reached {
                            v
                        } else {
                            format!("{beyond}{v}")
                        }
                    };
                    format!("{} .. {}", end(&p.lower, "<"), end(&p.upper, ">"))
                },
            );
            let _ = writeln!(
                t,
                "{name:<34} {draws:>21} {profile:>21} {:>21}",
                pair(*lo, *hi)
            );
        }
        t.push('\n');
    }
    let _ = writeln!(
        t,
        "what dominates each speed (first-order index from the draws):"
    );
    for sens in s
        .sensitivity
        .iter()
        .filter(|x| x.quantity.contains("speed"))
    {
        let _ = writeln!(t, "  {}: {}", sens.quantity, super::study::dominant(sens));
    }
    t
}

/// The folder of a reconstruction (`pim fit --out`, `pim uncertainty --out` of a scene case):
/// result.json, the table, the scene to scale, report.md and report.html; the speeds before
/// contact beside the EDR's (speed_history.svg) when a vehicle has one; with a study, its
/// table (the intervals of every phase) too.
pub fn write_reconstruction(
    dir: &std::path::Path,
    case: &Case,
    done: &pim_studies::reconstruct::Reconstructed,
    units: UnitSystem,
    record: &str,
    table: &str,
    study: Option<(&str, &str)>,
) -> Result<()> {
    let cannot_draw = |e| Failure::render(dir, e);
    // The fitted run-outs, found once for the scene's figure and its plan for CAD.
    let runouts = pim_render::runout::fitted_runouts(case, done)
        .map_err(cannot_draw)?
        .ok_or_else(|| {
            Failure::NoAnswer(format!(
                "{}: no reconstruction to write into {}",
                case.file,
                dir.display()
            ))
        })?;
    let svg = pim_render::runout::reconstruction_scene_of(case, done, &runouts, units)
        .map_err(cannot_draw)?;
    let dxf =
        pim_render::cad::reconstruction_dxf_of(case, done, &runouts, units).map_err(cannot_draw)?;
    let speeds =
        pim_render::speed_history::figure(case, done, units, pim_render::speed_history::WIDTH)
            .map_err(cannot_draw)?;
    let text = match study {
        Some((_, t)) => format!("{table}\n{t}"),
        None => table.to_string(),
    };
    let out = super::output::OutDir::create(dir)?;
    out.write("result.json", record)?;
    out.write("reconstruction.txt", table)?;
    if let Some((json, t)) = study {
        out.write("uncertainty.json", json)?;
        out.write("uncertainty.txt", t)?;
    }
    out.write("scene.svg", &svg)?;
    out.write_bytes("scene.dxf", &dxf)?;
    let mut md =
        format!("# Reconstruction\n\n```text\n{text}```\n\n![The scene to scale](scene.svg)\n");
    if let Some(f) = &speeds {
        out.write(&f.name, &f.svg)?;
        md.push_str(&format!(
            "\n![The speeds before contact: the answer and the EDR]({})\n",
            f.name
        ));
    }
    out.write("report.md", &md)?;
    out.write(
        "report.html",
        &pim_render::reconstruct::reconstruction_html(
            &title_of(case),
            &text,
            &svg,
            speeds.as_ref().map(|f| f.svg.as_str()),
        ),
    )?;
    out.commit()
}

/// The study of a scene case.
pub fn run(a: &UncertaintyArgs, case: &Case, warnings: usize) -> Result<ExitCode> {
    let (pool, bar) = super::study::pool_and_bar(a)?;
    let observer = super::study::Bar(bar.clone());
    observer.searching("the nominal reconstruction: each scene's run-outs searched");
    let (study, done) = pool
        .install(|| {
            reconstruct_study::run(
                case,
                a.model,
                pim_core::MomentForm::Corrected,
                pim_fit::MomentBranch::ALL.to_vec(),
                a.draws,
                a.seed,
                &observer,
            )
        })
        .map_err(Failure::from)?;
    bar.finish_and_clear();
    if study.feasible_draws == 0 {
        return Err(Failure::NoAnswer(format!(
            "{}: none of the {} draws has an admissible reconstruction, so there are no intervals",
            case.file, study.draws
        ))
        .into());
    }
    let units = a
        .units
        .map_or_else(|| UnitSystem::of(&case.written_units), Into::into);
    let record = json(&study)?;
    let text = table(&title_of(case), &study, units, case.written);
    if let Some(dir) = &a.out {
        // The report: the nominal reconstruction (the study's centre) with the intervals of
        // every phase.
        let nominal = json(&done.document)?;
        let fit_table = pim_render::reconstruct::reconstruction_table(
            &title_of(case),
            &done.document,
            units,
            case.written,
        );
        write_reconstruction(
            dir,
            case,
            &done,
            units,
            &nominal,
            &fit_table,
            Some((&record, &text)),
        )?;
    }
    print_out(match a.format {
        Format::Json => &record,
        Format::Table => &text,
    })?;
    Ok(crate::inputs::strict_status(a.strict, warnings, Vec::new()))
}
