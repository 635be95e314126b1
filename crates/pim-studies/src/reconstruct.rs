//! A case's reconstruction (`pim fit` of a case with scene evidence): the case's contact
//! evidence, its EDR speeds and pre-impact marks, and each vehicle's scene, through
//! [`pim_reconstruct`], and the document of the answer (SI in the natural frame, angles in
//! degrees, like every other document).

use crate::documents::DocumentError;
use crate::runout::{MotionOut, PoseOut};
use pim_case::case::Case;
pub use pim_documents::reconstruct_doc::{
    BestOut, CountsOut, EvidenceOut, EvidenceSource, ReconstructionOut, VehiclePhasesOut,
};
use pim_fit::{MomentBranch, COMPONENT_NAMES};
use pim_reconstruct::{
    ContactTerm, Contradiction, Earlier, EvidenceTerm, Outcome, Reconstruction, Tried,
};

pub use crate::reconstruct_input::{
    case_reconstruction, skid_lengths, CaseReconstruction, How, Reconstructed,
};

/// Reconstructs a case (see [`case_reconstruction`]).
///
/// # Errors
/// Bad input ([`DocumentError::Input`], located).
pub fn reconstruct(
    case: &Case,
    model: pim_fit::FitModel,
    moment_form: pim_core::MomentForm,
    branches: Vec<MomentBranch>,
) -> Result<Reconstructed, DocumentError> {
    let how = How {
        model,
        moment_form,
        branches,
    };
    reconstruct_searching(case, how, true, &Earlier::default())
}

/// As [`reconstruct`]; without `second_search` an answer that fits poorly is
/// not searched again (a row of the consistency table); with `earlier` (an earlier answer's
/// states and frictions, [`crate::earlier::earlier_states`]) also refined from them, the lower
/// answer kept.
///
/// # Errors
/// Bad input ([`DocumentError::Input`], located).
pub fn reconstruct_searching(
    case: &Case,
    how: How,
    second_search: bool,
    earlier: &Earlier,
) -> Result<Reconstructed, DocumentError> {
    let mut input = case_reconstruction(case, how.model, how.moment_form, how.branches.clone())?;
    if !second_search {
        input.settings.scatter_below_p = 0.0;
    }
    let r = (&input.reconstruction, &input.settings);
    let outcome = pim_reconstruct::reconstruct_from(r.0, r.1, earlier)
        .map_err(|e| DocumentError::Input(format!("{}: {e}", case.file)))?;
    finish(case, how, second_search, input, outcome)
}

/// The reconstructed case from the reconstruction `outcome` of `input` (at the case's stated
/// pose): with the pose at contact fitted where the case asks (`[contact_sigma]`: the inputs
/// and the answer at the fitted pose), and its document.
///
/// # Errors
/// A located error for a `[contact_sigma]` the case cannot use.
pub fn finish(
    case: &Case,
    how: How,
    second_search: bool,
    input: CaseReconstruction,
    outcome: Outcome,
) -> Result<Reconstructed, DocumentError> {
    let (input, outcome, pose) =
        crate::reconstruct_pose::fit_contact_pose(case, &how, second_search, input, outcome)?;
    let mut document = document(&input, &outcome);
    let fit = crate::reconstruct_pose::with_pose(&mut document, pose);
    Ok(Reconstructed {
        how,
        input,
        outcome,
        document,
        pose: fit,
    })
}

/// A piece of the contact evidence as the case names it (an observation by its `name`, an
/// EDR speed by its time) and the phase it belongs to.
fn contact_label(
    input: &CaseReconstruction,
    term: ContactTerm,
) -> (EvidenceSource, String, &'static str) {
    match term {
        ContactTerm::Component(k) => (
            EvidenceSource::Estimate { component: k },
            COMPONENT_NAMES[k].to_string(),
            if k < 6 { "impact" } else { "run_out" },
        ),
        ContactTerm::Observation(i) => {
            let name = input
                .labels
                .get(i)
                .cloned()
                .unwrap_or_else(|| format!("observation {}", i + 1));
            // The EDR speeds follow the case's own observations.
            match i
                .checked_sub(input.case_observations)
                .and_then(|j| input.edr_records.get(j))
            {
                Some(&(vehicle, index)) => {
                    (EvidenceSource::Edr { vehicle, index }, name, "pre_impact")
                }
                None => (EvidenceSource::Observation { index: i }, name, "impact"),
            }
        }
        ContactTerm::Combination(i) => (
            EvidenceSource::Combination { index: i },
            term.name(&input.reconstruction.contact),
            "impact",
        ),
        ContactTerm::Nonlinear(i) => (
            EvidenceSource::Nonlinear { index: i },
            input
                .reconstruction
                .nonlinear
                .0
                .get(i)
                .map_or_else(|| term.name(&input.reconstruction.contact), |t| t.name()),
            "impact",
        ),
    }
}

