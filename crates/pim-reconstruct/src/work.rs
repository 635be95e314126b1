//! The budget of work a search spends: counted in run-out right-hand side evaluations, never
//! timed.

use crate::point::Lin;

/// The work of the refinements, in run-out right-hand side evaluations and their equivalents
/// for the impact fits: counted, never timed, so that a budget ends the same refinements on
/// every machine ([`crate::Settings::refine_work`]).
pub(crate) struct Work {
    spent: std::sync::atomic::AtomicU64,
    limit: u64,
}

impl Work {
    pub(crate) fn new(limit: u64) -> Self {
        Work {
            spent: std::sync::atomic::AtomicU64::new(0),
            limit,
        }
    }

    pub(crate) fn add(&self, n: u64) {
        self.spent
            .fetch_add(n, std::sync::atomic::Ordering::Relaxed);
    }

    /// Charges a linearisation's run-outs (a failed one by the evaluations it spent).
    pub(crate) fn charge(&self, l: crate::Result<Lin>) -> crate::Result<Lin> {
        self.add(match &l {
            Ok(l) => l.lin.evaluations,
            Err(crate::ReconstructError::Runout(pim_runout::RunoutError::Integration {
                evaluations,
                ..
            })) => *evaluations,
            Err(_) => 1,
        });
        l
    }

    pub(crate) fn spent(&self) -> u64 {
        self.spent.load(std::sync::atomic::Ordering::Relaxed)
    }

    /// What is left of the budget.
    pub(crate) fn left(&self) -> u64 {
        self.limit.saturating_sub(self.spent())
    }

    pub(crate) fn exhausted(&self) -> bool {
        self.spent() > self.limit
    }

    /// A share of what is left for one refinement: at most a third of the whole budget, so
    /// that one combination crawling along a curved valley (or refined far from its scenes)
    /// leaves the others their turn; the refinement's spending is added back with
    /// [`Work::add`].
    pub(crate) fn share(&self) -> Work {
        Work::new((self.limit / 3).min(self.limit.saturating_sub(self.spent())))
    }
}
