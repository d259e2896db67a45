//! Whole-program output (state calls too, not only motion) compared with LinuxCNC's
//! standalone interpreter: each expectation is `rs274 -g -t tests/corpus/tool.tbl` on the same
//! program, the compared calls only (as the differential test keeps them), pasted verbatim
//! into `tests/rs274_calls/NAME.calls` (data, one call a line, named after its test).
//! Each test pins a difference that once existed; its name says which.

#[path = "interp_support.rs"]
mod support;

use support::{assert_calls, assert_rejected_on};

/// G93, G94 and G95 each print the feed mode (inverse time as per minute) and G94/G95 a zero feed.
#[test]
fn feed_mode_codes_forget_the_feed() {
    assert_calls(
        "G21 G94 F100\nG1 X1\nG95 S1000 F0.1\nG1 X2\nG93\nG1 X3 F2\nG94 F50\nG1 X4\nM2\n",
        include_str!("rs274_calls/feed_mode_codes_forget_the_feed.calls"),
    );
}

/// G54 under G54 prints nothing; a switch prints G5X, G92 and rotation; M2 G5X and rotation.
#[test]
fn reselecting_the_active_system_is_silent() {
    assert_calls(
        "G21 G54\nG10 L2 P2 X1 R10\nG92 X2\nG55\nG0 X1\nG55\nG54\nG0 X0\nM2\n",
        include_str!("rs274_calls/reselecting_the_active_system_is_silent.calls"),
    );
}

/// #5221…, #5211…, #5161… hold inches on rs274's inch machine, whatever G20/G21 says.
#[test]
fn offset_parameters_are_in_machine_units() {
    assert_calls(
        "G21\n#5221=3\n#5222=-2\nG54 G0 X0 Y0\n#5241=1\nG55 G0 X0\nG54\nG10 L2 P1 X1\nG92 X2\nG0 X1\n#5161=2\n#5162=1\nG28\nG20 G0 X1\n#5181=1\nG30 Z0.5\nM2\n",
        include_str!("rs274_calls/offset_parameters_are_in_machine_units.calls"),
    );
}

/// the corpus table's Z0.5 is 12.7 mm under G21 and 0.5 under G20.
#[test]
fn tool_table_is_in_machine_units() {
    assert_calls(
        "G21 T1 M6 G43\nG0 Z0\nG20 G43 H2\nG0 Z0\nM2\n",
        include_str!("rs274_calls/tool_table_is_in_machine_units.calls"),
    );
}

/// M2 after M7 prints MIST_OFF only; after M8 FLOOD_OFF only.
#[test]
fn program_end_turns_off_only_the_coolant_that_is_on() {
    assert_calls(
        "G21 M7\nG0 X1\nM2\n",
        include_str!("rs274_calls/program_end_turns_off_only_the_coolant_that_is_on.calls"),
    );
}

/// (DEBUG,…) prints a MESSAGE; #<_x> and #<_abs_x> follow the moves.
#[test]
fn debug_comments_are_messages_with_current_values() {
    assert_calls(
        "G21 G10 L2 P1 X1\nG0 X2 Y3\n(DEBUG, x #<_x> y #<_y> absx #<_abs_x>)\nG0 X#<_y>\nM2\n",
        include_str!("rs274_calls/debug_comments_are_messages_with_current_values.calls"),
    );
}

/// under G93 each feed move gets SET_FEED_RATE(length × F), lines and arcs, in program units.
#[test]
fn inverse_time_feed_is_printed_as_a_rate() {
    assert_calls(
        "G21 G93\nG1 X10 F2\nG2 X20 Y0 R5 F1\nG3 X10 Y0 I-5 J0 Z1 F3\nG3 X10 Y0 I5 F0.5\nG20 G1 X1 F2\nG94 G21 F100 G1 X0\nM2\n",
        include_str!("rs274_calls/inverse_time_feed_is_printed_as_a_rate.calls"),
    );
}

