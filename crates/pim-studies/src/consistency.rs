//! Which pieces of a scene's evidence agree: the reconstruction with each piece (or group of
//! pieces) left out in turn, its chi-square, probability and speeds, and the subsets that are
//! consistent.
//!
//! A refused or poorly fitting reconstruction says that the evidence as a whole disagrees, not
//! which of it. Leaving out one group at a time and refitting answers that: a group whose
//! removal makes the rest consistent is the suspect (or the one the others outvote), and the
//! spread of the speeds over the rows shows how much the answer rests on each piece.
//!
//! The groups are what a reconstructionist weighs as one piece of evidence: a vehicle's rest
//! position (its x, y and heading together), each tyre mark, each EDR speed, each named
//! observation, the case's `[estimates]` as a whole, and each prior of a pose fitted by
//! `[contact_sigma]`. A prior left out keeps its value fitted: its row fits the pose again from
//! the whole answer's without that prior ([`Case::without_contact_prior`]), one degree of
//! freedom fewer; every other row holds the pose where the whole answer put it, the priors'
//! share added. Pairs are left out among the evidence only. A pre-impact skid is not a group: it
//! turns the contact speed into the speed before braking and adds no residual, so it cannot
//! conflict with anything.
//!
//! Each row is a whole reconstruction (every count of turns searched) and, where the same
//! vehicles keep a scene, also the whole answer's combinations refined from where they ended
//! without the piece; the lower of the two is the row. Removing evidence can only lower the
//! minimum, so no row lies above the whole fit. A rest left out takes its count of turns with
//! it, and a vehicle left with no scene evidence leaves the reconstruction's run-outs. The
//! table costs about as many reconstructions as there are groups; the rows run in parallel on the current rayon
//! pool. When no single group explains the conflict, pairs are left out too (up to
//! [`MAX_PAIR_GROUPS`] groups). The whole table stays within [`TABLE_WORK`].

use crate::documents::DocumentError;
use crate::pieces::{left_out, pieces, Piece};
pub use crate::pieces::{piece_names, piece_of, pieces_named, switched_off, PieceId};
use pim_case::case::Case;
use pim_documents::reconstruct_doc::ReconstructionOut;
pub use pim_documents::reconstruct_doc::{Consistency, LeftOut};
use pim_fit::MomentBranch;
use pim_reconstruct::{Status, INCONSISTENT_P, POOR_FIT_P};
use rayon::prelude::*;

/// The table's budget of work: run-out right-hand side evaluations and their equivalents for
/// the impact fits, as a reconstruction counts its refinements (`work` of its document; each
/// row costs about as much as the reconstruction with all the evidence: 1.4 million for the
/// example with its EDR moved 8 mph, whose eight rows take 6 s on two cores). Beyond it the
/// table is not computed and says so; the count, not the time, decides, so the answer is the
/// same on every machine. A unit takes 0.4 to 1.3 us on one core of a 2020s machine.
pub const TABLE_WORK: u64 = 24_000_000;

/// Pairs of groups are left out only when there are at most this many groups (and no single
/// group explains the conflict): 28 pairs for 8 groups.
pub const MAX_PAIR_GROUPS: usize = 8;

/// The reconstruction of `case` (the whole case less some pieces): its own first search, and
/// the refinement of the whole answer's combinations of counts from where they ended there
/// ([`pim_reconstruct::refined_from`]), where the same vehicles have scenes; the lower
/// chi-square.
fn left_out_row(
    case: &Case,
    how: crate::reconstruct::How,
    whole: &crate::reconstruct::Reconstructed,
    prior: bool,
) -> Result<ReconstructionOut, DocumentError> {
    let Some(pose) = &whole.pose else {
        return left_out_at(case, how, whole);
    };
    if prior {
        // A prior of the pose left out: the pose fitted again from the whole answer, the
        // value still fitted, the prior's datum gone.
        let (input, outcome, fitted) = crate::reconstruct_pose::refit_without_prior(
            case,
            &how,
            (pose, &whole.input.settings),
        )?;
        let mut d = crate::reconstruct::document(&input, &outcome);
        crate::reconstruct_pose::with_pose(&mut d, fitted);
        return Ok(d);
    }
    // Any other piece: the pose held where the whole answer put it, its priors' share added
    // (a pose fit per row would cost the table ten times the answer).
    let posed = case.with_contact_held(&case.contact_unknowns()?, &pose.offsets)?;
    let mut d = left_out_at(&posed, how, whole)?;
    if let Some(b) = d.best.as_mut() {
        b.chi_square += pose.prior_chi_square;
        b.p_value = pim_fit::ChiSquare::p_value_of(b.degrees_of_freedom, b.chi_square);
    }
    Ok(d)
}

