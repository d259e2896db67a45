//! One error type for the application layer: a message that names the input and the fix.

use std::fmt;

#[derive(Clone, Debug, PartialEq)]
/// An error of the application layer, in words.
pub struct Error(pub String);

/// The message of a job stopped by its cancel flag.
pub const CANCELLED: &str = "cancelled";

impl Error {
    /// The message of anything displayable.
    pub fn from_display(e: impl fmt::Display) -> Error {
        Error(e.to_string())
    }

    /// `e` and its sources, `outer: inner: …` (the way the CLI has always printed errors).
    pub fn chain(e: &dyn std::error::Error) -> Error {
        let mut text = e.to_string();
        let mut source = e.source();
        while let Some(s) = source {
            text.push_str(": ");
            text.push_str(&s.to_string());
            source = s.source();
        }
        Error(text)
    }

    /// The error of a cancelled job.
    pub fn cancelled() -> Error {
        Error(CANCELLED.into())
    }

    /// True for the error of a cancelled job.
    pub fn is_cancelled(&self) -> bool {
        self.0 == CANCELLED
    }

    /// The parameter a message names by its command-line flag (`--safe-z 3: …` → `safe_z`),
    /// so a form can show the message beside that field.
    pub fn field(&self) -> Option<String> {
        let flag = self.0.strip_prefix("--")?;
        let end = flag
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
            .unwrap_or(flag.len());
        (end > 0).then(|| flag[..end].replace('-', "_"))
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Error {}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_come_from_the_flag_a_message_starts_with() {
        assert_eq!(
            Error("--safe-z 3 must be at or above --clear-z 5".into()).field(),
            Some("safe_z".into())
        );
        assert_eq!(
            Error("--shrink 40 %: use 0 to 20".into()).field(),
            Some("shrink".into())
        );
        assert_eq!(Error("a.svg: no paths".into()).field(), None);
        assert_eq!(Error("-- x".into()).field(), None);
    }
}
