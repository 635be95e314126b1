//! Why a case has no answer to show.

/// Why a case has no answer to show.
#[derive(Debug, thiserror::Error)]
pub enum AnswerError {
    /// The text is not a valid case (the message names the file, line and field).
    #[error("{0}")]
    Input(String),
    /// The case is valid but its question cannot be answered here yet.
    #[error("{0}")]
    Unsupported(String),
    /// A figure or drawing of the answer could not be made.
    #[error(transparent)]
    Render(#[from] pim_render::RenderError),
}
