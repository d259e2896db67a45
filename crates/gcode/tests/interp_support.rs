//! Shared helpers of the interpreter tests (included with `#[path]`): a minimal reader of
//! plain G-code lines (words, comments; no expressions) so the interpreter can be tested on
//! its own, and a runner that prints like `rs274 -g`.

#![allow(dead_code)]

use oficina_canon::{Canon, Units};
use oficina_gcode::Params;
use oficina_gcode::ToolTable;
use oficina_gcode::{canon_of, RunOptions};
use oficina_gcode::{to_rs274_text, Rs274Printer};
use oficina_gcode::{Block, Note, Word};
use oficina_gcode::{Diagnostic, Dialect, Severity, Span};
use oficina_gcode::{Flow, Interpreter, StartState};

/// Plain lines → blocks: `G1 X1.5 (comment)`, `(MSG, text)`, `;` comments.
pub(crate) fn blocks(text: &str) -> Vec<Block> {
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let line = i as u32 + 1;
        let mut b = Block {
            line,
            ..Block::default()
        };
        let chars: Vec<char> = raw.chars().collect();
        let mut k = 0;
        while k < chars.len() {
            let c = chars[k];
            if c == '(' {
                let end = chars[k..]
                    .iter()
                    .position(|&c| c == ')')
                    .map(|p| p + k)
                    .unwrap_or(chars.len());
                let text: String = chars[k + 1..end].iter().collect();
                if let Some(m) = text.strip_prefix("MSG,") {
                    b.notes.push(Note::Message(m.trim().to_string()));
                } else {
                    b.notes.push(Note::Comment(text));
                }
                k = end + 1;
            } else if c == ';' {
                break;
            } else if c.is_ascii_alphabetic() {
                let start = k;
                k += 1;
                while k < chars.len() && chars[k] == ' ' {
                    k += 1;
                }
                let num_start = k;
                while k < chars.len() && (chars[k].is_ascii_digit() || "+-.".contains(chars[k])) {
                    k += 1;
                }
                let s: String = chars[num_start..k].iter().collect();
                let value: f64 = s
                    .parse()
                    .unwrap_or_else(|_| panic!("bad number '{s}' on line {line}"));
                let letter = c.to_ascii_uppercase();
                if letter == 'N' {
                    b.n = Some(value);
                } else {
                    let span = Span::new(line, start as u32 + 1, (k - start) as u32);
                    b.words.push(Word {
                        letter,
                        value,
                        span,
                    });
                }
            } else {
                k += 1;
            }
        }
        out.push(b);
    }
    out
}

pub(crate) struct Run {
    pub(crate) ops: Vec<Canon>,
    pub(crate) errors: Vec<Diagnostic>,
}

pub(crate) fn run_with(text: &str, dialect: Dialect, tools: ToolTable, start: StartState) -> Run {
    let mut ops = Vec::new();
    let mut errors = Vec::new();
    let mut params = Params::new();
    let mut interp = Interpreter::new(dialect, &start, tools);
    interp.begin(&mut params, &mut |c| ops.push(c));
    for b in blocks(text) {
        match interp.execute(&b, &mut params, &mut |c| ops.push(c)) {
            Ok(Flow::End) => break,
            Ok(Flow::Continue) => {}
            // A G70–G72 cycle reads its profile through the program driver (`program.rs`),
            // which this block-by-block helper does not have.
            Ok(Flow::ReadProfile) => panic!("lathe cycles run through the program driver"),
            Err(e) => {
                errors.push(e);
                break;
            }
        }
    }
    interp.finish(&mut |c| ops.push(c));
    Run { ops, errors }
}

pub(crate) fn run(text: &str) -> Run {
    run_with(
        text,
        Dialect::LinuxCnc,
        ToolTable::new(),
        StartState::default(),
    )
}

/// The rs274 tool table of the differential corpus, read in inches as `rs274` does.
pub(crate) fn corpus_tools() -> ToolTable {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../tests/corpus/tool.tbl");
    let text = std::fs::read_to_string(path).expect("tests/corpus/tool.tbl");
    ToolTable::parse(&text, Units::Inch).unwrap()
}

/// The printed motion calls (what the differential comparison checks).
pub(crate) fn motion_text(ops: &[Canon]) -> Vec<String> {
    let mut p = Rs274Printer::new();
    let mut out = Vec::new();
    for c in ops {
        let mut buf = Vec::new();
        p.print(c, &mut buf).unwrap();
        let s = String::from_utf8(buf).unwrap().trim_end().to_string();
        if s.starts_with("STRAIGHT_") || s.starts_with("ARC_FEED") || s.starts_with("DWELL") {
            out.push(s);
        }
    }
    out
}

