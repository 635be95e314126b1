//! The pose at contact fitted (`[contact_sigma]`, see [`pim_case::contact_pose`]): the case's
//! reconstruction refitted at each pose by [`pim_reconstruct::fit_pose`], then searched again at
//! the fitted pose (every combination of counts of turns, and the pose fit's answer as one of
//! its starts); the priors join the answer's chi-square and its evidence table.

use crate::documents::DocumentError;
use crate::reconstruct_input::{case_reconstruction, CaseReconstruction, How};
use pim_case::case::Case;
use pim_case::contact_pose::ContactUnknown;
use pim_documents::reconstruct_doc::{
    ContactPoseOut, EvidenceOut, EvidenceSource, ReconstructionOut,
};
use pim_reconstruct::{Outcome, PoseFit, PoseStart, PoseUnknown, ReconstructError, Reconstruction};

/// The pose fitted, as the document gives it.
#[derive(Debug, Clone, Default)]
pub(crate) struct FittedPose {
    rows: Vec<ContactPoseOut>,
    /// Whether each row's prior weighs (false: left out, as a row of the consistency table
    /// leaves it out; then it is no row of the evidence table).
    weighed: Vec<bool>,
    fit: Option<PoseFit>,
}

/// The reconstruction of `case` with its pose at contact moved by `p`.
fn posed(
    (case, unknowns): (&Case, &[ContactUnknown]),
    how: &How,
    p: &[f64],
) -> Result<CaseReconstruction, DocumentError> {
    let c = case.with_contact(unknowns, p)?;
    case_reconstruction(&c, how.model, how.moment_form, how.branches.clone())
}

/// The pose fit's unknowns: each with its prior's deviation.
fn priors_of(unknowns: &[ContactUnknown]) -> Vec<PoseUnknown> {
    unknowns
        .iter()
        .map(|u| PoseUnknown {
            name: u.name.clone(),
            sigma: u.sigma,
            prior: u.prior,
        })
        .collect()
}

/// The reconstruction of a case's inputs, for the pose fit (its errors as the fit's).
fn built(
    input: Result<CaseReconstruction, DocumentError>,
) -> pim_reconstruct::Result<Reconstruction> {
    input
        .map(|i| i.reconstruction)
        .map_err(|e| ReconstructError::Input {
            field: "pose",
            reason: e.to_string(),
        })
}

/// `outcome` (the reconstruction of `case` as stated) with the pose at contact fitted where the
/// case asks (`[contact_sigma]`): the inputs and the answer at the fitted pose, the chi-square
/// with the priors, and the pose's rows. Unchanged without `[contact_sigma]` or an answer.
///
/// # Errors
/// A located error for a `[contact_sigma]` the case cannot use.
pub(crate) fn fit_contact_pose(
    case: &Case,
    how: &How,
    second_search: bool,
    input: CaseReconstruction,
    outcome: Outcome,
) -> Result<(CaseReconstruction, Outcome, FittedPose), DocumentError> {
    let unknowns = case.contact_unknowns()?;
    if unknowns.is_empty() || outcome.best.is_none() {
        return Ok((input, outcome, FittedPose::default()));
    };
    let zeros = vec![0.0; unknowns.len()];
    let best = outcome.best.as_ref().expect("an answer");
    let answer = settled(
        case,
        how,
        second_search,
        &input.settings,
        stated(&zeros, best),
    )?;
    if !second_search || !poor(&answer.1) {
        return Ok(answer);
    }
    // A pose fit that ends poor may have held the wrong counts of turns: the counts best at
    // a wrong stated pose need not be the truth's, and the pose fit holds them. The pose is
    // fitted again from each of the next combinations refined at the stated pose
    // ([`RUNNER_UPS`], lowest first), and the lowest whole cost (the priors' included) kept.
    // Like the second search, not for a row of the consistency table (`second_search`
    // false), which descends from the whole answer.
    let others = runner_ups(&input, &outcome, &best.counts());
    let mut answer = answer;
    // The pose fitted again from `start`, the lower whole cost kept.
    let again_from = |answer: &mut (CaseReconstruction, Outcome, FittedPose), start: PoseStart| {
        if let Ok(again) = settled(case, how, second_search, &input.settings, start) {
            if cost(&again.1) < cost(&answer.1) {
                *answer = again;
            }
        }
    };
    for other in &others {
        if !poor(&answer.1) {
            break;
        }
        again_from(&mut answer, stated(&zeros, other));
    }
    if !poor(&answer.1) {
        return Ok(answer);
    }
    // Still poor: the descent may have ended in another basin of the pose than the scene's.
    // Poses drawn from the priors are screened by refits from the answers above, and the
    // pose fitted again from the lowest ([`POSE_RESTARTS`]) below the answer's whole cost.
    let build = |p: &[f64]| built(posed((case, &unknowns), how, p));
    let from: Vec<&pim_reconstruct::Found> = std::iter::once(best).chain(&others).collect();
    let screened = pim_reconstruct::screened_poses(
        build,
        &priors_of(&unknowns),
        &input.settings,
        &from,
        pim_reconstruct::screened_count(unknowns.len()),
    );
    for s in screened.iter().take(POSE_RESTARTS) {
        if !poor(&answer.1) || s.cost >= cost(&answer.1) {
            break;
        }
        let start = PoseStart {
            offsets: &s.offsets,
            found: &s.found,
            jacobian: None,
            hold: false,
        };
        again_from(&mut answer, start);
    }
    Ok(answer)
}