/// What a piece of the contact evidence measures: a yaw rate for the components omega, the
/// nonlinear evidence's own quantity, else a speed (every observation kind is one).
fn contact_quantity(r: &Reconstruction, term: ContactTerm) -> &'static str {
    match term {
        ContactTerm::Component(k) if k % 3 == 2 => "yaw_rate",
        ContactTerm::Nonlinear(i) => r.nonlinear.0.get(i).map_or("speed", |t| t.quantity()),
        _ => "speed",
    }
}

/// Every piece of evidence against the best answer `b` (its contact state `u`): the contact
/// evidence, the fitted frictions, each scene's residuals, with its identity.
fn evidence_rows(
    input: &CaseReconstruction,
    b: &pim_reconstruct::Found,
    u: &pim_fit::Vector12,
) -> Vec<EvidenceOut> {
    let r = &input.reconstruction;
    let mut evidence = Vec::new();
    let mut push = |source: EvidenceSource,
                    name: String,
                    phase: &'static str,
                    quantity: &'static str,
                    residual: f64,
                    sigma: f64| {
        evidence.push(EvidenceOut {
            source,
            name,
            phase,
            quantity,
            residual,
            sigma,
            z: residual / sigma,
            share_percent: 100.0 * (residual / sigma).powi(2) / b.chi_square.max(1e-300),
        });
    };
    for c in r.contact_residuals(u) {
        let (source, name, phase) = contact_label(input, c.term);
        push(
            source,
            name,
            phase,
            contact_quantity(r, c.term),
            c.residual,
            r.sigma_of(&c),
        );
    }
    for (index, (f, mu)) in r.frictions.iter().zip(&b.frictions).enumerate() {
        push(
            EvidenceSource::Friction { index },
            f.name.clone(),
            "run_out",
            "friction",
            mu - f.value,
            f.sigma,
        );
    }
    for f in &b.scene {
        for res in &f.residuals {
            let heading = res.what.is_angle();
            let k = if heading {
                180.0 / std::f64::consts::PI
            } else {
                1.0
            };
            push(
                EvidenceSource::Scene {
                    vehicle: f.vehicle.index() as u8 + 1,
                    what: res.what,
                },
                format!("{} {}", f.vehicle, res.name),
                "run_out",
                if heading { "angle" } else { "length" },
                res.value * k,
                res.sigma * k,
            );
        }
    }
    evidence
}

/// The document of an outcome.
pub fn document(input: &CaseReconstruction, outcome: &Outcome) -> ReconstructionOut {
    let r = &input.reconstruction;
    let best = outcome.best.as_ref().map(|b| best_out(input, b));
    let counts = counts_out(outcome);
    let method = method_of(outcome, &counts);
    let proven = proven_of(outcome);
    let undetermined = crate::reconstruct_open::undetermined(r, &input.settings.runout, outcome);
    ReconstructionOut {
        units: pim_documents::records::SiUnits,
        kind: "reconstruction",
        status: outcome.status,
        // A contradiction names its residuals as the case names them.
        reason: match &outcome.contradiction {
            Some(c) => Some(c.describe(|t| match t {
                EvidenceTerm::Contact(term) => contact_label(input, *term).1,
                EvidenceTerm::Scene { vehicle, name } => format!("{vehicle} {name}"),
                EvidenceTerm::Friction(_) => Contradiction::default_name(r, t),
            })),
            None => outcome.reason.clone(),
        },
        best,
        scene_vehicles: r.scene.iter().map(|v| v.id.index() as u8 + 1).collect(),
        counts,
        runouts: outcome.runouts,
        fits: outcome.fits,
        work: outcome.work,
        first_search_work: outcome.first_work,
        method,
        proven,
        undetermined,
        consistency: None,
    }
}

/// The best answer's record: its coefficients, each vehicle's phases, the evidence and the
/// bounds it reached.
fn best_out(input: &CaseReconstruction, b: &pim_reconstruct::Found) -> BestOut {
    let s = &b.solution;
    let u = pim_fit::state_vector(&s.initial, &s.separation);
    let evidence = evidence_rows(input, b, &u);
    let vehicles = b.phases.iter().map(|p| vehicle_phases(b, p)).collect();
    BestOut {
        branch: b.branch,
        e: s.e,
        mu: s.mu,
        em: s.em,
        energy_loss_percent: s.energy_loss_percent,
        chi_square: b.chi_square,
        degrees_of_freedom: b.degrees_of_freedom,
        p_value: pim_fit::ChiSquare::p_value_of(b.degrees_of_freedom, b.chi_square),
        vehicles,
        evidence,
        iterations: b.iterations,
        converged: b.converged,
        certificate: b.certificate.clone(),
        contact_pose: Vec::new(),
        frictions: b.frictions.clone(),
        bounds_reached: {
            let branch = pim_fit::BranchReport {
                moment: b.branch,
                status: pim_fit::Status::Optimal,
                reason: None,
                solution: Some(s.clone()),
                identifiability: Vec::new(),
                certificate: b.certificate.clone(),
                geometry: None,
            };
            pim_documents::records::BranchRecord::new(&branch)
                .with_bounds(&branch, input.settings.fit.get(), &|x| {
                    input.set_bounds.contains(&x)
                })
                .bounds_reached
        },
    }
}

