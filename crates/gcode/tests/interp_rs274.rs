//! Motion calls compared with LinuxCNC's standalone interpreter: each expectation is the
//! output of `rs274 -t tests/corpus/tool.tbl -g` on the same program (motion lines only,
//! the text after `N..... `), pasted verbatim into `tests/rs274_calls/NAME.motion`.

#[path = "interp_support.rs"]
mod support;

use oficina_gcode::Dialect;
use oficina_gcode::StartState;

fn check(program: &str, rs274: &str) {
    let r = support::run_with(
        program,
        Dialect::LinuxCnc,
        support::corpus_tools(),
        StartState::default(),
    );
    assert!(r.errors.is_empty(), "{:?}", r.errors);
    support::assert_motion(&r.ops, rs274);
}

#[test]
fn arcs_match_rs274() {
    check(
        "G21 G17 G90\nG0 X1 Y2\nG1 F100 X10 Y2 Z3\nG2 X20 Y2 I5 J0\nG3 X10 Y2 R5\nG2 X0 Y0 R-7\nG3 X0 Y0 I3 J4 Z-2 P2\nG18 G2 X5 Z-2 I2.5 K0\nG19 G3 Y5 Z3 R5\nM2\n",
        include_str!("rs274_calls/arcs_match_rs274.motion"),
    );
}

#[test]
fn offsets_match_rs274() {
    check(
        "G21\nG10 L2 P1 X25.4 Y10 R10\nG92 X1\nG1 F100 X10 Y5\nG20\nG1 X1\nG21 G55\nG0 X0 Y0\nG10 L2 P2 X-5 Y-5 Z1\nG0 X0 Y0 Z0\nG92.1\nG53 G0 X0 Y0\nG54 G92.2 G0 X1\nM2\n",
        include_str!("rs274_calls/offsets_match_rs274.motion"),
    );
}

#[test]
fn cycles_match_rs274() {
    check(
        "G21 G17 G90 F100\nG0 Z5\nG98 G81 R1 Z-1 X1\nG99 X2\nG91 G98 X1 L2 R1 Z-2\nG90 G83 X5 Y0 R2 Z-3.5 Q1\nG73 X6 R2 Z-3.5 Q1\nG82 X7 R2 Z-1 P0.5\nG80 G0 Z10\nM2\n",
        include_str!("rs274_calls/cycles_match_rs274.motion"),
    );
}

#[test]
fn comp_match_rs274() {
    check(
        "G21 G17 G90\nT1 M6\nG0 X-10 Y-10\nG41 G1 X0 Y0 F100\nX20\nY20\nX0\nY0\nG40 G0 X-10 Y-10\nG42 G1 X0 Y0\nX20\nG3 X20 Y20 R10\nG1 X0\nY0\nG40 G0 X-10 Y-10\nM2\n",
        include_str!("rs274_calls/comp_match_rs274.motion"),
    );
}

#[test]
fn tool_length_inch_match_rs274() {
    check(
        "G20 G17 G90\nT2 M6 G43\nG0 X1 Y1 Z1\nG1 F10 Z-0.1\nG49 G0 Z2\nM2\n",
        include_str!("rs274_calls/tool_length_inch_match_rs274.motion"),
    );
}
