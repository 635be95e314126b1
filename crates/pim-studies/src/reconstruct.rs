//! A case's reconstruction (`pim fit` of a case with scene evidence): the case's contact
//! evidence, its EDR speeds and pre-impact marks, and each vehicle's scene, through
//! [`pim_reconstruct`], and the document of the answer (SI in the natural frame, angles in
//! degrees, like every other document).

use crate::documents::DocumentError;
use crate::fitcase::{self, CostChoice};
use crate::runout::{MotionOut, PoseOut};
use pim_case::case::Case;
use pim_case::scene_sections::PreImpactVehicleSection;
use pim_core::VehicleId;
pub use pim_documents::reconstruct_doc::{
    BestOut, CountsOut, EvidenceOut, ReconstructionOut, VehiclePhasesOut,
};
use pim_fit::{FitProblem, Knowledge, MomentBranch, Observation, ObservationKind, COMPONENT_NAMES};
use pim_reconstruct::{
    ContactTerm, Contradiction, EvidenceTerm, Outcome, Reconstruction, SceneVehicle, Settings,
    Skid, Tried,
};
use pim_runout::GRAVITY;

pub use crate::question::has_scene_evidence;

/// A case's reconstruction and how to search it.
#[derive(Debug, Clone)]
pub struct CaseReconstruction {
    /// The reconstruction.
    pub reconstruction: Reconstruction,
    /// The search settings (the case's `[bounds]`).
    pub settings: Settings,
    /// Labels of the contact problem's observations, in order.
    labels: Vec<String>,
    /// How many of them are the case's `[[observations]]` (the EDR speeds follow).
    case_observations: usize,
    /// The case's `[bounds]` (who set a bound the answer reaches).
    bounds: Option<pim_case::sections::BoundsSection>,
}

fn pre_impact_of(case: &Case, k: usize) -> Option<&PreImpactVehicleSection> {
    let p = case.content.pre_impact.as_ref()?;
    if k == 0 {
        p.vehicle1.as_ref()
    } else {
        p.vehicle2.as_ref()
    }
}

