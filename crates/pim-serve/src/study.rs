//! The uncertainty study of a case, run in the background while the page goes on: its
//! progress polled, cancellable, its document the one `pim uncertainty FILE --format json`
//! writes (the same draws for the same `--draws` and `--seed`).

use crate::AnswerError;
use pim_case::case::Case;
use pim_studies::question::Question;
use pim_studies::watch::Observer;
use std::collections::HashMap;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex};

/// Most draws a study of the page may ask for (the command line takes more).
pub const MAX_DRAWS: usize = 100_000;

/// The uncertainty study of a case's text: for a case with scene evidence the study of its
/// whole reconstruction, otherwise that of its impact fit; the document `pim uncertainty FILE
/// --draws DRAWS --seed SEED --format json` writes. The observer sees each finished draw and
/// can cancel: the draws finished then make the answer, and the document says so. The pieces
/// of evidence named `off` are switched off ([`crate::answer_without`]): the study of the case
/// without them.
///
/// # Errors
/// An invalid case, a name that is no piece of its evidence, or a study that has no answer
/// (nothing uncertain, no reconstruction).
pub fn study(
    file: &str,
    text: &str,
    (draws, seed): (usize, u64),
    off: &[String],
    observer: &dyn Observer,
) -> Result<serde_json::Value, AnswerError> {
    studied(file, text, (draws, seed), (off, None), observer).map(|s| s.document)
}

/// Most draws whose run-outs make a study's bands on the plan.
pub const BAND_DRAWS: usize = 40;

/// A study and the run-outs of its draws on the plan.
#[derive(Debug, Clone)]
pub struct Studied {
    /// The document `pim uncertainty FILE --format json` writes.
    pub document: serde_json::Value,
    /// For a scene case, each vehicle's CG path from the velocities at separation of the first
    /// [`BAND_DRAWS`] feasible draws on the draw's fitted road friction, on the page in `units`
    /// (`[vehicle, points]`): the study's spread of the run-outs, drawn as a band under the
    /// answer's paths.
    pub bands: Vec<crate::answer::VehiclePath>,
}

/// [`study`] with the bands of its run-outs on the plan in `units` (`None`: the case's own).
///
/// # Errors
/// As [`study`].
pub fn studied(
    file: &str,
    text: &str,
    (draws, seed): (usize, u64),
    (off, units): (&[String], Option<pim_case::units::UnitSystem>),
    observer: &dyn Observer,
) -> Result<Studied, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    if !(1..=MAX_DRAWS).contains(&draws) {
        return Err(AnswerError::Input(format!(
            "draws {draws}: must be between 1 and {MAX_DRAWS}"
        )));
    }
    let case = Case::from_text(file, text).map_err(|e| input(&e))?;
    let case = if off.is_empty() {
        case
    } else {
        pim_studies::consistency::switched_off(&case, off).map_err(|e| input(&e))?
    };
    let mut bands = Vec::new();
    let value = match Question::of(&case, None).question {
        Question::Reconstruction => {
            let (study, _) = pim_studies::reconstruct_study::run(
                &case,
                pim_fit::FitModel::Pim,
                pim_core::MomentForm::Corrected,
                pim_fit::MomentBranch::ALL.to_vec(),
                draws,
                seed,
                observer,
            )
            .map_err(|e| input(&e))?;
            // Each draw's run-outs on its own fitted road friction and zone frictions (a
            // vehicle on a surface of its own keeps its stated friction).
            let frictions = study.samples.get("road_friction");
            for (i, sep) in study.separations.iter().take(BAND_DRAWS).enumerate() {
                let mut drawn = case.clone();
                if let Some(mu) = frictions.and_then(|f| f.get(i)) {
                    drawn.set_road_friction(*mu);
                }
                for z in case.zone_frictions() {
                    let fitted = study.samples.get(&format!("zone{}_friction", z.zone + 1));
                    if let Some(mu) = fitted.and_then(|f| f.get(i)) {
                        drawn.set_zone_friction(z.zone, *mu);
                    }
                }
                bands.extend(crate::answer::paths(&drawn, *sep, units).unwrap_or_default());
            }
            serde_json::to_value(&study)
        }
        _ => {
            let unc = case.spreads();
            let study = pim_studies::uncertainty::run(
                &case,
                &unc,
                pim_studies::fitcase::CostChoice::Custom,
                pim_fit::FitSettings::default(),
                draws,
                seed,
                observer,
            )
            .map_err(|e| input(&e))?;
            serde_json::to_value(&study)
        }
    };
    Ok(Studied {
        document: value.map_err(|e| input(&e))?,
        bands,
    })
}

