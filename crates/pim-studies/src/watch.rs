//! Watching a study and cancelling it: one observer for every study that takes longer than a
//! moment (the uncertainty studies, the batches, the evidence consistency table).
//!
//! A face passes an [`Observer`]: the command line draws a progress bar from it, the Python
//! package calls back into Python (and cancels on Ctrl-C), the browser streams it. The study
//! reports `done` of `total` steps of a named phase, and asks [`Observer::cancelled`] before
//! each step: once it says yes, no new step starts, the steps running finish, and the study
//! returns promptly with what it has and says so ([`Cancelled`] in its document).

pub use pim_documents::watch::Cancelled;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// What watches a study: progress reports and a way to stop it. Both have defaults, so an
/// observer implements what it needs.
pub trait Observer: Sync {
    /// `done` of `total` steps of `phase` (`"draws"`, `"fits"`, `"cases"`, `"leave-one-out"`)
    /// are finished. Called from the study's worker threads, one call at a time within a phase
    /// and with `done` increasing: the last call of a finished phase says `total` of `total`.
    fn progress(&self, done: u64, total: u64, phase: &str) {
        let _ = (done, total, phase);
    }

    /// True once the study should stop: no new step starts.
    fn cancelled(&self) -> bool {
        false
    }
}

/// No progress, never cancelled.
#[derive(Debug, Clone, Copy, Default)]
pub struct Unwatched;

impl Observer for Unwatched {}

/// A cancel switch that can be shared with another thread (a signal handler, a web request):
/// an observer that reports nothing and stops once [`cancel`](Self::cancel) is called.
#[derive(Debug, Default)]
pub struct CancelSwitch(AtomicBool);

impl CancelSwitch {
    /// Asks the study to stop.
    pub fn cancel(&self) {
        self.0.store(true, Ordering::Relaxed);
    }
}

impl Observer for CancelSwitch {
    fn cancelled(&self) -> bool {
        self.0.load(Ordering::Relaxed)
    }
}

/// A study's side of its observer: one phase of `total` steps.
pub struct Phase<'a> {
    observer: &'a dyn Observer,
    name: &'static str,
    total: u64,
    /// Steps finished: counted and reported under one lock, so that reports go out one at a
    /// time and never backwards, though the workers finish their steps in any order.
    done: Mutex<u64>,
}

impl<'a> Phase<'a> {
    /// Starts a phase of `total` steps (reported as 0 of `total`).
    pub fn start(observer: &'a dyn Observer, name: &'static str, total: usize) -> Self {
        observer.progress(0, total as u64, name);
        Phase {
            observer,
            name,
            total: total as u64,
            done: Mutex::new(0),
        }
    }

    /// True when the observer asks to stop: the caller starts no new step.
    pub fn stopped(&self) -> bool {
        self.observer.cancelled()
    }

    /// One step finished.
    pub fn step(&self) {
        let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
        *done += 1;
        self.observer.progress(*done, self.total, self.name);
    }

    /// Steps finished so far.
    pub fn done(&self) -> u64 {
        *self.done.lock().unwrap_or_else(|e| e.into_inner())
    }

    /// [`Cancelled`] when the observer stopped the phase before its end, else `None`.
    pub fn cancelled(&self) -> Option<Cancelled> {
        let done = self.done();
        (self.stopped() && done < self.total).then(|| Cancelled {
            phase: self.name.to_string(),
            done: done as usize,
            asked: self.total as usize,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Records every report.
    #[derive(Default)]
    struct Recorder(Mutex<Vec<u64>>);

    impl Observer for Recorder {
        fn progress(&self, done: u64, _total: u64, _phase: &str) {
            // A report that takes a moment, so that the workers overtake each other.
            std::thread::yield_now();
            self.0.lock().unwrap().push(done);
        }
    }

    #[test]
    fn steps_finished_in_any_order_are_reported_in_order() {
        let recorder = Recorder::default();
        let phase = Phase::start(&recorder, "draws", 4000);
        std::thread::scope(|s| {
            for _ in 0..8 {
                s.spawn(|| (0..500).for_each(|_| phase.step()));
            }
        });
        let reports = recorder.0.into_inner().unwrap();
        assert_eq!(reports.first(), Some(&0));
        assert_eq!(reports.last(), Some(&4000));
        assert!(reports.windows(2).all(|w| w[0] < w[1]));
    }
}