/// The reconstruction of a case: its own estimates and observations (`[sigma]` required when it
/// has any: the scene's evidence has standard deviations, so the whole cost is a chi-square),
/// EDR speeds as observations, pre-impact skids, and every vehicle's scene.
///
/// # Errors
/// Located [`DocumentError::Input`] for anything the reconstruction cannot use.
pub fn case_reconstruction(
    case: &Case,
    model: pim_fit::FitModel,
    moment_form: pim_core::MomentForm,
    branches: Vec<MomentBranch>,
) -> Result<CaseReconstruction, DocumentError> {
    let c = &case.content;
    let impact = case.impact()?;
    // The geometry bounds estimate the impact geometry in a fit of the impact alone; the whole
    // reconstruction holds the geometry as given, so they are refused rather than ignored.
    if let Some(g) = fitcase::geometry(case)?.first() {
        let field = match g.input {
            pim_fit::GeometryInput::CrushAngle => "bounds.crush_angle".to_string(),
            other => format!("bounds.{}", other.name()),
        };
        return Err(case
            .error_at(
                &field,
                format!(
                    "the whole reconstruction holds the impact geometry as given, so it cannot \
                     estimate {}: give it a spread in [uncertainty] (drawn by `pim \
                     uncertainty`), or fit the impact alone with `pim fit --cost ...`",
                    g.input.name()
                ),
            )
            .into());
    }
    let unit = fitcase::sigma_unit(case)?;
    let mut contact = if fitcase::is_fit_case(case) {
        if unit.is_none() && (c.estimates.is_some() || !c.observations.is_empty()) {
            return Err(DocumentError::Input(format!(
                "{}: a fit of the scene needs standard deviations: give [sigma] for the \
                 estimates and `sigma` on each observation (the scene's evidence has them, so \
                 the whole cost is one chi-square), not [weights]",
                case.file
            )));
        }
        fitcase::problem(case, CostChoice::Custom)?
    } else {
        FitProblem {
            impact,
            components: [Knowledge::Unknown; 12],
            observations: Vec::new(),
            combinations: Vec::new(),
        }
    };
    let mut labels: Vec<String> = c
        .observations
        .iter()
        .enumerate()
        .map(|(i, o)| match &o.name {
            Some(n) => format!(
                "{n} ({} of vehicle{})",
                crate::residuals::kind_name(o.kind),
                o.vehicle
            ),
            None => format!(
                "observation {} ({} of vehicle{})",
                i + 1,
                crate::residuals::kind_name(o.kind),
                o.vehicle
            ),
        })
        .collect();
    let speed = case.written_units.speed.to_si();
    let length = case.written_units.length.to_si();
    let road = c
        .runout
        .as_ref()
        .and_then(|r| r.friction)
        .unwrap_or(pim_runout::DEFAULT_FRICTION);
    // EDR speeds: each the speed along the heading at contact, v - a t.
    let mut edr = Vec::new();
    let mut skids = [None, None];
    for (k, id) in [VehicleId::One, VehicleId::Two].into_iter().enumerate() {
        let Some(p) = pre_impact_of(case, k) else {
            continue;
        };
        let at = |f: &str| format!("pre_impact.vehicle{}.{f}", k + 1);
        if id == VehicleId::Two && case.is_barrier() {
            return Err(case
                .error_at(
                    &format!("pre_impact.vehicle{}", k + 1),
                    "a barrier does not move",
                )
                .into());
        }
        for (i, e) in p.edr.iter().enumerate() {
            let place = at(&format!("edr[{i}]"));
            let ok = |x: f64, lo: f64, hi: f64| x.is_finite() && x >= lo && x <= hi;
            if !ok(e.speed * speed, 0.0, pim_core::MAX_SPEED.min(150.0)) {
                return Err(case
                    .error_at(&place, format!("speed {}: from 0 to 150 m/s", e.speed))
                    .into());
            }
            if !ok(e.time, 0.0, 30.0) {
                return Err(case
                    .error_at(
                        &place,
                        format!("time {}: seconds before contact, 0 to 30", e.time),
                    )
                    .into());
            }
            if !ok(e.deceleration, -1.5, 1.5) {
                return Err(case
                    .error_at(
                        &place,
                        format!("deceleration {}: in g, from -1.5 to 1.5", e.deceleration),
                    )
                    .into());
            }
            if !(e.sigma.is_finite() && e.sigma * speed >= fitcase::SIGMA_MIN) {
                return Err(case
                    .error_at(
                        &place,
                        format!("sigma {}: a standard deviation above 0", e.sigma),
                    )
                    .into());
            }
            let value = e.speed * speed - e.deceleration * GRAVITY * e.time;
            edr.push((id, value, e.sigma * speed));
            labels.push(format!(
                "vehicle{} EDR speed {:.1} s before contact",
                k + 1,
                e.time
            ));
        }
        if let Some(d) = p.skid {
            let skid = Skid {
                distance: d * length,
                braking: p.braking.unwrap_or(1.0),
                grade: (p.grade.unwrap_or(0.0) / 100.0).atan(),
                friction: p.friction.unwrap_or(road),
            };
            skid.check().map_err(|e| {
                let field = match &e {
                    pim_reconstruct::ReconstructError::Input { field, .. } => *field,
                    _ => "skid",
                };
                let field = if field == "distance" { "skid" } else { field };
                DocumentError::from(case.error_at(&at(field), e.to_string()))
            })?;
            skids[k] = Some(skid);
        } else if p.braking.is_some() || p.grade.is_some() || p.friction.is_some() {
            return Err(case
                .error_at(
                    &format!("pre_impact.vehicle{}", k + 1),
                    "braking, grade and friction describe a skid: give its length, `skid`",
                )
                .into());
        }
    }
    // The unit of the weights: the case's, or the smallest EDR variance.
    let unit = unit.or_else(|| edr.iter().map(|(_, _, s)| s * s).min_by(f64::total_cmp));
    for (id, value, s) in edr {
        contact.observations.push(Observation {
            kind: ObservationKind::SpeedAlongHeading,
            vehicle: id,
            value,
            weight: unit.unwrap_or(1.0) / (s * s),
        });
    }
    let inputs = case.scene_inputs()?;
    let scene: Vec<SceneVehicle> = inputs
        .vehicles
        .iter()
        .filter_map(|v| {
            v.evidence.as_ref().map(|e| SceneVehicle {
                id: v.id,
                chassis: v.chassis.clone(),
                pose: v.start,
                evidence: e.clone(),
            })
        })
        .collect();
    let fit_settings = fitcase::settings(case, model, moment_form, branches)?;
    let mut settings = Settings::new(fit_settings);
    if inputs.duration.is_some() {
        return Err(DocumentError::Input(format!(
            "{}: [runout] duration follows a run-out for a stated time; a scene's rest is where \
             the vehicle stopped: leave duration out to reconstruct from the scene",
            case.file
        )));
    }
    settings.runout.time_limit = inputs.time_limit;
    let (crush, _) = crate::damage_fit::CrushEnergy::of_case(case, &impact)?;
    let mut nonlinear = pim_reconstruct::NonlinearEvidence::default();
    if let Some(c) = crush {
        nonlinear.0.push(std::sync::Arc::new(c));
    }
    // A skid whose friction is not stated apart brakes on the road of the run-outs.
    let skids_on_road = [0, 1].map(|k| {
        skids[k].is_some() && pre_impact_of(case, k).is_some_and(|p| p.friction.is_none())
    });
    let frictions = crate::reconstruct_friction::frictions_of(case, &scene, skids_on_road);
    let reconstruction = Reconstruction {
        contact,
        unit,
        scene,
        skids,
        nonlinear,
        frictions,
    };
    reconstruction
        .check()
        .map_err(|e| DocumentError::Input(format!("{}: {e}", case.file)))?;
    Ok(CaseReconstruction {
        reconstruction,
        settings,
        labels,
        case_observations: c.observations.len(),
        bounds: c.bounds,
    })
}

