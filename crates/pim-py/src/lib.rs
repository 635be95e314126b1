//! Python bindings of the PIM toolkit: the module `pim._pim`, re-exported by the package `pim`.
//!
//! Every function returns the document that the `pim` command prints with `--format json`, made
//! by the same library code (`pim_data::documents`, `pim_data::batch`, `pim_data::uncertainty`,
//! `pim_data::predict`), as Python objects (dicts, lists, floats). Nothing is computed here.

mod scene;

use pim_data::case::Case;
use pim_data::documents::{self, DocumentError};
use pim_fit::{CostPreset, MomentBranch};
use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use std::path::Path;

create_exception!(
    _pim,
    InputError,
    PyValueError,
    "Bad input: a case or data file that cannot be read, a field with a bad value, or an \
     argument out of its range. The message is the command line's: it names the file, line and \
     field. A ValueError."
);
create_exception!(
    _pim,
    NoSolution,
    PyException,
    "Valid input for which the model has no answer: singular or inconsistent equations, or (fit) \
     no moment branch with an admissible solution. For a fit, the exception's `document` holds \
     the fit's document, whose branches say why."
);

fn input_error(message: impl Into<String>) -> PyErr {
    InputError::new_err(without_dict_lines(message.into()))
}

/// A dict case is read as TOML written from it, whose lines and columns mean nothing to the
/// caller: `<dict>:2:8: vehicle1.mass: ...` is said `<dict>: vehicle1.mass: ...`.
fn without_dict_lines(message: String) -> String {
    const DICT: &str = "<dict>:";
    let mut out = String::with_capacity(message.len());
    let mut rest = message.as_str();
    while let Some(at) = rest.find(DICT) {
        out.push_str(&rest[..at + DICT.len()]);
        rest = &rest[at + DICT.len()..];
        // `LINE:COL:` right after the name.
        let digits = |s: &str| s.find(|c: char| !c.is_ascii_digit()).unwrap_or(s.len());
        let (l, after) = rest.split_at(digits(rest));
        if !l.is_empty() {
            if let Some(after) = after.strip_prefix(':') {
                let (c, after) = after.split_at(digits(after));
                if !c.is_empty() && after.starts_with(':') {
                    rest = &after[1..];
                }
            }
        }
    }
    out.push_str(rest);
    out
}

impl From<DocumentErrorPy> for PyErr {
    fn from(e: DocumentErrorPy) -> Self {
        match e.0 {
            DocumentError::Input(m) => input_error(m),
            DocumentError::NoAnswer(m) => NoSolution::new_err(without_dict_lines(m)),
        }
    }
}

/// A local wrapper so that `?` turns a document error into the right Python exception.
struct DocumentErrorPy(DocumentError);

impl From<DocumentError> for DocumentErrorPy {
    fn from(e: DocumentError) -> Self {
        DocumentErrorPy(e)
    }
}

impl From<pim_data::InputError> for DocumentErrorPy {
    fn from(e: pim_data::InputError) -> Self {
        DocumentErrorPy(e.into())
    }
}

/// A serialisable value as a Python object (through JSON, so that the document is exactly the
/// command line's).
fn to_py<T: serde::Serialize>(py: Python<'_>, value: &T) -> PyResult<Py<PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    let json = py.import("json")?;
    Ok(json.call_method1("loads", (text,))?.unbind())
}

/// Reads a text file, with the command line's message when it cannot.
/// Reads a case or data file as the command does: a regular file, read with a cap.
fn read(path: &Path, max_bytes: u64) -> PyResult<String> {
    let name = path.display().to_string();
    let meta =
        std::fs::metadata(path).map_err(|e| input_error(format!("{name}: cannot read: {e}")))?;
    pim_data::input::check_file(&name, &meta, max_bytes).map_err(|e| input_error(e.message))?;
    let file =
        std::fs::File::open(path).map_err(|e| input_error(format!("{name}: cannot read: {e}")))?;
    pim_data::input::read_text(&name, file, max_bytes).map_err(|e| input_error(e.message))
}

