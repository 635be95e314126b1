//! The damage section of a report: each damaged vehicle's crush profile drawn on its outline,
//! the crush energies beside PIM's energy loss, CRASH3's delta-V beside PIM's, and the fit with
//! the crush energy as evidence.

use super::doc::{Block, Section, Table};
use crate::{err, svg_figure, Figure};
use pim_case::case::Case;
use pim_case::damage::Side;
use pim_case::units::UnitSystem;
use pim_studies::damage_assess::Assessment;
use pim_studies::damage_fit::FitDamage;
use plotters::prelude::*;

/// The damage section (`None` when the case has no damage to show).
pub(super) fn section(
    case: &Case,
    at: Option<&Assessment>,
    fit: Option<&FitDamage>,
    u: UnitSystem,
) -> Result<Option<Section>, crate::RenderError> {
    let Some(a) = at.or_else(|| fit.and_then(|f| f.at_fit.as_ref())) else {
        return Ok(None);
    };
    let mut s = Section::new("Damage");
    s.text(
        "Crush energy by CRASH3's linear stiffness model (force per unit width A + B C), \
         integrated exactly over each profile with the crush linear between the measured \
         points, times the direction-of-force factor 1 + tan^2 of the force's angle from the \
         face's normal (held at 2 beyond 45 deg). CRASH3's delta-V follows from the total \
         energy with the effective masses k^2/(k^2+h^2) of the impulse's moment arm h.",
    );
    s.blocks.push(Block::Figure(
        profiles_figure(case, a)?,
        "The crush profiles on the outlines (body frame, nose up; depths to scale)".into(),
    ));
    let label = match fit {
        Some(_) => "At the fit's answer (without the crush energy)",
        None => "At the solution",
    };
    s.text(label.to_string());
    push_assessment(&mut s, a, u);
    if let Some(f) = fit {
        if let Some(why) = &f.not_evidence {
            s.text(format!("The crush energy is not fitted: {why}."));
        }
        if let Some(e) = &f.with_energy {
            s.text(format!(
                "Fitted with the crush energy as evidence ({} branch): e {:.4}, mu {:.4}, em \
                 {:.4}; delta-V {:.2} / {:.2} {}; energy loss {:.1} kJ; the energy's residual \
                 {:+.2} standard deviations; cost {:.6}, of which the case's evidence {:.6}. {}",
                e.moment.name(),
                e.e,
                e.mu,
                e.em,
                u.speed(e.delta_v[0]),
                u.speed(e.delta_v[1]),
                u.speed_label(),
                e.energy_loss / 1000.0,
                e.energy_z,
                e.cost,
                e.cost_without_energy,
                if e.proven {
                    "Proven optimal: the cost meets the certified optimum without the energy."
                        .to_string()
                } else {
                    format!(
                        "The best found, not proven global; no answer costs less than the \
                         certified optimum without the energy, {:.6}.",
                        e.lower_bound
                    )
                }
            ));
            if let Some(a) = &e.damage {
                push_assessment(&mut s, a, u);
            }
        }
    }
    Ok(Some(s))
}

fn push_assessment(s: &mut Section, a: &Assessment, u: UnitSystem) {
    let sp = u.speed_label();
    let mut t = Table::new(&[
        "vehicle",
        "face",
        "E, kJ",
        "PDOF, deg",
        "factor",
        "E with factor, kJ",
        &format!("BEV, {sp}"),
        "h, m",
        "gamma",
        &format!("CRASH3 dV, {sp}"),
        &format!("PIM dV, {sp}"),
    ]);
    for (k, v) in a.vehicles.iter().enumerate() {
        let Some(v) = v else { continue };
        t.row(vec![
            format!(
                "{}{}",
                k + 1,
                if v.measured { "" } else { " (force balance)" }
            ),
            v.side.name().into(),
            format!("{:.1}", v.crush_energy / 1000.0),
            format!("{:.1}", v.pdof),
            format!("{:.3}", v.pdof_factor),
            format!("{:.1}", v.energy / 1000.0),
            format!("{:.2}", u.speed(v.barrier_equivalent_speed)),
            format!("{:.2}", v.moment_arm),
            format!("{:.3}", v.effective_mass_factor),
            format!("{:.2}", u.speed(v.crash3_delta_v)),
            format!("{:.2}", u.speed(v.pim_delta_v)),
        ]);
    }
    s.blocks.push(Block::Table(t));
    let z =
        a.z.map_or_else(String::new, |z| format!(" ({z:+.2} standard deviations)"));
    s.text(format!(
        "Crush energy {:.1} +- {:.1} kJ; the energy loss it implies ({}) {:.1} kJ; PIM's energy \
         loss {:.1} kJ; difference {:+.1} kJ{z}. {}",
        a.crush_energy / 1000.0,
        a.crush_energy_sigma / 1000.0,
        a.relation.name(),
        a.expected_loss / 1000.0,
        a.energy_loss / 1000.0,
        a.difference / 1000.0,
        capitalised(&a.relation_note),
    ));
    if !a.warnings.is_empty() {
        s.blocks.push(Block::Warnings(a.warnings.clone()));
    }
}

