//! The reconstruction started also from an earlier answer: the answer of a neighbouring input
//! (the case before an edit, a step of a sweep) refined on the input as it is now.

use crate::error::Result;
use crate::outcome::{Found, Outcome, Tried, TriedCounts};
use crate::point::{linearised, stated_frictions, Lin};
use crate::problem::{Reconstruction, Settings};
use crate::refine::refine_start;
use crate::search::{answered, searched};
use crate::stages::unsaid;
use crate::work::Work;
use pim_core::VehicleId;

/// One vehicle's separation state in an earlier answer: the start [`reconstruct_from`] refines
/// from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EarlierState {
    /// The vehicle.
    pub vehicle: VehicleId,
    /// Its count of turns to the rest heading (`None` without one).
    pub turns: Option<i64>,
    /// Its CG velocity (m/s) and yaw rate (rad/s) at separation, in the reconstruction's frame.
    pub velocity: [f64; 3],
}

impl Found {
    /// Each scene vehicle's count of turns and separation velocity: where a search or a
    /// refinement starts from this answer ([`reconstruct_from`]).
    pub fn states(&self) -> Vec<EarlierState> {
        self.scene
            .iter()
            .map(|s| {
                let v = self.solution.separation.vehicle(s.vehicle);
                EarlierState {
                    vehicle: s.vehicle,
                    turns: s.turns,
                    velocity: [v.vx, v.vy, v.omega],
                }
            })
            .collect()
    }
}

/// [`crate::reconstruct`], and the combination of counts of `earlier` refined from its states
/// (every scene vehicle's must be given, else it is not used); the lower answer is kept.
///
/// The search alone is a function of the input: two inputs a tenth of a foot apart can end in
/// different basins when each holds a minimum the other's search does not reach. Started also
/// from the answer of the neighbouring input, the reconstruction finds that answer's basin
/// again where it still holds one, so a small change of the input changes the answer a little
/// (or finds a lower minimum). The refinement from `earlier` has a budget of work of its own
/// ([`Settings::refine_work`]) and counts in [`Outcome::work`].
///
/// # Errors
/// Input the search cannot use.
pub fn reconstruct_from(
    r: &Reconstruction,
    settings: &Settings,
    earlier: &[EarlierState],
) -> Result<Outcome> {
    let mut out = unsaid(r, settings)?;
    let states: Option<Vec<&EarlierState>> = r
        .scene
        .iter()
        .map(|s| earlier.iter().find(|e| e.vehicle == s.id))
        .collect();
    if let Some(states) = states.filter(|s| !s.is_empty()) {
        from_states(r, settings, &states, &mut out);
    }
    Ok(searched(r, out))
}

/// `out` with the refinement from `states` as its answer where that is lower.
fn from_states(
    r: &Reconstruction,
    settings: &Settings,
    states: &[&EarlierState],
    out: &mut Outcome,
) {
    let mus = stated_frictions(r);
    let start: Result<Vec<Lin>> = states
        .iter()
        .enumerate()
        .map(|(v, e)| linearised(r, settings, v, e.turns.unwrap_or(0), e.velocity, true, &mus))
        .collect();
    let Ok(start) = start else { return };
    // The scenes' cost at the earlier states (a start of the search's kind).
    let scene_alone = start.iter().map(|l| l.lin.cost).sum();
    let work = Work::new(settings.refine_work);
    let refined = refine_start(r, settings, start, None, &work);
    out.work += work.spent();
    let Ok(x) = refined else { return };
    out.fits += x.fits;
    let counts: Vec<Option<i64>> = states.iter().map(|e| e.turns).collect();
    let lower = out
        .best
        .as_ref()
        .is_none_or(|b| x.point.total < b.chi_square);
    let state = Tried::Refined {
        cost: x.point.total,
        iterations: x.iterations,
        converged: x.converged,
        abandoned: false,
    };
    let end = Some(crate::outcome::End::of(&x.point));
    match out.tried.iter_mut().find(|t| t.counts == counts) {
        Some(t) => {
            let higher = match t.state {
                Tried::Refined { cost, .. } => cost > x.point.total,
                _ => true,
            };
            if higher {
                t.state = state;
                t.end = end;
            }
        }
        None => out.tried.push(TriedCounts {
            counts,
            scene_alone,
            momentum_bound: None,
            state,
            end,
        }),
    }
    if lower {
        answered(r, out, Found::new(r, x.point, x.iterations, x.converged));
    }
}
