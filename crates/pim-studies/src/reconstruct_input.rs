//! A case's reconstruction as [`pim_reconstruct`] takes it: the case's contact evidence, its
//! EDR speeds and pre-impact marks, and each vehicle's scene, in SI and the natural frame.

use crate::documents::DocumentError;
use crate::fitcase::{self, CostChoice};
use pim_case::case::Case;
use pim_case::scene_sections::PreImpactVehicleSection;
use pim_core::VehicleId;
use pim_documents::reconstruct_doc::ReconstructionOut;
use pim_fit::{FitProblem, Knowledge, MomentBranch, Observation, ObservationKind};
use pim_reconstruct::{Outcome, Reconstruction, SceneVehicle, Settings, Skid};
use pim_runout::GRAVITY;

/// A case's reconstruction and how to search it.
#[derive(Debug, Clone)]
pub struct CaseReconstruction {
    /// The reconstruction.
    pub reconstruction: Reconstruction,
    /// The search settings (the case's `[bounds]`).
    pub settings: Settings,
    /// Labels of the contact problem's observations, in order.
    pub(crate) labels: Vec<String>,
    /// How many of them are the case's `[[observations]]` (the EDR speeds follow).
    pub(crate) case_observations: usize,
    /// Each EDR speed's vehicle (1 or 2) and record, in the order they follow the case's
    /// observations.
    pub(crate) edr_records: Vec<(u8, usize)>,
    /// The case's `[bounds]` (who set a bound the answer reaches).
    pub(crate) bounds: Option<pim_case::sections::BoundsSection>,
}

/// Checks vehicle `k`'s (0 or 1) EDR table (`edr_history`): each row's time and speed as a
/// record's, its accelerator a percentage.
fn check_history(
    case: &Case,
    k: usize,
    p: &PreImpactVehicleSection,
    speed: f64,
) -> Result<(), DocumentError> {
    for (i, r) in p.edr_history.iter().enumerate() {
        let place = format!("pre_impact.vehicle{}.edr_history[{i}]", k + 1);
        let row = pim_case::scene_sections::EdrWritten {
            speed: r.speed,
            time: r.time,
            deceleration: 0.0,
            sigma: 1.0,
        };
        check_edr(case, &place, &row, speed)?;
        if let Some(a) = r.accelerator.filter(|a| !(0.0..=100.0).contains(a)) {
            return Err(case
                .error_at(&place, format!("accelerator {a}: a percentage, 0 to 100"))
                .into());
        }
    }
    Ok(())
}

/// Checks an EDR record (`place` its path in the file): its speed (in the file's unit, `speed`
/// m/s each), time, deceleration and sigma.
fn check_edr(
    case: &Case,
    place: &str,
    e: &pim_case::scene_sections::EdrWritten,
    speed: f64,
) -> Result<(), DocumentError> {
    let ok = |x: f64, lo: f64, hi: f64| x.is_finite() && x >= lo && x <= hi;
    if !ok(e.speed * speed, 0.0, pim_core::MAX_SPEED.min(150.0)) {
        return Err(case
            .error_at(place, format!("speed {}: from 0 to 150 m/s", e.speed))
            .into());
    }
    if !ok(e.time, 0.0, 30.0) {
        return Err(case
            .error_at(
                place,
                format!("time {}: seconds before contact, 0 to 30", e.time),
            )
            .into());
    }
    if !ok(e.deceleration, -1.5, 1.5) {
        return Err(case
            .error_at(
                place,
                format!("deceleration {}: in g, from -1.5 to 1.5", e.deceleration),
            )
            .into());
    }
    if !(e.sigma.is_finite() && e.sigma * speed >= fitcase::SIGMA_MIN) {
        return Err(case
            .error_at(
                place,
                format!("sigma {}: a standard deviation above 0", e.sigma),
            )
            .into());
    }
    Ok(())
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
    refuse_geometry_bounds(case)?;
    let unit = fitcase::sigma_unit(case)?;
    let mut contact = contact_problem(case, unit, impact)?;
    let mut labels = observation_labels(case);
    let (edr, edr_records, skids) = pre_impact(case, &mut labels)?;
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
    let stated_apart = |k| {
        case.content
            .pre_impact(k)
            .is_some_and(|p| p.friction.is_some())
    };
    let skids_on_road = [0, 1].map(|k| skids[k].is_some() && !stated_apart(k));
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
        edr_records,
        bounds: c.bounds,
    })
}