/// How many of the screened poses ([`pim_reconstruct::screened_poses`]) below a poor answer's
/// whole cost the pose is fitted again from, lowest first.
pub const POSE_RESTARTS: usize = 2;

/// A pose fit from the stated pose (`zeros`: no offsets) and the answer `found` there.
fn stated<'a>(zeros: &'a [f64], found: &'a pim_reconstruct::Found) -> PoseStart<'a> {
    PoseStart {
        offsets: zeros,
        found,
        jacobian: None,
        hold: false,
    }
}

/// How many more combinations of counts of turns a poor pose fit is fitted again from (one
/// recovered the sweep's crash 71415 as well as two did, in 69 s instead of 149 s).
pub const RUNNER_UPS: usize = 1;

/// The whole cost of an answer (with the priors of the pose), infinite without one.
fn cost(out: &Outcome) -> f64 {
    out.best.as_ref().map_or(f64::INFINITY, |b| b.chi_square)
}

/// Whether an answer fits poorly ([`pim_reconstruct::Found::fits_poorly`]), or there is none.
fn poor(out: &Outcome) -> bool {
    out.best.as_ref().is_none_or(|b| b.fits_poorly())
}

/// The answers at the stated pose of the [`RUNNER_UPS`] combinations of `outcome` refined
/// lowest after its best (counts `best`), each refined again from where it ended.
fn runner_ups(
    input: &CaseReconstruction,
    outcome: &Outcome,
    best: &[Option<i64>],
) -> Vec<pim_reconstruct::Found> {
    let mut refined: Vec<(f64, &pim_reconstruct::TriedCounts)> = outcome
        .tried
        .iter()
        .filter(|t| t.counts != best && t.end.is_some())
        .filter_map(|t| match t.state {
            pim_reconstruct::Tried::Refined { cost, .. } => Some((cost, t)),
            _ => None,
        })
        .collect();
    refined.sort_by(|a, b| a.0.total_cmp(&b.0));
    refined
        .into_iter()
        .take(RUNNER_UPS)
        .filter_map(|(_, t)| {
            let mut one = outcome.clone();
            one.tried = vec![t.clone()];
            pim_reconstruct::redo(&input.reconstruction, &input.settings, &one, f64::INFINITY)
                .ok()
                .flatten()
        })
        .collect()
}

