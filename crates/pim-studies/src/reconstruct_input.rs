//! A case's reconstruction as [`pim_reconstruct`] takes it: the case's contact evidence, its
//! EDR speeds and pre-impact marks, and each vehicle's scene, in SI and the natural frame.

use crate::documents::DocumentError;
use crate::fitcase::{self, CostChoice};
use pim_case::case::Case;
use pim_case::pre_impact::PreImpactSkid;
use pim_core::VehicleId;
use pim_documents::reconstruct_doc::ReconstructionOut;
use pim_fit::{FitProblem, Knowledge, MomentBranch, Observation, ObservationKind};
use pim_reconstruct::{Outcome, Reconstruction, SceneVehicle, Settings, Skid};

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
    /// The search bounds the case's `[bounds]` sets (who set a bound the answer reaches).
    pub(crate) set_bounds: Vec<pim_fit::SearchBound>,
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
    let impact = case.impact()?;
    refuse_geometry_bounds(case)?;
    let unit = fitcase::sigma_unit(case)?;
    let mut contact = contact_problem(case, unit, impact)?;
    let mut labels = fitcase::observation_labels(case);
    let case_observations = labels.len();
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
    let skids_on_road = case
        .pre_impact_vehicles()?
        .map(|p| p.and_then(|p| p.skid).is_some_and(|s| !s.friction_stated));
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
        case_observations,
        edr_records,
        set_bounds: fitcase::set_bounds(case),
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
    Ok(if fitcase::is_fit_case(case) {
        if unit.is_none() && fitcase::has_weighed_evidence(case) {
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

/// The EDR speeds (vehicle, speed along the heading at contact, its standard deviation; each
/// labelled in `labels`), where each came from (vehicle number, record) and each vehicle's
/// skid.
fn pre_impact(case: &Case, labels: &mut Vec<String>) -> Result<PreImpact, DocumentError> {
    let mut edr = Vec::new();
    let mut edr_records = Vec::new();
    let mut skids = [None, None];
    for (k, p) in case.pre_impact_vehicles()?.into_iter().enumerate() {
        let Some(p) = p else { continue };
        let id = VehicleId::from_index(k);
        for e in &p.edr {
            edr.push((id, e.at_contact(), e.sigma));
            edr_records.push((k as u8 + 1, e.record));
            labels.push(format!(
                "vehicle{} EDR speed {:.1} s before contact",
                k + 1,
                e.time
            ));
        }
        skids[k] = p.skid.map(|s| skid_of(case, k, s)).transpose()?;
    }
    Ok((edr, edr_records, skids))
}

/// What [`pre_impact`] reads.
type PreImpact = (
    Vec<(VehicleId, f64, f64)>,
    Vec<(u8, usize)>,
    [Option<Skid>; 2],
);

/// Vehicle `k`'s skid before the impact, checked as a skid the reconstruction takes.
fn skid_of(case: &Case, k: usize, s: PreImpactSkid) -> Result<Skid, DocumentError> {
    let skid = Skid {
        distance: s.distance,
        braking: s.braking,
        grade: s.grade,
        friction: s.friction,
    };
    skid.check().map_err(|e| {
        let field = match &e {
            pim_reconstruct::ReconstructError::Input { field, .. } => *field,
            _ => "skid",
        };
        let field = if field == "distance" { "skid" } else { field };
        DocumentError::from(case.error_at(
            &format!("pre_impact.vehicle{}.{field}", k + 1),
            e.to_string(),
        ))
    })?;
    Ok(skid)
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
