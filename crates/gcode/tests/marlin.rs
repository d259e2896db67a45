//! The Marlin dialect: Makelangelo-style plotter programs read, checked and planned.

use oficina_canon::{Canon, CanonOp};
use oficina_gcode::{canon_of, Diagnostic, Dialect, RunOptions};

fn data(name: &str) -> String {
    let path = format!("{}/tests/data/marlin/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).unwrap()
}

fn marlin(text: &str) -> (Vec<Canon>, Vec<Diagnostic>) {
    canon_of(text, &RunOptions::check(Dialect::Marlin))
}

fn errors(d: &[Diagnostic]) -> Vec<&Diagnostic> {
    d.iter()
        .filter(|d| d.severity == oficina_gcode::Severity::Error)
        .collect()
}

fn dwell_total(ops: &[Canon]) -> f64 {
    ops.iter()
        .map(|c| match c.op {
            CanonOp::Dwell(s) => s,
            _ => 0.0,
        })
        .sum()
}

#[test]
fn the_dialect_is_named_marlin() {
    assert_eq!("marlin".parse::<Dialect>(), Ok(Dialect::Marlin));
    assert_eq!(Dialect::Marlin.to_string(), "marlin");
}

#[test]
fn a_makelangelo_program_checks_clean_with_its_pen_lifts_and_pause() {
    let (ops, diags) = marlin(&data("makelangelo_square.gcode"));
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    // Two strokes: pen down twice (M3 S25), up three times (M5, the first M280 included).
    let downs = ops
        .iter()
        .filter(|c| matches!(c.op, CanonOp::StartSpindle(_)))
        .count();
    let ups = ops
        .iter()
        .filter(|c| matches!(c.op, CanonOp::StopSpindle))
        .count();
    assert_eq!((downs, ups), (2, 3), "{ops:#?}");
    // M0's message: a pause and a message op, and a note saying so.
    assert!(ops
        .iter()
        .any(|c| c.line == 12 && c.op == CanonOp::ProgramStop));
    assert!(ops
        .iter()
        .any(|c| c.op == CanonOp::Message("Ready for pen change".into())));
    assert!(diags
        .iter()
        .any(|d| d.span.line == 12 && d.message.contains("pause: Ready for pen change")));
    // M117's text is a message, M84/M400 notes without motion.
    assert!(ops.iter().any(|c| c.op == CanonOp::Message("Done".into())));
    assert!(diags.iter().any(|d| d.message.contains("M84: motors off")));
    assert!(diags.iter().any(|d| d.message.contains("M400")));
    // G4 P500 is half a second; each M280 T250 a quarter: 5 × 0.25 + 0.5.
    assert!(
        (dwell_total(&ops) - 1.75).abs() < 1e-9,
        "{}",
        dwell_total(&ops)
    );
    // Arcs read with I J and with R.
    let arcs = ops
        .iter()
        .filter(|c| matches!(c.op, CanonOp::ArcFeed { .. }))
        .count();
    assert_eq!(arcs, 2);
}

#[test]
fn g4_p_is_milliseconds_and_s_seconds() {
    let (ops, diags) = marlin("G4 P250\nG4 S2\n");
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    let dwells: Vec<f64> = ops
        .iter()
        .filter_map(|c| match c.op {
            CanonOp::Dwell(s) => Some(s),
            _ => None,
        })
        .collect();
    assert_eq!(dwells, vec![0.25, 2.0]);
}

#[test]
fn g28_homes_the_named_axes_straight_to_the_stored_home() {
    let mut opts = RunOptions::check(Dialect::Marlin);
    opts.initial_params = vec![(5161, 5.0), (5162, 7.0)];
    let (ops, diags) = canon_of("G0 X30 Y40 Z2\nG28 X Y\nG0 X30 Y40\nG28\n", &opts);
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    let ends: Vec<(u32, [f64; 3])> = ops
        .iter()
        .filter_map(|c| match &c.op {
            CanonOp::StraightTraverse { to } => Some((c.line, [to.x, to.y, to.z])),
            _ => None,
        })
        .collect();
    // Line 2: through the current point (no detour), then X Y home, Z kept.
    let line2: Vec<[f64; 3]> = ends.iter().filter(|e| e.0 == 2).map(|e| e.1).collect();
    assert_eq!(line2.last(), Some(&[5.0, 7.0, 2.0]), "{ends:?}");
    assert!(line2.iter().all(|p| p[0] == 30.0 || p[0] == 5.0));
    // Line 4: every axis home.
    let line4: Vec<[f64; 3]> = ends.iter().filter(|e| e.0 == 4).map(|e| e.1).collect();
    assert_eq!(line4.last(), Some(&[5.0, 7.0, 0.0]), "{ends:?}");
    // The same in G91.
    let (ops, diags) = canon_of("G0 X30 Y40\nG91\nG28 X\n", &opts);
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    let last = ops
        .iter()
        .rev()
        .find_map(|c| match &c.op {
            CanonOp::StraightTraverse { to } => Some([to.x, to.y]),
            _ => None,
        })
        .unwrap();
    assert_eq!(last, [5.0, 40.0]);
    // In inches the home stays where it is (the parameters are millimetres).
    let (ops, diags) = canon_of("G20\nG0 X1 Y1\nG28 Y\n", &opts);
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    let last = ops
        .iter()
        .rev()
        .find_map(|c| match &c.op {
            CanonOp::StraightTraverse { to } => Some([to.x, to.y]),
            _ => None,
        })
        .unwrap();
    assert!(
        (last[0] - 25.4).abs() < 1e-9 && (last[1] - 7.0).abs() < 1e-9,
        "{last:?}"
    );
}

#[test]
fn a_checksum_mismatch_is_an_error_naming_the_line() {
    let (ops, diags) = marlin(&data("checksum.gcode"));
    let errs = errors(&diags);
    assert_eq!(errs.len(), 1, "{diags:#?}");
    assert_eq!(errs[0].span.line, 3);
    assert!(
        errs[0].message.contains("checksum mismatch on line 3"),
        "{}",
        errs[0].message
    );
    // Lines 1 and 2, whose checksums hold, ran.
    assert!(ops
        .iter()
        .any(|c| c.line == 2 && c.op == CanonOp::StopSpindle));
    // A checksum without a line number is Marlin's refusal too.
    let (_, diags) = marlin("G1 X1*0\n");
    assert!(errors(&diags)[0].message.contains("without a line number"));
}

#[test]
fn what_marlin_lacks_is_refused_with_a_hint() {
    for (line, what) in [
        ("G41 D1", "cutter radius"),
        ("G43 H1", "tool length"),
        ("G81 X1 Y1 Z-1 R1", "canned cycles"),
        ("G1 X#1", "parameters"),
        ("G1 X[1+2]", "expressions"),
        ("o100 sub", "o-words"),
        ("M6", "pen change"),
        ("T1", "not a Marlin command"),
    ] {
        let (_, diags) = marlin(&format!("{line}\n"));
        let e = errors(&diags);
        assert_eq!(e.len(), 1, "{line}: {diags:#?}");
        let text = format!("{} {}", e[0].message, e[0].help.clone().unwrap_or_default());
        assert!(text.contains(what), "{line}: {text}");
    }
}

#[test]
fn one_command_per_line_and_e_words_ignored() {
    let (ops, diags) = marlin("G21 G90 G94 G17\nG1 X5 Y5 E3 F600\n");
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    assert!(diags.iter().any(|d| d.span.line == 1
        && d.severity == oficina_gcode::Severity::Warning
        && d.message.contains("G90 G94 G17")));
    assert!(diags
        .iter()
        .any(|d| d.span.line == 2 && d.message.contains("E words")));
    assert!(ops
        .iter()
        .any(|c| matches!(&c.op, CanonOp::StraightFeed { to } if to.x == 5.0)));
}

#[test]
fn the_other_dialects_read_marlin_lines_as_before() {
    // `M280` is not LinuxCNC's: the LinuxCNC dialect still refuses it.
    let (_, diags) = canon_of("M280 P0 S90\n", &RunOptions::check(Dialect::LinuxCnc));
    assert!(!errors(&diags).is_empty());
}

#[test]
/// The first move of a program: straight from wherever the machine is to home (no detour
/// through the interpreter's unknown start point).
fn g28_first_in_a_work_offset() {
    let mut opts = RunOptions::check(Dialect::Marlin);
    opts.initial_params = vec![
        (5221, 500.0),
        (5222, -400.0),
        (5161, 500.0),
        (5162, -400.0),
        (5163, 5.0),
    ];
    let (ops, diags) = canon_of("G28 X Y\nG0 X10 Y10\n", &opts);
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    for c in &ops {
        if let CanonOp::StraightTraverse { to } = &c.op {
            assert!(to.x > 100.0, "{ops:#?}");
        }
    }
}

#[test]
fn a_line_without_a_command_is_ignored_as_marlin_does() {
    // Marlin answers "Unknown command" and goes on: F3000 sets nothing, the feed stays
    // Marlin's power-up 1500 mm/min; X10 Y10 does not move.
    let (ops, diags) = marlin("F3000\nG1 X5\nX10 Y10\n");
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    let warned: Vec<u32> = diags
        .iter()
        .filter(|d| d.severity == oficina_gcode::Severity::Warning)
        .map(|d| d.span.line)
        .collect();
    assert_eq!(warned, vec![1, 3]);
    assert!(ops.iter().any(|c| c.op == CanonOp::SetFeedRate(1500.0)));
    assert!(!ops.iter().any(|c| c.op == CanonOp::SetFeedRate(3000.0)));
    assert_eq!(
        ops.iter()
            .filter(|c| matches!(c.op, CanonOp::StraightFeed { .. }))
            .count(),
        1
    );
}

proptest::proptest! {
    /// Any line, however odd, is read without a panic and its diagnostics point into it.
    #[test]
    fn any_line_is_read_without_panic(line in "[GMNTXYZFEPSIJRO0-9 .;*()#\\[\\]é-]{0,24}") {
        let (_, diags) = marlin(&format!("{line}\n"));
        for d in diags {
            proptest::prop_assert!(d.span.line <= 1, "{d:?}");
        }
    }
}

#[test]
fn odd_lines_are_refused_not_panicked_on() {
    for line in [
        "é",
        "N",
        "N1",
        "N1 *",
        "*",
        "G",
        "M",
        "G1 X",
        "M280 P0 S",
        "(",
        ";",
        "N5 é*0",
        "G4 P-1",
    ] {
        let _ = marlin(&format!("{line}\n"));
    }
}

#[test]
fn program_ends_are_ignored_with_a_warning_and_msg_comments_unwrapped() {
    let (ops, diags) = marlin("M0 (MSG, pen 2: red)\nG1 X1 F600\nM30\n");
    assert!(errors(&diags).is_empty(), "{diags:#?}");
    assert!(ops
        .iter()
        .any(|c| c.op == CanonOp::Message("pen 2: red".into())));
    assert!(diags.iter().any(|d| d.span.line == 3
        && d.severity == oficina_gcode::Severity::Warning
        && d.help.as_deref().unwrap_or("").contains("SD card")));
    assert!(!ops.iter().any(|c| c.op == CanonOp::ProgramEnd));
}
