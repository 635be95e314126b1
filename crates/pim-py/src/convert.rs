//! What every function of the package shares: its exceptions, reading a case, converting
//! arguments and documents between Python and Rust.

use pim_case::case::Case;
use pim_fit::{CostPreset, MomentBranch};
use pim_studies::documents::DocumentError;
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

pub(crate) fn input_error(message: impl Into<String>) -> PyErr {
    InputError::new_err(without_dict_lines(message.into()))
}

/// A dict case is read as TOML written from it, whose lines and columns mean nothing to the
/// caller: `<dict>:2:8: vehicle1.mass: ...` is said `<dict>: vehicle1.mass: ...`.
pub(crate) fn without_dict_lines(message: String) -> String {
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
pub(crate) struct DocumentErrorPy(pub(crate) DocumentError);

impl From<DocumentError> for DocumentErrorPy {
    fn from(e: DocumentError) -> Self {
        DocumentErrorPy(e)
    }
}

impl From<pim_case::InputError> for DocumentErrorPy {
    fn from(e: pim_case::InputError) -> Self {
        DocumentErrorPy(e.into())
    }
}

/// A serialisable value as a Python object (through JSON, so that the document is exactly the
/// command line's).
pub(crate) fn to_py<T: serde::Serialize>(py: Python<'_>, value: &T) -> PyResult<Py<PyAny>> {
    let text = serde_json::to_string(value)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    let json = py.import("json")?;
    Ok(json.call_method1("loads", (text,))?.unbind())
}

/// Reads a text file, with the command line's message when it cannot.
/// Reads a case or data file as the command does: a regular file, read with a cap.
pub(crate) fn read(path: &Path, max_bytes: u64) -> PyResult<String> {
    let name = path.display().to_string();
    let meta =
        std::fs::metadata(path).map_err(|e| input_error(format!("{name}: cannot read: {e}")))?;
    pim_case::input::check_file(&name, &meta, max_bytes).map_err(|e| input_error(e.message))?;
    let file =
        std::fs::File::open(path).map_err(|e| input_error(format!("{name}: cannot read: {e}")))?;
    pim_case::input::read_text(&name, file, max_bytes).map_err(|e| input_error(e.message))
}

/// A case from TOML text, a path (str or os.PathLike) or a dict of the case file's shape.
pub(crate) fn load_case(py: Python<'_>, case: &Bound<'_, PyAny>) -> PyResult<Case> {
    let (name, text) = case_text(py, case)?;
    let case = Case::from_text(&name, &text).map_err(|e| input_error(e.message))?;
    pim_case::damage::Damage::of(&case).map_err(|e| input_error(e.message))?;
    Ok(case)
}

/// A case for the run-out: one with an impact, or a motion case (`[start]`, no impact).
pub(crate) fn load_runout_case(py: Python<'_>, case: &Bound<'_, PyAny>) -> PyResult<Case> {
    let (name, text) = case_text(py, case)?;
    if pim_case::motion::is_motion(&text) {
        return Case::motion_from_text(&name, &text).map_err(|e| input_error(e.message));
    }
    let case = Case::from_text(&name, &text).map_err(|e| input_error(e.message))?;
    pim_case::damage::Damage::of(&case).map_err(|e| input_error(e.message))?;
    Ok(case)
}

/// The name and TOML text of a case given as text, a path or a dict.
fn case_text(py: Python<'_>, case: &Bound<'_, PyAny>) -> PyResult<(String, String)> {
    Ok(if case.is_instance_of::<PyDict>() {
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
                read(Path::new(&s), pim_case::case::MAX_CASE_BYTES)?,
            )
        } else {
            ("<text>".to_string(), s)
        }
    } else if let Ok(p) = case.extract::<std::path::PathBuf>() {
        (
            p.display().to_string(),
            read(&p, pim_case::case::MAX_CASE_BYTES)?,
        )
    } else {
        return Err(input_error(
            "case: give TOML text, a path to a case file, or a dict of the same shape",
        ));
    })
}

/// A named choice of the library (moment form, cost function, branch, model), read by the
/// library's own names; `field` names the argument in the error.
pub(crate) fn named<T: std::str::FromStr<Err = pim_core::UnknownName>>(
    field: &str,
    name: &str,
) -> PyResult<T> {
    name.parse()
        .map_err(|e| input_error(format!("{field}: {e}")))
}

pub(crate) fn moment_form(name: &str) -> PyResult<pim_core::MomentForm> {
    named("moment_form", name)
}

pub(crate) fn model(name: &str) -> PyResult<pim_fit::FitModel> {
    named("model", name)
}

pub(crate) fn options(no_slip: bool, moment_form: &str) -> PyResult<pim_core::SolveOptions> {
    Ok(pim_core::SolveOptions {
        moment_form: self::moment_form(moment_form)?,
        tangential: if no_slip {
            pim_core::TangentialCondition::NoSlip
        } else {
            pim_core::TangentialCondition::Sliding
        },
    })
}