/// Compare motion calls with rs274's (the text after `N..... `), numbers within 1e-4.
pub(crate) fn assert_motion(ops: &[Canon], expected: &str) {
    let got = motion_text(ops);
    let want: Vec<&str> = expected
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    assert_eq!(
        got.len(),
        want.len(),
        "number of motion calls differs:\n{}",
        got.join("\n")
    );
    for (g, w) in got.iter().zip(&want) {
        let name = |s: &str| s.split('(').next().unwrap_or("").to_string();
        assert_eq!(name(g), name(w), "\ngot  {g}\nwant {w}");
        let nums = |s: &str| -> Vec<f64> {
            s[s.find('(').unwrap() + 1..s.rfind(')').unwrap()]
                .split(',')
                .map(|x| x.trim().parse::<f64>().unwrap())
                .collect()
        };
        let (a, b) = (nums(g), nums(w));
        assert_eq!(a.len(), b.len());
        for (x, y) in a.iter().zip(&b) {
            assert!((x - y).abs() <= 1.01e-4, "\ngot  {g}\nwant {w}");
        }
    }
}

/// Calls the differential test compares ([`oficina_testkit::rs274::COMPARED`]) that the
/// expectations of these tests were pasted without: spindle orientation, spindle-synchronised
/// motion and rigid tapping.
const NOT_PASTED: &[&str] = &[
    "ORIENT_SPINDLE",
    "SPINDLE.0.WAIT_ORIENT_COMPLETE",
    "START_SPEED_FEED_SYNC",
    "STOP_SPEED_FEED_SYNCH",
    "RIGID_TAP",
];

/// Options of the standalone `rs274 -t tests/corpus/tool.tbl`: its machine is in inches.
pub(crate) fn rs274_options() -> RunOptions {
    let mut opts = RunOptions {
        tool_table: corpus_tools(),
        ..RunOptions::default()
    };
    opts.start.machine_units = Units::Inch;
    opts
}

/// A whole program through the front end and the interpreter, printed like `rs274 -g`,
/// only the compared calls.
pub(crate) fn rs274_calls(program: &str) -> (Vec<String>, Vec<Diagnostic>) {
    let (ops, diags) = canon_of(program, &rs274_options());
    let text = to_rs274_text(&ops);
    let calls = text
        .lines()
        .filter(|l| {
            let name = l.split('(').next().unwrap_or_default();
            oficina_testkit::rs274::COMPARED.contains(&name) && !NOT_PASTED.contains(&name)
        })
        .map(str::to_string)
        .collect();
    (calls, diags)
}

/// Numbers within 1e-4 (both print four decimals), everything else exactly.
fn same_call(got: &str, want: &str) -> bool {
    let split = |s: &str| -> Vec<String> {
        s.split(|c: char| c == ',' || c == '(' || c == ')' || c.is_whitespace())
            .filter(|t| !t.is_empty())
            .map(str::to_string)
            .collect()
    };
    let (a, b) = (split(got), split(want));
    a.len() == b.len()
        && a.iter()
            .zip(&b)
            .all(|(x, y)| match (x.parse::<f64>(), y.parse::<f64>()) {
                (Ok(p), Ok(q)) => (p - q).abs() <= 1.01e-4,
                _ => x == y,
            })
}

/// The program runs cleanly and prints the calls rs274 printed (`expected`, one a line).
pub(crate) fn assert_calls(program: &str, expected: &str) {
    let (got, diags) = rs274_calls(program);
    assert!(diags.is_empty(), "{diags:?}");
    let want: Vec<&str> = expected
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    for (i, w) in want.iter().enumerate() {
        let g = got.get(i).map(String::as_str).unwrap_or("(nothing)");
        assert!(
            same_call(g, w),
            "call #{}:\n got  {g}\n want {w}\nall we printed:\n{}",
            i + 1,
            got.join("\n")
        );
    }
    assert_eq!(
        got.len(),
        want.len(),
        "extra calls:\n{}",
        got[want.len()..].join("\n")
    );
}

/// The program is rejected, first on `line` (where rs274 stops).
pub(crate) fn assert_rejected_on(program: &str, line: u32) {
    let (_, diags) = rs274_calls(program);
    let first = diags.first().expect("the program must be rejected");
    assert_eq!(first.severity, Severity::Error);
    assert_eq!(first.span.line, line, "{first:?}");
}

#[test]
fn mini_reader_reads_words_and_comments() {
    let b = blocks("N10 G1 X-1.5 y2 (hello) ; rest");
    assert_eq!(b[0].n, Some(10.0));
    assert_eq!(b[0].words.len(), 3);
    assert_eq!(b[0].words[1].value, -1.5);
    assert_eq!(b[0].notes, vec![Note::Comment("hello".into())]);
}
