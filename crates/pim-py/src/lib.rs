//! Python bindings of the PIM toolkit: the module `pim._pim`, re-exported by the package `pim`.
//!
//! Every function returns the document that the `pim` command prints with `--format json`, made
//! by the same library code (`pim_studies::documents`, `pim_studies::batch`, `pim_studies::uncertainty`,
//! `pim_studies::predict`), as Python objects (dicts, lists, floats). Nothing is computed here.

mod convert;
mod edit;
mod scene;

use convert::*;
use pim_studies::documents;
use pyo3::prelude::*;

/// The report of `pim report` for a case: its HTML page and its Markdown, as a pair (the
/// figures are inline in the HTML).
#[pyfunction]
#[pyo3(signature = (case, cost = None, draws = None, seed = None, units = None, solve = false))]
fn report(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    cost: Option<&str>,
    draws: Option<Bound<'_, PyAny>>,
    seed: Option<Bound<'_, PyAny>>,
    units: Option<&str>,
    solve: bool,
) -> PyResult<(String, String)> {
    let draws = draws_arg(draws.as_ref(), 0)?;
    let seed = seed_arg(seed.as_ref())?;
    let options = pim_render::report::make::Options {
        cost: cost.map(self::cost).transpose()?,
        model: pim_fit::FitModel::Pim,
        solve,
        draws,
        seed,
        units: units_of(units)?,
    };
    let case = load_case(py, case)?;
    let made = detached(py, None, || pim_render::report::make::make(&case, &options))?
        .map_err(DocumentErrorPy)?;
    Ok((made.document.html(), made.document.markdown()))
}

/// Solves a case forwards ([initial] given) or backwards ([final] given) with its
/// [coefficients]; the document of `pim solve --format json`.
#[pyfunction]
#[pyo3(signature = (case, no_slip = false, moment_form = "corrected"))]
fn solve(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    no_slip: bool,
    moment_form: &str,
) -> PyResult<Py<PyAny>> {
    let case = load_case(py, case)?;
    let solved =
        documents::solve(&case, &options(no_slip, moment_form)?).map_err(DocumentErrorPy)?;
    to_py(py, &solved.document)
}

/// Fits the coefficients e, mu, e_m and the twelve velocity components of a case; the
/// document of `pim fit --format json` (dict with `cost_function`, `branches`, `best`, `notes`).
///
/// case: TOML text, a path to a case file, or a dict of the same shape: [vehicle1],
///   [vehicle2] (mass kg, yaw_inertia kg m^2, heading deg = where the nose points,
///   impact_point = {x, y} m from the CG or d and phi), [impact] crush_angle (deg),
///   [estimates.initial] / [estimates.final] (vx, vy m/s, omega rad/s per vehicle; partial
///   allowed), optional [weights] or [sigma], [known], [bounds], [[observations]], [units],
///   convention = "brach" for the papers' form. `pim fit --help` describes every field.
/// cost: "q1" separation velocities known exactly, contact velocities estimated; "q2" contact
///   velocities known exactly, separation velocities estimated (Brach's fits); "q3" all twelve
///   estimated; None: the case's [known] held fixed and [estimates] estimated.
/// branches: "free" (e_m in [-1, 0]) and / or "zero" (e_m = 1, no moment impulse); each is
///   searched globally and its optimum certified.
/// moment_form: "corrected" (default) or "brach1983" (the 1983 paper's moment equation).
/// model: "pim" (default) or "tangential": normal and tangential restitution with a friction
///   limit (e, et, friction within [bounds] e, et, friction; no moment impulse, one branch
///   "zero", whose `tangential` entry gives the contact mode, et and the friction limits).
///
/// Raises InputError for bad input (the command line's message) and NoSolution when no
/// branch has an admissible solution; its `document` attribute holds the document, whose
/// branches give the reasons.
#[pyfunction]
#[pyo3(signature = (case, cost = None, branches = vec!["free".to_string(), "zero".to_string()], moment_form = "corrected", model = "pim"))]
#[pyo3(
    text_signature = "(case, cost=None, branches=('free', 'zero'), moment_form='corrected', model='pim')"
)]
fn fit(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    cost: Option<&str>,
    branches: Vec<String>,
    moment_form: &str,
    model: &str,
) -> PyResult<Py<PyAny>> {
    let case = load_case(py, case)?;
    let cost = cost.map(self::cost).transpose()?;
    if pim_studies::question::Question::of(&case, cost).question
        == pim_studies::question::Question::Reconstruction
    {
        return Err(input_error(format!(
            "{}: the case has scene evidence ([scene]): pim.reconstruct(case) fits all three \
             phases (the scene, the impact, the pre-impact evidence); pim.fit(case, cost=...) \
             fits the velocity estimates alone",
            case.file
        )));
    }
    let branches = self::branches(branches)?;
    let form = self::moment_form(moment_form)?;
    let model = self::model(model)?;
    let fitted = detached(py, None, || {
        documents::fit(&case, cost, model, form, branches)
    })?
    .map_err(DocumentErrorPy)?;
    let document = to_py(py, &fitted.document)?;
    if fitted.report.best.is_none() {
        let err = NoSolution::new_err(format!(
            "{}: no branch has an admissible solution (the reasons are in the document)",
            case.file
        ));
        err.value(py).setattr("document", document)?;
        return Err(err);
    }
    Ok(document)
}