/// G87: the spindle stops after the move to the offset point at R.
#[test]
fn back_boring_moves_off_centre_before_stopping_the_spindle() {
    assert_calls(
        "G21 G0 Z10\nM3 S500\nG98 G87 X1 Y1 Z-3 R1 I0.5 J0.5 K-6 F100\nG80\nM2\n",
        include_str!("rs274_calls/back_boring_moves_off_centre_before_stopping_the_spindle.calls"),
    );
}

/// rs274: `Straight feed in concave corner cannot be reached by the tool without gouging` at `Y0.5`.
#[test]
fn concave_corner_too_small_gouges() {
    assert_rejected_on("G21 G17 G90 G94\nT2 M6\nG0 X-10 Y-10\nG41 D2 G1 X0 Y0 F100\nG1 X20\nY20\nX19\nY0.5\nX0\nG40 G1 X-10 Y-10\nM2\n", 8);
}

/// rs274: `Cannot change tools with cutter radius compensation on` at `T1 M6`.
#[test]
fn tool_change_under_cutter_comp() {
    assert_rejected_on(
        "G21 G17 G90 G94\nT2 M6\nG0 X-5 Y-5\nG41 D2 G1 X0 Y0 F100\nT1 M6\nG40\nM2\n",
        5,
    );
}

/// rs274: `Requested tool 77 not found in the tool table` at `G10 L1 P77 Z1`.
#[test]
fn g10_l1_tool_not_in_table() {
    assert_rejected_on("G21\nG10 L1 P77 Z1\nM2\n", 2);
}

/// rs274: `Cannot feed with zero spindle speed in feed per rev mode` at `G95 F0.2 G1 X3`.
#[test]
fn feed_per_rev_without_spindle_speed() {
    assert_rejected_on("G21 G17 G90 G94\nG95 F0.2 G1 X3\nM2\n", 2);
}

/// rs274: `File ended with no percent sign or program end` at `G1 X2 F100`.
#[test]
fn file_without_program_end() {
    assert_rejected_on("G21 G0 X1\nG1 X2 F100\n", 2);
}

/// rs274: `File ended with no percent sign` at `G1 X2 F100`.
#[test]
fn percent_file_without_closing_percent() {
    assert_rejected_on("%\nG21 G0 X1\nG1 X2 F100\n", 3);
}
/// G80 on its own line cancels the cycle: the next G98 cycle starts from the current height.
#[test]
fn g80_alone_ends_a_run_of_cycles() {
    assert_calls(
        "G21 F100\nG98 G81 X1 Y-2 Z-5 R2.4\nG80\nG98 G81 X-9 Y8 Z-2 R1.9\nG80\nM2\n",
        include_str!("rs274_calls/g80_alone_ends_a_run_of_cycles.calls"),
    );
}

/// after a cycle rs274 restores G61.1 and restates the naive-CAM tolerance.
#[test]
fn cycles_restore_the_naive_cam_tolerance_in_every_mode() {
    assert_calls(
        "G21 G64 P0.1 Q0.05\nG61.1\nF100 M3 S100\nG81 X1 Y1 Z-1 R1\nG80\nM2\n",
        include_str!("rs274_calls/cycles_restore_the_naive_cam_tolerance_in_every_mode.calls"),
    );
}

/// M2 prints ENABLE_FEED_OVERRIDE after M49 (and only the feed one).
#[test]
fn program_end_turns_the_feed_override_back_on() {
    assert_calls(
        "G21 M49\nG0 X1\nM2\n",
        include_str!("rs274_calls/program_end_turns_the_feed_override_back_on.calls"),
    );
}

/// under rotation G10 L20 X… moves both XY offsets so Y still reads the same.
#[test]
fn g10_l20_keeps_the_reading_of_the_axis_not_named() {
    assert_calls(
        "G21 G10 L2 P1 X1 Y2 R30\nG0 X3 Y4\nG10 L20 P1 X5\nG1 X0 F100\nM2\n",
        include_str!("rs274_calls/g10_l20_keeps_the_reading_of_the_axis_not_named.calls"),
    );
}
