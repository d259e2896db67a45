//! One error type for the application layer: a message that names the input and the fix.

use std::fmt;

#[derive(Clone, Debug, PartialEq)]
pub struct Error(pub String);

impl Error {
    pub fn from_display(e: impl fmt::Display) -> Error {
        Error(e.to_string())
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}