/// The plan of a batch from the Python arguments.
fn batch_plan(
    costs: Vec<String>,
    branches: Vec<String>,
    e_max: f64,
    moment_form: &str,
    models: Vec<String>,
    conditions: &str,
) -> PyResult<pim_studies::batch::BatchPlan> {
    let costs = costs
        .iter()
        .map(|c| cost(c))
        .collect::<PyResult<Vec<_>>>()?;
    let models = models
        .iter()
        .map(|m| model(m))
        .collect::<PyResult<Vec<_>>>()?;
    let plan = pim_studies::batch::BatchPlan::new(
        &costs,
        &self::branches(branches)?,
        e_max,
        self::moment_form(moment_form)?,
    )
    .map_err(|e| input_error(e.to_string()))?
    .with_models(&models);
    match conditions {
        "corrected" => Ok(plan),
        "v18" => Ok(plan.with_v18_conditions()),
        other => Err(input_error(format!(
            "conditions: expected \"corrected\" or \"v18\", got {other:?}"
        ))),
    }
}

/// Refits every test of a RICSAC-style data file under each cost function and branch; the
/// records of `pim batch DATA --format json` (a list, one dict per test, cost function and
/// branch). The fits run on `threads` cores (default all) without holding the GIL; the records
/// are the same for any thread count. `tests` keeps only those test numbers. `models`:
/// "pim" and / or "tangential" (each record's `model` says which; `pim batch --model`).
#[pyfunction]
#[pyo3(signature = (path = std::path::PathBuf::from("data/ricsac.csv"), costs = vec!["q1".to_string(), "q2".to_string(), "q3".to_string()], branches = vec!["free".to_string(), "zero".to_string()], threads = None, e_max = pim_fit::DEFAULT_E_RANGE[1], moment_form = "corrected", tests = None, models = vec!["pim".to_string()], conditions = "corrected"))]
#[pyo3(
    text_signature = "(path='data/ricsac.csv', costs=('q1', 'q2', 'q3'), branches=('free', 'zero'), threads=None, e_max=0.2, moment_form='corrected', tests=None, models=('pim',), conditions='corrected')"
)]
#[allow(clippy::too_many_arguments)]
fn batch(
    py: Python<'_>,
    path: std::path::PathBuf,
    costs: Vec<String>,
    branches: Vec<String>,
    threads: Option<Bound<'_, PyAny>>,
    e_max: f64,
    moment_form: &str,
    tests: Option<Vec<u32>>,
    models: Vec<String>,
    conditions: &str,
) -> PyResult<Py<PyAny>> {
    let plan = batch_plan(costs, branches, e_max, moment_form, models, conditions)?;
    let file = path.display().to_string();
    let mut rows = pim_case::ricsac::parse(&file, &read(&path, pim_case::ricsac::MAX_DATA_BYTES)?)
        .map_err(|e| input_error(e.message))?;
    if let Some(keep) = tests {
        for t in &keep {
            if !rows.iter().any(|r| r.test == *t) {
                return Err(input_error(format!("tests: test {t} is not in {file}")));
            }
        }
        rows.retain(|r| keep.contains(&r.test));
    }
    let threads = threads_arg(threads.as_ref())?;
    let records = detached(py, threads, || {
        pim_studies::batch::run(&rows, &plan, &pim_studies::watch::Unwatched)
    })?;
    to_py(py, &records)
}

