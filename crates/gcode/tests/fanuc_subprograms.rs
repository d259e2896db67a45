//! Fanuc-style subprograms (`O100` … `M99`, `M98 P… L…`) and the option that disables them,
//! LinuxCNC's `DISABLE_FANUC_STYLE_SUB`. The enabled behaviour is compared with `rs274` by
//! the corpus programs `tests/corpus/fanuc_*.ngc` (crates/cli/tests/differential.rs); the
//! disabled one needs an INI file, so it is checked here: the messages are rs274's, pasted,
//! and re-read from `rs274 -i` when it is installed.

#[path = "interp_support.rs"]
mod support;

use oficina_gcode::canon_of;

const BARE_O: &str = "O0001 (MAIN)\nG21\nG0 X1\nM2\n";
const M98: &str = "G21\nG0 X1\nM98 P100\nM2\nO100\nG0 X2\nM99\n";
const M99_MAIN: &str = "G21\nG0 X1\nM99\n";

/// The first error of `program` with Fanuc-style subprograms disabled.
fn disabled_error(program: &str) -> Option<(u32, String)> {
    let mut opts = support::rs274_options();
    opts.disable_fanuc_subs = true;
    let (_, diags) = canon_of(program, &opts);
    diags.first().map(|d| (d.span.line, d.message.clone()))
}

/// rs274's stderr for `program` run with `DISABLE_FANUC_STYLE_SUB = 1`, when rs274 exists.
fn rs274_disabled(program: &str) -> Option<String> {
    if !oficina_testkit::rs274::installed() {
        eprintln!("rs274 is not installed: only the pasted messages are checked");
        return None;
    }
    // One directory per program: the tests run in parallel.
    let dir = std::env::temp_dir().join(format!(
        "oficina-fanuc-{}-{}",
        std::process::id(),
        program.len()
    ));
    std::fs::create_dir_all(&dir).ok()?;
    let ini = dir.join("disabled.ini");
    let ngc = dir.join("p.ngc");
    std::fs::write(&ini, "[RS274NGC]\nDISABLE_FANUC_STYLE_SUB = 1\n").ok()?;
    std::fs::write(&ngc, program).ok()?;
    let out = oficina_testkit::rs274::command(&dir)
        .arg("-i")
        .arg(&ini)
        .arg("-g")
        .arg(&ngc)
        .output()
        .ok()?;
    let _ = std::fs::remove_dir_all(&dir);
    Some(String::from_utf8_lossy(&out.stderr).into_owned())
}

#[test]
fn disabled_bare_o_word_is_refused_with_rs274s_message() {
    let want = "DISABLE_FANUC_STYLE_SUB disabled in INI file, but found bare O-word";
    assert_eq!(disabled_error(BARE_O), Some((1, want.to_string())));
    if let Some(stderr) = rs274_disabled(BARE_O) {
        assert!(stderr.contains(want), "rs274 said: {stderr}");
    }
}

#[test]
fn disabled_m98_is_refused_with_rs274s_message() {
    let want = "DISABLE_FANUC_STYLE_SUB set in INI file, but found m98";
    assert_eq!(disabled_error(M98), Some((3, want.to_string())));
    if let Some(stderr) = rs274_disabled(M98) {
        assert!(stderr.contains(want), "rs274 said: {stderr}");
    }
}

#[test]
fn m99_ends_the_main_program_even_when_disabled() {
    let mut opts = support::rs274_options();
    opts.disable_fanuc_subs = true;
    let (ops, diags) = canon_of(M99_MAIN, &opts);
    assert!(diags.is_empty(), "{diags:?}");
    let text = oficina_gcode::to_rs274_text(&ops);
    assert!(text.contains("PROGRAM_END()"), "{text}");
    if let Some(stderr) = rs274_disabled(M99_MAIN) {
        assert!(!stderr.contains("DISABLE"), "rs274 said: {stderr}");
    }
}

/// An "endless" M99 main program runs once: the same calls as with M2, then the end.
#[test]
fn endless_m99_program_runs_once_like_m2() {
    let (with_m99, d1) = support::rs274_calls(M99_MAIN);
    let (with_m2, d2) = support::rs274_calls(&M99_MAIN.replace("M99", "M2"));
    assert!(d1.is_empty() && d2.is_empty(), "{d1:?} {d2:?}");
    assert_eq!(with_m99, with_m2);
    assert_eq!(
        with_m99
            .iter()
            .filter(|c| c.starts_with("STRAIGHT_TRAVERSE"))
            .count(),
        1
    );
}

/// `rs274 -g` on this program printed these traverses (pasted).
#[test]
fn m98_repeats_and_returns_to_the_line_after_the_call() {
    let (calls, diags) =
        support::rs274_calls("G21 G90\nM98 P7 L3\nG0 X0\nM2\nO7\nG91 G0 X2\nG90\nM99\n");
    assert!(diags.is_empty(), "{diags:?}");
    let traverses: Vec<&str> = calls
        .iter()
        .map(String::as_str)
        .filter(|c| c.starts_with("STRAIGHT_TRAVERSE"))
        .collect();
    assert_eq!(
        traverses,
        [
            "STRAIGHT_TRAVERSE(2.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
            "STRAIGHT_TRAVERSE(4.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
            "STRAIGHT_TRAVERSE(6.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
            "STRAIGHT_TRAVERSE(0.0000, 0.0000, 0.0000, 0.0000, 0.0000, 0.0000)",
        ]
    );
}