fn capitalised(t: &str) -> String {
    let mut c = t.chars();
    match c.next() {
        Some(f) => f.to_uppercase().chain(c).collect::<String>() + ".",
        None => String::new(),
    }
}

/// The outline of vehicle `k` about its CG: (CG to front, CG to rear, width), m.
fn outline(case: &Case, k: usize) -> (f64, f64, f64) {
    let (o, _) = case.vehicle(k).outline();
    (o.cg_to_front, o.cg_to_rear, o.width)
}

/// The crushed face's points in the body frame (x forward, y left): the measured points from
/// one end of the damage to the other (front and rear: from the left side to the right; sides:
/// from front to rear), each moved in by its depth.
fn profile_points(
    side: Side,
    depths: &[f64],
    width: f64,
    offset: f64,
    o: (f64, f64, f64),
) -> Vec<(f64, f64)> {
    let n = depths.len();
    let at = |i: usize| offset + width / 2.0 - width * i as f64 / (n - 1).max(1) as f64;
    depths
        .iter()
        .enumerate()
        .map(|(i, c)| match side {
            Side::Front => (o.0 - c, at(i)),
            Side::Rear => (-o.1 + c, at(i)),
            Side::Left => (at(i), o.2 / 2.0 - c),
            Side::Right => (at(i), -o.2 / 2.0 + c),
        })
        .collect()
}

/// The figure `damage.svg`: each damaged vehicle's outline with its crushed region.
fn profiles_figure(case: &Case, a: &Assessment) -> Result<Figure, crate::RenderError> {
    let damaged: Vec<usize> = (0..2).filter(|&k| a.vehicles[k].is_some()).collect();
    let panels = damaged.len().max(1) as u32;
    // Each centre of damage in SI and the natural frame, as the case resolves it.
    let stated =
        pim_case::damage::Damage::of(case).map_err(pim_studies::documents::DocumentError::from)?;
    let offsets: Vec<f64> = damaged
        .iter()
        .map(|&k| {
            stated
                .as_ref()
                .and_then(|d| d.vehicles[k].as_ref())
                .map_or(0.0, |v| v.offset)
        })
        .collect();
    svg_figure("damage.svg", (420 * panels, 470), |root| {
        let areas = root.split_evenly((1, panels as usize));
        for ((area, &k), offset) in areas.iter().zip(&damaged).zip(&offsets) {
            let v = a.vehicles[k].as_ref().expect("damaged");
            let o = outline(case, k);
            let half = (o.0.max(o.1) + 0.3).max(o.2 / 2.0 + 0.3);
            let mut chart = ChartBuilder::on(area)
                .caption(
                    format!("vehicle {} ({} damage)", k + 1, v.side.name()),
                    ("sans-serif", 16),
                )
                .margin(10)
                .x_label_area_size(30)
                .y_label_area_size(40)
                .build_cartesian_2d(-half..half, -half..half)
                .map_err(err)?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_desc("m, to the right +")
                .y_desc("m (forward +)")
                .draw()
                .map_err(err)?;
            // Nose up: plot (y_body flipped so that left is left, x_body up).
            let to = |(x, y): (f64, f64)| (-y, x);
            let corners = [
                (o.0, o.2 / 2.0),
                (o.0, -o.2 / 2.0),
                (-o.1, -o.2 / 2.0),
                (-o.1, o.2 / 2.0),
            ];
            let mut ring: Vec<(f64, f64)> = corners.iter().map(|&p| to(p)).collect();
            ring.push(ring[0]);
            chart
                .draw_series(std::iter::once(PathElement::new(
                    ring,
                    BLACK.stroke_width(2),
                )))
                .map_err(err)?;
            let off = *offset;
            let crushed = profile_points(v.side, &v.depths, v.width, off, o);
            let face: Vec<(f64, f64)> =
                profile_points(v.side, &vec![0.0; v.depths.len()], v.width, off, o);
            let mut region: Vec<(f64, f64)> = face.iter().map(|&p| to(p)).collect();
            region.extend(crushed.iter().rev().map(|&p| to(p)));
            let red = RGBColor(214, 39, 40);
            chart
                .draw_series(std::iter::once(Polygon::new(
                    region,
                    red.mix(0.35).filled(),
                )))
                .map_err(err)?;
            chart
                .draw_series(std::iter::once(PathElement::new(
                    crushed.iter().map(|&p| to(p)).collect::<Vec<_>>(),
                    red.stroke_width(2),
                )))
                .map_err(err)?;
            chart
                .draw_series(crushed.iter().map(|&p| Circle::new(to(p), 3, red.filled())))
                .map_err(err)?;
            chart
                .draw_series(std::iter::once(Cross::new(
                    (0.0, 0.0),
                    5,
                    BLACK.stroke_width(2),
                )))
                .map_err(err)?;
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("E {:.1} kJ", v.crush_energy / 1000.0),
                    (-half * 0.9, -half * 0.85),
                    ("sans-serif", 13).into_font(),
                )))
                .map_err(err)?;
        }
        Ok(())
    })
}