/// Refits every row of RICSAC-style CSV text (the header and columns of data/ricsac.csv) under
/// each cost function, model and branch; the CSV of `pim batch DATA --format csv` (one row per
/// test, cost function, model and branch, fixed columns). `name` names the text in error
/// messages. The frame-in, frame-out `pim.fit_frame` is built on it.
#[pyfunction]
#[pyo3(signature = (text, name = "<frame>", costs = vec!["q1".to_string(), "q2".to_string(), "q3".to_string()], branches = vec!["free".to_string(), "zero".to_string()], threads = None, e_max = pim_fit::DEFAULT_E_RANGE[1], moment_form = "corrected", models = vec!["pim".to_string()], conditions = "corrected"))]
#[pyo3(
    text_signature = "(text, name='<frame>', costs=('q1', 'q2', 'q3'), branches=('free', 'zero'), threads=None, e_max=0.2, moment_form='corrected', models=('pim',), conditions='corrected')"
)]
#[allow(clippy::too_many_arguments)]
fn batch_csv(
    py: Python<'_>,
    text: &str,
    name: &str,
    costs: Vec<String>,
    branches: Vec<String>,
    threads: Option<Bound<'_, PyAny>>,
    e_max: f64,
    moment_form: &str,
    models: Vec<String>,
    conditions: &str,
) -> PyResult<String> {
    let plan = batch_plan(costs, branches, e_max, moment_form, models, conditions)?;
    let rows = pim_case::ricsac::parse(name, text).map_err(|e| input_error(e.message))?;
    let threads = threads_arg(threads.as_ref())?;
    let records = detached(py, threads, || {
        pim_studies::batch::run(&rows, &plan, &pim_studies::watch::Unwatched)
    })?;
    pim_render::batch_tables::records_csv(&records).map_err(|e| input_error(e.to_string()))
}

/// Propagates the case's stated uncertainties ([sigma], [uncertainty]) through the fit by a
/// seeded parametric bootstrap; the document of `pim uncertainty --format json`.
#[pyfunction]
#[pyo3(signature = (case, cost = None, draws = None, seed = None, threads = None, model = "pim", progress = None))]
#[pyo3(
    text_signature = "(case, cost=None, draws=200, seed=1, threads=None, model='pim', progress=None)"
)]
#[allow(clippy::too_many_arguments)] // one per keyword argument of the Python function
fn uncertainty(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    cost: Option<&str>,
    draws: Option<Bound<'_, PyAny>>,
    seed: Option<Bound<'_, PyAny>>,
    threads: Option<Bound<'_, PyAny>>,
    model: &str,
    progress: Option<Bound<'_, PyAny>>,
) -> PyResult<Py<PyAny>> {
    let (draws, seed, threads) = study_args(draws, seed, threads)?;
    let case = load_case(py, case)?;
    case.impact().map_err(|e| input_error(e.message))?;
    let preset = cost.map(self::cost).transpose()?;
    if pim_studies::question::Question::of(&case, preset).question
        == pim_studies::question::Question::Reconstruction
    {
        // Never the study of the contact estimates alone for a scene case.
        return Err(input_error(format!(
            "{}: the case has scene evidence ([scene]): pim.reconstruct_uncertainty(case) draws \
             the whole reconstruction (the scene, the impact, the pre-impact evidence); \
             pim.uncertainty(case, cost=...) draws the velocity estimates alone",
            case.file
        )));
    }
    let choice = match preset {
        Some(c) => pim_studies::fitcase::CostChoice::Preset(c),
        None => pim_studies::fitcase::CostChoice::Custom,
    };
    let unc = case.spreads();
    let model = self::model(model)?;
    let study = crate::convert::watched(py, threads, progress, |observer| {
        pim_studies::uncertainty::run(
            &case,
            &unc,
            choice,
            pim_fit::FitSettings {
                model,
                ..Default::default()
            },
            draws,
            seed,
            observer,
        )
    })?
    .map_err(|e| input_error(e.message))?;
    to_py(py, &study)
}

