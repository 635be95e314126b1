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

/// An earlier answer, as [`reconstruct_from`] starts from it: each scene vehicle's state and
/// the frictions its run-outs ran on.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Earlier {
    /// Each scene vehicle's count of turns and separation velocity.
    pub states: Vec<EarlierState>,
    /// The frictions the earlier answer's run-outs ran on, one per
    /// [`Reconstruction::frictions`] (the fitted ones); `None`, or a list of another length
    /// (a friction zone added or taken away since), starts on the stated frictions. A long
    /// run-out fitted on a friction of 0.53 and started again on a stated 0.60 ends metres
    /// from the rest it met: the start would not be the earlier answer.
    pub frictions: Option<Vec<f64>>,
}

impl Found {
    /// Each scene vehicle's count of turns and separation velocity, and the frictions the
    /// run-outs ran on: where a search or a refinement starts from this answer
    /// ([`reconstruct_from`]).
    pub fn earlier(&self) -> Earlier {
        let states = self
            .scene
            .iter()
            .map(|s| {
                let v = self.solution.separation.vehicle(s.vehicle);
                EarlierState {
                    vehicle: s.vehicle,
                    turns: s.turns,
                    velocity: [v.vx, v.vy, v.omega],
                }
            })
            .collect();
        Earlier {
            states,
            frictions: Some(self.frictions.clone()),
        }
    }
}

/// [`crate::reconstruct`], and the combination of counts of `earlier` refined from its states
/// (every scene vehicle's must be given, else it is not used), on the frictions its run-outs
/// ran on; the lower answer is kept.
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
    earlier: &Earlier,
) -> Result<Outcome> {
    let mut out = unsaid(r, settings)?;
    let work = Work::new(settings.refine_work);
    let from = from_earlier(r, settings, earlier, &work);
    out.work += work.spent();
    if let Some(from) = from {
        kept(r, from, &mut out);
    }
    Ok(searched(r, out))
}

/// The refinement from `earlier` alone, without the search ([`reconstruct_from`] keeps it
/// where it is lower than the search's): the answer of `earlier`'s counts of turns refined on
/// `r` from its states and frictions, with a budget of work of [`Settings::refine_work`].
/// `None` where `earlier` lacks a scene vehicle's state or the refinement fails.
pub fn refine_earlier(r: &Reconstruction, settings: &Settings, earlier: &Earlier) -> Option<Found> {
    let work = Work::new(settings.refine_work);
    from_earlier(r, settings, earlier, &work)
        .map(|f| Found::new(r, f.x.point, f.x.iterations, f.x.converged))
}

/// A refinement from an earlier answer: where it ended, the cost of the scenes alone at its
/// start, and its counts of turns.
struct FromEarlier {
    x: crate::refine::Refined,
    scene_alone: f64,
    counts: Vec<Option<i64>>,
}

/// The refinement from `earlier`'s states, on its frictions where they fit `r` (else the
/// stated ones); `None` where a scene vehicle's state is missing or the refinement fails.
fn from_earlier(
    r: &Reconstruction,
    settings: &Settings,
    earlier: &Earlier,
    work: &Work,
) -> Option<FromEarlier> {
    let states: Vec<&EarlierState> = r
        .scene
        .iter()
        .map(|s| earlier.states.iter().find(|e| e.vehicle == s.id))
        .collect::<Option<_>>()
        .filter(|s: &Vec<&EarlierState>| !s.is_empty())?;
    let mus = earlier
        .frictions
        .clone()
        .filter(|m| m.len() == r.frictions.len() && m.iter().all(|x| x.is_finite() && *x > 0.0))
        .unwrap_or_else(|| stated_frictions(r));
    let start: Vec<Lin> = states
        .iter()
        .enumerate()
        .map(|(v, e)| linearised(r, settings, v, e.turns.unwrap_or(0), e.velocity, true, &mus))
        .collect::<Result<_>>()
        .ok()?;
    // The scenes' cost at the earlier states (a start of the search's kind).
    let scene_alone = start.iter().map(|l| l.lin.cost).sum();
    let x = refine_start(r, settings, start, None, work).ok()?;
    Some(FromEarlier {
        x,
        scene_alone,
        counts: states.iter().map(|e| e.turns).collect(),
    })
}

/// `out` with the refinement `from` an earlier answer as its answer where that is lower, and
/// as its counts' entry where that ended higher.
fn kept(r: &Reconstruction, from: FromEarlier, out: &mut Outcome) {
    let FromEarlier {
        x,
        scene_alone,
        counts,
    } = from;
    out.fits += x.fits;
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
