//! Diagnostics: every error names where (line, column, length) and what to do.

use std::fmt;

/// A place in the source: 1-based line, 1-based column (in characters), length in characters.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Span {
    pub line: u32,
    pub col: u32,
    pub len: u32,
}

impl Span {
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

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    Warning,
    Error,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Diagnostic {
    pub severity: Severity,
    pub span: Span,
    /// What is wrong, e.g. "arc end point radius differs from start radius by 0.0213 mm".
    pub message: String,
    /// What to do about it, when there is something useful to say.
    pub help: Option<String>,
    /// The firmware's own error number where the dialect has one (grbl's `error:N`).
    pub code: Option<u16>,
}

impl Diagnostic {
    pub fn error(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Error,
            span,
            message: message.into(),
            help: None,
            code: None,
        }
    }

    pub fn warning(span: Span, message: impl Into<String>) -> Diagnostic {
        Diagnostic {
            severity: Severity::Warning,
            span,
            message: message.into(),
            help: None,
            code: None,
        }
    }

    pub fn with_help(mut self, help: impl Into<String>) -> Diagnostic {
        self.help = Some(help.into());
        self
    }

    pub fn with_code(mut self, code: u16) -> Diagnostic {
        self.code = Some(code);
        self
    }

    /// Render like a compiler: `file:line:col: error: message`, the source line, a caret, help.
    pub fn render(&self, file: &str, source_line: Option<&str>) -> String {
        let kind = match self.severity {
            Severity::Warning => "warning",
            Severity::Error => "error",
        };
        let code = self
            .code
            .map(|c| format!("[error:{c}] "))
            .unwrap_or_default();
        let mut s = format!(
            "{file}:{}:{}: {kind}: {code}{}\n",
            self.span.line, self.span.col, self.message
        );
        if let Some(text) = source_line {
            let gutter = format!("{}", self.span.line);
            s.push_str(&format!("{gutter} | {text}\n"));
            let pad: String = text
                .chars()
                .take(self.span.col.saturating_sub(1) as usize)
                .map(|c| if c == '\t' { '\t' } else { ' ' })
                .collect();
            let carets = "^".repeat(self.span.len.max(1) as usize);
            s.push_str(&format!("{} | {pad}{carets}\n", " ".repeat(gutter.len())));
        }
        if let Some(h) = &self.help {
            s.push_str(&format!("  = help: {h}\n"));
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