/// Brach (1984) section 6: delta-V predicted from the impact speeds, masses and energy loss
/// for every test of a data file; the document of `pim predict-dv --format json`.
#[pyfunction]
#[pyo3(signature = (path = std::path::PathBuf::from("data/ricsac.csv"), e = 0.0))]
#[pyo3(text_signature = "(path='data/ricsac.csv', e=0.0)")]
fn predict_dv(py: Python<'_>, path: std::path::PathBuf, e: f64) -> PyResult<Py<PyAny>> {
    let file = path.display().to_string();
    let tests = pim_case::ricsac::parse(&file, &read(&path, pim_case::ricsac::MAX_DATA_BYTES)?)
        .map_err(|e| input_error(e.message))?;
    let rows =
        pim_studies::predict::predict_all(&file, &tests, e).map_err(|e| input_error(e.message))?;
    to_py(py, &pim_documents::schema::PredictionsOut { tests: rows })
}

/// The scale diagram of `pim draw` as SVG text: the case at contact (outlines, CGs, impact
/// centre, crush surface), solved with its [coefficients] when it has them and a state, with
/// the estimated contact velocities of a fit case. Labelled in the case's units and frame, or
/// in `units` ("si", "us" or "kmh"). Write it to a file or show it with IPython.display.SVG.
#[pyfunction]
#[pyo3(signature = (case, no_slip = false, moment_form = "corrected", units = None))]
fn draw(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    no_slip: bool,
    moment_form: &str,
    units: Option<&str>,
) -> PyResult<String> {
    let units = units_of(units)?;
    let case = load_case(py, case)?;
    let mut diagram = pim_render::diagram::case_diagram(&case, &options(no_slip, moment_form)?)
        .map_err(DocumentErrorPy)?;
    if let Some(u) = units {
        diagram.units = u;
    }
    diagram
        .svg()
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))
}

/// The compiled part of the package `pim`.
#[pymodule]
fn _pim(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("NoSolution", py.get_type::<NoSolution>())?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    m.add_function(wrap_pyfunction!(report, m)?)?;
    m.add_function(wrap_pyfunction!(fit, m)?)?;
    m.add_function(wrap_pyfunction!(batch, m)?)?;
    m.add_function(wrap_pyfunction!(batch_csv, m)?)?;
    m.add_function(wrap_pyfunction!(uncertainty, m)?)?;
    m.add_function(wrap_pyfunction!(predict_dv, m)?)?;
    m.add_function(wrap_pyfunction!(draw, m)?)?;
    m.add_function(wrap_pyfunction!(edit::edit_case, m)?)?;
    m.add_function(wrap_pyfunction!(edit::case_version, m)?)?;
    m.add_function(wrap_pyfunction!(scene::runout, m)?)?;
    m.add_function(wrap_pyfunction!(scene::reconstruct, m)?)?;
    m.add_function(wrap_pyfunction!(scene::reconstruct_many, m)?)?;
    m.add_function(wrap_pyfunction!(scene::reconstruct_uncertainty, m)?)?;
    Ok(())
}
