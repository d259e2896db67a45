//! LinuxCNC tool tables (`.tbl`): one tool a line, `T1 P1 Z10 D6 ;comment`.
//! Words: T tool number, P pocket, X Y Z A B C offsets, D diameter, I J Q (lathe angles and
//! orientation, kept for round trips). Values are in the table's units (LinuxCNC: machine
//! units; the standalone `rs274` reads tables in inches).

use crate::diag::{Diagnostic, Span};
use oficina_canon::Units;
use std::collections::BTreeMap;

/// One tool of the table.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Tool {
    /// Tool number (the `T` word).
    pub number: u32,
    /// Pocket number in the tool changer.
    pub pocket: u32,
    /// X Y Z A B C offsets, mm (A B C in degrees).
    pub offset: [f64; 6],
    /// Diameter, mm.
    pub diameter: f64,
    /// The comment of its line in the table file.
    pub comment: String,
}

/// Tools by number, as a LinuxCNC tool table file lists them.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ToolTable {
    tools: BTreeMap<u32, Tool>,
}

/// The comment of every tool of [`ToolTable::rs274_default`].
pub(crate) const RS274_DEFAULT_COMMENT: &str = "rs274 standalone default (no tool table given)";

/// Longest line accepted: a tool table line is short; this bounds memory on a wrong file.
const MAX_LINE: usize = 4096;

impl ToolTable {
    /// An empty table.
    pub fn new() -> ToolTable {
        ToolTable::default()
    }

    /// The table LinuxCNC's standalone `rs274` runs with when it is given none (no `-t`):
    /// tools 1, 2 and 3 in pockets 1, 2 and 3, lengths and diameters in inches (measured with
    /// `rs274 -g` from a fresh `HOME`: `#5403` and `#5410` after `T1 M6 G43` under G20 are
    /// 0.511 and 0.125; tool 4 is "not found"). Each tool's comment is
    /// [`RS274_DEFAULT_COMMENT`], so an error can say that no table was given.
    pub fn rs274_default() -> ToolTable {
        let mut table = ToolTable::new();
        for (number, z, d) in [(1, 0.511, 0.125), (2, 0.1, 0.0625), (3, 1.273, 0.201)] {
            table.insert(Tool {
                number,
                pocket: number,
                offset: [0.0, 0.0, z * Units::Inch.mm(), 0.0, 0.0, 0.0],
                diameter: d * Units::Inch.mm(),
                comment: RS274_DEFAULT_COMMENT.to_string(),
            });
        }
        table
    }

    /// Whether this is [`ToolTable::rs274_default`], the table used when none was given.
    pub fn is_rs274_default(&self) -> bool {
        !self.is_empty() && self.iter().all(|t| t.comment == RS274_DEFAULT_COMMENT)
    }

    /// The tool with this number.
    pub fn get(&self, number: u32) -> Option<&Tool> {
        self.tools.get(&number)
    }

    /// Add the tool, replacing one with the same number.
    pub fn insert(&mut self, tool: Tool) {
        self.tools.insert(tool.number, tool);
    }

    /// How many tools the table holds.
    pub fn len(&self) -> usize {
        self.tools.len()
    }

    /// Whether the table holds no tool.
    pub fn is_empty(&self) -> bool {
        self.tools.is_empty()
    }

    /// The tools in order of their numbers.
    pub fn iter(&self) -> impl Iterator<Item = &Tool> {
        self.tools.values()
    }

