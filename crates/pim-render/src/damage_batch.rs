//! The crush of a data file's tests (`pim batch DATA --damage CRUSH`): a table, a CSV and the
//! figure of crush energy against the fitted energy loss.

use crate::{csv_error, err, svg_figure, Figure};
use pim_case::units::UnitSystem;
use pim_studies::ricsac_damage::DamageRecord;
use plotters::prelude::*;
use std::fmt::Write;

fn kj(x: f64) -> f64 {
    x / 1000.0
}

/// The table `damage.txt`.
pub fn damage_table(records: &[DamageRecord], u: UnitSystem) -> String {
    let sp = u.speed_label();
    let mut s = String::new();
    let _ = writeln!(
        s,
        "Crush energy (CRASH3 linear stiffness, EDCRASH RICSAC profiles) against the Q2 fit \
         (Brach's fit of the separation velocities), energies in kJ, delta-V in {sp}"
    );
    let _ = writeln!(
        s,
        "{:>4}  {:<12} {:>7} {:>7} {:>5} {:>5} {:>8} {:>6} {:>8} {:>8} {:>6}  {:>11} {:>11} {:>11} {:>11}  {:>6} {:>6} {:>8} {:>6} {:>7}",
        "test", "faces", "E1", "E2", "f1", "f2", "crush", "+-", "Q2 loss", "diff", "z",
        "CRASH3 dV", "PIM dV", "B&S dV", "McHenry dV",
        "e", "mu", "loss", "z", "proven"
    );
    let _ = writeln!(
        s,
        "{:>4}  {:<12} {:>7} {:>7} {:>5} {:>5} {:>8} {:>6} {:>8} {:>8} {:>6}  {:>11} {:>11} {:>11} {:>11}  {:<30}",
        "", "", "", "", "", "", "", "", "", "", "", "1 / 2", "1 / 2", "1 / 2", "1 / 2",
        "with the crush as evidence:"
    );
    let pair = |a: f64, b: f64| format!("{:.2} / {:.2}", u.speed(a), u.speed(b));
    let (mut sum_crush, mut sum_loss, mut n) = (0.0, 0.0, 0);
    for r in records {
        let Some(d) = &r.damage else {
            let _ = writeln!(
                s,
                "{:>4}  {}",
                r.test,
                r.error.as_deref().unwrap_or("no answer")
            );
            continue;
        };
        let Some(a) = &d.at_fit else {
            let _ = writeln!(s, "{:>4}  the Q2 fit has no admissible answer", r.test);
            continue;
        };
        let v = |k: usize| a.vehicles[k].as_ref();
        let (Some(v1), Some(v2)) = (v(0), v(1)) else {
            continue;
        };
        sum_crush += a.crush_energy;
        sum_loss += a.energy_loss;
        n += 1;
        let faces = format!("{}/{}", r.sides[0].name(), r.sides[1].name());
        let measured = |bs: bool| {
            r.measured.map_or_else(
                || "-".to_string(),
                |m| {
                    if bs {
                        pair(m.brach_smith_dv1, m.brach_smith_dv2)
                    } else {
                        pair(m.mchenry_dv1, m.mchenry_dv2)
                    }
                },
            )
        };
        let with = d.with_energy.as_ref().map_or_else(
            || "-".to_string(),
            |f| {
                format!(
                    "{:>6.3} {:>6.3} {:>8.1} {:>+6.2} {:>7}",
                    f.e,
                    f.mu,
                    kj(f.energy_loss),
                    f.energy_z,
                    if f.proven { "yes" } else { "no" }
                )
            },
        );
        let _ = writeln!(
            s,
            "{:>4}  {:<12} {:>7.1} {:>7.1} {:>5.2} {:>5.2} {:>8.1} {:>6.1} {:>8.1} {:>+8.1} {:>+6.2}  {:>11} {:>11} {:>11} {:>11}  {}",
            r.test,
            faces,
            kj(v1.energy),
            kj(v2.energy),
            v1.pdof_factor,
            v2.pdof_factor,
            kj(a.crush_energy),
            kj(a.crush_energy_sigma),
            kj(a.energy_loss),
            kj(a.difference),
            a.z.unwrap_or(0.0),
            pair(v1.crash3_delta_v, v2.crash3_delta_v),
            pair(v1.pim_delta_v, v2.pim_delta_v),
            measured(true),
            measured(false),
            with
        );
    }
    if n > 0 {
        let _ = writeln!(
            s,
            "\nover {n} tests the crush energy is {:.2} times the Q2 fit's energy loss ({:.0} kJ \
             against {:.0} kJ)",
            sum_crush / sum_loss,
            kj(sum_crush),
            kj(sum_loss)
        );
    }
    let _ = writeln!(
        s,
        "E1, E2: each car's crush energy with its direction-of-force factor f = 1 + tan^2 (held at \
         2 beyond 45 deg); faces from phi and the outline; +- from an assumed 10 % of A and B and \
         2 cm per depth (none published); diff = Q2 loss - crush, z = diff / sigma; B&S: Brach & \
         Smith 2002, McHenry: McHenry & McHenry 1997 (Neades 2011 Table 5.3). The fit with the \
         crush as evidence weighs the velocity residuals as if their sigma were 1 m/s; 'proven' \
         when its cost meets the certified optimum without the crush, else the best found."
    );
    s
}

