//! The run-out and the reconstruction of a scene, for Python.

use crate::convert::{
    detached, input_error, load_case, load_runout_case, study_args, to_py, units_of,
    DocumentErrorPy, NoSolution,
};
use pim_studies::documents::DocumentError;
use pyo3::prelude::*;

/// The run-out of `pim runout` for a case: each vehicle from its separation velocities to rest,
/// or its separation velocities estimated from the scene; a motion case (`[start]`, no impact)
/// from its stated state. Returns the document of
/// `pim runout --format json` and, with `draw`, the plan view's SVG. `source` is "final",
/// "solve", "fit" or "scene" (default: the first the case has); `cost` is the fit's with
/// `source="fit"`. Raises NoSolution (its `document` the run-out's) when a run-out reaches its
/// time limit or no candidate reaches the scene's evidence.
#[pyfunction]
#[pyo3(signature = (case, source = None, cost = None, sample = 0.1, draw = false, every = 0.5, units = None, wheels = false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn runout(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    source: Option<&str>,
    cost: Option<&str>,
    sample: f64,
    draw: bool,
    every: f64,
    units: Option<&str>,
    wheels: bool,
) -> PyResult<(Py<PyAny>, Option<String>)> {
    use pim_studies::runout::Source;
    for (name, x) in [("sample", sample), ("every", every)] {
        if !(x.is_finite() && (0.001..=3600.0).contains(&x)) {
            return Err(input_error(format!(
                "{name} = {x}: must be between 0.001 and 3600 s"
            )));
        }
    }
    let source = match source {
        None => None,
        Some("final") => Some(Source::Final),
        Some("solve") => Some(Source::Solve),
        Some("fit") => Some(Source::Fit),
        Some("scene") => Some(Source::Scene),
        Some(other) => {
            return Err(input_error(format!(
                "source = {other:?}: not an accepted value; accepted: \"final\", \"solve\", \
                 \"fit\", \"scene\""
            )))
        }
    };
    let units = units_of(units)?;
    let cost = cost.map(crate::convert::cost).transpose()?;
    let case = load_runout_case(py, case)?;
    let result = detached(py, None, || -> Result<_, DocumentError> {
        let given = match source {
            Some(Source::Fit) => Some(pim_studies::runout::fitted_separation(&case, cost)?),
            _ => None,
        };
        pim_studies::runout::runout(&case, source, given, sample, wheels)
    })?
    .map_err(DocumentErrorPy)?;
    let document = to_py(py, &result.document)?;
    if let Some(why) = result.no_answer() {
        let err = NoSolution::new_err(format!("{}: {why}", case.file));
        err.value(py).setattr("document", document)?;
        return Err(err);
    }
    let svg = if draw {
        let units = units.unwrap_or_else(|| pim_case::units::UnitSystem::of(&case.written_units));
        let title = pim_render::text::case_title(&case);
        Some(
            pim_render::runout::runout_svg(&title, &result, units, case.written, every)
                .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?,
        )
    } else {
        None
    };
    Ok((document, svg))
}

/// The three phases of a case with scene evidence in one fit (`pim fit` of such a case): its
/// document and, with `draw`, the scene to scale as SVG.
#[pyfunction]
#[pyo3(signature = (case, branches = vec!["free".to_string(), "zero".to_string()], model = "pim", draw = false, units = None))]
pub(crate) fn reconstruct(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    branches: Vec<String>,
    model: &str,
    draw: bool,
    units: Option<&str>,
) -> PyResult<(Py<PyAny>, Option<String>)> {
    let units = units_of(units)?;
    let case = load_case(py, case)?;
    let branches = crate::convert::branches(branches)?;
    let model = crate::convert::model(model)?;
    let done = crate::convert::watched(py, None, None, |observer| {
        pim_studies::consistency::answer(
            &case,
            model,
            pim_core::MomentForm::Corrected,
            branches,
            observer,
        )
    })?
    .map_err(DocumentErrorPy)?;
    let document = to_py(py, &done.document)?;
    if done.outcome.best.is_none() || done.outcome.status != pim_reconstruct::Status::Found {
        let err = NoSolution::new_err(format!(
            "{}: no reconstruction: {}",
            case.file,
            done.document.reason.as_deref().unwrap_or("none found")
        ));
        err.value(py).setattr("document", document)?;
        return Err(err);
    }
    let svg = if draw {
        let units = units.unwrap_or_else(|| pim_case::units::UnitSystem::of(&case.written_units));
        pim_render::runout::reconstruction_scene(&case, &done, units)
            .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?
    } else {
        None
    };
    Ok((document, svg))
}

