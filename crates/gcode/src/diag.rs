//! Diagnostics: every error names where (line, column, length) and what to do.

use std::fmt;

/// A place in the source: 1-based line, 1-based column (in characters), length in characters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    /// 1-based line.
    pub line: u32,
    /// 1-based column (in characters).
    pub col: u32,
    /// Length in columns (0 for a point).
    pub len: u32,
}

impl Span {
    /// The span of `len` columns from `col` on `line`.
    pub fn new(line: u32, col: u32, len: u32) -> Span {
        Span { line, col, len }
    }

    /// The whole of `line` (column 1, no length): for errors about a block as a whole.
    pub fn line(line: u32) -> Span {
        Span {
            line,
            col: 1,
            len: 0,
        }
    }
}

/// How bad a diagnostic is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    /// Information: what will happen to the line (a sender that handles it, say).
    Note,
    /// The program runs on; something deserves a look.
    Warning,
    /// The program (or the block, in check mode) cannot run.
    Error,
}

/// A message about the program, with where it applies.
#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    /// Warning or error.
    pub severity: Severity,
    /// Where in the source it applies.
    pub span: Span,
    /// What is wrong, e.g. "arc end point radius differs from start radius by 0.0213 mm".
    pub message: String,
    /// What to do about it, when there is something useful to say.
    pub help: Option<String>,
    /// The firmware's own error number where the dialect has one (grbl's `error:N`).
    pub code: Option<u16>,
}

impl Diagnostic {
    /// An error at `span`.
    pub fn error(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            span,
            message: message.into(),
            help: None,
            code: None,
        }
    }

    /// A warning at `span`.
    pub fn warning(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            span,
            message: message.into(),
            help: None,
            code: None,
        }
    }

    /// A note at `span`: not a fault, what will happen there.
    pub fn note(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Note,
            span,
            message: message.into(),
            help: None,
            code: None,
        }
    }

    /// The same diagnostic with a hint on how to fix it.
    pub fn with_help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    /// The same diagnostic with a numeric code (grbl's error number).
    pub fn with_code(mut self, code: u16) -> Diagnostic {
        self.code = Some(code);
        self
    }

    /// Render like a compiler: `file:line:col: error: message`, the source line, a caret, help.
    /// At most [`crate::text::QUOTE_WIDTH`] columns of the line are quoted, around the place,
    /// and control characters are escaped, so whatever the file holds fits a terminal.
    pub fn render(&self, file: &str, source_line: Option<&str>) -> String {
        use crate::text::{escape, quote};
        // A firmware code reads like rustc's `error[E0308]`: "error" is said once.
        let kind = match (self.severity, self.code) {
            (Severity::Note, _) => "note".to_string(),
            (Severity::Warning, None) => "warning".to_string(),
            (Severity::Error, None) => "error".to_string(),
            (Severity::Warning, Some(c)) => format!("warning[grbl:{c}]"),
            (Severity::Error, Some(c)) => format!("error[grbl:{c}]"),
        };
        let mut s = format!(
            "{}:{}:{}: {kind}: {}\n",
            escape(file),
            self.span.line,
            self.span.col,
            escape(&self.message)
        );
        if let Some(text) = source_line {
            let q = quote(text, self.span.col, self.span.len);
            let gutter = format!("{}", self.span.line);
            s.push_str(&format!("{gutter} | {}\n", q.text));
            s.push_str(&format!(
                "{} | {}{}\n",
                " ".repeat(gutter.len()),
                " ".repeat(q.pad),
                "^".repeat(q.width)
            ));
        }
        if let Some(h) = &self.help {
            s.push_str(&format!("  = help: {}\n", escape(h)));
        }
        s
    }
}

impl fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}: {}", self.span.line, self.span.col, self.message)
    }
}

impl std::error::Error for Diagnostic {}
