//! The answer's motion on the page, for the time slider: each vehicle's outline and CG from
//! where its braking began through contact to rest ([`pim_studies::playback`]), sampled every
//! [`STEP`] seconds.

use pim_case::case::Case;
use pim_case::units::UnitSystem;
use serde::Serialize;

/// The time between the samples sent to the page, s (the page interpolates between them).
pub const STEP: f64 = 0.04;

/// The motion on the page.
#[derive(Debug, Serialize, Default, Clone)]
pub struct PlanMotion {
    /// The earliest time shown (the first braking's start, or the approach), s; 0 is contact.
    pub start: f64,
    /// The latest time (the last vehicle at rest), s.
    pub end: f64,
    /// Each vehicle's track.
    pub vehicles: Vec<PlanTrack>,
}

/// One vehicle's track on the page.
#[derive(Debug, Serialize, Default, Clone)]
pub struct PlanTrack {
    /// 1 or 2.
    pub vehicle: u8,
    /// Whether it braked before contact (else it approached at its contact velocity).
    pub braking: bool,
    /// The sample times, s, increasing; one is 0 (contact).
    pub times: Vec<f64>,
    /// Its outline at each time (a closed polygon, display length unit on the page).
    pub outlines: Vec<Vec<[f64; 2]>>,
    /// Its CG at each time.
    pub cg: Vec<[f64; 2]>,
}

/// The motion of the answer `best` of `done` (its fitted run-outs `fitted`) on the page of
/// `case` in the display units `units`.
pub(crate) fn motion_on_page(
    case: &Case,
    done: &pim_studies::reconstruct::Reconstructed,
    best: &pim_reconstruct::Found,
    fitted: &pim_studies::runout::RunoutResult,
    units: UnitSystem,
) -> PlanMotion {
    let page = pim_render::plan::Page::of(case.written);
    let tracks = pim_studies::playback::tracks(done, best, fitted, STEP);
    let vehicles: Vec<PlanTrack> = tracks
        .iter()
        .map(|t| PlanTrack {
            vehicle: t.vehicle.index() as u8 + 1,
            braking: t.braking,
            times: t.poses.iter().map(|(s, _)| *s).collect(),
            outlines: t
                .poses
                .iter()
                .map(|(_, m)| {
                    pim_render::runout::outline_on_page(fitted, t.index, m, units, case.written)
                        .into_iter()
                        .map(|(h, v)| [h, v])
                        .collect()
                })
                .collect(),
            cg: t
                .poses
                .iter()
                .map(|(_, m)| {
                    let (h, v) = page.xy((units.length(m.x), units.length(m.y)));
                    [h, v]
                })
                .collect(),
        })
        .collect();
    let first = |v: &PlanTrack| v.times.first().copied().unwrap_or(0.0);
    let last = |v: &PlanTrack| v.times.last().copied().unwrap_or(0.0);
    PlanMotion {
        start: vehicles.iter().map(first).fold(0.0, f64::min),
        end: vehicles.iter().map(last).fold(0.0, f64::max),
        vehicles,
    }
}
