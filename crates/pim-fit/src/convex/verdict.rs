//! What the convex route decided for a branch, and what it did.

use crate::certificate::Fallback;
use crate::inner::{At, Candidate};

/// What the convex solve of a branch found.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Verdict {
    /// The global optimum of the branch.
    Optimal {
        at: At,
        candidate: Candidate,
        counts: Counts,
    },
    /// No point of the branch is feasible: every sign pattern of every e_m interval is empty
    /// (the patterns together contain the feasible set).
    Infeasible { counts: Counts },
    /// The general search must decide (see the module documentation), with the reason.
    Search(Fallback),
}

/// What the convex solve did, for the certificate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub(crate) struct Counts {
    /// Sign patterns of the branch.
    pub patterns: usize,
    /// Patterns solved to their optimum.
    pub solved: usize,
    /// Patterns stopped by their lower bound or found empty.
    pub pruned: usize,
    /// e_m intervals solved (1 in the zero branch).
    pub intervals: usize,
}