/// [`left_out_row`] at the case's pose.
fn left_out_at(
    case: &Case,
    how: crate::reconstruct::How,
    whole: &crate::reconstruct::Reconstructed,
) -> Result<ReconstructionOut, DocumentError> {
    let fresh = crate::reconstruct::reconstruct_searching(case, how, false, &Default::default())?;
    let ids =
        |r: &pim_reconstruct::Reconstruction| r.scene.iter().map(|s| s.id).collect::<Vec<_>>();
    let same_scenes = ids(&fresh.input.reconstruction) == ids(&whole.input.reconstruction);
    if !same_scenes || whole.outcome.best.is_none() {
        return Ok(fresh.document);
    }
    let input = &fresh.input;
    let Ok(Some(followed)) =
        pim_reconstruct::refined_from(&input.reconstruction, &input.settings, &whole.outcome)
    else {
        return Ok(fresh.document);
    };
    let cost =
        |o: &pim_reconstruct::Outcome| o.best.as_ref().map_or(f64::INFINITY, |b| b.chi_square);
    if cost(&followed) < cost(&fresh.outcome) {
        // The row's own search (what it compared, what it spent), with the answer the whole
        // answer's start found.
        let mut out = fresh.outcome;
        out.status = followed.status;
        out.reason = followed.reason;
        out.contradiction = followed.contradiction;
        out.best = followed.best;
        Ok(crate::reconstruct::document(input, &out))
    } else {
        Ok(fresh.document)
    }
}

fn row(left_out: Vec<String>, d: Result<ReconstructionOut, DocumentError>) -> LeftOut {
    let mut r = LeftOut {
        left_out,
        status: "failed".into(),
        chi_square: None,
        degrees_of_freedom: None,
        p_value: None,
        consistent: false,
        speed_at_contact: [None; 2],
        speed_before_braking: [None; 2],
        largest: None,
        error: None,
    };
    match d {
        Err(e) => r.error = Some(e.to_string()),
        Ok(d) => {
            r.status = match d.status {
                Status::Found => "found",
                Status::Inconsistent => "inconsistent",
                Status::NoSolution => "no_solution",
            }
            .into();
            if let Some(b) = &d.best {
                r.chi_square = Some(b.chi_square);
                r.degrees_of_freedom = Some(b.degrees_of_freedom);
                r.p_value = b.p_value;
                r.consistent =
                    d.status == Status::Found && b.p_value.is_some_and(|p| p >= POOR_FIT_P);
                for v in &b.vehicles {
                    let k = usize::from(v.vehicle - 1).min(1);
                    r.speed_at_contact[k] = Some(v.speed_at_contact);
                    r.speed_before_braking[k] = v.speed_before_braking;
                }
                r.largest = b
                    .evidence
                    .iter()
                    .max_by(|a, b| a.z.abs().total_cmp(&b.z.abs()))
                    .map(|e| (e.name.clone(), e.z));
            }
        }
    }
    r
}

/// True when a reconstruction calls for the table: refused, or found with a probability below
/// [`POOR_FIT_P`].
pub fn wanted(d: &ReconstructionOut) -> bool {
    d.status != Status::Found
        || d.best
            .as_ref()
            .is_some_and(|b| b.p_value.is_some_and(|p| p < POOR_FIT_P))
}