    /// Parse a table whose lengths are in `units`; errors name line and column.
    pub fn parse(text: &str, units: Units) -> Result<ToolTable, Diagnostic> {
        let mut table = ToolTable::new();
        for (i, raw) in text.lines().enumerate() {
            let line_no = i as u32 + 1;
            if raw.len() > MAX_LINE {
                return Err(
                    Diagnostic::error(Span::line(line_no), "tool table line is too long")
                        .with_help("is this really a LinuxCNC .tbl file?"),
                );
            }
            let (body, comment) = match raw.find(';') {
                Some(k) => (&raw[..k], raw[k + 1..].trim()),
                None => (raw, ""),
            };
            if body.trim().is_empty() {
                continue;
            }
            let mut tool = Tool {
                comment: comment.to_string(),
                ..Tool::default()
            };
            let mut has_t = false;
            let mut col = 0usize;
            for word in body.split_whitespace() {
                col = body[col..].find(word).map(|k| k + col).unwrap_or(col);
                let span = Span::new(line_no, col as u32 + 1, word.chars().count() as u32);
                col += word.len();
                let mut chars = word.chars();
                let letter = chars.next().unwrap_or(' ').to_ascii_uppercase();
                let value: f64 = chars.as_str().parse().map_err(|_| {
                    Diagnostic::error(
                        span,
                        format!("'{word}' is not a letter followed by a number"),
                    )
                    .with_help("tool table words look like T1 P1 Z10.5 D6")
                })?;
                let length = value * units.mm();
                // NaN, infinity, or a number that overflows once converted to mm would reach
                // the positions of every move made with the tool (found by fuzzing).
                if !length.is_finite() {
                    return Err(Diagnostic::error(
                        span,
                        format!("'{word}' is not a finite number of {}", units_name(units)),
                    )
                    .with_help("tool table values are lengths and angles of a real tool"));
                }
                match letter {
                    'T' | 'P' => {
                        if value < 0.0 || value.fract() != 0.0 || value > u32::MAX as f64 {
                            return Err(Diagnostic::error(
                                span,
                                format!("{letter} must be a whole number ≥ 0, not {value}"),
                            ));
                        }
                        if letter == 'T' {
                            tool.number = value as u32;
                            has_t = true;
                        } else {
                            tool.pocket = value as u32;
                        }
                    }
                    'X' => tool.offset[0] = length,
                    'Y' => tool.offset[1] = length,
                    'Z' => tool.offset[2] = length,
                    'A' => tool.offset[3] = value,
                    'B' => tool.offset[4] = value,
                    'C' => tool.offset[5] = value,
                    'D' => tool.diameter = length,
                    'U' | 'V' | 'W' | 'I' | 'J' | 'Q' => {}
                    _ => {
                        return Err(Diagnostic::error(
                            span,
                            format!("unknown tool table word '{letter}'"),
                        )
                        .with_help("known words: T P X Y Z A B C U V W D I J Q"))
                    }
                }
            }
            if !has_t {
                return Err(Diagnostic::error(
                    Span::line(line_no),
                    "tool table line without T word",
                )
                .with_help(
                    "each line describes one tool: T<number> P<pocket> Z<length> D<diameter>",
                ));
            }
            table.insert(tool);
        }
        Ok(table)
    }

    /// Write the table back in LinuxCNC's format, lengths in `units`.
    pub fn to_tbl(&self, units: Units) -> String {
        let mut s = String::new();
        for t in self.tools.values() {
            let k = units.mm();
            s.push_str(&format!(
                "T{} P{} X{} Y{} Z{} D{} ;{}\n",
                t.number,
                t.pocket,
                t.offset[0] / k,
                t.offset[1] / k,
                t.offset[2] / k,
                t.diameter / k,
                t.comment
            ));
        }
        s
    }
}

fn units_name(units: Units) -> &'static str {
    match units {
        Units::Mm => "mm",
        Units::Inch => "inches",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_linuxcnc_lines() {
        let t = ToolTable::parse("T1 P1 Z10 D6 ;end mill\n\nT2 P2 Z-5 X1 D3\n", Units::Mm).unwrap();
        assert_eq!(t.len(), 2);
        assert_eq!(t.get(1).unwrap().offset[2], 10.0);
        assert_eq!(t.get(1).unwrap().diameter, 6.0);
        assert_eq!(t.get(1).unwrap().comment, "end mill");
        assert_eq!(t.get(2).unwrap().offset[0], 1.0);
        let inch = ToolTable::parse("T1 Z1", Units::Inch).unwrap();
        assert_eq!(inch.get(1).unwrap().offset[2], 25.4);
        let back = ToolTable::parse(&t.to_tbl(Units::Mm), Units::Mm).unwrap();
        assert_eq!(back, t);
    }

    #[test]
    fn the_standalone_default_holds_three_tools_in_inches() {
        let t = ToolTable::rs274_default();
        assert!(t.is_rs274_default());
        assert_eq!(t.iter().map(|t| t.number).collect::<Vec<_>>(), [1, 2, 3]);
        assert!((t.get(1).unwrap().offset[2] - 12.9794).abs() < 1e-9);
        assert!((t.get(3).unwrap().diameter - 5.1054).abs() < 1e-9);
        assert!(t.get(4).is_none());
        assert!(!ToolTable::parse("T1 Z1", Units::Mm)
            .unwrap()
            .is_rs274_default());
    }

    #[test]
    fn errors_name_the_word() {
        let e = ToolTable::parse("T1 P1\nT2 Zabc", Units::Mm).unwrap_err();
        assert_eq!((e.span.line, e.span.col), (2, 4));
        assert!(ToolTable::parse("P1 Z1", Units::Mm).is_err());
        assert!(ToolTable::parse("T-1", Units::Mm).is_err());
    }
}