/// The geometry bounds estimate the impact geometry in a fit of the impact alone; the whole
/// reconstruction holds the geometry as given, so they are refused rather than ignored.
fn refuse_geometry_bounds(case: &Case) -> Result<(), DocumentError> {
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
    Ok(())
}

/// The impact's own evidence: the case's estimates and observations where it is a fit case,
/// nothing known otherwise.
fn contact_problem(
    case: &Case,
    unit: Option<f64>,
    impact: pim_core::Impact,
) -> Result<FitProblem, DocumentError> {
    let c = &case.content;
    Ok(if fitcase::is_fit_case(case) {
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
    })
}

/// The case's observations as the tables name them.
fn observation_labels(case: &Case) -> Vec<String> {
    case.content
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
        .collect()
}

/// The EDR speeds (vehicle, speed along the heading at contact, its standard deviation; each
/// labelled in `labels`), where each came from (vehicle number, record) and each vehicle's
/// skid.
fn pre_impact(case: &Case, labels: &mut Vec<String>) -> Result<PreImpact, DocumentError> {
    let speed = case.written_units.speed.to_si();
    let road = case
        .content
        .runout
        .as_ref()
        .and_then(|r| r.friction)
        .unwrap_or(pim_runout::DEFAULT_FRICTION);
    // EDR speeds: each the speed along the heading at contact, v - a t.
    let mut edr = Vec::new();
    let mut edr_records = Vec::new();
    let mut skids = [None, None];
    for (k, id) in [VehicleId::One, VehicleId::Two].into_iter().enumerate() {
        let Some(p) = case.content.pre_impact(k) else {
            continue;
        };
        let at = |f: &str| format!("pre_impact.vehicle{}.{f}", k + 1);
        if id == VehicleId::Two && case.is_barrier() {
            let place = format!("pre_impact.vehicle{}", k + 1);
            return Err(case.error_at(&place, "a barrier does not move").into());
        }
        check_history(case, k, p, speed)?;
        for (i, e) in p.edr.iter().enumerate() {
            check_edr(case, &at(&format!("edr[{i}]")), e, speed)?;
            let value = e.speed * speed - e.deceleration * GRAVITY * e.time;
            edr.push((id, value, e.sigma * speed));
            edr_records.push((k as u8 + 1, i));
            labels.push(format!(
                "vehicle{} EDR speed {:.1} s before contact",
                k + 1,
                e.time
            ));
        }
        skids[k] = skid_of(case, k, p, road)?;
    }
    Ok((edr, edr_records, skids))
}

/// What [`pre_impact`] reads.
type PreImpact = (
    Vec<(VehicleId, f64, f64)>,
    Vec<(u8, usize)>,
    [Option<Skid>; 2],
);

/// Vehicle `k`'s skid before the impact (`pre_impact` section `p`; on the road's friction
/// `road` unless it states its own), checked.
fn skid_of(
    case: &Case,
    k: usize,
    p: &PreImpactVehicleSection,
    road: f64,
) -> Result<Option<Skid>, DocumentError> {
    let at = |f: &str| format!("pre_impact.vehicle{}.{f}", k + 1);
    let length = case.written_units.length.to_si();
    let Some(d) = p.skid else {
        if p.braking.is_some() || p.grade.is_some() || p.friction.is_some() {
            return Err(case
                .error_at(
                    &format!("pre_impact.vehicle{}", k + 1),
                    "braking, grade and friction describe a skid: give its length, `skid`",
                )
                .into());
        }
        return Ok(None);
    };
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
    Ok(Some(skid))
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
    /// The pose at contact fitted (`[contact_sigma]`): the offsets from the stated pose (in
    /// the order of [`Case::contact_unknowns`]), the answer there, and the Jacobian a study's
    /// draws start from.
    pub pose: Option<pim_reconstruct::PoseFit>,
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
