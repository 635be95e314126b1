//! The stages of a reconstruction: the first search, the second from the scatter, the
//! continuation before a refusal and its last look (see the crate docs, steps 1 to 6).

use crate::error::Result;
use crate::outcome::{Found, Outcome, Status, Tried};
use crate::problem::{Reconstruction, Settings};
use crate::refine::refine_start;
use crate::search::{answered, refined_from, search, searched, Look};

/// Reconstructs the collision: see the crate docs.
///
/// # Errors
/// Input the search cannot use ([`crate::ReconstructError`]). A scene no admissible impact
/// reaches is an [`Outcome`] with [`Status::NoSolution`].
pub fn reconstruct(r: &Reconstruction, settings: &Settings) -> Result<Outcome> {
    Ok(searched(r, unsaid(r, settings)?))
}

/// [`reconstruct`] before its refusal says what was searched.
pub(crate) fn unsaid(r: &Reconstruction, settings: &Settings) -> Result<Outcome> {
    r.check()?;
    // One budget of work for both searches. The first may spend half of it: a first search
    // that refines many combinations far from their scenes (each one's run-outs long and
    // slow) must not leave the second, from the scatter, nothing; where the first answer
    // fits, the second is not needed.
    let work = crate::work::Work::new(settings.refine_work / 2);
    let first = search(r, settings, (Look::Quick, None), &work)?;
    let fits_well = first.best.as_ref().is_some_and(|b| {
        pim_fit::ChiSquare::p_value_of(b.degrees_of_freedom, b.chi_square)
            .is_some_and(|p| p >= settings.scatter_below_p)
    });
    if fits_well {
        return Ok(first);
    }
    // The second search refines with at most as much work again as the first spent, and at
    // least half the budget, within what is left (each refinement with at most a third of
    // its budget: `Work::share`): a bound of its time on evidence whose impact fits or
    // run-outs are slow.
    let spent = work.spent();
    let limit = (spent + spent.max(settings.refine_work / 2)).min(settings.refine_work);
    let work = crate::work::Work::new(limit);
    work.add(spent);
    let second = search(r, settings, (Look::Scatter, Some(&first)), &work)?;
    let cost = |o: &Outcome| o.best.as_ref().map_or(f64::INFINITY, |b| b.chi_square);
    let (runouts, fits, work) = (
        first.runouts + second.runouts,
        first.fits + second.fits,
        work.spent(),
    );
    let mut out = if cost(&second) <= cost(&first) {
        second
    } else {
        first
    };
    out.runouts = runouts;
    out.fits = fits;
    out.work = work;
    out.first_work = spent;
    out.scattered = true;
    if out.status == Status::Inconsistent {
        continue_best(r, settings, &mut out);
    }
    if out.status == Status::Inconsistent {
        out = looked_finely(r, settings, out)?;
    }
    Ok(out)
}

/// A refusal's last look: each steered vehicle's scene searched once more from a scatter whose
/// grid is mapped at every quarter rad/s of yaw rate, from where the searches' lowest
/// refinements ended too, the other scenes' candidates kept. Steered wheels hold a car rolling
/// on a curve of radius `R = L / tan(delta)` (wheelbase `L`, steer angle `delta`), so its yaw
/// rate stays near `v / R`: where the distance to the rest fixes the speed, the states that
/// reach the rest have nearly one yaw rate, and their branch of the rest curve can be a closed
/// loop between two whole yaw rates that the scatter's planes never cross (a car turned once
/// around by its wheels on a 76 m run-out, whose states reaching its rest all lie between -1
/// and 0 rad/s). The search has a budget of its own
/// (half the whole budget again: it runs only where the answer would be refused). The lower
/// answer is kept, and the continuation runs on it where it is still refused.
fn looked_finely(r: &Reconstruction, settings: &Settings, mut out: Outcome) -> Result<Outcome> {
    if !r.scene.iter().any(crate::looks::steered) {
        return Ok(out);
    }
    let work = crate::work::Work::new(settings.refine_work / 2);
    let mut fine = search(r, settings, (Look::Fine, Some(&out)), &work)?;
    let cost = |o: &Outcome| o.best.as_ref().map_or(f64::INFINITY, |b| b.chi_square);
    if cost(&fine) >= cost(&out) {
        out.runouts += fine.runouts;
        out.fits += fine.fits;
        out.work += work.spent();
        return Ok(out);
    }
    // The continuation spends what a whole budget of work has left after the fine search.
    fine.work = work.spent();
    if fine.status == Status::Inconsistent {
        continue_best(r, settings, &mut fine);
    }
    fine.work += out.work;
    fine.runouts += out.runouts;
    fine.fits += out.fits;
    fine.first_work = out.first_work;
    fine.scattered = true;
    Ok(fine)
}

/// The scene's standard deviations widened `k` times (rest positions, headings and marks).
fn widened(r: &Reconstruction, k: f64) -> Reconstruction {
    let mut w = r.clone();
    for s in &mut w.scene {
        if let Some(rest) = s.evidence.rest.as_mut() {
            rest.sigma_xy = rest.sigma_xy.map(|x| x * k);
            rest.sigma_heading *= k;
        }
        for m in &mut s.evidence.marks {
            m.sigma *= k;
        }
    }
    w
}

/// The widenings of the scene's standard deviations a continuation passes through, the last
/// the evidence as given.
const CONTINUATION: [f64; 5] = [16.0, 8.0, 4.0, 2.0, 1.0];

