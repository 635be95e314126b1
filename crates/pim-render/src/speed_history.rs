//! `speed_history.svg`: each vehicle's speed before contact as the answer has it, beside what
//! its event data recorder stored (plotters, SVG).
//!
//! Per vehicle with an EDR (`[pre_impact.vehicleN] edr` or `edr_history`), one panel, time
//! before contact along x (0 at contact, negative before), speed along y:
//! - the recorded table (`edr_history`): a dot per row, filled red with the brake on, open
//!   blue with it off or not recorded; the accelerator pedal in grey against the right axis
//!   (percent);
//! - each EDR record of evidence (`edr`): its speed at its time, with its standard deviation;
//! - the answer: a vehicle that braked (`skid`) at its speed before braking, then slowing at
//!   the skid's rate to its speed at contact ([`pim_studies::playback::LeadIn`], the same
//!   history the motion plays back); a vehicle without a skid at its speed at contact over
//!   the second the motion shows before contact (the answer says nothing earlier);
//! - for each record, the speed the answer gives it: its stated deceleration drawn from the
//!   speed at contact back to the record's time (`vc + a t`), so that the record's distance
//!   from the end of its line is its residual. Where the records' decelerations and the skid
//!   disagree, the lines show it: each record is evidence through its own deceleration.

use crate::{err, svg_figure, Figure};
use pim_case::case::Case;
use pim_case::pre_impact::PreImpactVehicle;
use pim_case::units::UnitSystem;
use pim_core::VehicleId;
use pim_studies::reconstruct::Reconstructed;
use plotters::prelude::*;

const GRAVITY: f64 = 9.806_65;

/// What the marks are, above the panels (plotters' own legend would cover the data).
const KEY: [&str; 3] = [
    "Black: the answer (its skid, or its speed at contact); dot: at contact.",
    "Circles: the EDR's table (red: brake on). Grey: accelerator %, right axis.",
    "Green: EDR records (+- sd), and the speed the answer gives each.",
];

/// The height of the key above the panels, pixels.
const KEY_HEIGHT: u32 = 56;

/// The width of the figure in a report, pixels.
pub const WIDTH: u32 = 760;
const ON: RGBColor = RGBColor(214, 39, 40);
const OFF: RGBColor = RGBColor(31, 119, 180);
const PEDAL: RGBColor = RGBColor(150, 150, 150);
const RECORD: RGBColor = RGBColor(44, 160, 44);

/// The figure, `width` pixels wide (each vehicle's panel 0.45 of that high), or `None` when
/// no vehicle has an EDR or there is no answer; speeds in `u`. [`WIDTH`] for a report.
///
/// # Errors
/// A drawing that fails (plotters).
pub fn figure(
    case: &Case,
    done: &Reconstructed,
    u: UnitSystem,
    width: u32,
) -> Result<Option<Figure>, crate::RenderError> {
    let Some(best) = done.outcome.best.as_ref() else {
        return Ok(None);
    };
    let pre_impact = case
        .pre_impact_vehicles()
        .map_err(pim_studies::documents::DocumentError::from)?;
    let shown: Vec<(VehicleId, PreImpactVehicle)> = [VehicleId::One, VehicleId::Two]
        .into_iter()
        .zip(pre_impact)
        .filter_map(|(id, p)| p.map(|p| (id, p)))
        .filter(|(_, p)| !p.edr.is_empty() || !p.history.is_empty())
        .collect();
    if shown.is_empty() {
        return Ok(None);
    }
    let height = width * 45 / 100;
    let figure = svg_figure(
        "speed_history.svg",
        (width, KEY_HEIGHT + height * shown.len() as u32),
        |root| {
            let (key, panels) = root.split_vertically(KEY_HEIGHT);
            for (i, line) in KEY.iter().enumerate() {
                key.draw(&Text::new(
                    *line,
                    (12, 6 + 16 * i as i32),
                    ("sans-serif", 12).into_font(),
                ))
                .map_err(err)?;
            }
            for (area, (id, p)) in panels.split_evenly((shown.len(), 1)).iter().zip(&shown) {
                let lead = pim_studies::playback::lead_in(done, best, *id);
                panel(area, *id, p, &lead, u)?;
            }
            Ok(())
        },
    )?;
    Ok(Some(figure))
}

