//! The check of a program, as data: every diagnostic with its place, extents, path lengths,
//! tools and the planner's time on a machine profile (what `oficina check` prints and the
//! workbench's editor shows).

use crate::text::reader;
use crate::tools::{tool_rows, ToolRow};
use oficina_canon::Pos;
use oficina_canon::{Extents, Summarizer, Summary};
use oficina_gcode::CanonStream;
use oficina_gcode::RunOptions;
use oficina_gcode::ToolTable;
use oficina_gcode::{Diagnostic, Dialect, Severity};
use oficina_motion::{Estimate, MotionError, Profile};
use serde::Serialize;
use std::io::{BufRead, Seek};
use std::sync::Arc;

/// How to check a program: on which machine, in which dialect.
pub struct CheckOptions {
    /// The machine whose planner gives the time.
    pub profile: Profile,
    /// The G-code dialect.
    pub dialect: Dialect,
}

/// One diagnostic: 1-based line and column, the length of the marked text.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct Diag {
    /// Line, from 1.
    pub line: u32,
    /// Column, from 1.
    pub col: u32,
    /// Length of the marked text.
    pub len: u32,
    /// `error`, `warning` or `note`.
    pub severity: &'static str,
    /// What is wrong.
    pub message: String,
    /// How to fix it, when known.
    pub help: Option<String>,
}

impl From<&Diagnostic> for Diag {
    fn from(d: &Diagnostic) -> Diag {
        Diag {
            line: d.span.line,
            col: d.span.col,
            len: d.span.len,
            severity: match d.severity {
                Severity::Error => "error",
                Severity::Warning => "warning",
                Severity::Note => "note",
            },
            message: d.message.clone(),
            help: d.help.clone(),
        }
    }
}

/// An axis-aligned box in machine mm; `None` when no move of that kind exists.
#[derive(Clone, Debug, Serialize, PartialEq)]
pub struct ExtentsBox {
    /// Lowest X, Y, Z.
    pub min: [f64; 3],
    /// Highest X, Y, Z.
    pub max: [f64; 3],
}

fn extents_box(e: &Extents) -> Option<ExtentsBox> {
    (!e.is_empty()).then_some(ExtentsBox {
        min: e.min,
        max: e.max,
    })
}

#[derive(Clone, Debug, Serialize, PartialEq)]
/// The look-ahead planner's time for a program.
pub struct TimeEstimate {
    /// Machine time, s.
    pub seconds: f64,
    /// Planned segments.
    pub segments: u64,
}

#[derive(Clone, Debug, Serialize, PartialEq)]
/// What a check found: diagnostics, extents, lengths, tools and times.
pub struct CheckReport {
    /// Every diagnostic, in order.
    pub diagnostics: Vec<Diag>,
    /// How many diagnostics are errors.
    pub errors: usize,
    /// How many are warnings.
    pub warnings: usize,
    /// Canonical operations made.
    pub operations: u64,
    /// The box of the feed moves.
    pub feed_extents: Option<ExtentsBox>,
    /// The box of the rapids.
    pub rapid_extents: Option<ExtentsBox>,
    /// Feed path length, mm.
    pub feed_length: f64,
    /// Rapid path length, mm.
    pub rapid_length: f64,
    /// Feed moves.
    pub feed_moves: u64,
    /// Rapid moves.
    pub rapid_moves: u64,
    /// Arcs among the feed moves.
    pub arcs: u64,
    /// Tools changed to, in order.
    pub tools: Vec<u32>,
    /// The tools the program uses as the tool table gives them (diameter, length offset);
    /// `None` for a tool the table lacks. Empty when the check had no table.
    pub tool_table: Vec<(u32, Option<ToolRow>)>,
    /// Programmed feeds only, no acceleration: a lower bound.
    pub feed_rate_seconds: f64,
    /// The look-ahead planner's time on the profile, or why there is none.
    pub time: Result<TimeEstimate, String>,
    /// The machine profile's name.
    pub machine: String,
}

/// Interpret `text` in check mode on `opts.profile`: the summary covers the whole program even
/// where the planner stops early (an unreachable point).
pub fn check_program(text: &Arc<String>, opts: &CheckOptions) -> CheckReport {
    check_program_with_tools(text, opts, &ToolTable::default())
}

/// [`check_program`] with a tool table: G43 H length offsets move the checked and planned
/// path, G41/G42 D take the tool's radius, and the report lists each used tool's data.
pub fn check_program_with_tools(
    text: &Arc<String>,
    opts: &CheckOptions,
    tools: &ToolTable,
) -> CheckReport {
    check_for_sender(text, opts, tools, &oficina_grbl::ToolChange::default())
}