/// The HTML report of a case's text: the page `pim report FILE` writes (its uncertainty study
/// with its default draws and seed when the case says what is uncertain).
///
/// # Errors
/// An invalid case, or one the report cannot be made of.
pub fn report(file: &str, text: &str) -> Result<String, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let case = Case::from_text(file, text).map_err(|e| input(&e))?;
    let made = pim_render::report::make::make(&case, &pim_render::report::make::Options::default())
        .map_err(|e| input(&e))?;
    Ok(made.document.html())
}

/// The plan of the case's reconstruction for CAD (`scene.dxf` of `pim fit --out`), in the
/// display units `units` (`None`: the case's own).
///
/// # Errors
/// Text that is not a valid case, a case without scene evidence, or no reconstruction found.
pub fn scene_dxf(
    file: &str,
    text: &str,
    units: Option<pim_case::units::UnitSystem>,
) -> Result<Vec<u8>, AnswerError> {
    let input = |e: &dyn std::fmt::Display| AnswerError::Input(e.to_string());
    let case = Case::from_text(file, text).map_err(|e| input(&e))?;
    if Question::of(&case, None).question != Question::Reconstruction {
        return Err(AnswerError::Input(format!(
            "{file}: the plan for CAD is a reconstruction's: the case has no scene evidence"
        )));
    }
    let done = pim_studies::consistency::answer(
        &case,
        pim_fit::FitModel::Pim,
        pim_core::MomentForm::Corrected,
        vec![pim_fit::MomentBranch::Free, pim_fit::MomentBranch::Zero],
        &pim_studies::watch::Unwatched,
    )
    .map_err(|e| input(&e))?;
    let units = units.unwrap_or_else(|| pim_case::units::UnitSystem::of(&case.written_units));
    pim_render::cad::reconstruction_dxf(&case, &done, units)?
        .ok_or_else(|| AnswerError::Input(format!("{file}: no reconstruction found to draw")))
}

/// Most studies (or batches) computed at once; the others wait their turn.
pub const RUNNING_AT_ONCE: usize = 2;

/// Most studies waiting for their turn; a study asked for beyond them is refused (the page
/// is told to wait or cancel one).
pub const WAITING_AT_MOST: usize = 6;

/// Most ended studies kept for the page to read (older ones are forgotten, their memory
/// released).
const ENDED_KEPT: usize = 8;

/// The niceness of the studies' threads: a study takes the processor only when the live
/// answers of the page leave it (Linux's scheduler weighs nice 10 about a tenth of nice 0).
const STUDY_NICENESS: i32 = 10;

/// The threads every study and batch of the server computes on: as many as the machine has
/// cores, each at [`STUDY_NICENESS`], apart from the threads that answer the page's edits
/// (tokio's blocking workers and rayon's global pool), so that a study never queues ahead of
/// a live answer.
fn study_pool() -> &'static rayon::ThreadPool {
    static POOL: std::sync::OnceLock<rayon::ThreadPool> = std::sync::OnceLock::new();
    POOL.get_or_init(|| {
        rayon::ThreadPoolBuilder::new()
            .thread_name(|i| format!("pim-study-{i}"))
            .start_handler(|_| {
                // Best effort: where the system refuses, the study runs at normal priority.
                let _ = rustix::process::setpriority_process(
                    Some(rustix::thread::gettid()),
                    STUDY_NICENESS,
                );
            })
            .build()
            .unwrap_or_else(|_| {
                rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .build()
                    .expect("a one-thread pool")
            })
    })
}

/// One study running or run: its progress, its cancel switch and, once ended, its outcome.
#[derive(Debug, Default)]
pub(crate) struct Running {
    done: AtomicU64,
    total: AtomicU64,
    cancel: AtomicBool,
    started: AtomicBool,
    outcome: Mutex<Option<Result<Studied, String>>>,
}

