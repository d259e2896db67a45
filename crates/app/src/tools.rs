//! The tool table the page edits: LinuxCNC's format (`T1 P1 D6 Z12.5 ;flat end mill`),
//! read by the interpreter's own parser, whose line, column and message come back.

use oficina_canon::Units;
use oficina_gcode::ToolTable;
use serde::Serialize;

/// Name of the table in the job folder.
pub const TOOL_TABLE_FILE: &str = "tool.tbl";

#[derive(Clone, Serialize, Debug, PartialEq)]
/// One row of a tool table.
pub struct ToolRow {
    /// Tool number (T).
    pub number: u32,
    /// Pocket (P).
    pub pocket: u32,
    /// Diameter (D), mm.
    pub diameter: f64,
    /// Length offset (Z), mm.
    pub length: f64,
    /// The comment after `;`.
    pub comment: String,
}

#[derive(Serialize, Debug, PartialEq)]
/// Where and why a tool table cannot be read.
pub struct ToolTableError {
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub col: u32,
    /// What is wrong.
    pub message: String,
}

/// The table of `text` (lengths in mm) as the interpreter takes it (G43 H, G41 D, M6), or
/// where and why it cannot be read.
pub fn parse_tool_table(text: &str) -> Result<ToolTable, ToolTableError> {
    ToolTable::parse(text, Units::Mm).map_err(|d| ToolTableError {
        line: d.span.line,
        col: d.span.col,
        message: d.message,
    })
}

/// The tools of a table as the page lists them.
pub fn tool_rows(table: &ToolTable) -> Vec<ToolRow> {
    table
        .iter()
        .map(|t| ToolRow {
            number: t.number,
            pocket: t.pocket,
            diameter: t.diameter,
            length: t.offset[2],
            comment: t.comment.clone(),
        })
        .collect()
}

/// The tools of `text` (lengths in mm), or where and why it cannot be read.
pub fn check_tool_table(text: &str) -> Result<Vec<ToolRow>, ToolTableError> {
    parse_tool_table(text).map(|t| tool_rows(&t))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tools_are_read_and_errors_placed() {
        let rows = check_tool_table("T1 P1 D6 Z12.5 ;flat\nT2 P2 D3.175 Z20\n").unwrap();
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].diameter, 6.0);
        assert_eq!(rows[0].length, 12.5);
        assert_eq!(rows[1].number, 2);
        let e = check_tool_table("T1 P1 D6\nT2 P2 Dx\n").unwrap_err();
        assert_eq!(e.line, 2, "{e:?}");
        assert!(!e.message.is_empty());
    }
}
