//! A batch of case files (`pim batch DIR`): every file answered under every cost choice, in
//! parallel, and the counts a summary reports. The caller reads the files (this crate does no
//! I/O) and writes the records as they come.

use crate::batch::{BatchPlan, Outcome};
use crate::batch_scene::{add_intervals, case_records};
use crate::case_records::CaseRecord;
use crate::fitcase::CostChoice;
use crate::watch::{Observer, Phase};
use rayon::prelude::*;
use std::collections::BTreeMap;

/// One file of the batch: its name and its text, or why it could not be read (it then gives
/// failed records, like a file that does not parse, and the batch goes on).
#[derive(Debug, Clone)]
pub struct CaseText {
    /// The file's name, as the records name it.
    pub name: String,
    /// Its content, or the reason it could not be read.
    pub text: Result<String, String>,
}

/// What a batch of case files asks: the cost choices every file is answered under (a file's own
/// cost is [`CostChoice::Custom`]), the plan, and with `draws > 0` the intervals of each best
/// record (`draws` draws from `seed`).
#[derive(Debug, Clone)]
pub struct CaseBatch {
    /// The cost choices.
    pub choices: Vec<CostChoice>,
    /// The fit settings, branches and conditions.
    pub plan: BatchPlan,
    /// Draws of the intervals (0: none).
    pub draws: usize,
    /// Their seed.
    pub seed: u64,
}

impl CaseBatch {
    /// The records of each file, in the files' order (each file's records in cost, then branch
    /// order), answered in parallel. The observer sees each finished file (phase `case files`)
    /// and can cancel: the files not started then give no records.
    pub fn records(&self, files: &[CaseText], observer: &dyn Observer) -> Vec<Vec<CaseRecord>> {
        let phase = Phase::start(observer, "case files", files.len());
        files
            .par_iter()
            .map(|f| {
                if phase.stopped() {
                    return Vec::new();
                }
                let out = self.file_records(f);
                phase.step();
                out
            })
            .collect()
    }

    fn file_records(&self, f: &CaseText) -> Vec<CaseRecord> {
        match &f.text {
            Ok(text) => self
                .choices
                .iter()
                .flat_map(|&c| {
                    let mut recs = case_records(&f.name, text, c, &self.plan);
                    if self.draws > 0 {
                        if let Some(best) = recs.iter_mut().find(|r| r.best) {
                            add_intervals(best, text, &self.plan, self.draws, self.seed);
                        }
                    }
                    recs
                })
                .collect(),
            Err(e) => self
                .choices
                .iter()
                .flat_map(|&c| self.plan.branches.iter().map(move |&m| (c, m)))
                .map(|(c, m)| CaseRecord::failed(&f.name, c, m, Some(e.clone())))
                .collect(),
        }
    }
}

/// The counts of a batch's summary, added to as the records come.
#[derive(Debug, Clone, Default)]
pub struct Tally {
    /// Records by cost function and outcome.
    pub by_cost: BTreeMap<String, BTreeMap<String, usize>>,
    /// Records.
    pub records: usize,
    /// Records without a solution.
    pub unsolved: usize,
    /// Files none of whose records has an answer.
    pub files_failed: usize,
    /// Each file that could not be read or fitted, with its reason.
    pub failed: Vec<String>,
    /// Records without the intervals `--draws` asked for, with the reason (e.g. nothing in the
    /// case is uncertain).
    pub no_intervals: Vec<String>,
    /// What in the files had no effect (each once).
    pub notes: Vec<String>,
}

impl Tally {
    /// Adds one file's records; the reasons it failed, when it did (each names the file, and
    /// the line and field), to report as they come.
    pub fn add_file(&mut self, records: &[CaseRecord]) -> Vec<String> {
        let mut reasons: Vec<String> = Vec::new();
        if records.iter().all(|r| r.outcome == Outcome::Failed) {
            self.files_failed += 1;
            for why in records.iter().filter_map(|r| r.error.as_deref()) {
                if reasons.last().map(String::as_str) != Some(why) {
                    reasons.push(why.to_string());
                }
            }
            self.failed.extend(reasons.iter().cloned());
        }
        for r in records {
            self.add(r);
        }
        reasons
    }

    fn add(&mut self, r: &CaseRecord) {
        *self
            .by_cost
            .entry(r.cost_function.name().to_string())
            .or_default()
            .entry(r.outcome.to_string())
            .or_default() += 1;
        self.records += 1;
        if !r.outcome.solved() {
            self.unsolved += 1;
        }
        if let Some(why) = &r.intervals_error {
            self.no_intervals.push(why.clone());
        }
        for n in &r.notes {
            if !self.notes.contains(n) {
                self.notes.push(n.clone());
            }
        }
    }
}