/// The reconstruction of `case`, whose whole answer's pose fit is `whole` (searched with
/// `settings`, which a prior left out does not change), with the prior of
/// one of its pose's values left out (`case` as [`Case::without_contact_prior`] gives it):
/// the pose fitted again from the whole answer (its pose, its answer there and its Jacobian).
/// Leaving a prior out can only lower the minimum, and the fit descends from the whole
/// answer's.
///
/// # Errors
/// As [`fit_contact_pose`].
pub(crate) fn refit_without_prior(
    case: &Case,
    how: &How,
    (whole, settings): (&PoseFit, &pim_reconstruct::Settings),
) -> Result<(CaseReconstruction, Outcome, FittedPose), DocumentError> {
    let first = PoseStart {
        offsets: &whole.offsets,
        found: &whole.found,
        jacobian: Some(&whole.jacobian),
        hold: false,
    };
    settled(case, how, false, settings, first)
}

/// The pose of `case` fitted from `first`, then searched again at the fitted pose (and fitted
/// again where another combination of counts fits better there): the inputs and the answer at
/// the fitted pose, the chi-square with the priors, and the pose's rows.
fn settled(
    case: &Case,
    how: &How,
    second_search: bool,
    settings: &pim_reconstruct::Settings,
    first: PoseStart,
) -> Result<(CaseReconstruction, Outcome, FittedPose), DocumentError> {
    let unknowns = case.contact_unknowns()?;
    let at_pose = |p: &[f64]| -> Result<CaseReconstruction, DocumentError> {
        let mut i = posed((case, &unknowns), how, p)?;
        if !second_search {
            i.settings.scatter_below_p = 0.0;
        }
        Ok(i)
    };
    let build = |p: &[f64]| built(posed((case, &unknowns), how, p));
    let priors = priors_of(&unknowns);
    let fail = |e: pim_reconstruct::ReconstructError| {
        DocumentError::Input(format!("{}: the pose at contact: {e}", case.file))
    };
    let mut fit = pim_reconstruct::fit_pose(build, &priors, settings, first).map_err(fail)?;
    // Searched again at the fitted pose; where another combination of counts of turns fits
    // the evidence better there, the pose is fitted again from it (the counts and the pose
    // each fitted in turn, at most twice).
    let mut rounds = 0;
    let (posed, mut out) = loop {
        let posed = at_pose(&fit.offsets)?;
        let out = pim_reconstruct::reconstruct_from(
            &posed.reconstruction,
            &posed.settings,
            &fit.found.earlier(),
        )
        .map_err(|e| DocumentError::Input(format!("{}: {e}", case.file)))?;
        let other = out
            .best
            .as_ref()
            .filter(|b| b.counts() != fit.counts && b.chi_square < fit.found.chi_square - 1e-6);
        let Some(other) = other.filter(|_| rounds < 2) else {
            break (posed, out);
        };
        rounds += 1;
        let again = PoseStart {
            offsets: &fit.offsets,
            found: other,
            jacobian: None,
            hold: false,
        };
        match pim_reconstruct::fit_pose(build, &priors, &posed.settings, again) {
            Ok(f)
                if f.found.chi_square + f.prior_chi_square
                    < fit.found.chi_square + fit.prior_chi_square =>
            {
                fit = f
            }
            _ => break (posed, out),
        }
    };
    if let Some(b) = out.best.as_mut() {
        b.chi_square += fit.prior_chi_square;
        if b.refused() && out.status == pim_reconstruct::Status::Found {
            out.status = pim_reconstruct::Status::Inconsistent;
            out.reason = Some(format!(
                "with the priors of the pose at contact the chi-square is {:.1} with {} degrees \
                 of freedom: the pose the scene asks for lies beyond what [contact_sigma] allows",
                b.chi_square, b.degrees_of_freedom
            ));
        }
    }
    let stated = case.contact_values(&unknowns)?;
    let rows = rows_of(&unknowns, &stated, &fit.offsets, &fit.sigmas);
    Ok((
        posed,
        out,
        FittedPose {
            rows,
            weighed: unknowns.iter().map(|u| u.prior).collect(),
            fit: Some(fit),
        },
    ))
}

