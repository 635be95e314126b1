//! The error type of pim-runout.

/// What can go wrong before or during a run-out.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RunoutError {
    /// A field of the vehicle, the start or the evidence has a value the model cannot use.
    #[error("{field}: {reason}")]
    Input {
        /// The field, as named in the case file (`wheelbase`, `friction`, `rest.x`, ...).
        field: &'static str,
        /// What is wrong with it and what is accepted.
        reason: String,
    },
    /// The integrator gave up (step-size underflow or its step limit) before the vehicle came
    /// to rest or the time limit was reached.
    #[error("the integration of the run-out failed at t = {time} s: {reason}")]
    Integration {
        /// Time reached, s.
        time: f64,
        /// The integrator's reason.
        reason: String,
        /// Right-hand side evaluations spent before it gave up (at least six per accepted step):
        /// the work of a failed run-out, for a caller that budgets work.
        evaluations: u64,
    },
}

/// Result alias of pim-runout.
pub type Result<T> = std::result::Result<T, RunoutError>;