/// One vehicle's speeds and states through its phases in the best answer.
fn vehicle_phases(b: &pim_reconstruct::Found, p: &pim_reconstruct::Phases) -> VehiclePhasesOut {
    let s = &b.solution;
    let k = p.vehicle.index();
    let (c, sep) = (
        *s.initial.vehicle(p.vehicle),
        *s.separation.vehicle(p.vehicle),
    );
    let f = b.scene.iter().find(|f| f.vehicle == p.vehicle);
    let motion = |v: pim_core::VehicleVelocity| MotionOut {
        x: 0.0,
        y: 0.0,
        heading: 0.0,
        vx: v.vx,
        vy: v.vy,
        yaw_rate: v.omega,
    };
    let (mut contact, mut separation) = (motion(c), motion(sep));
    if let Some(f) = f {
        let start = MotionOut::from(&f.runout.start);
        for m in [&mut contact, &mut separation] {
            m.x = start.x;
            m.y = start.y;
            m.heading = start.heading;
        }
    }
    VehiclePhasesOut {
        vehicle: k as u8 + 1,
        speed_before_braking: p.before_braking,
        speed_at_contact: p.contact,
        speed_at_separation: p.separation,
        speed_at_rest: f.map(|_| 0.0),
        contact,
        separation,
        turns: f.and_then(|f| f.turns),
        rest: f.map(|f| PoseOut {
            x: f.runout.rest.x,
            y: f.runout.rest.y,
            heading: f.runout.rest.heading.to_degrees(),
        }),
        runout_distance: p.runout_distance,
        runout_time: p.runout_time,
    }
}

/// Every combination of counts tried, with what became of it.
fn counts_out(outcome: &Outcome) -> Vec<CountsOut> {
    let best_index = outcome.best_index();
    outcome
        .tried
        .iter()
        .enumerate()
        .map(|(i, t)| {
            let (chi_square, state, reason) = match &t.state {
                Tried::Refined {
                    cost, abandoned, ..
                } => {
                    let state = if *abandoned {
                        "abandoned"
                    } else if best_index == Some(i) {
                        "best"
                    } else {
                        "refined"
                    };
                    (Some(*cost), state, None)
                }
                Tried::NotRefined { reason } => (None, "not_refined", Some(reason.clone())),
                Tried::NoImpact { reason } => (None, "no_impact", Some(reason.clone())),
            };
            CountsOut {
                turns: t.counts.clone(),
                scene_alone: t.scene_alone,
                momentum_bound: t.momentum_bound,
                chi_square,
                state,
                reason,
            }
        })
        .collect()
}

/// How the answer was searched, in words.
fn method_of(outcome: &Outcome, counts: &[CountsOut]) -> String {
    let refined = counts.iter().filter(|c| c.chi_square.is_some()).count();
    let mut method = format!(
        "each scene alone gave one separation state per count of turns and the other local \
         minima near it ({} combinations of counts); each combination was bounded by its \
         momentum balance, and {refined} refined by Gauss-Newton over the separation state with \
         the exact impact fit inside ({} run-outs, {} impact fits)",
        counts.len(),
        outcome.runouts,
        outcome.fits
    );
    if outcome.scattered {
        method.push_str(
            "; the first search's answer fit poorly, so every scene was searched again with \
             each count also explored from the separation states whose run-outs end at \
             the rest position (one per yaw rate from -10 to 10 rad/s), and the lower answer kept",
        );
    }
    method
}

/// What is proven of the answer, in words.
fn proven_of(outcome: &Outcome) -> String {
    match &outcome.best {
        Some(b) => format!(
            "the coefficients and both velocity states are the certified optimum of the impact \
             fit with the scenes linearised at the found separation state (route: {}); the \
             separation state is a local minimum of the whole chi-square, found from the \
             scenes' own candidates, not proven global",
            match b.certificate.method.route {
                pim_fit::Route::Convex => "convex decomposition",
                pim_fit::Route::Grid => "grid search with lower bounds",
            }
        ),
        None => "nothing: no admissible impact was found".into(),
    }
}