/// [`check_program_with_tools`] where grbl firmware will receive the program from Oficina's
/// sender under the tool-change policy `tc`: `M6` and the `%` tape marks are the sender's
/// (read as it sends them, with a note on each such line) instead of grbl's refusal.
pub fn check_for_sender(
    text: &Arc<String>,
    opts: &CheckOptions,
    tools: &ToolTable,
    tc: &oficina_grbl::ToolChange,
) -> CheckReport {
    let profile = &opts.profile;
    let mut run = RunOptions::check(opts.dialect);
    run.initial_params = crate::run_options::initial_params_for(profile, run.dialect);
    run.tool_table = tools.clone();
    let [x, y, z] = profile.start;
    let summarizer = Summarizer::new(Pos::xyz(x, y, z), profile.axis_rapid_rates());
    // For grbl: the program as the sender sends it (pausing at M6), as `oficina check` reads it.
    let (text, notes) = match opts.dialect {
        Dialect::Grbl => {
            let (view, notes) = oficina_grbl::sender_view(text.as_bytes(), tc);
            // Only ASCII bytes were blanked: the text stays UTF-8.
            let view = String::from_utf8(view).unwrap_or_else(|_| text.to_string());
            (Arc::new(view), crate::program::sender_notes(notes))
        }
        _ => (text.clone(), Vec::new()),
    };
    let c = interpret(reader(&text), run, profile, summarizer);
    let (mut diags, planned) = (c.diagnostics, c.time);
    if !notes.is_empty() {
        diags.extend(notes);
        diags.sort_by_key(|d| d.span.line);
    }
    let mut r = report(&diags, c.summary, c.operations, planned, &profile.name);
    if !tools.is_empty() {
        let rows = tool_rows(tools);
        r.tool_table = r
            .tools
            .iter()
            .map(|&n| (n, rows.iter().find(|t| t.number == n).cloned()))
            .collect();
    }
    r
}

/// A program interpreted (in the mode `run` says) and planned on a profile.
pub struct CheckedSource {
    /// Every diagnostic, in order.
    pub diagnostics: Vec<Diagnostic>,
    /// Extents, lengths, tools and the feed-rate time of the whole program.
    pub summary: Summary,
    /// Canonical operations made.
    pub operations: u64,
    /// The look-ahead planner's estimate, or why it stopped.
    pub time: Result<Estimate, MotionError>,
}

/// Interpret `source` with `run` and plan it on `profile` (`oficina check`): moves are bounded
/// by each joint's top speed; the summary covers the whole program even where the planner
/// stops early.
pub fn check_source<R: BufRead + Seek + Send + 'static>(
    source: R,
    run: RunOptions,
    profile: &Profile,
) -> CheckedSource {
    let [x, y, z] = profile.start;
    let summarizer = Summarizer::with_bound(
        Pos::xyz(x, y, z),
        Box::new(oficina_motion::JointBound::new(profile)),
    );
    interpret(source, run, profile, summarizer)
}

fn interpret<R: BufRead + Seek + Send + 'static>(
    source: R,
    run: RunOptions,
    profile: &Profile,
    mut summarizer: Summarizer,
) -> CheckedSource {
    let mut ops = 0u64;
    let mut stream = CanonStream::spawn(source, run);
    let planned = oficina_motion::estimate(
        stream.by_ref().inspect(|c| {
            ops += 1;
            summarizer.add(&c.op);
        }),
        profile,
    );
    // The planner may stop early (an unreachable point); the summary still covers it all.
    for c in stream.by_ref() {
        ops += 1;
        summarizer.add(&c.op);
    }
    CheckedSource {
        diagnostics: stream.finish(),
        summary: summarizer.finish(),
        operations: ops,
        time: planned,
    }
}

