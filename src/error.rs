//! The one error type of the crate.
//!
//! Every function that takes user input returns `Result<_, Error>`. An error names the offending
//! field with its path in the scenario JSON (`model.V`, `alpha`, `simulate.steps`, …) and says
//! why, so the CLI and the page can show it as is: "model.V must be symmetric positive
//! semidefinite (smallest eigenvalue −0.5)".

use std::fmt;

/// A rejected input or a computation that cannot go on, with the field it concerns.
#[derive(Debug, Clone, PartialEq)]
pub struct Error {
    /// Path of the offending field in the scenario (`model.F`, `alpha`, …), or `""` when the
    /// error is not about one field.
    pub field: String,
    /// What is wrong, in words a user can act on.
    pub message: String,
}

impl Error {
    /// An error about `field`.
    pub fn field(field: impl Into<String>, message: impl Into<String>) -> Self {
        Error {
            field: field.into(),
            message: message.into(),
        }
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.field.is_empty() {
            write!(f, "{}", self.message)
        } else {
            write!(f, "{} {}", self.field, self.message)
        }
    }
}

impl std::error::Error for Error {}

/// Result with the crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;
