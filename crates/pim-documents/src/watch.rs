//! The document types of `watch` (what the study of the same name in pim-studies writes).

use serde::Serialize;

/// A study that was cancelled: what it had done. Its answer is made of those steps alone.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, schemars::JsonSchema)]
pub struct Cancelled {
    /// The phase that was stopped.
    pub phase: String,
    /// Its steps finished (the answer uses these).
    pub done: usize,
    /// Its steps asked for.
    pub asked: usize,
}

impl std::fmt::Display for Cancelled {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "cancelled after {} of {} {}: the answer is made of those alone",
            self.done, self.asked, self.phase
        )
    }
}
