//! A program checked as grbl firmware will receive it from Oficina's sender: `M6` (and the
//! `%` tape marks) are what the sender handles under its tool-change policy, so the check
//! reads the sender's view ([`oficina_grbl::sender_view`]) and says in a note what happens
//! on each such line, instead of grbl's refusal of `M6`.

use crate::check::{check_program_with_tools, CheckOptions, CheckReport, Diag};
use oficina_gcode::ToolTable;
use oficina_grbl::{sender_view, ToolChange};
use std::sync::Arc;

/// [`check_program_with_tools`] of what the sender streams under `tc`, with its notes.
pub fn check_for_sender(
    text: &Arc<String>,
    opts: &CheckOptions,
    tools: &ToolTable,
    tc: &ToolChange,
) -> CheckReport {
    let (view, notes) = sender_view(text.as_bytes(), tc);
    // Only ASCII words and marks are blanked: the view stays UTF-8 (else check the text as is).
    let view = String::from_utf8(view).map_or_else(|_| text.clone(), Arc::new);
    let mut report = check_program_with_tools(&view, opts, tools);
    report
        .diagnostics
        .extend(notes.into_iter().filter(|n| !n.message.is_empty()).map(|n| Diag {
            line: n.line,
            col: n.col,
            len: n.len,
            severity: "note",
            message: n.message,
            help: None,
        }));
    report.diagnostics.sort_by_key(|d| (d.line, d.col));
    report
}

#[cfg(test)]
mod tests {
    use super::*;
    use oficina_gcode::Dialect;

    #[test]
    fn m6_is_a_note_under_pause_and_an_error_as_written() {
        let text = Arc::new("G21 G90\nT2 M6\nG0 X1\nM2\n".to_string());
        let opts = CheckOptions {
            profile: crate::profile::resolve(crate::profile::DEFAULT).unwrap(),
            dialect: Dialect::Grbl,
        };
        let r = check_for_sender(&text, &opts, &ToolTable::default(), &ToolChange::default());
        assert_eq!(r.errors, 0, "{:?}", r.diagnostics);
        let note = r.diagnostics.iter().find(|d| d.severity == "note").unwrap();
        assert_eq!(note.line, 2);
        assert!(note.message.contains("pauses"), "{}", note.message);
        let r = check_for_sender(&text, &opts, &ToolTable::default(), &ToolChange::as_written());
        assert!(r.errors > 0, "{:?}", r.diagnostics);
    }
}