/// The consistency table of `case`, whose reconstruction with all its evidence is `all`.
///
/// # Errors
/// None of its own: a row whose reconstruction fails on its input says so in the row.
pub fn table(
    case: &Case,
    whole: &crate::reconstruct::Reconstructed,
    model: pim_fit::FitModel,
    moment_form: pim_core::MomentForm,
    branches: &[MomentBranch],
    observer: &dyn crate::watch::Observer,
) -> Consistency {
    let all = &whole.document;
    let run = |without: &[Piece]| {
        let c = left_out(case, without);
        let names = without.iter().map(|p| p.name(case)).collect();
        // Each row by the first search alone (the rows are compared with each other, and a
        // row that fits poorly without one piece is what the table looks for, not a reason to
        // search it again), and from the whole answer too: removing evidence can only lower
        // the minimum, so the whole answer's separation states, refined without the piece,
        // bound the row from above; the lower of the two is the row.
        let how = crate::reconstruct::How {
            model,
            moment_form,
            branches: branches.to_vec(),
        };
        let prior = without.iter().any(|p| matches!(p, Piece::Prior(_)));
        row(names, left_out_row(&c, how, whole, prior))
    };
    let all_row = row(Vec::new(), Ok(all.clone()));
    let groups = pieces(case);
    // The work of a row is about that of the whole reconstruction: a budget of work, so that
    // the table's cost is bounded the same on every machine. A reconstruction that its own
    // budget ended is not repeated.
    let per_row = all.first_search_work.max(1);
    let ended = all.first_search_work > pim_reconstruct::REFINE_WORK;
    if ended || groups.len() as u64 * per_row > TABLE_WORK {
        let summary = if ended {
            "Not computed: the reconstruction itself ended on its budget of work (its impact \
             fits or run-outs are very slow), so leaving out each piece would repeat that. \
             Leave out the pieces with the largest residuals by hand, one at a time."
                .to_string()
        } else {
            format!(
                "Not computed: leaving out each of its {} pieces would take about {} units of \
                 work ({per_row} per reconstruction), beyond the table's budget of \
                 {TABLE_WORK}. Leave out the pieces with the largest residuals by hand, one at \
                 a time.",
                groups.len(),
                groups.len() as u64 * per_row
            )
        };
        return Consistency {
            all: all_row,
            rows: Vec::new(),
            consistent_without: Vec::new(),
            summary,
            cancelled: None,
        };
    }
    let singles: Vec<Vec<Piece>> = groups.iter().map(|p| vec![*p]).collect();
    // Pairs of the evidence's pieces (a prior of the pose is left out alone).
    let evidence: Vec<Piece> = groups
        .iter()
        .copied()
        .filter(|p| !matches!(p, Piece::Prior(_)))
        .collect();
    let pairs_count = evidence.len() * evidence.len().saturating_sub(1) / 2;
    let phase = crate::watch::Phase::start(observer, "pieces left out", singles.len());
    let run_all = |list: &[Vec<Piece>], phase: &crate::watch::Phase| -> Vec<LeftOut> {
        list.par_iter()
            .filter_map(|w| {
                if phase.stopped() {
                    return None;
                }
                let r = run(w);
                phase.step();
                Some(r)
            })
            .collect()
    };
    let mut rows = run_all(&singles, &phase);
    let mut cancelled = phase.cancelled();
    if cancelled.is_none()
        && !rows.iter().any(|r| r.consistent)
        && evidence.len() <= MAX_PAIR_GROUPS
        && (groups.len() + pairs_count) as u64 * per_row <= TABLE_WORK
    {
        let pairs: Vec<Vec<Piece>> = (0..evidence.len())
            .flat_map(|i| (i + 1..evidence.len()).map(move |j| (i, j)))
            .map(|(i, j)| vec![evidence[i], evidence[j]])
            .collect();
        let phase = crate::watch::Phase::start(observer, "pairs left out", pairs.len());
        rows.extend(run_all(&pairs, &phase));
        cancelled = phase.cancelled();
    }
    let consistent_without: Vec<Vec<String>> = rows
        .iter()
        .filter(|r| r.consistent)
        .map(|r| r.left_out.clone())
        .collect();
    let mut summary = summary(&all_row, &rows, &consistent_without, groups.len());
    if let Some(c) = &cancelled {
        summary = format!("The table was {c}. {summary}");
    }
    Consistency {
        all: all_row,
        rows,
        consistent_without,
        summary,
        cancelled,
    }
}

