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

/// Why a combination of counts has no point to refine from, or a step none: not an error of
/// the input but an outcome ([`crate::Tried::NoImpact`] gives its message as the reason).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(crate) enum NoPoint {
    /// The impact fit of the linearised problem refused it.
    #[error(transparent)]
    Fit(#[from] pim_fit::FitError),
    /// No moment branch has an admissible impact (the first branch's reason).
    #[error("{0}")]
    NoImpact(String),
    /// The impact fit ended without an optimum.
    #[error("the impact fit ended {0:?}")]
    Ended(pim_fit::Status),
    /// A run-out of the fitted separation state failed.
    #[error("the run-out of the fitted separation state failed")]
    Runout,
    /// A run-out could not be differentiated.
    #[error(transparent)]
    Differentiated(#[from] ReconstructError),
    /// A candidate of a scene's run-out could not be linearised.
    #[error("a candidate's run-out could not be linearised")]
    Unlinearised,
}

/// Result alias of pim-reconstruct.
pub type Result<T> = std::result::Result<T, ReconstructError>;