/// Vehicle `id`'s panel: its EDR `p` and the answer's lead-in `lead`, speeds in `u`.
fn panel(
    area: &DrawingArea<SVGBackend<'_>, plotters::coord::Shift>,
    id: VehicleId,
    p: &PreImpactVehicle,
    lead: &pim_studies::playback::LeadIn,
    u: UnitSystem,
) -> Result<(), crate::RenderError> {
    let label = u.speed_label();
    let speed = |si: f64| u.speed(si);
    let (earliest, history, records) = answer_lines(p, lead);
    let lines: Vec<&[(f64, f64)]> = std::iter::once(history.as_slice())
        .chain(records.iter().map(|r| r.as_slice()))
        .collect();
    let mut ys: Vec<f64> = lines
        .iter()
        .flat_map(|l| l.iter())
        .map(|p| u.speed(p.1))
        .collect();
    ys.extend(p.history.iter().map(|r| speed(r.speed)));
    ys.extend(
        p.edr
            .iter()
            .flat_map(|e| [speed(e.speed - e.sigma), speed(e.speed + e.sigma)]),
    );
    let lo = ys.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = ys.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    let pad = 0.1 * (hi - lo).max(2.0);
    let mut chart = ChartBuilder::on(area)
        .caption(
            format!("vehicle {}: speed before contact", id.index() + 1),
            ("sans-serif", 15),
        )
        .margin(10)
        .x_label_area_size(36)
        .y_label_area_size(50)
        .right_y_label_area_size(44)
        .build_cartesian_2d(-(earliest + 0.2)..0.2, (lo - pad).max(0.0)..hi + pad)
        .map_err(err)?
        .set_secondary_coord(-(earliest + 0.2)..0.2, 0.0..100.0);
    chart
        .configure_mesh()
        .light_line_style(RGBColor(238, 238, 238))
        .x_desc("time before contact [s]")
        .y_desc(format!("speed [{label}]"))
        .draw()
        .map_err(err)?;
    let pedal: Vec<(f64, f64)> = p
        .history
        .iter()
        .filter_map(|r| r.accelerator.map(|a| (-r.time, a)))
        .collect();
    if !pedal.is_empty() {
        chart
            .configure_secondary_axes()
            .y_desc("accelerator [%]")
            .draw()
            .map_err(err)?;
        chart
            .draw_secondary_series(LineSeries::new(pedal, PEDAL.stroke_width(1)))
            .map_err(err)?;
    }
    chart
        .draw_series(LineSeries::new(
            history.iter().map(|&(t, v)| (-t, u.speed(v))),
            BLACK.stroke_width(2),
        ))
        .map_err(err)?;
    for r in &records {
        chart
            .draw_series(LineSeries::new(
                r.iter().map(|&(t, v)| (-t, u.speed(v))),
                RECORD.stroke_width(1),
            ))
            .map_err(err)?;
    }
    chart
        .draw_series(std::iter::once(Circle::new(
            (0.0, u.speed(lead.speed)),
            4,
            BLACK.filled(),
        )))
        .map_err(err)?;
    chart
        .draw_series(p.history.iter().map(|r| {
            let at = (-r.time, speed(r.speed));
            if r.brake == Some(true) {
                Circle::new(at, 4, ON.filled())
            } else {
                Circle::new(at, 4, OFF.stroke_width(2))
            }
        }))
        .map_err(err)?;
    for e in &p.edr {
        let (t, v, s) = (-e.time, speed(e.speed), speed(e.sigma));
        chart
            .draw_series(LineSeries::new(
                [(t, v - s), (t, v + s)],
                RECORD.stroke_width(2),
            ))
            .map_err(err)?;
        chart
            .draw_series(std::iter::once(Cross::new(
                (t, v),
                6,
                RECORD.stroke_width(2),
            )))
            .map_err(err)?;
    }
    Ok(())
}

/// How far back a panel reaches (s), the answer's history and its line for each record.
type Lines = (f64, Vec<(f64, f64)>, Vec<[(f64, f64); 2]>);

/// How far back vehicle `p`'s panel reaches (s), the answer's speed history (the skid's, or
/// its speed at contact held over the approach the motion plays back: without a skid the
/// answer says nothing earlier) and the speed it gives each record (`vc + a t`, the record's
/// own deceleration): `(tau, speed m/s)` points.
fn answer_lines(p: &PreImpactVehicle, lead: &pim_studies::playback::LeadIn) -> Lines {
    let earliest = p
        .history
        .iter()
        .map(|r| r.time)
        .chain(p.edr.iter().map(|e| e.time))
        .chain(lead.braking.then_some(lead.duration))
        .fold(0.5_f64, f64::max);
    let taus: Vec<f64> = (0..=200).map(|i| earliest * f64::from(i) / 200.0).collect();
    let shown_back = if lead.braking {
        earliest
    } else {
        lead.duration.min(earliest)
    };
    let history: Vec<(f64, f64)> = taus
        .iter()
        .filter(|&&t| t <= shown_back)
        .map(|&t| (t, lead.speed_before(t)))
        .collect();
    let records: Vec<[(f64, f64); 2]> = p
        .edr
        .iter()
        .map(|e| {
            let a = e.deceleration * GRAVITY;
            [(0.0, lead.speed), (e.time, lead.speed + a * e.time)]
        })
        .collect();
    (earliest, history, records)
}