fn rows_of(
    unknowns: &[ContactUnknown],
    stated: &[f64],
    offsets: &[f64],
    sigmas: &[f64],
) -> Vec<ContactPoseOut> {
    unknowns
        .iter()
        .zip(stated)
        .zip(offsets.iter().zip(sigmas))
        .map(|((u, s), (p, sd))| {
            let shown = |x: f64| {
                if u.input.is_angle() {
                    x.to_degrees()
                } else {
                    x
                }
            };
            ContactPoseOut {
                name: u.name.clone(),
                quantity: if u.input.is_angle() {
                    "angle"
                } else {
                    "length"
                },
                mirrored: u.input.mirrored(),
                stated: shown(*s),
                fitted: shown(s + p),
                sigma: shown(*sd),
                prior_sigma: shown(u.sigma),
                z: p / u.sigma,
            }
        })
        .collect()
}

/// The document with the fitted pose: its rows, and each prior a row of the evidence table
/// (the shares of the chi-square taken again with them).
pub(crate) fn with_pose(document: &mut ReconstructionOut, pose: FittedPose) -> Option<PoseFit> {
    let Some(b) = document.best.as_mut() else {
        return pose.fit;
    };
    if pose.rows.is_empty() {
        return pose.fit;
    }
    for (index, (r, _)) in pose
        .rows
        .iter()
        .zip(&pose.weighed)
        .enumerate()
        .filter(|(_, (_, w))| **w)
    {
        b.evidence.push(EvidenceOut {
            source: EvidenceSource::ContactPrior { index },
            name: format!("{} at contact (prior)", r.name),
            phase: "impact",
            quantity: r.quantity,
            residual: r.fitted - r.stated,
            sigma: r.prior_sigma,
            z: r.z,
            share_percent: 0.0,
        });
    }
    // Every combination compared was searched at the fitted pose: its priors add alike.
    let priors = pose.fit.as_ref().map_or(0.0, |f| f.prior_chi_square);
    for c in &mut document.counts {
        if let Some(x) = c.chi_square.as_mut() {
            *x += priors;
        }
    }
    let Some(b) = document.best.as_mut() else {
        return pose.fit;
    };
    let total = b.chi_square.max(1e-300);
    for e in &mut b.evidence {
        e.share_percent = 100.0 * e.z * e.z / total;
    }
    // A prior left out takes its datum with it; its value is still an unknown.
    let left_out = pose.weighed.iter().filter(|w| !**w).count();
    if left_out > 0 {
        b.degrees_of_freedom = (b.degrees_of_freedom - left_out as i64).max(0);
        b.p_value = pim_fit::ChiSquare::p_value_of(b.degrees_of_freedom, b.chi_square);
    }
    b.contact_pose = pose.rows;
    pose.fit
}

/// The pose at contact in an uncertainty study: each prior's centre drawn by its deviation
/// (the stated pose moved, as a measurement of it would move), and each draw's pose fitted
/// again from the nominal answer, the nominal Jacobian held.
pub(crate) struct StudyPose<'a> {
    unknowns: Vec<ContactUnknown>,
    priors: Vec<PoseUnknown>,
    /// The nominal case's stated values (m, rad).
    stated: Vec<f64>,
    fit: &'a PoseFit,
    /// The search settings (the case's; no draw changes them).
    settings: &'a pim_reconstruct::Settings,
}