/// Each vehicle's braking before the impact: its length, m (for the plan view).
pub fn skid_lengths(input: &CaseReconstruction) -> Vec<(VehicleId, f64)> {
    [VehicleId::One, VehicleId::Two]
        .into_iter()
        .filter_map(|id| input.reconstruction.skids[id.index()].map(|s| (id, s.distance)))
        .collect()
}

/// A case's reconstruction, searched, with its document.
#[derive(Debug, Clone)]
pub struct Reconstructed {
    /// How it was reconstructed (what a study around it redoes in every draw).
    pub how: How,
    /// The inputs.
    pub input: CaseReconstruction,
    /// The search's answer.
    pub outcome: Outcome,
    /// The document.
    pub document: ReconstructionOut,
}

/// How a case is reconstructed: the impact model fitted, its moment equation and the moment
/// branches searched.
#[derive(Debug, Clone, PartialEq)]
pub struct How {
    /// The impact model.
    pub model: pim_fit::FitModel,
    /// The moment equation.
    pub moment_form: pim_core::MomentForm,
    /// The moment branches searched.
    pub branches: Vec<MomentBranch>,
}

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
    reconstruct_searching(case, how, true, &[])
}

/// As [`reconstruct`]; without `second_search` an answer that fits worse than its median is
/// not searched again (a row of the consistency table); with `earlier` (an earlier answer's
/// states, [`crate::earlier::earlier_states`]) also refined from them, the lower answer kept.
///
/// # Errors
/// Bad input ([`DocumentError::Input`], located).
pub fn reconstruct_searching(
    case: &Case,
    how: How,
    second_search: bool,
    earlier: &[pim_reconstruct::EarlierState],
) -> Result<Reconstructed, DocumentError> {
    let mut input = case_reconstruction(case, how.model, how.moment_form, how.branches.clone())?;
    if !second_search {
        input.settings.scatter_below_p = 0.0;
    }
    let r = (&input.reconstruction, &input.settings);
    let outcome = pim_reconstruct::reconstruct_from(r.0, r.1, earlier)
        .map_err(|e| DocumentError::Input(format!("{}: {e}", case.file)))?;
    let document = document(&input, &outcome);
    Ok(Reconstructed {
        how,
        input,
        outcome,
        document,
    })
}

