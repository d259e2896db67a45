//! A program ready to stream: each line cleaned as grbl would clean it (fewer bytes on the
//! wire, exact character counts) and tied to its line number in the file, so every report
//! can name the line the user sees in the editor.

use crate::gline;
use crate::toolchange::{ToolChange, ToolStop};

/// One line to send, with where it came from.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamLine {
    /// 1-based line number in the source file.
    pub file_line: usize,
    /// What is sent (without the newline).
    pub text: String,
}

/// A program cleaned for streaming to grbl (not `oficina_machine::Job`, which is a program
/// and its pace handed to any machine).
#[derive(Clone, Debug, PartialEq)]
pub struct StreamProgram {
    /// The name for reports (usually the file name).
    pub name: String,
    /// The lines to send, in order.
    pub lines: Vec<StreamLine>,
    /// How its `M6` lines are handled ([`StreamProgram::with_tool_change`]); by default they
    /// go to the firmware as written.
    pub tool_change: ToolChange,
    /// Where the sender stops for a tool change: before these lines, in order.
    pub tool_stops: Vec<ToolStop>,
}

impl StreamProgram {
    /// Cleans every line; empty lines, comments and `%` tape marks are dropped. A line that
    /// cannot fit grbl's line buffer is an error naming the file line.
    pub fn from_text(name: &str, text: &str) -> Result<StreamProgram, String> {
        let mut lines = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let clean = gline::clean(raw).map_err(|_| {
                format!("{name}:{}: line is longer than grbl's {}-character line buffer after removing spaces and comments", i + 1, gline::MAX_LINE)
            })?;
            if clean.is_empty() || clean == "%" {
                continue;
            }
            lines.push(StreamLine {
                file_line: i + 1,
                text: clean,
            });
        }
        Ok(StreamProgram {
            name: name.to_string(),
            lines,
            tool_change: ToolChange::default(),
            tool_stops: Vec::new(),
        })
    }

    /// Lines to send.
    pub fn len(&self) -> usize {
        self.lines.len()
    }

    /// No line to send.
    pub fn is_empty(&self) -> bool {
        self.lines.is_empty()
    }

    /// Index of the first job line at or after `file_line` (for "resume from line N").
    pub fn index_of_file_line(&self, file_line: usize) -> Option<usize> {
        self.lines.iter().position(|l| l.file_line >= file_line)
    }

    /// FNV-1a of the sent text, so a journal is never applied to a different program.
    pub fn fingerprint(&self) -> u64 {
        let mut h: u64 = 0xcbf29ce484222325;
        for l in &self.lines {
            for b in l.text.bytes().chain(std::iter::once(b'\n')) {
                h ^= b as u64;
                h = h.wrapping_mul(0x100000001b3);
            }
        }
        h
    }

    /// Bytes on the wire for the lines `from..`.
    pub fn bytes_from(&self, from: usize) -> usize {
        self.lines.iter().skip(from).map(|l| l.text.len() + 1).sum()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_file_lines() {
        let j =
            StreamProgram::from_text("a.nc", "%\n(header)\nG21 G90\n\ng1 x1 ; cut\n%\n").unwrap();
        assert_eq!(
            j.lines,
            vec![
                StreamLine {
                    file_line: 3,
                    text: "G21G90".into()
                },
                StreamLine {
                    file_line: 5,
                    text: "G1X1".into()
                }
            ]
        );
        assert_eq!(j.index_of_file_line(4), Some(1));
        assert_eq!(j.bytes_from(0), 7 + 5);
        let long = format!("G1{}", " X1".repeat(60));
        assert!(StreamProgram::from_text("b.nc", &format!("G0\n{long}\n"))
            .unwrap_err()
            .starts_with("b.nc:2:"));
    }
}