fn summary(all: &LeftOut, rows: &[LeftOut], consistent: &[Vec<String>], groups: usize) -> String {
    let p = all
        .p_value
        .map_or_else(|| "no answer".to_string(), |p| format!("p = {p:.1e}"));
    let head = format!(
        "With all of its evidence the reconstruction {} ({p}).",
        if all.status == "found" && all.consistent {
            "fits"
        } else if all.p_value.is_some_and(|p| p >= INCONSISTENT_P) {
            "fits poorly"
        } else {
            "is refused"
        }
    );
    if groups == 0 {
        return format!("{head} It has no piece of evidence that can be left out.");
    }
    // The suspects: pieces without which the rest fits as well as its standard deviations
    // lead one to expect (chi-square at most its degrees of freedom), best first.
    let mut suspects: Vec<&LeftOut> = rows
        .iter()
        .filter(|r| r.left_out.len() == 1 && r.consistent)
        .filter(|r| r.chi_square.unwrap_or(f64::INFINITY) <= judged(r))
        .collect();
    suspects.sort_by(|a, b| {
        a.chi_square
            .unwrap_or(0.0)
            .total_cmp(&b.chi_square.unwrap_or(0.0))
    });
    let describe = |r: &&LeftOut| {
        format!(
            "{} (chi-square {:.2} without it)",
            r.left_out[0],
            r.chi_square.unwrap_or(f64::NAN)
        )
    };
    if !suspects.is_empty() {
        let named: Vec<String> = suspects.iter().map(describe).collect();
        let one = named.len() == 1;
        return format!(
            "{head} Leaving out {} makes the rest fit as well as its standard deviations lead one \
             to expect: {}. {} with the rest of the evidence; {} check {} before signing either \
             answer.",
            if one {
                "this piece"
            } else {
                "any one of these pieces"
            },
            named.join("; "),
            if one {
                "It disagrees"
            } else {
                "Each disagrees"
            },
            if one {
                "the speeds without it show what it moves;"
            } else {
                "the evidence alone cannot say which is wrong, and the speeds without each show \
                 what the choice moves;"
            },
            if one { "it" } else { "them" }
        );
    }
    let singles: Vec<String> = consistent
        .iter()
        .filter(|w| w.len() == 1)
        .map(|w| w[0].clone())
        .collect();
    if !singles.is_empty() {
        return format!(
            "{head} Without {} the rest is consistent, though not a close fit: look at {} first.",
            join_or(&singles),
            if singles.len() == 1 { "it" } else { "them" }
        );
    }
    let pairs: Vec<String> = consistent
        .iter()
        .filter(|w| w.len() == 2)
        .map(|w| format!("{} with {}", w[0], w[1]))
        .collect();
    if !pairs.is_empty() {
        return format!(
            "{head} No single piece explains the conflict; leaving out {} together makes the \
             rest consistent.",
            join_or(&pairs)
        );
    }
    let tried = if rows.len() > groups {
        "no piece and no pair of pieces"
    } else {
        "no single piece"
    };
    format!(
        "{head} Leaving out {tried} makes the rest consistent: the conflict is spread over \
         several pieces, or the model's inputs (friction, wheels, masses, geometry) are off."
    )
}

/// The chi-square a fit with these degrees of freedom is expected to reach (its mean).
fn judged(r: &LeftOut) -> f64 {
    pim_fit::judged_dof(r.degrees_of_freedom.unwrap_or(1)) as f64
}

fn join_or(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [a] => a.clone(),
        [rest @ .., last] => format!("{} or {last}", rest.join(", ")),
    }
}

/// A case's reconstruction as every face answers it: [`reconstruct`], with the consistency
/// table when the answer is refused or fits poorly ([`wanted`]); the observer watches the
/// table's rows and can cancel it.
///
/// # Errors
/// Bad input ([`DocumentError::Input`], located).
pub fn answer(
    case: &Case,
    model: pim_fit::FitModel,
    moment_form: pim_core::MomentForm,
    branches: Vec<MomentBranch>,
    observer: &dyn crate::watch::Observer,
) -> Result<crate::reconstruct::Reconstructed, DocumentError> {
    answer_from(
        case,
        (model, moment_form, branches),
        &Default::default(),
        observer,
    )
}

/// [`answer`], the reconstruction also refined from an earlier answer's states
/// ([`crate::reconstruct::reconstruct_searching`]).
///
/// # Errors
/// Bad input ([`DocumentError::Input`], located).
pub fn answer_from(
    case: &Case,
    (model, moment_form, branches): (pim_fit::FitModel, pim_core::MomentForm, Vec<MomentBranch>),
    earlier: &crate::earlier::Earlier,
    observer: &dyn crate::watch::Observer,
) -> Result<crate::reconstruct::Reconstructed, DocumentError> {
    let how = crate::reconstruct::How {
        model,
        moment_form,
        branches: branches.clone(),
    };
    let mut done = crate::reconstruct::reconstruct_searching(case, how, true, earlier)?;
    if wanted(&done.document) {
        let t = table(case, &done, model, moment_form, &branches, observer);
        done.document.consistency = Some(t);
    }
    Ok(done)
}
