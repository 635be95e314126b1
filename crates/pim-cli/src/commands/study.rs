//! What both uncertainty studies of the command share (of a fit case and of a scene case): the
//! thread pool and progress bar of the draws, and the line of dominant inputs.

use crate::args::{Format, UncertaintyArgs};
use crate::error::Failure;
use anyhow::Result;
use pim_studies::uncertainty::Sensitivity;

/// A progress bar as a study's observer: it shows the study's phase and its steps done.
pub struct Bar(pub indicatif::ProgressBar);

impl Bar {
    /// A bar on standard error when `show` and standard error is a terminal, else hidden.
    pub fn on_terminal(show: bool) -> Self {
        Bar(
            if show && std::io::IsTerminal::is_terminal(&std::io::stderr()) {
                indicatif::ProgressBar::new(0)
            } else {
                indicatif::ProgressBar::hidden()
            },
        )
    }

    /// Until the first phase with steps begins: a spinner saying `what` is being done, with the
    /// time it has taken (a search that cannot count its steps ahead: a realistic scene's
    /// takes seconds).
    pub fn searching(&self, what: &str) {
        if self.0.is_hidden() {
            return;
        }
        if let Ok(style) = indicatif::ProgressStyle::with_template("{spinner} {msg} ({elapsed})") {
            self.0.set_style(style);
        }
        self.0.set_message(what.to_string());
        // No length: the first phase's steps give it, and the bar's style with it.
        self.0.set_length(0);
        self.0
            .enable_steady_tick(std::time::Duration::from_millis(120));
    }
}

impl pim_studies::watch::Observer for Bar {
    fn progress(&self, done: u64, total: u64, phase: &str) {
        if self.0.length() != Some(total) {
            self.0.set_length(total);
            if let Ok(style) =
                indicatif::ProgressStyle::with_template("{msg} {wide_bar} {pos}/{len} ({elapsed})")
            {
                self.0.set_style(style);
            }
        }
        self.0.set_position(done);
        self.0.set_message(phase.to_string());
    }
}

/// A bar that several calls of a study fill one after the other: a call's steps are shown
/// after the `before` steps of the calls before it.
pub struct Offset<'a> {
    /// The bar.
    pub bar: &'a Bar,
    /// Steps done before this call.
    pub before: u64,
}

impl pim_studies::watch::Observer for Offset<'_> {
    fn progress(&self, done: u64, _total: u64, _phase: &str) {
        self.bar.0.set_position(self.before + done);
    }
}

/// The three inputs that dominate a quantity, with their first-order indices.
pub fn dominant(sens: &Sensitivity) -> String {
    let list: Vec<String> = sens
        .inputs
        .iter()
        .take(3)
        .map(|(n, v)| format!("{n} {v:.2}"))
        .collect();
    if list.is_empty() {
        "none above 0.02".to_string()
    } else {
        list.join("; ")
    }
}

/// The thread pool of `--threads` and the progress bar of the draws (shown for a table on a
/// terminal).
pub fn pool_and_bar(a: &UncertaintyArgs) -> Result<(rayon::ThreadPool, indicatif::ProgressBar)> {
    let show = a.format == Format::Table && std::io::IsTerminal::is_terminal(&std::io::stderr());
    let bar = if show {
        let b = indicatif::ProgressBar::new(a.draws as u64);
        b.set_message("refitting draws");
        b
    } else {
        indicatif::ProgressBar::hidden()
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(a.threads.unwrap_or(0))
        .build()
        .map_err(|e| Failure::Input(format!("--threads: {e}")))?;
    Ok((pool, bar))
}
