//! The error type of pim-studies: input text that cannot be used, with a message that names the
//! file, the line and the field.

/// Bad input: the message names the file, line (where known) and field, e.g.
/// `case.toml: vehicle1.mass: expected a number, got the text "heavy"`.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{message}")]
pub struct InputError {
    /// The file (or other source) the input came from, as given.
    pub file: String,
    /// The whole message, starting with the file.
    pub message: String,
}

impl InputError {
    /// An error about `file`; `what` says where in it and what is wrong.
    pub fn new(file: &str, what: impl std::fmt::Display) -> Self {
        InputError {
            file: file.to_string(),
            message: format!("{file}: {what}"),
        }
    }

    /// An error whose message already names its file (`file:line: ...`).
    pub fn located(file: &str, message: String) -> Self {
        InputError {
            file: file.to_string(),
            message,
        }
    }
}

/// Result alias of pim-studies.
pub type Result<T> = std::result::Result<T, InputError>;
