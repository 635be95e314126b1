//! The error type of pim-fit: a problem or settings that cannot be fitted at all.

/// Invalid fit problems and settings. Infeasible data are not errors: they are a
/// [`crate::Status`] of a successful fit.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FitError {
    /// The collision or a velocity value is invalid (message from pim-core).
    #[error(transparent)]
    Core(#[from] pim_core::PimError),
    /// A weight is not in (0, 1].
    #[error("{what}: weight {value} must be in (0, 1]")]
    BadWeight {
        /// Which estimate or observation.
        what: String,
        /// The weight.
        value: f64,
    },
    /// A target value is not finite, or beyond any plausible size (|value| > 1e4).
    #[error("{what}: value {value} is not a finite number of plausible size (|value| <= 1e4)")]
    NonFinite {
        /// Which estimate or observation.
        what: String,
        /// The value.
        value: f64,
    },
    /// A bound is malformed.
    #[error("bounds: {0}")]
    BadBounds(String),
    /// Nothing is estimated or observed: there is nothing to fit.
    #[error("nothing to fit: no velocity component is estimated and no observation is given")]
    NothingToFit,
    /// More components are held fixed than the equations can accept.
    #[error("{0}")]
    OverDetermined(String),
    /// Data about a fixed barrier, which does not move.
    #[error("{0}")]
    Barrier(String),
}

/// Result alias of pim-fit.
pub type Result<T> = std::result::Result<T, FitError>;
