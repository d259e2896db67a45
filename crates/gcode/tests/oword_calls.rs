//! O-word calls beyond one file and the comments that talk to the operator: subroutines in
//! their own files on the search path (LinuxCNC's SUBROUTINE_PATH), `o[expression]` labels,
//! `(print, …)` and `(abort, …)`. Behaviour on the corpus programs `oword_*.ngc` is compared
//! with rs274 by crates/cli/tests/differential.rs; these pin the details.

#[path = "interp_support.rs"]
mod support;

use oficina_gcode::canon_of;
use oficina_gcode::Severity;
use std::path::PathBuf;

fn lib_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../tests/corpus/oword_lib")
}

fn run_with_path(program: &str, path: Vec<PathBuf>) -> (String, Vec<oficina_gcode::Diagnostic>) {
    let mut opts = support::rs274_options();
    opts.subroutine_path = path;
    let (ops, diags) = canon_of(program, &opts);
    (oficina_gcode::to_rs274_text(&ops), diags)
}

/// `rs274 -i oword_lib/paths.ini` printed these feeds for the same program (pasted).
#[test]
fn a_subroutine_file_on_the_path_is_called_and_returns_to_the_caller() {
    let (text, diags) = run_with_path(
        "G21 G90\no<peck> call [1] [2] [-3]\nG0 X9\nM2\n",
        vec![PathBuf::from("/nonexistent"), lib_dir()],
    );
    assert!(diags.is_empty(), "{diags:?}");
    let moves: Vec<&str> = text.lines().filter(|l| l.starts_with("STRAIGHT")).collect();
    assert_eq!(
        moves,
        [
            "STRAIGHT_TRAVERSE(1.0000, 2.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
            "STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)",
            "STRAIGHT_FEED(1.0000, 2.0000, -3.0000, 0.0000, 0.0000, 0.0000)",
            "STRAIGHT_TRAVERSE(1.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)",
            "STRAIGHT_TRAVERSE(9.0000, 2.0000, 2.0000, 0.0000, 0.0000, 0.0000)",
        ]
    );
}

#[test]
fn without_the_path_the_call_is_an_error_at_the_call() {
    let (_, diags) = run_with_path("G21\no<peck> call [1] [2] [-3]\nM2\n", Vec::new());
    let e = diags.first().expect("an error");
    assert_eq!(e.span.line, 2);
    assert!(
        e.message.contains("o<peck> is not defined"),
        "{}",
        e.message
    );
}

#[test]
fn a_file_without_its_sub_is_named_in_the_error() {
    // paths.ini is in the directory but holds no o<paths> sub.
    let dir = oficina_testkit::scratch_dir("oword");
    std::fs::write(dir.join("empty.ngc"), "G0 X1\nM2\n").unwrap();
    let (_, diags) = run_with_path("G21\no<empty> call\nM2\n", vec![dir.clone()]);
    let _ = std::fs::remove_dir_all(&dir);
    let e = diags.first().expect("an error");
    assert!(
        e.message.contains("empty.ngc does not define o<empty> sub"),
        "{}",
        e.message
    );
}

#[test]
fn a_name_with_a_path_never_leaves_the_search_path() {
    // oword_lib/../oword_lib/peck.ngc exists, but a name is a file name, not a path.
    let (_, diags) = run_with_path("G21\no<../oword_lib/peck> call\nM2\n", vec![lib_dir()]);
    let e = diags.first().expect("an error");
    assert!(e.message.contains("is not defined"), "{}", e.message);
}

#[test]
fn o_bracket_labels_must_be_whole_numbers() {
    let (_, diags) = run_with_path(
        "G21\no100 sub\nG0 X1\no100 endsub\no[100.5] call\nM2\n",
        Vec::new(),
    );
    let e = diags.first().expect("an error");
    assert_eq!(e.span.line, 5);
    assert!(e.message.contains("not an o-word number"), "{}", e.message);
}

/// rs274 prints `(print, …)` on its output, outside the canonical calls; Oficina reports it
/// as a warning and emits no MESSAGE.
#[test]
fn print_is_reported_not_emitted() {
    let (text, diags) = run_with_path("#1=2\n(print, one #1)\nG0 X1\nM2\n", Vec::new());
    assert!(!text.contains("MESSAGE"), "{text}");
    assert_eq!(diags.len(), 1, "{diags:?}");
    assert_eq!(diags[0].severity, Severity::Warning);
    assert_eq!(diags[0].message, "(print)  one 2.000000");
}

/// rs274 stops with " stop at 3.000000" (the text after the comma, substituted).
#[test]
fn abort_stops_with_its_message() {
    let (text, diags) = run_with_path(
        "G21\n#1=3\nG0 X1\n(abort, stop at #1)\nG0 X2\nM2\n",
        Vec::new(),
    );
    assert!(!text.contains("2.0000, 0.0000, 0.0000"), "{text}");
    let e = diags.first().expect("an error");
    assert_eq!((e.span.line, e.message.as_str()), (4, " stop at 3.000000"));
}