/// The CSV `damage.csv`: one row per test.
pub fn damage_csv(records: &[DamageRecord]) -> Result<String, crate::RenderError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "test",
        "face1",
        "face2",
        "crush_energy1_j",
        "crush_energy2_j",
        "pdof_factor1",
        "pdof_factor2",
        "crush_energy_j",
        "crush_energy_sigma_j",
        "q2_energy_loss_j",
        "difference_j",
        "z",
        "crash3_dv1_mps",
        "crash3_dv2_mps",
        "pim_dv1_mps",
        "pim_dv2_mps",
        "bev1_mps",
        "bev2_mps",
        "jb_dv1_mps",
        "jb_dv2_mps",
        "brach_smith_dv1_mps",
        "brach_smith_dv2_mps",
        "mchenry_dv1_mps",
        "mchenry_dv2_mps",
        "with_energy_e",
        "with_energy_mu",
        "with_energy_em",
        "with_energy_loss_j",
        "with_energy_z",
        "with_energy_proven",
        "error",
    ])
    .map_err(csv_error)?;
    for r in records {
        let mut row = vec![
            r.test.to_string(),
            r.sides[0].name().into(),
            r.sides[1].name().into(),
        ];
        let a = r.damage.as_ref().and_then(|d| d.at_fit.as_ref());
        let f = r.damage.as_ref().and_then(|d| d.with_energy.as_ref());
        let num = |x: Option<f64>| x.map_or_else(String::new, |x| format!("{x}"));
        let v = |k: usize| a.and_then(|a| a.vehicles[k].as_ref());
        row.push(num(v(0).map(|v| v.energy)));
        row.push(num(v(1).map(|v| v.energy)));
        row.push(num(v(0).map(|v| v.pdof_factor)));
        row.push(num(v(1).map(|v| v.pdof_factor)));
        row.push(num(a.map(|a| a.crush_energy)));
        row.push(num(a.map(|a| a.crush_energy_sigma)));
        row.push(num(a.map(|a| a.energy_loss)));
        row.push(num(a.map(|a| a.difference)));
        row.push(num(a.and_then(|a| a.z)));
        row.push(num(v(0).map(|v| v.crash3_delta_v)));
        row.push(num(v(1).map(|v| v.crash3_delta_v)));
        row.push(num(v(0).map(|v| v.pim_delta_v)));
        row.push(num(v(1).map(|v| v.pim_delta_v)));
        row.push(num(v(0).map(|v| v.barrier_equivalent_speed)));
        row.push(num(v(1).map(|v| v.barrier_equivalent_speed)));
        let m = r.measured;
        for x in [
            m.map(|m| m.jb_dv1),
            m.map(|m| m.jb_dv2),
            m.map(|m| m.brach_smith_dv1),
            m.map(|m| m.brach_smith_dv2),
            m.map(|m| m.mchenry_dv1),
            m.map(|m| m.mchenry_dv2),
            f.map(|f| f.e),
            f.map(|f| f.mu),
            f.map(|f| f.em),
            f.map(|f| f.energy_loss),
            f.map(|f| f.energy_z),
        ] {
            row.push(num(x));
        }
        row.push(f.map_or_else(String::new, |f| f.proven.to_string()));
        row.push(r.error.clone().unwrap_or_default());
        w.write_record(&row).map_err(csv_error)?;
    }
    String::from_utf8(w.into_inner().map_err(csv_error)?).map_err(csv_error)
}

