//! The run-out: its table and its plan view (each path, the outline at regular times and at
//! rest, the scene's evidence), to scale.

use crate::runout_plan::outline_of;
use pim_case::units::UnitSystem;
use pim_core::Convention;
use pim_runout::Motion;
use pim_studies::runout::RunoutResult;

pub use crate::runout_table::runout_table;

/// Vehicle `k`'s crush profile at the pose `m` on the page: the damaged face's ends and the
/// crushed points between them (each depth measured in from the face, equally spaced over the
/// damaged width about its offset; the first depth at the left end of the front or rear, the
/// front end of a side), a closed polygon, in the display length unit of `units`.
pub fn damage_on_page(
    r: &RunoutResult,
    k: usize,
    m: &Motion,
    damage: &pim_case::damage::VehicleDamage,
    units: UnitSystem,
    frame: Convention,
) -> Vec<(f64, f64)> {
    use pim_case::damage::Side;
    let (length, width, front) = outline_of(r, k);
    let depths = &damage.profile.depths;
    let n = depths.len().max(2) - 1;
    let w = damage.profile.width;
    // Along the face (its coordinate from the first end) and in from it: body (x, y).
    let at = |along: f64, depth: f64| -> (f64, f64) {
        match damage.side {
            Side::Front => (front - depth, damage.offset + w / 2.0 - along),
            Side::Rear => (front - length + depth, damage.offset + w / 2.0 - along),
            Side::Left => (damage.offset + w / 2.0 - along, width / 2.0 - depth),
            Side::Right => (damage.offset + w / 2.0 - along, -width / 2.0 + depth),
        }
    };
    let mut body = vec![at(0.0, 0.0)];
    body.extend(
        depths
            .iter()
            .enumerate()
            .map(|(i, &d)| at(w * i as f64 / n as f64, d)),
    );
    body.push(at(w, 0.0));
    body.push(at(0.0, 0.0));
    let page = crate::plan::Page::of(frame);
    body.iter()
        .map(|&(x, y)| {
            let (gx, gy) = m.point([x, y]);
            page.xy((units.length(gx), units.length(gy)))
        })
        .collect()
}

/// The plan view of the run-out as SVG: each vehicle's CG path, its outline at separation
/// (bold), every `every` seconds (light) and at rest (filled), the rest position given by the
/// scene (dashed outline, cross at its CG) and the marks (circles of one sd).
pub fn runout_svg(
    title: &str,
    r: &RunoutResult,
    units: UnitSystem,
    frame: Convention,
    every: f64,
) -> Result<String, crate::RenderError> {
    scene_svg(title, r, &[], units, frame, every)
}

pub use crate::runout_plan::{
    outline_on_page, scene_svg, start_outline_on_page, tyre_traces, Approach,
};

/// The scene to scale of a case's reconstruction: each run-out as the reconstruction fitted it
/// (on its fitted road friction; the residuals printed are the evidence table's), the braking
/// before the impact, the scene's evidence, in `units` and the case's frame (what `pim fit
/// --out`, the report and Python draw alike). `None` without an answer.
pub fn reconstruction_scene(
    case: &pim_case::case::Case,
    done: &pim_studies::reconstruct::Reconstructed,
    units: UnitSystem,
) -> Result<Option<String>, crate::RenderError> {
    let Some(runouts) = fitted_runouts(case, done)? else {
        return Ok(None);
    };
    reconstruction_scene_of(case, done, &runouts, units).map(Some)
}

/// The run-outs every drawing of the reconstruction `done` of `case` draws (the fitted ones,
/// sampled every 0.02 s; [`pim_studies::runout::fitted`]), found once for several drawings.
/// `None` without an answer.
///
/// # Errors
/// The fitted run-outs cannot be found again (a message).
pub fn fitted_runouts(
    case: &pim_case::case::Case,
    done: &pim_studies::reconstruct::Reconstructed,
) -> Result<Option<pim_studies::runout::RunoutResult>, crate::RenderError> {
    let Some(best) = &done.outcome.best else {
        return Ok(None);
    };
    pim_studies::runout::fitted(case, best, 0.02, false)
        .map(Some)
        .map_err(crate::err)
}

/// [`reconstruction_scene`] of the fitted run-outs `runouts` ([`fitted_runouts`]).
///
/// # Errors
/// The drawing cannot be made (a message).
pub fn reconstruction_scene_of(
    case: &pim_case::case::Case,
    done: &pim_studies::reconstruct::Reconstructed,
    runouts: &pim_studies::runout::RunoutResult,
    units: UnitSystem,
) -> Result<String, crate::RenderError> {
    let approach: Vec<Approach> = pim_studies::reconstruct::skid_lengths(&done.input)
        .into_iter()
        .map(|(vehicle, length)| Approach { vehicle, length })
        .collect();
    scene_svg(
        &crate::text::case_title(case),
        runouts,
        &approach,
        units,
        case.written,
        0.5,
    )
}