pub(crate) fn cost(name: &str) -> PyResult<CostPreset> {
    named("cost", name)
}

pub(crate) fn branches(names: Vec<String>) -> PyResult<Vec<MomentBranch>> {
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
pub(crate) fn draws_arg(draws: Option<&Bound<'_, PyAny>>, lo: u64) -> PyResult<Option<usize>> {
    draws
        .filter(|d| !d.is_none())
        .map(|d| Ok(whole(d, "draws", lo, pim_case::ranges::MAX_DRAWS as u64)? as usize))
        .transpose()
}

/// A `seed` argument: 1 when not given, else any whole number that fits 64 bits.
pub(crate) fn seed_arg(seed: Option<&Bound<'_, PyAny>>) -> PyResult<u64> {
    seed.filter(|s| !s.is_none())
        .map_or(Ok(1), |s| whole(s, "seed", 0, u64::MAX))
}

/// A whole-number argument in `lo..=hi`, or InputError naming it and the range (never
/// Python's bare OverflowError or TypeError).
pub(crate) fn whole(value: &Bound<'_, PyAny>, name: &str, lo: u64, hi: u64) -> PyResult<u64> {
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
pub(crate) fn threads_arg(threads: Option<&Bound<'_, PyAny>>) -> PyResult<Option<usize>> {
    threads
        .filter(|t| !t.is_none())
        .map(|t| whole(t, "threads", 1, pim_case::ranges::MAX_THREADS as u64).map(|n| n as usize))
        .transpose()
}

/// Runs `f` on a rayon pool of `threads` (default: all cores) without holding the GIL.
pub(crate) fn detached<T: Send>(
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

/// The observer of a study run from Python: the workers record the latest progress, and the
/// calling thread (which holds the interpreter between polls) passes it to the `progress`
/// callback, stops the study when the callback returns a true value, and on Ctrl-C.
struct PyWatch {
    latest: std::sync::Mutex<Option<(u64, u64, String)>>,
    stop: std::sync::atomic::AtomicBool,
}

impl pim_studies::watch::Observer for PyWatch {
    fn progress(&self, done: u64, total: u64, phase: &str) {
        if let Ok(mut l) = self.latest.lock() {
            *l = Some((done, total, phase.to_string()));
        }
    }

    fn cancelled(&self) -> bool {
        self.stop.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// Runs a study on `threads` threads without the interpreter lock, watched: `progress(done,
/// total, phase)` is called from this thread about every 50 ms while it runs (and once at the
/// end); a true return value cancels the study, which then returns what it has (its document
/// says `cancelled`). Ctrl-C cancels it too, and raises `KeyboardInterrupt` once the workers
/// have stopped. An exception in the callback cancels the study and is raised.
pub(crate) fn watched<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    progress: Option<Bound<'_, PyAny>>,
    f: impl FnOnce(&dyn pim_studies::watch::Observer) -> T + Send,
) -> PyResult<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| input_error(format!("threads: {e}")))?;
    let watch = PyWatch {
        latest: std::sync::Mutex::new(None),
        stop: std::sync::atomic::AtomicBool::new(false),
    };
    let mut raised: Option<PyErr> = None;
    let report = |py: Python<'_>, raised: &mut Option<PyErr>| {
        let latest = watch.latest.lock().ok().and_then(|mut l| l.take());
        let answer = match (&progress, latest) {
            (Some(cb), Some((done, total, phase))) => cb.call1((done, total, phase)).map(Some),
            _ => Ok(None),
        };
        let stop = match answer.and_then(|a| a.map_or(Ok(false), |a| a.is_truthy())) {
            Ok(stop) => stop,
            Err(e) => {
                raised.get_or_insert(e);
                true
            }
        };
        if let Err(e) = py.check_signals() {
            raised.get_or_insert(e);
        }
        if stop || raised.is_some() {
            watch.stop.store(true, std::sync::atomic::Ordering::Relaxed);
        }
    };
    let out = std::thread::scope(|s| {
        let handle = s.spawn(|| pool.install(|| f(&watch)));
        while !handle.is_finished() {
            py.detach(|| std::thread::sleep(std::time::Duration::from_millis(50)));
            report(py, &mut raised);
        }
        handle.join()
    });
    report(py, &mut raised);
    let out = out.map_err(|_| input_error("the study stopped on an internal error".to_string()))?;
    match raised {
        Some(e) => Err(e),
        None => Ok(out),
    }
}

/// A `units` argument: `"si"`, `"us"`, `"kmh"` or `None` (the case's own).
pub(crate) fn units_of(units: Option<&str>) -> PyResult<Option<pim_case::units::UnitSystem>> {
    use pim_case::units::UnitSystem;
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

/// The arguments of a study: draws (default 200), seed (default 1), threads.
pub(crate) fn study_args(
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