impl Observer for Running {
    fn progress(&self, done: u64, total: u64, _phase: &str) {
        self.done.fetch_max(done, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
    }

    fn cancelled(&self) -> bool {
        self.cancel.load(Ordering::Relaxed)
    }
}

impl Running {
    /// What the page polls: `{id, state, done, total}`, with the `document` once done
    /// (`state` `waiting` for its turn, `running`, `done`, `cancelled` or `failed` with its
    /// `error`).
    pub(crate) fn report(&self, id: u64) -> serde_json::Value {
        let (done, total) = (
            self.done.load(Ordering::Relaxed),
            self.total.load(Ordering::Relaxed),
        );
        let outcome = self.outcome.lock().map(|o| o.clone()).unwrap_or(None);
        match outcome {
            None => {
                let state = if self.started.load(Ordering::Relaxed) {
                    "running"
                } else {
                    "waiting"
                };
                serde_json::json!({ "id": id, "state": state, "done": done, "total": total })
            }
            Some(Ok(Studied { document, bands })) => {
                let state = if document.get("cancelled").is_some_and(|c| !c.is_null()) {
                    "cancelled"
                } else {
                    "done"
                };
                let bands: Vec<serde_json::Value> = bands
                    .iter()
                    .map(|(vehicle, path)| serde_json::json!({ "vehicle": vehicle, "path": path }))
                    .collect();
                serde_json::json!({
                    "id": id, "state": state, "done": done, "total": total, "document": document,
                    "bands": bands,
                })
            }
            Some(Err(error)) => {
                let state = if self.cancelled() {
                    "cancelled"
                } else {
                    "failed"
                };
                serde_json::json!({
                    "id": id, "state": state, "done": done, "total": total, "error": error,
                })
            }
        }
    }

    /// Asks the study to stop: no new draw starts (a study still waiting never starts).
    pub(crate) fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    fn ended(&self) -> bool {
        self.outcome.lock().is_ok_and(|o| o.is_some())
    }
}

/// A study refused because [`RUNNING_AT_ONCE`] are running and [`WAITING_AT_MOST`] waiting.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Busy;

/// The studies of a server, by number.
#[derive(Debug, Default)]
pub(crate) struct Studies {
    next: AtomicU64,
    running: Mutex<HashMap<u64, Arc<Running>>>,
    /// How many are computing now, and the signal of a turn freed.
    turns: Arc<(Mutex<usize>, std::sync::Condvar)>,
}

impl Studies {
    /// Starts a study in the background (the page's answers go on meanwhile); its number.
    pub(crate) fn start(
        &self,
        (path, text): (String, String),
        (draws, seed): (usize, u64),
        (off, units): (Vec<String>, Option<pim_case::units::UnitSystem>),
    ) -> Result<u64, Busy> {
        self.start_job(move |run| {
            studied(&path, &text, (draws, seed), (&off, units), run).map_err(|e| e.to_string())
        })
    }

    /// Starts a job in the background (a study or a batch): its number, to poll and cancel it
    /// by. It waits its turn behind [`RUNNING_AT_ONCE`] others and computes on the studies'
    /// own threads; refused when [`WAITING_AT_MOST`] already wait.
    pub(crate) fn start_job(
        &self,
        job: impl FnOnce(&Running) -> Result<Studied, String> + Send + 'static,
    ) -> Result<u64, Busy> {
        let run = Arc::new(Running::default());
        let id = {
            let Ok(mut m) = self.running.lock() else {
                return Err(Busy);
            };
            if m.values().filter(|r| !r.ended()).count() >= RUNNING_AT_ONCE + WAITING_AT_MOST {
                return Err(Busy);
            }
            // The last few ended studies are kept; older ones are forgotten.
            let mut ended: Vec<u64> = m
                .iter()
                .filter(|(_, r)| r.ended())
                .map(|(k, _)| *k)
                .collect();
            ended.sort_unstable();
            for k in ended.iter().rev().skip(ENDED_KEPT - 1) {
                m.remove(k);
            }
            let id = self.next.fetch_add(1, Ordering::Relaxed) + 1;
            m.insert(id, run.clone());
            id
        };
        let turns = self.turns.clone();
        std::thread::spawn(move || {
            let (count, freed) = &*turns;
            {
                let mut n = count.lock().unwrap_or_else(|e| e.into_inner());
                while *n >= RUNNING_AT_ONCE && !run.cancelled() {
                    n = freed
                        .wait_timeout(n, std::time::Duration::from_millis(100))
                        .unwrap_or_else(|e| e.into_inner())
                        .0;
                }
                if run.cancelled() {
                    drop(n);
                    if let Ok(mut o) = run.outcome.lock() {
                        *o = Some(Err("cancelled before it started".to_string()));
                    }
                    return;
                }
                *n += 1;
            }
            run.started.store(true, Ordering::Relaxed);
            let outcome = study_pool().install(|| job(run.as_ref()));
            if let Ok(mut o) = run.outcome.lock() {
                *o = Some(outcome);
            }
            *count.lock().unwrap_or_else(|e| e.into_inner()) -= 1;
            freed.notify_all();
        });
        Ok(id)
    }

    /// The study numbered `id`.
    pub(crate) fn get(&self, id: u64) -> Option<Arc<Running>> {
        self.running.lock().ok()?.get(&id).cloned()
    }
}
