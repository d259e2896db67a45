//! RS274/NGC front end: text → blocks → canonical operations.
//!
//! ```
//! use oficina_canon::{CanonOp, Pos};
//! use oficina_gcode::{canon_of, RunOptions};
//!
//! // A feed move and a clockwise half circle, read as LinuxCNC reads them.
//! let program = "G21 G90 G17\nG1 X10 F600\nG2 X20 I5 J0\nM2\n";
//! let (ops, diagnostics) = canon_of(program, &RunOptions::default());
//! assert!(diagnostics.is_empty(), "{diagnostics:?}");
//! let moves: Vec<_> = ops
//!     .iter()
//!     .filter(|c| matches!(c.op, CanonOp::StraightFeed { .. } | CanonOp::ArcFeed { .. }))
//!     .collect();
//! assert_eq!(moves[0].line, 2);
//! assert_eq!(moves[0].op, CanonOp::StraightFeed { to: Pos::xyz(10.0, 0.0, 0.0) });
//! let CanonOp::ArcFeed { end, center, turns, .. } = moves[1].op else { panic!() };
//! assert_eq!((end.x, center, turns), (20.0, [15.0, 0.0], -1));
//! ```
//!
//! The stages, each in its own (private) module:
//! - `lex`: characters → tokens with spans (words, numbers, expressions, comments, O-words);
//! - `parse`: tokens → one syntax tree per line ([`Line`]);
//! - `expr` and `params`: expression evaluation against numbered/named parameters;
//! - `exec`: streams lines from a reader, runs O-word control flow (sub/call/if/while/do/
//!   repeat), evaluates every expression and yields [`Block`]s with plain values;
//! - `interp`: the modal interpreter: blocks → [`oficina_canon::Canon`] records;
//! - `print`: canonical operations in the text format of LinuxCNC's standalone `rs274`.
//!
//! What other crates use is the flat list below. `text` and `grbl_errors` stay public
//! modules because their names (`decode`, `escape`, `quote`; `error_text`, `error_codes`)
//! read well only behind them.

mod ast;
mod block;
mod bytes;
mod decimal;
mod diag;
mod exec;
mod expr;
pub mod grbl_errors;
mod header;
mod ini;
mod interp;
mod lex;
mod marlin;
mod params;
mod parse;
mod print;
mod program;
mod stream;
pub mod text;

pub use ast::Line;
pub use block::{Block, Note, Word};
pub use diag::{Diagnostic, Severity, Span};
pub use exec::{Executor, Limits, ProgramEnd, DEFAULT_MAX_LINE_LEN};
pub use header::{machine_hint, MachineHint};
pub use ini::{parse_var_file, IniSettings};
pub use interp::tool_table::{Tool, ToolTable};
pub use interp::{Flow, Interpreter, StartState};
pub use lex::Compact;
pub use params::Params;
pub use parse::parse_line;
pub use print::{to_rs274_text, Rs274Printer};
pub use program::{canon_of, run, run_text, Driver, RunOptions};
pub use stream::CanonStream;

/// The G-code dialect a program is read in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Dialect {
    /// LinuxCNC's RS274/NGC (the reference; default).
    #[default]
    LinuxCnc,
    /// grbl 1.1: accepts and rejects what grbl does, with grbl's error numbers.
    Grbl,
    /// The dialect of seed 002 (2006): G90/G91 are linear feed moves, I/J are absolute arc
    /// centres, motion codes are modal.
    Legacy2006,
    /// Marlin 2.x as pen plotters and lasers run it (Makelangelo): one command per line,
    /// `M0`/`M117` messages, `G4 P` in milliseconds, `G28` homing, `M280` servo pen lifts,
    /// checksums checked.
    Marlin,
}

impl std::fmt::Display for Dialect {
    /// The name `FromStr` reads back.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Dialect::LinuxCnc => "linuxcnc",
            Dialect::Grbl => "grbl",
            Dialect::Legacy2006 => "legacy-2006",
            Dialect::Marlin => "marlin",
        })
    }
}

impl std::str::FromStr for Dialect {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "linuxcnc" | "rs274" | "ngc" => Ok(Dialect::LinuxCnc),
            "grbl" => Ok(Dialect::Grbl),
            "legacy-2006" | "legacy" | "legacy2006" => Ok(Dialect::Legacy2006),
            "marlin" => Ok(Dialect::Marlin),
            other => Err(format!(
                "unknown dialect '{other}': use linuxcnc, grbl, marlin or legacy-2006"
            )),
        }
    }
}
