//! How a search looks at the scenes: each scene vehicle's candidates from the run-out inverse,
//! quickly, from a scatter, or from a finer scatter (a steered vehicle's last look).

use crate::error::Result;
use crate::outcome::{Outcome, Tried, TriedCounts};
use crate::problem::{Reconstruction, Settings};
use pim_runout::{Estimate, EstimateSettings};

/// How a search looks at the scenes: quickly (the first search), from a scatter (the
/// second), or from a scatter whose grid is mapped at every quarter rad/s of yaw rate (the
/// last look before a refusal).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Look {
    Quick,
    Scatter,
    Fine,
}

/// True when the vehicle's front wheels are steered during its run-out.
pub(crate) fn steered(s: &crate::problem::SceneVehicle) -> bool {
    s.chassis.steer.iter().any(|&a| a != 0.0)
}

/// Tolerance of the run-outs of the first search's scene-alone candidates.
const CANDIDATE_TOLERANCE: f64 = 1e-6;

/// The candidates of one scene vehicle from the run-out inverse.
pub(crate) fn candidates(
    r: &Reconstruction,
    settings: &Settings,
    vehicle: usize,
    (scatter, fine): (bool, bool),
    earlier: Option<&Outcome>,
) -> Result<Estimate> {
    let s = &r.scene[vehicle];
    // The road friction is held at its value in the reconstruction (its spread is drawn by an
    // uncertainty study), so the scene alone is searched with it held too.
    let evidence = pim_runout::Evidence {
        friction_sigma: None,
        ..s.evidence.clone()
    };
    // The candidates are starts of the refinement, which runs at full precision: the first
    // search's quick look searches them on run-outs of tolerance CANDIDATE_TOLERANCE; the
    // second, thorough one at the run-outs' own precision. A long steered or rolling run-out's
    // rest moves by tens of standard deviations per m/s, and its scene polished on run-outs of
    // 1e-6 can miss an exact solution the same search finds at 1e-10 (a braked, steered
    // vehicle's 68 m run-out: its true count's candidate at 10,130 against 0.20).
    let es = EstimateSettings {
        turns: settings.turns,
        runout: if scatter {
            settings.runout
        } else {
            settings.runout.no_finer_than(CANDIDATE_TOLERANCE)
        },
        scatter,
        // The first search looks quickly; the second (where the first answer fits poorly)
        // from every start and the scatter.
        quick: !scatter,
        starts: earlier.map_or_else(Vec::new, |e| answers_of(e, vehicle)),
        fine,
        ..EstimateSettings::default()
    };
    Ok(pim_runout::estimate(&s.chassis, &s.pose, &evidence, &es)?)
}

/// At most this many of an earlier search's refined combinations give the scenes' inverse
/// starts from the impact's side (the lowest).
const ANSWER_STARTS: usize = 3;

/// Scene vehicle `v`'s separation states where an earlier search's lowest refinements ended,
/// with their counts of turns: starts of the scene's inverse from the impact's side.
fn answers_of(earlier: &Outcome, v: usize) -> Vec<(Option<i64>, [f64; 3])> {
    let mut refined: Vec<(f64, &TriedCounts)> = earlier
        .tried
        .iter()
        .filter_map(|t| match (&t.state, &t.end) {
            (Tried::Refined { cost, .. }, Some(_)) => Some((*cost, t)),
            _ => None,
        })
        .collect();
    refined.sort_by(|a, b| a.0.total_cmp(&b.0));
    refined
        .iter()
        .take(ANSWER_STARTS)
        .filter_map(|(_, t)| Some((t.counts[v], *t.end.as_ref()?.velocities.get(v)?)))
        .collect()
}
