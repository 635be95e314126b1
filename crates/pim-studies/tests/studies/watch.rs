//! One observer for every study: progress reported step by step and never backwards, and a cancelled study returns
//! promptly with the steps it finished and says so, while a watched study that is not cancelled
//! gives exactly the answer of an unwatched one.

use pim_case::case::Case;
use pim_studies::watch::{Observer, Unwatched};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

fn case() -> Case {
    let p = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/cases/ricsac7_uncertainty.toml"
    );
    Case::from_text(
        "ricsac7_uncertainty.toml",
        &std::fs::read_to_string(p).unwrap(),
    )
    .unwrap()
}

fn study(draws: usize, observer: &dyn Observer) -> pim_studies::uncertainty::Study {
    let case = case();
    pim_studies::uncertainty::run(
        &case,
        &case.spreads(),
        pim_studies::fitcase::CostChoice::Preset(pim_fit::CostPreset::Q2),
        pim_fit::FitSettings::default(),
        draws,
        1,
        observer,
    )
    .unwrap()
}

/// Records every report; cancels once `stop_after` steps are done.
struct Recorder {
    reports: Mutex<Vec<(u64, u64, String)>>,
    done: AtomicU64,
    stop_after: u64,
}

impl Recorder {
    fn new(stop_after: u64) -> Self {
        Recorder {
            reports: Mutex::new(Vec::new()),
            done: AtomicU64::new(0),
            stop_after,
        }
    }
}

impl Observer for Recorder {
    fn progress(&self, done: u64, total: u64, phase: &str) {
        self.done.fetch_max(done, Ordering::Relaxed);
        self.reports
            .lock()
            .unwrap()
            .push((done, total, phase.to_string()));
    }

    fn cancelled(&self) -> bool {
        self.done.load(Ordering::Relaxed) >= self.stop_after
    }
}

#[test]
fn progress_is_reported_in_order_and_watching_changes_nothing() {
    let r = Recorder::new(u64::MAX);
    let watched = study(30, &r);
    // Reported as they arrive: in increasing order (a step that finishes after a later one is
    // covered by the later report), from 0 to every draw done.
    let reports = r.reports.into_inner().unwrap();
    assert_eq!(reports.first(), Some(&(0, 30, "draws".to_string())));
    assert_eq!(reports.last(), Some(&(30, 30, "draws".to_string())));
    assert!(reports.windows(2).all(|w| w[0].0 < w[1].0), "{reports:?}");
    assert!(reports
        .iter()
        .all(|(_, total, phase)| *total == 30 && phase == "draws"));
    assert!(watched.cancelled.is_none());
    assert_eq!(watched, study(30, &Unwatched));
}

#[test]
fn a_cancelled_study_returns_the_draws_it_finished() {
    let asked = 1_000_000;
    let r = Recorder::new(5);
    let s = study(asked, &r);
    let c = s.cancelled.clone().expect("cancelled");
    assert_eq!((c.asked, c.phase.as_str()), (asked, "draws"));
    // The draws in flight when it was cancelled finish (one per thread).
    assert!(
        c.done >= 5 && c.done <= 5 + rayon::current_num_threads(),
        "{c:?}"
    );
    assert_eq!(s.draws, c.done);
    assert!(s.feasible_draws <= s.draws && !s.quantities.is_empty());
    let json = serde_json::to_value(&s).unwrap();
    assert_eq!(json["cancelled"]["done"], c.done);
    assert!(c
        .to_string()
        .starts_with(&format!("cancelled after {} of {asked} draws", c.done)));
}

#[test]
fn a_study_cancelled_before_it_starts_makes_no_draw() {
    let switch = pim_studies::watch::CancelSwitch::default();
    switch.cancel();
    let s = study(50, &switch);
    assert_eq!(s.draws, 0);
    assert_eq!(s.cancelled.unwrap().done, 0);
}