/// At most this many combinations are continued before a refusal: the best, and the others
/// [`continue_best`] names.
const CONTINUED: usize = 3;

/// A refused answer searched once more before it is refused: the best combination of counts
/// refined by continuation, from its end, first with the scene's standard deviations widened
/// sixteen times (the impact and the contact evidence lead, the scene only pulls), then
/// narrowed step by step to the evidence as given, each stage refined from the one before. A
/// refinement that crawled in a curved valley of the full evidence, or stopped in a basin the
/// contact evidence does not want, is led around it. So is each other refined combination that
/// could still be answered:
/// - one whose scenes alone cost less than a refusal's chi-square (their cost is the least the
///   combination can cost where the scenes' search found their minima; above that level it is
///   refused whatever the impact);
/// - one whose momentum bound lies more than [`Settings::refine_margin`] below the best while
///   its refinement ended more than the margin above that bound (the linearisation that
///   bounded it did not hold on the way: a first step that overshot into a basin of its own);
///
/// the lowest scenes alone first, [`CONTINUED`] in all, within the budget of work the searches
/// left. The lowest answer is kept.
fn continue_best(r: &Reconstruction, settings: &Settings, out: &mut Outcome) {
    let (Some(best), Some(i)) = (out.best.as_ref(), out.best_index()) else {
        return;
    };
    let best_cost = best.chi_square;
    let dof = best.degrees_of_freedom;
    // Scenes alone that the evidence would not refuse: the combination may still meet it.
    let admissible = |scene: f64| {
        pim_fit::ChiSquare::p_value_of(dof, scene)
            .is_some_and(|p| p >= crate::outcome::INCONSISTENT_P)
    };
    let mut chosen = vec![i];
    let mut others: Vec<(f64, usize)> = out
        .tried
        .iter()
        .enumerate()
        .filter(|&(k, _)| k != i)
        .filter_map(|(k, t)| match (&t.state, t.momentum_bound, &t.end) {
            (Tried::Refined { cost, .. }, Some(bound), Some(_))
                if (*cost > bound + settings.refine_margin
                    && bound + settings.refine_margin < best_cost)
                    || admissible(t.scene_alone) =>
            {
                Some((t.scene_alone, k))
            }
            _ => None,
        })
        .collect();
    others.sort_by(|a, b| a.0.total_cmp(&b.0));
    chosen.extend(others.iter().map(|o| o.1).take(CONTINUED - 1));
    // What the two searches left of the one budget of work.
    let work = crate::work::Work::new(settings.refine_work.saturating_sub(out.work));
    let mut lowest: Option<(usize, crate::refine::Refined)> = None;
    for k in chosen {
        if work.exhausted() {
            break;
        }
        let (Some(end), counts) = (out.tried[k].end.clone(), out.tried[k].counts.clone()) else {
            continue;
        };
        if let Some(x) = continued(r, settings, &counts, end, &work, &mut out.fits) {
            if lowest
                .as_ref()
                .is_none_or(|l| x.point.total < l.1.point.total)
            {
                lowest = Some((k, x));
            }
        }
    }
    out.work += work.spent();
    let Some((k, x)) = lowest else { return };
    if x.point.total >= best_cost {
        return;
    }
    out.tried[k].state = Tried::Refined {
        cost: x.point.total,
        iterations: x.iterations,
        converged: x.converged,
        abandoned: false,
    };
    out.tried[k].end = Some(crate::outcome::End::of(&x.point));
    answered(r, out, Found::new(r, x.point, x.iterations, x.converged));
}

/// One combination's continuation from `end` (see [`continue_best`]): its answer on the
/// evidence as given, or `None` where a stage fails or is already refused (narrowing the
/// scene's deviations only raises the minimum: each scene term's weight grows, the others
/// stay).
fn continued(
    r: &Reconstruction,
    settings: &Settings,
    counts: &[Option<i64>],
    end: crate::outcome::End,
    work: &crate::work::Work,
    fits: &mut usize,
) -> Option<crate::refine::Refined> {
    let mut at = end;
    let mut last = None;
    for k in CONTINUATION {
        let rk = widened(r, k);
        let start = at.linearised(&rk, settings, counts).ok()?;
        let x = refine_start(&rk, settings, start, Some(at.state), work).ok()?;
        at = crate::outcome::End::of(&x.point);
        *fits += x.fits;
        if Found::new(&rk, x.point.clone(), x.iterations, x.converged).refused() {
            return None;
        }
        // The last stage is the evidence as given.
        last = Some(x);
    }
    last
}

/// The reconstruction of evidence a little changed from that of `previous` (a rest position
/// dragged on the plan): the combinations `previous` refined to within
/// [`Settings::refine_margin`] of its best are refined again from where they ended ([`crate::redo`]),
/// the lowest kept; the scenes are not searched again, and the outcome keeps `previous`'s list
/// of the combinations compared. A fast answer to follow a change with (a few Gauss-Newton
/// steps), not a search: where none of them refines, the whole search runs.
///
/// # Errors
/// Input the search cannot use.
pub fn follow(r: &Reconstruction, settings: &Settings, previous: &Outcome) -> Result<Outcome> {
    match refined_from(r, settings, previous)? {
        Some(out) => Ok(out),
        None => reconstruct(r, settings),
    }
}