/// A case from TOML text, a path (str or os.PathLike) or a dict of the case file's shape.
fn load_case(py: Python<'_>, case: &Bound<'_, PyAny>) -> PyResult<Case> {
    let (name, text) = if case.is_instance_of::<PyDict>() {
        let json: String = py
            .import("json")?
            .call_method1("dumps", (case,))?
            .extract()?;
        let value: serde_json::Value =
            serde_json::from_str(&json).map_err(|e| input_error(format!("<dict>: {e}")))?;
        let text = toml::to_string(&value).map_err(|e| {
            input_error(format!(
                "<dict>: cannot be written as a case file: {e} (a None has no TOML form: \
                     leave the field out)"
            ))
        })?;
        ("<dict>".to_string(), text)
    } else if case.is_instance_of::<PyString>() {
        let s: String = case.extract()?;
        let looks_like_path = !s.contains('\n') && !s.contains('=');
        if looks_like_path {
            (
                s.clone(),
                read(Path::new(&s), pim_data::case::MAX_CASE_BYTES)?,
            )
        } else {
            ("<text>".to_string(), s)
        }
    } else if let Ok(p) = case.extract::<std::path::PathBuf>() {
        (
            p.display().to_string(),
            read(&p, pim_data::case::MAX_CASE_BYTES)?,
        )
    } else {
        return Err(input_error(
            "case: give TOML text, a path to a case file, or a dict of the same shape",
        ));
    };
    Case::from_text(&name, &text).map_err(|e| input_error(e.message))
}

/// A named choice of the library (moment form, cost function, branch, model), read by the
/// library's own names; `field` names the argument in the error.
fn named<T: std::str::FromStr<Err = String>>(field: &str, name: &str) -> PyResult<T> {
    name.parse()
        .map_err(|e| input_error(format!("{field}: {e}")))
}

fn moment_form(name: &str) -> PyResult<pim_core::MomentForm> {
    named("moment_form", name)
}

fn model(name: &str) -> PyResult<pim_fit::FitModel> {
    named("model", name)
}

fn options(no_slip: bool, moment_form: &str) -> PyResult<pim_core::SolveOptions> {
    Ok(pim_core::SolveOptions {
        moment_form: self::moment_form(moment_form)?,
        tangential: if no_slip {
            pim_core::TangentialCondition::NoSlip
        } else {
            pim_core::TangentialCondition::Sliding
        },
    })
}

fn cost(name: &str) -> PyResult<CostPreset> {
    named("cost", name)
}

fn branches(names: Vec<String>) -> PyResult<Vec<MomentBranch>> {
    let mut out = Vec::new();
    for n in names {
        let b: MomentBranch = named("branches", &n)?;
        if !out.contains(&b) {
            out.push(b);
        }
    }
    if out.is_empty() {
        return Err(input_error(
            "branches: give at least one of \"free\", \"zero\"",
        ));
    }
    Ok(out)
}

/// A `draws` argument: `None` when not given, else a whole number from `lo` to the largest
/// study.
fn draws_arg(draws: Option<&Bound<'_, PyAny>>, lo: u64) -> PyResult<Option<usize>> {
    draws
        .filter(|d| !d.is_none())
        .map(|d| Ok(whole(d, "draws", lo, pim_data::ranges::MAX_DRAWS as u64)? as usize))
        .transpose()
}

/// A `seed` argument: 1 when not given, else any whole number that fits 64 bits.
fn seed_arg(seed: Option<&Bound<'_, PyAny>>) -> PyResult<u64> {
    seed.filter(|s| !s.is_none())
        .map_or(Ok(1), |s| whole(s, "seed", 0, u64::MAX))
}

/// A whole-number argument in `lo..=hi`, or InputError naming it and the range (never
/// Python's bare OverflowError or TypeError).
fn whole(value: &Bound<'_, PyAny>, name: &str, lo: u64, hi: u64) -> PyResult<u64> {
    let bad = || {
        input_error(format!(
            "{name} = {}: expected a whole number from {lo} to {hi}",
            value
                .repr()
                .map_or_else(|_| "?".to_string(), |r| r.to_string())
        ))
    };
    if value.is_instance_of::<pyo3::types::PyBool>() {
        return Err(bad());
    }
    let n: i128 = value.extract().map_err(|_| bad())?;
    if n < i128::from(lo) || n > i128::from(hi) {
        return Err(bad());
    }
    Ok(n as u64)
}

/// The `threads` argument: None (all cores) or 1 to the largest accepted.
fn threads_arg(threads: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    threads
        .filter(|t| !t.is_none())
        .map(|t| whole(t, "threads", 1, pim_data::ranges::MAX_THREADS as u64).map(|n| n as usize))
        .transpose()
}

/// Runs `f` on a rayon pool of `threads` (default: all cores) without holding the GIL.
fn detached<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    f: impl FnOnce() -> T + Send,
) -> PyResult<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| input_error(format!("threads: {e}")))?;
    Ok(py.detach(|| pool.install(f)))
}