fn report(
    diags: &[Diagnostic],
    s: Summary,
    operations: u64,
    planned: Result<Estimate, MotionError>,
    machine: &str,
) -> CheckReport {
    let errors = diags
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .count();
    CheckReport {
        diagnostics: diags.iter().map(Diag::from).collect(),
        errors,
        warnings: diags
            .iter()
            .filter(|d| d.severity == Severity::Warning)
            .count(),
        operations,
        feed_extents: extents_box(&s.feed_extents),
        rapid_extents: extents_box(&s.rapid_extents),
        feed_length: s.feed_length,
        rapid_length: s.rapid_length,
        feed_moves: s.feed_moves,
        rapid_moves: s.rapid_moves,
        arcs: s.arcs,
        tools: s.tools,
        tool_table: Vec::new(),
        feed_rate_seconds: s.feed_rate_seconds,
        time: planned
            .map(|e| TimeEstimate {
                seconds: e.seconds,
                segments: e.segments,
            })
            .map_err(|e| e.to_string()),
        machine: machine.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check(text: &str) -> CheckReport {
        let profile = crate::profile::resolve("grbl-router").unwrap();
        check_program(
            &Arc::new(text.to_string()),
            &CheckOptions {
                profile,
                dialect: Dialect::LinuxCnc,
            },
        )
    }

    #[test]
    fn a_square_has_its_extents_length_and_time() {
        let r =
            check("G21 G90 G54\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG1 X10 F600\nY10\nX0\nY0\nG0 Z5\nM2\n");
        assert_eq!(r.errors, 0, "{:?}", r.diagnostics);
        // A 6 mm plunge (Z5 to Z-1) + 4 sides of 10 mm, fed.
        assert!((r.feed_length - 46.0).abs() < 1e-9, "{}", r.feed_length);
        let f = r.feed_extents.unwrap();
        // Machine coordinates: the box is 10 x 10 whatever the stored G54 is.
        assert!((f.max[0] - f.min[0] - 10.0).abs() < 1e-9);
        assert!((f.max[1] - f.min[1] - 10.0).abs() < 1e-9);
        let t = r.time.unwrap();
        // 40 mm at 600 mm/min is 4 s and the plunge 3.6 s: acceleration only adds to it.
        assert!(t.seconds > 7.6 && t.seconds < 12.0, "{}", t.seconds);
    }

    #[test]
    fn the_tool_table_moves_g43_and_g41_paths_and_names_each_tools_data() {
        let text = Arc::new(
            "G21 G90 G17\nT1 M6\nG43 H1\nG0 X0 Y0 Z5\nG1 Z-1 F100\nG41 D1\nG1 X10 Y0 F600\nX10 Y10\nG40\nG0 Z5\nT2 M6\nM2\n".to_string(),
        );
        let opts = CheckOptions {
            profile: crate::profile::resolve("grbl-router").unwrap(),
            dialect: Dialect::LinuxCnc,
        };
        let bare = check_program(&text, &opts);
        let table = crate::tools::parse_tool_table("T1 P1 D6 Z12.5 ;flat 6\n").unwrap();
        let with = check_program_with_tools(&text, &opts, &table);
        // The interpreter refuses T2, which the table lacks (LinuxCNC's message), and only it.
        assert_eq!(with.errors, 1, "{:?}", with.diagnostics);
        assert_eq!(with.diagnostics[0].line, 11, "{:?}", with.diagnostics);
        assert!(with.diagnostics[0].message.contains("tool 2"));
        let (b, w) = (bare.feed_extents.unwrap(), with.feed_extents.unwrap());
        // G43 H1 lifts every programmed Z by the tool's 12.5 mm length.
        assert!((w.min[2] - b.min[2] - 12.5).abs() < 1e-9, "{b:?} {w:?}");
        // G41 D1 keeps the tool's 3 mm radius left of the path: the leg up X10 is cut with
        // the centre at X7 (without the table's diameter it would be on X10).
        assert!((w.max[0] - b.max[0] + 3.0).abs() < 1e-6, "{b:?} {w:?}");
        assert_eq!(with.tool_table.len(), 1, "{:?}", with.tool_table);
        let t1 = with.tool_table[0].1.as_ref().unwrap();
        assert_eq!(
            (with.tool_table[0].0, t1.diameter, t1.length),
            (1, 6.0, 12.5)
        );
        assert!(bare.tool_table.is_empty());
    }

    #[test]
    fn grbl_programs_are_checked_as_the_sender_sends_them() {
        let text = Arc::new("%\nG21 G90\nT2 M6\nG0 X1\nG41 G1 X2 F100\nM30\n%\n".to_string());
        let opts = CheckOptions {
            profile: oficina_motion::resolve("grbl-router").unwrap(),
            dialect: Dialect::Grbl,
        };
        let r = check_program(&text, &opts);
        let at = |sev: &str| -> Vec<u32> {
            r.diagnostics
                .iter()
                .filter(|d| d.severity == sev)
                .map(|d| d.line)
                .collect()
        };
        assert_eq!(at("note"), [1, 3, 7], "{:?}", r.diagnostics);
        assert_eq!(
            at("error"),
            [5],
            "G41 is still grbl's error: {:?}",
            r.diagnostics
        );
        assert_eq!((r.errors, r.warnings), (1, 0));
    }

    #[test]
    fn errors_carry_line_and_column_and_the_check_goes_on() {
        let r = check("G0 X0\nG1 X10 Qbad\nG2 X10 Y10\nG1 X5 F100\nM2\n");
        assert!(r.errors >= 1, "{:?}", r.diagnostics);
        let d = &r.diagnostics[0];
        assert_eq!(d.line, 2, "{d:?}");
        assert!(d.col >= 1);
        assert!(r.diagnostics.iter().all(|d| !d.message.is_empty()));
    }

    #[test]
    fn m6_is_a_note_under_pause_and_an_error_as_written() {
        let text = Arc::new("G21 G90\nT2 M6\nG0 X1\nM2\n".to_string());
        let opts = CheckOptions {
            profile: crate::profile::resolve(crate::profile::DEFAULT).unwrap(),
            dialect: Dialect::Grbl,
        };
        let r = super::check_for_sender(
            &text,
            &opts,
            &ToolTable::default(),
            &oficina_grbl::ToolChange::default(),
        );
        assert_eq!(r.errors, 0, "{:?}", r.diagnostics);
        let note = r.diagnostics.iter().find(|d| d.severity == "note").unwrap();
        assert_eq!(note.line, 2);
        assert!(note.message.contains("pauses"), "{}", note.message);
        let r = super::check_for_sender(
            &text,
            &opts,
            &ToolTable::default(),
            &oficina_grbl::ToolChange::as_written(),
        );
        assert!(r.errors > 0, "{:?}", r.diagnostics);
    }
}