impl<'a> StudyPose<'a> {
    /// The study's pose of `case` reconstructed as `done`; `None` where the case fits none.
    ///
    /// # Errors
    /// A located error for a `[contact_sigma]` the case cannot use, or an `[uncertainty]`
    /// spread on a value the reconstruction fits.
    pub(crate) fn of(
        case: &Case,
        done: &'a crate::reconstruct_input::Reconstructed,
    ) -> Result<Option<StudyPose<'a>>, DocumentError> {
        let unknowns = case.contact_unknowns()?;
        let Some(fit) = done.pose.as_ref().filter(|_| !unknowns.is_empty()) else {
            return Ok(None);
        };
        let unc = case.spreads();
        for (k, v) in [unc.vehicle1, unc.vehicle2].iter().enumerate() {
            let drawn = [
                ("heading", v.heading.is_some()),
                ("impact_point", v.impact_point.is_some()),
                ("d", v.d.is_some()),
                ("phi", v.phi.is_some()),
            ];
            let posed = unknowns.iter().any(|u| u.input.vehicle() == Some(k));
            if let Some((key, _)) = drawn.iter().find(|(_, d)| *d).filter(|_| posed) {
                return Err(case
                    .error_at(
                        &format!("uncertainty.vehicle{}.{key}", k + 1),
                        format!(
                            "vehicle{}'s pose at contact is fitted ([contact_sigma]) and \
                             its prior drawn by the study: leave out this spread",
                            k + 1
                        ),
                    )
                    .into());
            }
        }
        if unc.impact.crush_angle.is_some()
            && unknowns
                .iter()
                .any(|u| u.input == pim_case::contact_pose::PoseInput::CrushAngle)
        {
            return Err(case
                .error_at(
                    "uncertainty.impact.crush_angle",
                    "the crush angle is fitted ([contact_sigma]) and its prior drawn by the \
                     study: leave out this spread",
                )
                .into());
        }
        let stated = case.contact_values(&unknowns)?;
        let priors = priors_of(&unknowns);
        Ok(Some(StudyPose {
            unknowns,
            priors,
            stated,
            fit,
            settings: &done.input.settings,
        }))
    }

    /// The priors' centres, drawn: offsets (m, rad) about 0.
    pub(crate) fn inputs(&self) -> Vec<crate::uncertainty::Input> {
        self.unknowns
            .iter()
            .map(|u| {
                let one = [u.clone()];
                crate::uncertainty::Input {
                    name: format!("{} at contact (prior)", u.name),
                    spread: pim_case::spread::Spread::Normal(u.sigma),
                    nominal: 0.0,
                    apply: Box::new(move |case: &mut Case, x| {
                        if let Ok(c) = case.with_contact(&one, &[x]) {
                            *case = c;
                        }
                    }),
                }
            })
            .collect()
    }

    /// The pose's quantities at `offsets` from the nominal case's stated pose: `contact
    /// vehicle1.heading` and so on, lengths m, angles deg.
    pub(crate) fn quantities(&self, offsets: &[f64]) -> Vec<(String, f64)> {
        self.unknowns
            .iter()
            .zip(self.stated.iter().zip(offsets))
            .map(|(u, (s, p))| {
                let x = s + p;
                let x = if u.input.is_angle() {
                    x.to_degrees()
                } else {
                    x
                };
                (format!("contact {}", u.name), x)
            })
            .collect()
    }

    /// The nominal pose's quantities.
    pub(crate) fn nominal(&self) -> Vec<(String, f64)> {
        self.quantities(&self.fit.offsets)
    }

    /// One draw `c` of the nominal `case`: its pose fitted from the nominal answer `best`, the
    /// answer with the priors in its chi-square and the pose's quantities; `None` where it has
    /// no answer the evidence as drawn accepts.
    pub(crate) fn draw(
        &self,
        (case, c): (&Case, &Case),
        how: &How,
        best: &pim_reconstruct::Found,
    ) -> Option<(pim_reconstruct::Found, Vec<(String, f64)>)> {
        let eps = c.contact_offsets_from(case, &self.unknowns).ok()?;
        let p0: Vec<f64> = self
            .fit
            .offsets
            .iter()
            .zip(&eps)
            .map(|(p, e)| p - e)
            .collect();
        let build = |p: &[f64]| built(posed((c, &self.unknowns), how, p));
        let start = PoseStart {
            offsets: &p0,
            found: best,
            jacobian: Some(&self.fit.jacobian),
            hold: true,
        };
        let fit = pim_reconstruct::fit_pose(build, &self.priors, self.settings, start).ok()?;
        let mut found = fit.found;
        found.chi_square += fit.prior_chi_square;
        if found.refused() {
            return None;
        }
        let from_nominal: Vec<f64> = eps.iter().zip(&fit.offsets).map(|(e, p)| e + p).collect();
        Some((found, self.quantities(&from_nominal)))
    }
}