/// A `units` argument: `"si"`, `"us"`, `"kmh"` or `None` (the case's own).
fn units_of(units: Option<&str>) -> PyResult<Option<pim_data::units::UnitSystem>> {
    use pim_data::units::UnitSystem;
    Ok(match units {
        None => None,
        Some("si") => Some(UnitSystem::Si),
        Some("us") => Some(UnitSystem::Us),
        Some("kmh") => Some(UnitSystem::Kmh),
        Some(other) => {
            return Err(input_error(format!(
                "units = {other:?}: not an accepted value; accepted: \"si\", \"us\", \"kmh\""
            )))
        }
    })
}

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
    if cost.is_none() && pim_data::reconstruct::has_scene_evidence(&case) {
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
) -> PyResult<pim_data::batch::BatchPlan> {
    let costs = costs
        .iter()
        .map(|c| cost(c))
        .collect::<PyResult<Vec<_>>>()?;
    let models = models
        .iter()
        .map(|m| model(m))
        .collect::<PyResult<Vec<_>>>()?;
    let plan = pim_data::batch::BatchPlan::new(
        &costs,
        &self::branches(branches)?,
        e_max,
        self::moment_form(moment_form)?,
    )
    .map_err(input_error)?
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
    let mut rows = pim_data::ricsac::parse(&file, &read(&path, pim_data::ricsac::MAX_DATA_BYTES)?)
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
    let records = detached(py, threads, || pim_data::batch::run(&rows, &plan, &|| {}))?;
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
    let rows = pim_data::ricsac::parse(name, text).map_err(|e| input_error(e.message))?;
    let threads = threads_arg(threads.as_ref())?;
    let records = detached(py, threads, || pim_data::batch::run(&rows, &plan, &|| {}))?;
    pim_render::batch_tables::records_csv(&records).map_err(input_error)
}

/// Propagates the case's stated uncertainties ([sigma], [uncertainty]) through the fit by a
/// seeded parametric bootstrap; the document of `pim uncertainty --format json`.
#[pyfunction]
#[pyo3(signature = (case, cost = None, draws = None, seed = None, threads = None, model = "pim"))]
#[pyo3(text_signature = "(case, cost=None, draws=200, seed=1, threads=None, model='pim')")]
fn uncertainty(
    py: Python<'_>,
    case: &Bound<'_, PyAny>,
    cost: Option<&str>,
    draws: Option<Bound<'_, PyAny>>,
    seed: Option<Bound<'_, PyAny>>,
    threads: Option<Bound<'_, PyAny>>,
    model: &str,
) -> PyResult<Py<PyAny>> {
    let (draws, seed, threads) = study_args(draws, seed, threads)?;
    let case = load_case(py, case)?;
    case.impact().map_err(|e| input_error(e.message))?;
    let choice = match cost {
        Some(c) => pim_data::fitcase::CostChoice::Preset(self::cost(c)?),
        None => pim_data::fitcase::CostChoice::Custom,
    };
    let unc = case.content.uncertainty.unwrap_or_default();
    let model = self::model(model)?;
    let study = detached(py, threads, || {
        pim_data::uncertainty::run(
            &case,
            &unc,
            choice,
            pim_fit::FitSettings {
                model,
                ..Default::default()
            },
            draws,
            seed,
            &|| {},
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
    let tests = pim_data::ricsac::parse(&file, &read(&path, pim_data::ricsac::MAX_DATA_BYTES)?)
        .map_err(|e| input_error(e.message))?;
    let rows =
        pim_data::predict::predict_all(&file, &tests, e).map_err(|e| input_error(e.message))?;
    to_py(py, &serde_json::json!({ "tests": rows }))
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
        .map_err(pyo3::exceptions::PyRuntimeError::new_err)
}

/// The arguments of a study: draws (default 200), seed (default 1), threads.
fn study_args(
    draws: Option<Bound<'_, PyAny>>,
    seed: Option<Bound<'_, PyAny>>,
    threads: Option<Bound<'_, PyAny>>,
) -> PyResult<(usize, u64, Option<usize>)> {
    Ok((
        draws_arg(draws.as_ref(), 1)?.unwrap_or(200),
        seed_arg(seed.as_ref())?,
        threads_arg(threads.as_ref())?,
    ))
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
    m.add_function(wrap_pyfunction!(scene::runout, m)?)?;
    m.add_function(wrap_pyfunction!(scene::reconstruct, m)?)?;
    m.add_function(wrap_pyfunction!(scene::reconstruct_uncertainty, m)?)?;
    Ok(())
}