/// Intervals through all three phases of a case with scene evidence (`pim uncertainty` of
/// such a case): the study's document.
#[pyfunction]
#[pyo3(signature = (case, draws = None, seed = None, threads = None, model = "pim", progress = None))]
pub(crate) fn reconstruct_uncertainty(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    draws: Option<Bound<'_, PyAny>>,
    seed: Option<Bound<'_, PyAny>>,
    threads: Option<Bound<'_, PyAny>>,
    model: &str,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let (draws, seed, threads) = study_args(draws, seed, threads)?;
    let case = load_case(py, case)?;
    let model = crate::convert::model(model)?;
    let (study, _) = crate::convert::watched(py, threads, progress, |observer| {
        pim_studies::reconstruct_study::run(
            &case,
            model,
            pim_core::MomentForm::Corrected,
            pim_fit::MomentBranch::ALL.to_vec(),
            draws,
            seed,
            observer,
        )
    })?
    .map_err(DocumentErrorPy)?;
    to_py(py, &study)
}

/// One record of a scene case for `pim.scene_frame`: its reconstruction's status, chi-square,
/// coefficients, each vehicle's speeds per phase and turns, and the fitted road friction (SI);
/// a case that cannot be read or reconstructed gives its status and reason only.
fn scene_record(name: &str, text: &str) -> serde_json::Value {
    use serde_json::json;
    let failed = |reason: String| json!({"case": name, "status": "failed", "reason": reason});
    let case = match pim_case::case::Case::from_text(name, text) {
        Ok(c) => c,
        Err(e) => return failed(e.to_string()),
    };
    if !case.has_scene_evidence() {
        return failed(format!(
            "{name}: no scene evidence ([scene] rest positions or marks): not a reconstruction"
        ));
    }
    let done = match pim_studies::reconstruct::reconstruct(
        &case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        vec![pim_fit::MomentBranch::Free, pim_fit::MomentBranch::Zero],
    ) {
        Ok(d) => d,
        Err(e) => return failed(e.to_string()),
    };
    let d = &done.document;
    // The summary `pim batch` records, flattened, with the coefficients and the friction.
    let rec = pim_documents::reconstruct_doc::SceneRecord::of(d);
    let mut row = json!({
        "case": name,
        "status": serde_json::to_value(rec.status).unwrap_or_default(),
        "reason": rec.reason,
    });
    let Some(b) = &d.best else { return row };
    row["chi_square"] = json!(rec.chi_square);
    row["degrees_of_freedom"] = json!(rec.degrees_of_freedom);
    row["p_value"] = json!(rec.p_value);
    row["e"] = json!(b.e);
    row["mu"] = json!(b.mu);
    row["em"] = json!(b.em);
    row["energy_loss_percent"] = json!(b.energy_loss_percent);
    for v in &rec.vehicles {
        let k = v.vehicle;
        row[format!("v{k}_before_braking")] = json!(v.speed_before_braking);
        row[format!("v{k}_contact")] = json!(v.speed_at_contact);
        row[format!("v{k}_separation")] = json!(v.speed_at_separation);
        row[format!("v{k}_turns")] = json!(v.turns);
    }
    if let Some(best) = &done.outcome.best {
        let road = done
            .input
            .reconstruction
            .frictions
            .iter()
            .position(|f| f.zone.is_none());
        row["road_friction"] = json!(road.map(|g| best.frictions[g]));
    }
    row
}

/// The records of many scene cases, reconstructed in parallel on `threads` cores (`None`:
/// every core), in the order given, as a JSON list (`pim.scene_frame`).
#[pyfunction]
#[pyo3(signature = (names, texts, threads = None))]
pub(crate) fn reconstruct_many(
    py: Python<'_>,
    names: Vec<String>,
    texts: Vec<String>,
    threads: Option<Bound<'_, PyAny>>,
) -> PyResult<String> {
    use rayon::prelude::*;
    if names.len() != texts.len() {
        return Err(input_error(format!(
            "{} names for {} case texts",
            names.len(),
            texts.len()
        )));
    }
    let threads = crate::convert::threads_arg(threads.as_ref())?;
    let rows: Vec<serde_json::Value> = detached(py, threads, || {
        names
            .par_iter()
            .zip(&texts)
            .map(|(n, t)| scene_record(n, t))
            .collect()
    })?;
    serde_json::to_string(&rows).map_err(|e| input_error(e.to_string()))
}
