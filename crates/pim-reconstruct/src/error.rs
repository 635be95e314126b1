//! The error type of pim-reconstruct.

/// Input a reconstruction cannot use. A scene that no admissible impact reaches is not an
/// error: it is an [`Outcome`](crate::Outcome) with status
/// [`Status::NoSolution`](crate::Status::NoSolution) and the reason.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReconstructError {
    /// A field of the reconstruction has a value the search cannot use.
    #[error("{field}: {reason}")]
    Input {
        /// The field (`scene`, `final`, `distance`, ...).
        field: &'static str,
        /// What is wrong with it and what is accepted.
        reason: String,
    },
    /// A vehicle, start or evidence the run-out model cannot use.
    #[error(transparent)]
    Runout(#[from] pim_runout::RunoutError),
    /// The impact fit's problem or settings are invalid.
    #[error(transparent)]
    Fit(#[from] pim_fit::FitError),
}

/// Result alias of pim-reconstruct.
pub type Result<T> = std::result::Result<T, ReconstructError>;