/// A piece of the contact evidence as the case names it (an observation by its `name`, an
/// EDR speed by its time) and the phase it belongs to.
fn contact_label(input: &CaseReconstruction, term: ContactTerm) -> (String, &'static str) {
    match term {
        ContactTerm::Component(k) => (
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
            let phase = if i >= input.case_observations {
                "pre_impact"
            } else {
                "impact"
            };
            (name, phase)
        }
        ContactTerm::Combination(_) => (term.name(&input.reconstruction.contact), "impact"),
        ContactTerm::Nonlinear(i) => (
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

/// The document of an outcome.
pub fn document(input: &CaseReconstruction, outcome: &Outcome) -> ReconstructionOut {
    let r = &input.reconstruction;
    let best = outcome.best.as_ref().map(|b| {
        let s = &b.solution;
        let u = pim_fit::state_vector(&s.initial, &s.separation);
        let mut evidence = Vec::new();
        let mut push = |name: String,
                        phase: &'static str,
                        quantity: &'static str,
                        residual: f64,
                        sigma: f64| {
            evidence.push(EvidenceOut {
                name,
                phase,
                quantity,
                residual,
                sigma,
                z: residual / sigma,
                share_percent: 100.0 * (residual / sigma).powi(2) / b.chi_square.max(1e-300),
            });
        };
        for c in r.contact_residuals(&u) {
            let (name, phase) = contact_label(input, c.term);
            push(
                name,
                phase,
                contact_quantity(r, c.term),
                c.residual,
                r.sigma_of(&c),
            );
        }
        for (f, mu) in r.frictions.iter().zip(&b.frictions) {
            push(f.name.clone(), "run_out", "friction", mu - f.value, f.sigma);
        }
        for f in &b.scene {
            for res in &f.residuals {
                let heading = res.name.contains("heading");
                let k = if heading {
                    180.0 / std::f64::consts::PI
                } else {
                    1.0
                };
                push(
                    format!("{} {}", f.vehicle, res.name),
                    "run_out",
                    if heading { "angle" } else { "length" },
                    res.value * k,
                    res.sigma * k,
                );
            }
        }
        let vehicles = b
            .phases
            .iter()
            .map(|p| {
                let k = p.vehicle.index();
                let (c, sep) = if k == 0 {
                    (s.initial.vehicle1, s.separation.vehicle1)
                } else {
                    (s.initial.vehicle2, s.separation.vehicle2)
                };
                let f = b.scene.iter().find(|f| f.vehicle == p.vehicle);
                let motion = |v: pim_core::VehicleVelocity| MotionOut {
                    x: 0.0,
                    y: 0.0,
                    heading: 0.0,
                    vx: v.vx,
                    vy: v.vy,
                    yaw_rate: v.omega,
                };
                let mut contact = motion(c);
                let mut separation = motion(sep);
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
            })
            .collect();
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
                let bounds = input.bounds;
                pim_documents::records::BranchRecord::new(&branch)
                    .with_bounds(&branch, input.settings.fit.get(), &|x| {
                        fitcase::bound_in(bounds.as_ref(), x)
                    })
                    .bounds_reached
            },
        }
    });
    let best_index = outcome.best_index();
    let counts = outcome
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
        .collect::<Vec<_>>();
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
            "; the first search's answer fit worse than its median, so every scene was searched \
             again with each count also explored from the separation states whose run-outs end at \
             the rest position (one per yaw rate from -10 to 10 rad/s), and the lower answer kept",
        );
    }
    let proven = match &outcome.best {
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
    };
    let undetermined = crate::reconstruct_open::undetermined(r, &input.settings.runout, outcome);
    ReconstructionOut {
        units: pim_documents::records::SiUnits,
        kind: "reconstruction",
        status: outcome.status,
        // A contradiction names its residuals as the case names them.
        reason: match &outcome.contradiction {
            Some(c) => Some(c.describe(|t| match t {
                EvidenceTerm::Contact(term) => contact_label(input, *term).0,
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
