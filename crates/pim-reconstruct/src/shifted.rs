//! The last search before a refusal: the scenes searched again on the fitted road friction
//! moved by its standard deviation either way.
//!
//! With the friction held, a count's scene (a rest position and heading: three equations in
//! three unknowns) has isolated solutions, and they move fast with the friction: a free-rolling
//! car's rest moves tens of metres when the friction changes by 0.05 (its sliding phase, which
//! sets the speed it rolls on with, shortens), so the solution the impact wants on the true
//! friction is often on no branch of the solutions on the stated one, and the refinement (over
//! the separation states and the friction together) cannot reach it from them: the states that
//! meet the rest within its few tenths of a metre form a thin curved valley. Where the answer
//! would be refused and the friction is fitted (stated with its spread), the scenes are
//! searched again on the friction [`FRICTION_SHIFTS`] standard deviations off, each start's
//! refinement from that friction (its prior still at the stated value), and the lowest answer
//! kept.

use crate::error::Result;
use crate::outcome::{Outcome, Status};
use crate::problem::{Reconstruction, Settings};
use crate::refine::Work;
use crate::search::{one_per_counts, search};

/// The fitted frictions' shifts the last search starts from, in their standard deviations.
pub(crate) const FRICTION_SHIFTS: [f64; 2] = [-1.5, 1.5];

/// `out` (refused) with the lowest answer of the searches on the shifted frictions where that
/// is lower; each search may spend a quarter of [`Settings::refine_work`] on its refinements.
pub(crate) fn search_shifted(
    r: &Reconstruction,
    settings: &Settings,
    out: &mut Outcome,
) -> Result<()> {
    if r.frictions.is_empty() || !settings.shift_frictions {
        return Ok(());
    }
    for shift in FRICTION_SHIFTS {
        if out.status != Status::Inconsistent {
            break;
        }
        let work = Work::new(settings.refine_work / 4);
        let o = search(r, settings, (true, shift), &work)?;
        let (runouts, fits, spent) = (
            out.runouts + o.runouts,
            out.fits + o.fits,
            out.work + o.work,
        );
        let cost = |o: &Outcome| o.best.as_ref().map_or(f64::INFINITY, |b| b.chi_square);
        let mut tried = std::mem::take(&mut out.tried);
        tried.extend(o.tried.iter().cloned());
        if cost(&o) < cost(out) {
            let first_work = out.first_work;
            *out = o;
            out.first_work = first_work;
        }
        out.tried = one_per_counts(tried);
        out.runouts = runouts;
        out.fits = fits;
        out.work = spent;
        out.scattered = true;
    }
    Ok(())
}