/// The figure `crush_energy.svg`: per test the crush energy (with its sigma) against the Q2
/// fit's energy loss, and both again at the fit with the crush as evidence (its PDOF factors
/// move with the fitted impulse); the line of equality.
pub fn crush_energy_figure(records: &[DamageRecord]) -> Result<Figure, crate::RenderError> {
    // (test, loss, crush, its sigma, (loss, crush) with the crush as evidence), kJ.
    type Point = (u32, f64, f64, f64, Option<(f64, f64)>);
    let points: Vec<Point> = records
        .iter()
        .filter_map(|r| {
            let d = r.damage.as_ref()?;
            let a = d.at_fit.as_ref()?;
            Some((
                r.test,
                kj(a.energy_loss),
                kj(a.crush_energy),
                kj(a.crush_energy_sigma),
                d.with_energy.as_ref().and_then(|f| {
                    let c = f.damage.as_ref()?.crush_energy;
                    Some((kj(f.energy_loss), kj(c)))
                }),
            ))
        })
        .collect();
    let top = points
        .iter()
        .map(|p| {
            let (l, c) = p.4.unwrap_or((0.0, 0.0));
            p.1.max(p.2 + p.3).max(l).max(c)
        })
        .fold(10.0f64, f64::max)
        * 1.1;
    svg_figure("crush_energy.svg", (720, 640), |root| {
        let mut chart = ChartBuilder::on(root)
            .caption(
                "RICSAC: crush energy (CRASH3) against the fitted energy loss",
                ("sans-serif", 18),
            )
            .margin(14)
            .x_label_area_size(44)
            .y_label_area_size(58)
            .build_cartesian_2d(0.0..top, 0.0..top)
            .map_err(err)?;
        chart
            .configure_mesh()
            .x_desc("kinetic energy loss of the fit, kJ")
            .y_desc("crush energy of both cars, kJ")
            .draw()
            .map_err(err)?;
        chart
            .draw_series(LineSeries::new(
                [(0.0, 0.0), (top, top)],
                BLACK.mix(0.5).stroke_width(1),
            ))
            .map_err(err)?
            .label("crush energy = energy loss (CRASH3's convention)")
            .legend(|(x, y)| PathElement::new([(x, y), (x + 16, y)], BLACK.mix(0.5)));
        let blue = RGBColor(31, 119, 180);
        let orange = RGBColor(255, 127, 14);
        chart
            .draw_series(points.iter().map(|p| {
                PathElement::new([(p.1, p.2 - p.3), (p.1, p.2 + p.3)], blue.stroke_width(1))
            }))
            .map_err(err)?;
        chart
            .draw_series(
                points
                    .iter()
                    .map(|p| Circle::new((p.1, p.2), 4, blue.filled())),
            )
            .map_err(err)?
            .label("the Q2 fit (velocities only); bars: +- 1 sigma of the crush")
            .legend(move |(x, y)| Circle::new((x + 8, y), 4, blue.filled()));
        chart
            .draw_series(points.iter().filter_map(|p| {
                p.4.map(|(l, c)| TriangleMarker::new((l, c), 5, orange.filled()))
            }))
            .map_err(err)?
            .label("the Q2 fit with the crush energy as evidence")
            .legend(move |(x, y)| TriangleMarker::new((x + 8, y), 5, orange.filled()));
        chart
            .draw_series(points.iter().map(|p| {
                Text::new(
                    format!("{}", p.0),
                    (p.1, p.2),
                    ("sans-serif", 12).into_font().color(&BLACK),
                )
            }))
            .map_err(err)?;
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        Ok(())
    })
}
