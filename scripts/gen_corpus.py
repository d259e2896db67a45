#!/usr/bin/env python3
"""Generate the differential G-code corpus in tests/corpus/ (good) and tests/corpus/bad/.

The programs are deterministic; the output is committed so the corpus can be read and
reviewed without running this script. Re-run after editing:

    python3 scripts/gen_corpus.py && scripts/check_corpus.sh

Every good program must run to completion under LinuxCNC's `rs274 -g -t tests/corpus/tool.tbl`
and every bad one must be rejected by it (scripts/check_corpus.sh verifies both).
"""

import os

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "corpus")
GOOD = {}
BAD = {}


def good(name, text):
    assert name not in GOOD, name
    GOOD[name] = text


def bad(name, text):
    assert name not in BAD, name
    BAD[name] = text


def prog(*lines, units="G21", end="M2"):
    """A program with a safe preamble (units, plane, absolute, feed) and an end code."""
    body = [f"{units} G17 G90 G94 G40 G49 G80 G54"] + list(lines) + [end]
    return "\n".join(body) + "\n"


# --- straight moves -------------------------------------------------------------------------
good("line_g0_g1_abs", prog("G0 X1 Y2 Z3", "F200", "G1 X10 Y2", "G1 Y12 Z-1", "G0 Z5", "X0 Y0"))
good("line_g91_incremental", prog("G0 X1 Y1", "G91", "G1 X5 F150", "Y5", "X-5 Y-5 Z-2", "G0 Z2", "G90 G0 X0 Y0"))
good("line_modal_motion", prog("F120 G1 X1", "X2", "Y3", "Z-1", "X0 Y0 Z0"))
good("line_inch", prog("G0 X1 Y1", "G1 X2.5 F10", "Y0.125", units="G20"))
good("line_inch_mm_switch", prog("G0 X1", "G20 G0 X1", "G21 G1 X3 F100", "G20 G1 Y1 F4", "G21 G0 Z2"))
good("line_abc_axes", prog("G0 A10 B20 C30", "G1 X5 A45 F100", "G1 B-90 C0 Y2", "G91 G1 A10", "G90 G0 A0 B0 C0"))
good("line_numbers_formats", prog("G0 X.5 Y-.25 Z+1.", "G1 X0010.000 F+100.", "G1 X-0.0001"))
good("line_only_feed_and_speed", prog("F50", "S1000", "G1 X1", "F25.5 X2"))
good("line_rapid_many", prog(*[f"G0 X{i * 1.5:.3f} Y{(i * 7) % 11 * 0.7:.3f}" for i in range(40)]))
good("line_feed_many", prog("F333", *[f"G1 X{(i * 13) % 17 * 0.9:.4f} Y{(i * 5) % 7 * 1.3:.4f} Z{-(i % 3) * 0.2:.2f}" for i in range(60)]))

# --- arcs: every plane, direction and form ----------------------------------------------------
PLANES = {
    "g17": ("G17", "X", "Y", "Z", "I", "J"),
    "g18": ("G18", "Z", "X", "Y", "K", "I"),
    "g19": ("G19", "Y", "Z", "X", "J", "K"),
}
for pname, (pcode, a, b, n, ia, ib) in PLANES.items():
    for dcode in ("G2", "G3"):
        pre = [f"{pcode} F100", f"G0 {a}0 {b}0 {n}1"]
        good(f"arc_{pname}_{dcode.lower()}_offsets", prog(*pre, f"G1 {n}0", f"{dcode} {a}10 {b}0 {ia}5 {ib}0", f"{dcode} {a}5 {b}5 {ia}-5 {ib}0"))
        good(f"arc_{pname}_{dcode.lower()}_radius", prog(*pre, f"{dcode} {a}10 {b}0 R5", f"{dcode} {a}10 {b}6 R3.5", f"{dcode} {a}0 {b}0 R8"))
        good(f"arc_{pname}_{dcode.lower()}_neg_radius", prog(*pre, f"{dcode} {a}10 {b}0 R-6", f"{dcode} {a}4 {b}4 R-9"))
        good(f"arc_{pname}_{dcode.lower()}_full_circle", prog(*pre, f"G1 {a}5", f"{dcode} {ia}3 {ib}0", f"{dcode} {a}5 {b}0 {ia}-2 {ib}1"))
        good(f"arc_{pname}_{dcode.lower()}_helix", prog(*pre, f"{dcode} {a}10 {b}0 {n}-2 {ia}5 {ib}0", f"{dcode} {a}10 {b}0 {n}-6 {ia}-5 {ib}0 P3"))
        good(f"arc_{pname}_{dcode.lower()}_incremental", prog(*pre, "G91", f"{dcode} {a}4 {b}4 {ia}4 {ib}0", f"{dcode} {a}-4 {b}-4 R4", "G90"))
        good(f"arc_{pname}_{dcode.lower()}_abs_centres", prog(*pre, "G90.1", f"{dcode} {a}10 {b}0 {ia}5 {ib}0", f"{dcode} {a}0 {b}0 {ia}5 {ib}0", "G91.1", f"{dcode} {a}10 {b}0 {ia}5 {ib}0"))
good("arc_inch_mixed", prog("G0 X0 Y0", "G2 X1 Y1 I1 J0 F5", "G3 X2 Y0 R1", "G2 X2 Y0 I0.5 P2 Z-0.1", units="G20"))
good("arc_small_segments", prog("G0 X0 Y0 F400", *[f"G{2 + i % 2} X{i + 1} Y0 R0.5" for i in range(30)]))
good("arc_quadrants", prog("G0 X10 Y0 F300", "G3 X0 Y10 I-10 J0", "G3 X-10 Y0 I0 J-10", "G3 X0 Y-10 I10 J0", "G3 X10 Y0 I0 J10"))
good("arc_tiny_radius_diff", prog("G0 X0 Y0 F300", "G2 X10 Y0 I5.0004 J0"))
good("arc_helix_abc", prog("G0 X0 Y0 F100", "G2 X0 Y0 I5 J0 Z-3 A90"))

# --- dwell ----------------------------------------------------------------------------------
good("dwell_basic", prog("G4 P0.5", "G0 X1", "G4 P2", "G4 P0"))
good("dwell_with_motion_modal", prog("G1 X1 F100", "G4 P1.25", "X2", "G4 P[1+2]"))

# --- coordinate systems, G10, G52, G53, G92 --------------------------------------------------
WCS = ["G54", "G55", "G56", "G57", "G58", "G59", "G59.1", "G59.2", "G59.3"]
for p, w in enumerate(WCS, start=1):
    good(f"wcs_{w.lower().replace('.', '_')}_l2", prog(f"G10 L2 P{p} X{p} Y{-p * 2} Z{p * 0.5}", w, "G0 X0 Y0 Z0", "G1 X5 Y5 F100", "G54"))
good("wcs_g10_l2_p0_current", prog("G55", "G10 L2 P0 X3 Y4", "G0 X0 Y0", "G54 G0 X0 Y0"))
good("wcs_g10_l2_rotation", prog("G10 L2 P1 X1 Y1 R30", "G0 X10 Y0", "G1 X10 Y10 F100", "G2 X0 Y10 R5", "G10 L2 P1 R0"))
good("wcs_g10_l20", prog("G0 X2 Y3", "G10 L20 P1 X0 Y0", "G0 X1 Y1", "G10 L20 P2 Z10", "G55 G0 Z0", "G54"))
good("wcs_g10_l20_incremental_mode", prog("G91 G0 X2 Y2", "G10 L20 P1 X1", "G0 X1", "G90 G0 X0"))
good("wcs_g52_local", prog("G0 X1 Y1", "G52 X10 Y10", "G0 X1 Y1", "G1 X2 F100", "G52 X0 Y0", "G0 X1 Y1"))
good("wcs_g53_machine", prog("G10 L2 P1 X5 Y5", "G0 X0 Y0", "G53 G0 X0 Y0", "G53 G1 X1 Y1 F100", "G0 X1 Y1"))
good("wcs_g92_family", prog("G0 X3 Y3", "G92 X0 Y0", "G0 X1 Y1", "G92.2", "G0 X1 Y1", "G92.3", "G0 X1 Y1", "G92.1", "G0 X1 Y1"))
good("wcs_g92_with_g55", prog("G10 L2 P2 X10", "G55 G0 X0", "G92 X1", "G0 X0", "G54 G0 X0", "G92.1", "G0 X0"))
good("wcs_g92_inch", prog("G0 X1", "G92 X0", "G0 X1", "G21 G0 X1", "G20 G92.1 G0 X0", units="G20"))
good("wcs_params_direct", prog("#5221 = 3", "#5222 = -2", "G54 G0 X0 Y0", "#5241 = 1", "G55 G0 X0 Y0", "G54"))

# --- G28 / G30 ------------------------------------------------------------------------------
good("home_g28_default", prog("G0 X5 Y5 Z5", "G28", "G0 X1"))
good("home_g28_1_store", prog("G0 X3 Y4 Z5", "G28.1", "G0 X0 Y0 Z0", "G28", "G28 X1 Y1"))
good("home_g30_params", prog("#5181 = 10", "#5182 = 20", "#5183 = 3", "G0 X1 Y1 Z1", "G30", "G30 Z6"))
good("home_g30_1_store", prog("G0 X7 Y8 Z9", "G30.1", "G0 X0 Y0 Z0", "G30"))
good("home_g28_incremental", prog("#5161 = 2", "#5162 = 2", "G0 X5 Y5", "G91 G28 X1 Y0", "G90"))
good("home_g28_wcs", prog("G10 L2 P1 X10 Y10", "#5161 = 1", "G0 X0 Y0", "G28"))

# --- planes, units, distance mode -----------------------------------------------------------
good("plane_switching", prog("G18", "G19", "G17", "G0 X1", "G18 G2 X1 Z2 R2 F100", "G17"))
good("units_inch_program", prog("G0 X0.5 Y0.5", "G1 X1.5 F12", "G2 X2.5 Y0.5 R1", "G4 P1", units="G20"))

# --- control modes --------------------------------------------------------------------------
good("ctrl_g61_g64", prog("G61", "G1 X1 F100", "G61.1", "G1 X2", "G64", "G1 X3", "G64 P0.05", "G1 X4", "G64 P0.05 Q0.01", "G1 X5"))
good("ctrl_g64_inch", prog("G64 P0.001 Q0.0005", "G1 X1 F10", units="G20"))

# --- feed modes -----------------------------------------------------------------------------
good("feed_g93_inverse", prog("G93", "G1 X10 F2", "G1 Y10 F0.5", "G2 X0 Y10 R10 F1", "G94 F100 G1 X0 Y0"))
good("feed_g95_per_rev", prog("M3 S1000", "G95 G1 X10 F0.1", "Y5 F0.05", "G94 G1 X0 F200", "M5"))
good("feed_mode_switches", prog("F100", "G93 G1 X1 F3", "G94", "G1 X2 F50", "S100 M3", "G95 F0.2 G1 X3", "G94", "M5"))

# --- spindle, coolant, tools, overrides -----------------------------------------------------
good("spindle_m3_m4_m5", prog("S1200 M3", "G1 X1 F100", "M4", "S800", "M5", "M3 S3000", "M5"))
good("coolant_m7_m8_m9", prog("M7", "M8", "G0 X1", "M9", "M8", "M9"))
good("tool_m6_sequence", prog("T1 M6", "G43", "G0 Z1", "T2", "M6", "G43 H2", "G0 Z1", "T5 M6 G43", "G0 Z0", "G49"))
good("tool_g43_h_other", prog("T1 M6", "G43 H4", "G0 Z0", "G43 H10", "G0 Z0", "G49 G0 Z0"))
good("tool_g43_1_dynamic", prog("G43.1 Z2.5", "G0 Z0", "G43.1 Z-1", "G0 Z0", "G49", "G0 Z0"))
good("tool_g10_l1", prog("G10 L1 P3 Z0.2 R0.05", "T3 M6 G43", "G0 Z0", "G10 L1 P4 Z0.5", "T4 M6 G43", "G0 Z1"))
good("tool_g10_l10", prog("T2 M6", "G0 Z10", "G10 L10 P2 Z5", "G43 H2", "G0 Z5"))
good("tool_t0_unload", prog("T1 M6", "T0 M6", "G0 X1"))
good("tool_inch", prog("T2 M6 G43", "G0 Z1", "G41 D2 G1 X1 Y0 F5", "Y1", "G40 G1 X0 Y0", units="G20"))
good("override_m48_m53", prog("M48", "M49", "M48", "M50 P0", "M50 P1", "M50", "M51 P0", "M51 P1", "M52 P1", "M52 P0", "M53 P1", "M53 P0", "G0 X1"))
good("prog_m0_m1", prog("G0 X1", "M0", "G0 X2", "M1", "G0 X3"))
good("prog_m30_end", prog("M3 S100", "M8", "G1 X1 F10", end="M30"))
good("prog_m2_resets", prog("G91 G0 X1", "G20", "M3 S10 M8", "G93 F1 G1 X1"))
good("prog_percent_delimited", "%\nG21 G0 X1\nG1 Y2 F100\n%\n")

# --- cutter compensation --------------------------------------------------------------------
def cc(name, *lines, units="G21"):
    good(name, prog("T2 M6", *lines, units=units))


# A square traversed counter-clockwise has its inside on the left (G41), clockwise on the right.
cc("comp_g41_square_inside", "G0 X10 Y10", "G41 D2 G1 X0 Y0 F100", "X20", "Y20", "X0", "Y0", "G40 G1 X10 Y10")
cc("comp_g42_square_inside", "G0 X10 Y10", "G42 D2 G1 X0 Y0 F100", "Y20", "X20", "Y0", "X0", "G40 G1 X10 Y10")
cc("comp_g41_square_outside", "G0 X-10 Y-10", "G41 D2 G1 X0 Y0 F100", "Y20", "X20", "Y0", "X0", "G40 G1 X-10 Y-10")
cc("comp_g42_square_outside", "G0 X-10 Y-10", "G42 D2 G1 X0 Y0 F100", "X20", "Y20", "X0", "Y0", "G40 G1 X-10 Y-10")
cc("comp_g41_circle_outside", "G0 X-10 Y0", "G41 D2 G1 X0 Y0 F100", "G2 X0 Y0 I10 J0", "G40 G1 X-10 Y0")
cc("comp_g42_circle_inside", "G0 X10 Y0", "G42 D2 G1 X0 Y0 F100", "G2 X0 Y0 I10 J0", "G40 G1 X10 Y0")
cc("comp_g41_line_arc_mix", "G0 X-5 Y-5", "G41 D2 G1 X0 Y0 F100", "X10", "G3 X20 Y10 I0 J10", "G1 Y20", "G3 X10 Y30 R10", "G1 X0", "Y0", "G40 G1 X-5 Y-5")
cc("comp_g42_line_arc_mix", "G0 X-5 Y-5", "G42 D2 G1 X0 Y0 F100", "Y20", "G2 X10 Y30 R10", "G1 X20", "G2 X30 Y20 I0 J-10", "G1 Y0", "X0", "G40 G1 X-5 Y-5")
cc("comp_g41_1_dynamic", "G0 X-5 Y-5", "G41.1 D4 G1 X0 Y0 F100", "X10", "Y10", "X0", "Y0", "G40 G0 X-5 Y-5")
cc("comp_g42_1_dynamic_lr", "G0 X-5 Y-5", "G42.1 D3 G1 X0 Y0 F100", "Y10", "X10", "Y0", "X0", "G40 G0 X-5 Y-5")
cc("comp_entry_arc", "G0 X-10 Y0", "G41 D2 G1 X-5 Y0 F100", "G3 X0 Y5 I5 J0", "G1 X10", "Y-5", "G40 G1 X20 Y-5")
cc("comp_z_moves_between", "G0 X-10 Y-10 Z5", "G41 D2 G1 X0 Y0 F100", "G1 Z-1", "X10", "Z-2", "Y10", "G0 Z5", "G40 G0 X-10 Y-10")
cc("comp_obtuse_and_acute", "G0 X-10 Y0", "G41 D2 G1 X0 Y0 F100", "X10 Y2", "X20 Y0", "X15 Y15", "X0 Y10", "X0 Y0", "G40 G1 X-10 Y0")
cc("comp_inch", "G0 X-1 Y-1", "G41 D2 G1 X0 Y0 F10", "X2", "Y2", "G40 G1 X3 Y3", units="G20")
cc("comp_tool_change_radius", "T1 M6", "G0 X-10 Y0", "G42 D1 G1 X0 Y0 F100", "X10", "G2 X20 Y0 R5", "G40 G1 X30 Y-5", "G41 D5 G1 X30 Y0", "X40", "G40 G1 X50 Y5")
cc("comp_incremental", "G0 X-5 Y-5", "G91", "G41 D2 G1 X5 Y5 F100", "X10", "Y10", "X-10", "G40 G1 X-5 Y-5", "G90")
cc("comp_g41_tangent_arcs", "G0 X-10 Y0", "G41 D2 G1 X0 Y0 F100", "G2 X10 Y0 R5", "G3 X20 Y0 R5", "G2 X30 Y0 R5", "G40 G1 X40 Y0")
cc("comp_exit_arc_move", "G0 X0 Y-10", "G42 D2 G1 X0 Y0 F100", "X10", "G40", "G1 X20 Y-10")

# --- canned cycles --------------------------------------------------------------------------
def cyc(name, *lines, units="G21"):
    good(name, prog("G0 Z10", *lines, "G80", "G0 Z10", units=units))


for ret in ("G98", "G99"):
    r = ret.lower()
    cyc(f"cycle_g81_{r}", f"{ret} G81 X1 Y1 Z-2 R1 F100", "X5", "Y5", "X1")
    cyc(f"cycle_g82_{r}", f"{ret} G82 X1 Y1 Z-2 R1 P0.5 F100", "X5 Y3")
    cyc(f"cycle_g83_{r}", f"{ret} G83 X1 Y1 Z-5 R1 Q1.5 F100", "X4")
    cyc(f"cycle_g73_{r}", f"{ret} G73 X1 Y1 Z-5 R1 Q1.2 F100", "X4")
    cyc(f"cycle_g84_{r}", "M3 S500", f"{ret} G84 X1 Y1 Z-3 R1 F50", "X3")
    cyc(f"cycle_g85_{r}", f"{ret} G85 X1 Y1 Z-3 R1 F100", "X3")
    cyc(f"cycle_g86_{r}", "M3 S500", f"{ret} G86 X1 Y1 Z-3 R1 P0.2 F100", "X3")
    cyc(f"cycle_g88_{r}", "M3 S500", f"{ret} G88 X1 Y1 Z-3 R1 P0.3 F100", "X3")
    cyc(f"cycle_g89_{r}", f"{ret} G89 X1 Y1 Z-3 R1 P0.4 F100", "X3")
cyc("cycle_g87_back_bore", "M3 S500", "G98 G87 X1 Y1 Z-3 R1 I0.5 J0.5 K-6 F100")
cyc("cycle_g81_g91_repeat", "G0 X0 Y0", "G91 G99 G81 X2 Y1 Z-3 R-8 L4 F100", "G90")
cyc("cycle_g83_g91_repeat", "G0 X0 Y0", "G91 G98 G83 X3 Z-4 R-9 Q1 L3 F100", "G90")
cyc("cycle_g73_g91_repeat", "G0 X0 Y0", "G91 G99 G73 Y2 Z-4 R-9 Q1 L2 F100", "G90")
cyc("cycle_g82_g91_repeat", "G0 X0 Y0", "G91 G98 G82 X-1 Y-1 Z-2 R-9 P0.1 L5 F100", "G90")
cyc("cycle_g81_repeat_abs", "G0 X0 Y0", "G90 G81 X2 Y2 Z-3 R1 L3 F100")
cyc("cycle_g81_plane_g18", "G18", "G0 Y10", "G81 X1 Z1 Y-2 R5 F100", "X3", "G17")
cyc("cycle_g81_plane_g19", "G19", "G0 X10", "G81 Y1 Z1 X-2 R5 F100", "Z3", "G17")
cyc("cycle_g81_inch", "G0 Z1", "G81 X0.1 Y0.1 Z-0.1 R0.05 F5", "X0.2", units="G20")
cyc("cycle_r_below_start", "G0 Z0.5", "G98 G81 X1 Y1 Z-2 R1 F100", "X2")
cyc("cycle_modal_reuse", "G81 X1 Y1 Z-1 R2 F100", "X2", "Z-3", "R3 X4", "G82 Z-2 R3 P0.1 X5", "G83 Z-2 R3 Q0.5 X6")
cyc("cycle_with_tool_offset", "T1 M6 G43", "G0 Z5", "G81 X1 Y1 Z-2 R1 F100", "X2")

# --- parameters and expressions ---------------------------------------------------------------
good("param_numbered", prog("#1 = 5", "#2 = [#1 * 2]", "#3 = #2", "G0 X#1 Y#2 Z#3", "#[#1] = 7", "G1 X#5 F100"))
good("param_same_line_semantics", prog("#1 = 1", "#1 = 2 G0 X#1", "G0 X#1", "#2 = 3 #3 = #2", "G0 Y#3"))
good("param_named_local_global", prog("#<width> = 12.5", "#<_glob> = 3", "G0 X#<width> Y#<_glob>", "#<Mixed Case name> = 4", "G0 Z#<mixedcasename>"))
good("param_system_read", prog("G0 X3 Y4", "#1 = #5420", "#2 = #5421", "G0 X[#1 + #2]", "#3 = #<_x>", "G0 Y#3"))
good("param_persistent_ranges", prog("#100 = 1.5", "#4999 = 2", "#31 = 3", "G0 X[#100 + #4999 + #31]"))
good("expr_operators", prog("#1 = [2 + 3 * 4]", "#2 = [[2 + 3] * 4]", "#3 = [2 ** 3 ** 2]", "#4 = [17 MOD 5]", "#5 = [-17 MOD 5]", "#6 = [10 / 4 - 1]", "G0 X#1 Y#2 Z#3", "G0 X#4 Y#5 Z#6"))
good("expr_logical", prog("#1 = [1 EQ 1]", "#2 = [1 NE 1]", "#3 = [2 GT 1]", "#4 = [2 GE 2]", "#5 = [1 LT 2]", "#6 = [3 LE 2]",
                          "G0 X#1 Y#2 Z#3", "G0 X#4 Y#5 Z#6", "#7 = [1 AND 0]", "#8 = [1 OR 0]", "#9 = [1 XOR 1]", "G0 X#7 Y#8 Z#9"))
good("expr_functions_trig", prog("G0 X[SIN[30]] Y[COS[60]] Z[TAN[45]]", "G0 X[ASIN[0.5]] Y[ACOS[0.5]] Z[ATAN[1]/[1]]", "G0 X[ATAN[-1]/[-1]] Y[ATAN[1]/[-1]]"))
good("expr_functions_misc", prog("G0 X[ABS[-3.5]] Y[SQRT[16]] Z[EXP[1]]", "G0 X[LN[10]] Y[FIX[-2.5]] Z[FUP[-2.5]]", "G0 X[ROUND[2.5]] Y[ROUND[-2.5]] Z[FIX[2.7] + FUP[2.2]]"))
good("expr_exists", prog("#<a> = 1", "G0 X[EXISTS[#<a>]] Y[EXISTS[#<nope>]]"))
good("expr_precedence_mix", prog("#1 = [1 + 2 * 3 ** 2 / 9 - 4 MOD 3]", "#2 = [1 + 2 GT 2 AND 3 LT 4]", "#3 = [-[2] ** 2]", "G0 X#1 Y#2 Z#3"))
good("expr_nested_deep", prog("G0 X[[[[1 + 2] * [3 - 4]] / [5 + 6]] * 11] Y[ABS[[SIN[90] - 2] * 3]]"))
good("expr_in_words", prog("G[0] X1", "F[50 * 2] G[1] X[2 + 1]", "S[1000 / 2] M[3]", "M5", "G4 P[0.25 * 2]"))

# --- O-word control flow ----------------------------------------------------------------------
def oword(name, *lines):
    good(name, "\n".join(["G21 G17 G90 G94"] + list(lines) + ["M2"]) + "\n")


oword("o_sub_call_args", "o100 sub", "G0 X#1 Y#2", "G1 Z#3 F100", "o100 endsub", "o100 call [1] [2] [-1]", "o100 call [4] [5] [-2]")
oword("o_sub_return_value", "o200 sub", "o200 return [#1 * 2]", "o200 endsub", "o200 call [21]", "G0 X#<_value>")
oword("o_sub_named", "o<square> sub", "G1 X#1 F100", "Y#1", "X0", "Y0", "o<square> endsub", "o<square> call [5]", "o<square> call [2.5]")
oword("o_sub_nested", "o1 sub", "G0 X#1", "o1 endsub", "o2 sub", "o1 call [#1 + 1]", "o1 call [#1 + 2]", "o2 endsub", "o2 call [10]")
oword("o_sub_locals_restored", "#1 = 99", "o3 sub", "#1 = 5", "G0 X#1", "o3 endsub", "o3 call [1]", "G0 Y#1")
oword("o_sub_return_early", "o4 sub", "o4 if [#1 GT 2]", "o4 return", "o4 endif", "G0 X#1", "o4 endsub", "o4 call [1]", "o4 call [3]", "o4 call [2]")
oword("o_if_elseif_else", "#1 = 2", "o10 if [#1 EQ 1]", "G0 X1", "o10 elseif [#1 EQ 2]", "G0 X2", "o10 else", "G0 X3", "o10 endif",
      "o11 if [0]", "G0 Y9", "o11 else", "G0 Y1", "o11 endif")
oword("o_while", "#1 = 0", "o20 while [#1 LT 5]", "G0 X#1", "#1 = [#1 + 1]", "o20 endwhile")
oword("o_do_while", "#1 = 10", "o21 do", "G0 X#1", "#1 = [#1 + 1]", "o21 while [#1 LT 3]", "#2 = 0", "o22 do", "G0 Y#2", "#2 = [#2 + 1]", "o22 while [#2 LT 3]")
oword("o_repeat", "o30 repeat [4]", "G91 G0 X1", "o30 endrepeat", "G90 G0 X0", "o31 repeat [0]", "G0 Y5", "o31 endrepeat")
oword("o_break_continue", "#1 = 0", "o40 while [#1 LT 10]", "#1 = [#1 + 1]", "o41 if [#1 MOD 2 EQ 0]", "o40 continue", "o41 endif",
      "o42 if [#1 GT 7]", "o40 break", "o42 endif", "G0 X#1", "o40 endwhile", "G0 Y#1")
oword("o_loop_spiral", "#<r> = 1", "F200", "o50 while [#<r> LE 5]", "G1 X#<r> Y0", "G3 X[-#<r>] Y0 R#<r>", "G3 X#<r> Y0 R#<r>", "#<r> = [#<r> + 1]", "o50 endwhile")
oword("o_sub_recursive", "o60 sub", "G0 X#1", "o61 if [#1 GT 0]", "o60 call [#1 - 1]", "o61 endif", "o60 endsub", "o60 call [4]")
oword("o_named_flow", "#<i> = 0", "o<loop> while [#<i> LT 3]", "o<inner> repeat [2]", "G91 G0 Y1", "o<inner> endrepeat", "G90 G0 X#<i>", "#<i> = [#<i> + 1]", "o<loop> endwhile")
oword("o_sub_grid_holes", "o<hole> sub", "G0 X#1 Y#2", "G1 Z-1 F100", "G0 Z1", "o<hole> endsub",
      "#<x> = 0", "o70 while [#<x> LT 3]", "#<y> = 0", "o71 while [#<y> LT 2]", "o<hole> call [#<x> * 10] [#<y> * 10]", "#<y> = [#<y> + 1]", "o71 endwhile", "#<x> = [#<x> + 1]", "o70 endwhile")
oword("o_sub_defined_after_use_order", "o80 sub", "G0 X1", "o80 endsub", "G0 X0", "o80 call", "G0 X2")
oword("o_sub_return_in_loop", "o90 sub", "#2 = 0", "o91 while [1]", "#2 = [#2 + 1]", "o92 if [#2 GE #1]", "o90 return [#2]", "o92 endif", "o91 endwhile", "o90 endsub", "o90 call [4]", "G0 X#<_value>")

# --- comments, messages, block delete, spelling -----------------------------------------------
good("text_comments", prog("(a comment)", "G0 X1 (inline comment) Y2", "G1 X2 F100 ; semicolon comment", "(MSG, hello operator)", "(msg,lower case msg)", "(DEBUG, x is #<_x>)"))
good("text_block_delete", prog("/G0 X5", "G0 X1", "/ G1 X2 F100", "G0 Y1"))
good("text_case_and_spacing", prog("g0x1y2", "G 1 X 3 . 5 F 1 0 0", "g1   y-2.25", "\tG0\tZ1", "n10 g0 x0", "N20G0Y0", "  G0   X  1  "))
good("text_line_numbers", prog("N1 G0 X1", "N2 G1 X2 F100", "N00003 G1 Y2", "N99999 G0 Z1"))
good("text_empty_lines", "G21 G90\n\n\nG0 X1\n   \n(only comment)\nG0 Y1\nM2\n")
good("text_multiple_words_one_line", prog("G0 G90 G17 G21 X1 Y1 Z1 F100 S100 M3", "G1 X2 M8", "M9 M5 G0 Z2"))
good("text_msg_and_motion", prog("(MSG,starting)", "G0 X1", "(MSG,middle part)", "G1 X2 F10", "(MSG,done)"))
good("text_percent_and_trailing", "%\n(header)\nG21 G90 G0 X1\nG1 X2 F100\nM2\n%\n")
good("text_after_m2_ignored", "G21 G0 X1\nM2\nG0 X5\n")

# --- combined, realistic jobs -------------------------------------------------------------------
good("job_pocket_spiral", prog("T1 M6 G43", "S12000 M3", "M8", "G0 X0 Y0 Z2", "G1 Z-1 F50", "F300",
                               *[w for r in (1, 2, 3, 4, 5) for w in (f"G1 X{r} Y0", f"G3 X{r} Y0 I{-r} J0")], "G0 Z5", "M9", "M5"))
good("job_profile_with_comp", prog("T2 M6 G43 H2", "M3 S8000", "G0 X-10 Y-10 Z5", "G1 Z-2 F100", "G41 D2 G1 X0 Y0", "G1 X40", "G3 X50 Y10 R10", "G1 Y30",
                                   "G3 X40 Y40 R10", "G1 X0", "Y0", "G40 G1 X-10 Y-10", "G0 Z5", "M5"))
good("job_drill_pattern", prog("T3 M6 G43", "M3 S3000", "G0 Z10", "G99 G83 X10 Y10 Z-8 R2 Q2 F120", "X20", "X30", "Y20", "X20", "G98 X10", "G80", "M5"))
good("job_engrave_inch", prog("T8 M6 G43", "M3 S20000", "G0 X0 Y0 Z0.1", "G1 Z-0.01 F5", "G1 X0.5 F20", "G2 X1 Y0.5 R0.5", "G1 Y1", "G0 Z0.1", "M5", units="G20"))
good("job_multi_wcs", prog("G10 L2 P1 X0 Y0", "G10 L2 P2 X100 Y0", "G10 L2 P3 X0 Y100", "o1 sub", "G0 X0 Y0", "G1 X10 F100", "G2 X10 Y0 I-5 J0", "o1 endsub",
                           "G54", "o1 call", "G55", "o1 call", "G56", "o1 call", "G54"))
good("job_helix_bore", prog("T1 M6 G43", "M3 S9000", "G0 X5 Y0 Z1", "G1 Z0 F100", "G3 X5 Y0 I-5 J0 Z-4 P4", "G3 X5 Y0 I-5 J0", "G0 Z5"))
good("job_param_circle_points", prog("#1 = 0", "F500", "o1 while [#1 LT 360]", "G1 X[10 * COS[#1]] Y[10 * SIN[#1]]", "#1 = [#1 + 15]", "o1 endwhile"))
good("job_g92_repeat_parts", prog("o1 repeat [3]", "G0 X0 Y0", "G1 X5 F200", "G1 Y5", "G0 X10 Y0", "G92 X0 Y0", "o1 endrepeat", "G92.1"))
good("job_face_zigzag", prog("T10 M6 G43", "G0 X0 Y0 Z1", "G1 Z0 F100", *[f"G1 X{50 if i % 2 == 0 else 0} Y{i * 4}" for i in range(12)], "G0 Z5"))
good("job_inverse_time_arcs", prog("G93", "G1 X5 F10", "G2 X10 Y5 I0 J5 F5", "G3 X15 Y10 R5 F5", "G1 X0 Y0 F2", "G94"))
good("job_rotated_wcs_pocket", prog("G10 L2 P1 X20 Y20 R45", "G0 X0 Y0", "G1 X10 F100", "Y5", "G3 X0 Y5 R5", "G1 Y0", "G10 L2 P1 X0 Y0 R0"))

# --- bad programs: rs274 must reject them, and so must Oficina ------------------------------------
def badp(name, *lines):
    bad(name, "\n".join(["G21 G17 G90 G94"] + list(lines) + ["M2"]) + "\n")


badp("unknown_g_code", "G0 X1", "G7.5 X2")
badp("unknown_m_code", "G0 X1", "M123")
badp("unused_e_word", "G0 X1", "G1 X2 E5 F100")
badp("unused_q_word", "G1 X2 F100 Q7")
badp("stray_symbol", "G1 X2 F100 $")
badp("letter_without_number", "G1 X2 F100 G")
badp("modal_group_conflict_motion", "G0 G1 X1 F100")
badp("modal_group_conflict_plane", "G17 G18")
badp("modal_group_conflict_units", "G20 G21")
badp("two_m_same_group", "M3 M4 S100")
badp("g1_without_feed", "G0 X1", "G1 X2")
badp("arc_radius_mismatch", "G0 X0 Y0", "G2 X10 Y0 I4 J0 F100")
badp("arc_r_too_small", "G0 X0 Y0", "G2 X10 Y0 R2 F100")
badp("arc_no_offsets", "G0 X0 Y0", "G2 X10 Y0 F100")
badp("arc_r_full_circle", "G0 X0 Y0", "G2 X0 Y0 R5 F100")
badp("arc_wrong_plane_offset", "G0 X0 Y0", "G2 X10 Y0 I5 K1 F100")
badp("comp_concave_gouge", "T2 M6", "G0 X-10 Y-10", "G41 D2 G1 X0 Y0 F100", "G1 X20", "Y20", "X19", "Y0.5", "X0", "G40 G1 X-10 Y-10")
badp("comp_arc_smaller_than_tool", "T2 M6", "G0 X-10 Y-10", "G41 D2 G1 X0 Y0 F100", "G1 X20", "G3 X21 Y1 I0 J1", "G1 Y20", "G40 G1 X0")
badp("comp_entry_too_short", "T2 M6", "G0 X0 Y0", "G41 D2 G1 X0 Y1 F100", "G1 X10", "G40 G1 X0")
badp("comp_tool_change_while_on", "T2 M6", "G0 X-5 Y-5", "G41 D2 G1 X0 Y0 F100", "T1 M6", "G40")
badp("comp_missing_tool", "G0 X0", "G41 D77 G1 X1 F100")
badp("undefined_named_param", "G0 X#<nowhere>")
badp("division_by_zero", "#1 = 0", "G0 X[1 / #1]")
badp("sqrt_negative", "G0 X[SQRT[-1]]")
badp("ln_nonpositive", "G0 X[LN[0]]")
badp("acos_out_of_range", "G0 X[ACOS[2]]")
badp("unmatched_endsub", "o100 endsub")
badp("unmatched_endwhile", "G0 X1", "o5 endwhile")
badp("unclosed_bracket", "G0 X[1 + 2")
badp("unclosed_comment", "G0 X1 (oops")
badp("unknown_function", "G0 X[FOO[1]]")
badp("call_undefined_sub", "o999 call")
badp("endif_without_if", "o1 endif")
badp("word_repeated", "G0 X1 X2")
badp("negative_feed", "G1 X1 F-5")
badp("negative_spindle", "S-100 M3")
badp("g4_without_p", "G4")
badp("g10_l2_bad_p", "G10 L2 P12 X1")
badp("g10_l1_unknown_tool", "G10 L1 P77 Z1")
badp("cycle_without_r", "G81 X1 Y1 Z-1 F100")
badp("cycle_g83_without_q", "G83 X1 Y1 Z-1 R1 F100")
badp("cycle_r_in_g91_l0", "G91 G81 X1 Z-1 R1 L0 F100")
badp("g84_spindle_off", "M5", "G84 X1 Y1 Z-1 R1 F100")
badp("g53_in_g91", "G91 G53 G0 X1")
badp("g53_with_comp", "T2 M6", "G0 X-10 Y-10", "G41 D2 G1 X0 Y0 F100", "G53 G1 X5")
badp("g43_unknown_tool", "G43 H99", "G0 Z0")
badp("read_only_param", "#<_x> = 3")
badp("param_out_of_range", "#6000 = 1")
badp("g93_arc_without_f", "G93", "G1 X1 F10", "G2 X2 Y1 R1")
badp("axis_words_without_motion_g80", "G80 X1")
badp("g2_comp_too_small_radius", "T10 M6", "G0 X-5 Y0", "G42 D10 G1 X0 Y0 F100", "G2 X2 Y0 R1", "G40 G1 X5")
badp("m6_with_bad_tool", "T999 M6")
badp("bad_number", "G0 X1.2.3")
badp("o_number_mismatch", "o1 if [1]", "G0 X1", "o2 endif")
badp("g42_1_l_word_not_g18", "G42.1 D3 L0 G1 X0 Y0 F100")
badp("cycle_change_without_r", "G0 Z10", "G81 X1 Y1 Z-1 R2 F100", "G82 P0.1 X5")
badp("g95_zero_spindle", "G95 F0.2 G1 X3")
badp("oword_with_other_words", "o1 sub", "G0 X1", "o1 endsub", "G54 o1 call")
badp("exponent_number", "G1 Y1e0 F100")
bad("no_program_end", "G21 G0 X1\nG1 X2 F100\n")
bad("call_with_wrong_end", "G21\no1 sub\nG0 X1\no2 endsub\no1 call\nM2\n")

# Splines (issue 27): G5, G5.1, G5.2/G5.3 as rs274 reads them.
good('spline_g5_1_quadratic', '(G5.1 quadratic B-splines: I J is the control point from the start; G5.1 is not modal)\nG21 G17 G90 G94 G40 G49 G80 G54\nG0 X0 Y0 Z1\nG1 Z-0.5 F200\nG5.1 X10 Y0 I5 J8\nG5.1 X20 Y0 I5 J-8\nX25 Y2\nG91 G5.1 X10 Y10 I10 J0\nG90 G1 X0 Y0\nG0 Z5\nM2\n')
good('spline_g5_2_nurbs', '(G5.2 NURBS: control points with weights P, order L, ended by G5.3; then G1 from the last point)\nG21 G17 G90 G94 G40 G49 G80 G54\nG0 X0 Y0 Z1\nG1 Z-1 F250\nG5.2 X0 Y10 P1 L3\nX10 Y10 P0.7071\nX10 Y0 P1\nG5.3\nG1 X20 Y0\nG5.2 P2 L4\nX25 Y10 P1\nX30 Y-10 P3\nX35 Y10 P1\nX40 Y0 P1\nG5.3\nG1 X50\nG0 Z5\nM2\n')
good('spline_g5_cubic', '(G5 cubic splines: I J from the start, P Q from the end; a G5 without I J continues smoothly)\n(G5 leaves the motion mode as it was: X Y alone after it is the G1 before it)\nG21 G17 G90 G94 G40 G49 G80 G54\nG0 X0 Y0 Z1\nG1 Z-1 F300\nG5 I0 J10 P0 Q-10 X20 Y0\nG5 P0 Q10 X40 Y0\nG5 X60 Y5 P-5 Q0\nX70 Y5\nG91 G5 I5 J5 P0 Q-5 X10 Y10\nG90 G1 Y20\nG0 Z5\nM2\n')
good('spline_offsets_inch', '(splines under work offsets, G92 and inches: control points are program coordinates)\nG20 G17 G90 G94 G40 G49 G80\nG10 L2 P2 X1 Y2 Z0\nG55\nG92 X0.5 Y0.5\nG0 X0 Y0 Z0.1\nG1 Z-0.02 F20\nG5 I0 J0.5 P0 Q-0.5 X1 Y0\nG5.1 X2 Y0 I0.5 J0.4\nG5.2 X2 Y1 P1\nX3 Y1 P1\nX3 Y0 P1\nG5.3\nG1 X4\nG92.1 G54\nG0 Z1\nM2\n')
good('spline_tolerance_g64', '(G64 P sets the tolerance the curve is followed with; rs274 prints one NURBS_FEED either way)\nG21 G17 G90 G94 G40 G49 G80 G54\nG64 P0.2\nG0 X0 Y0\nG1 X1 F500\nG5 I0 J30 P0 Q-30 X50 Y0\nG61\nG5 I0 J-30 P0 Q30 X100 Y0\nG1 X110\nM2\n')
bad('spline_g5_1_without_j', 'G21 G17 G90 F100\nG0 X0 Y0\nG5.1 X10 Y0 I5\nM2\n')
bad('spline_g5_3_without_g5_2', 'G21 G17 G90 F100\nG0 X0 Y0\nG1 X1\nG5.3\nM2\n')
bad('spline_g5_in_xz_plane', 'G21 G18 G90 F100\nG0 X0 Y0 Z0\nG5 I1 J1 P1 Q1 X10 Y0\nM2\n')
bad('spline_g5_with_z', 'G21 G17 G90 F100\nG0 X0 Y0\nG5 I1 J1 P1 Q1 X10 Y0 Z-1\nM2\n')
bad('spline_g5_without_pq', 'G21 G17 G90 F100\nG0 X0 Y0\nG5 I1 J1 X10 Y0\nM2\n')
bad('spline_nurbs_fewer_points_than_order', 'G21 G17 G90 F100\nG0 X0 Y0\nG5.2 X1 Y1 P1 L4\nX2 Y0 P1\nG5.3\nM2\n')
bad('spline_nurbs_zero_weight', 'G21 G17 G90 F100\nG0 X0 Y0\nG5.2 X1 Y1 P1\nX2 Y0\nG5.3\nM2\n')
bad('spline_with_cutter_comp', 'G21 G17 G90 F100\nT1 M6\nG0 X-5 Y-5\nG41 G1 X0 Y0\nG5 I0 J5 P0 Q-5 X10 Y0\nG40\nM2\n')

# G0 / G1 without axis words (issue 27): rs274 moves to where it is.
good('motion_g0_g1_without_axes', '(G0 and G1 without axis words: rs274 moves to where it is, a move of length zero)\nG21 G17 G90 G94 G40 G49 G80 G54\nG0 X1 Y2 Z3\nG0\nG1 F100\nG91 G1\nG90 X5\nG1 F200 M3 S1000\nG0\nM2\n')
good('comp_g1_without_axes', '(a G1 without axis words under cutter compensation)\nG21 G17 G90 G94 G40 G49 G80 G54 F100\nT1 M6\nG0 X1\nG41 G1 X5 Y5\nG1\nX10\nG40 G0 X0 Y0\nM2\n')

# Splines under G93 (issue 27).
good('spline_inverse_time', '(G93: a spline takes its F like an arc; rs274 prints no feed rate for it)\nG21 G17 G90 G40 G49 G80 G54 G93\nG1 X1 F2\nG5 I0 J10 P0 Q-10 X20 Y0 F1\nG5.1 X30 Y0 I5 J5 F3\nG1 X35 F2\nG94 F100\nM2\n')
bad('spline_inverse_time_without_f', 'G21 G17 G90 G93\nG1 X1 F2\nG5.1 X30 Y0 I5 J5\nM2\n')


# Classes found on LinuxCNC's own tests/interp, tests/ccomp, tests/oword and nc_files
# (issue 27 item 1, measured by scripts/lcnc-agreement). Written here, not copied.
good('lcnc_exists_numbered', prog('(EXISTS on a numbered parameter: 1 for #1 to #5601, the number may be an expression)', '#1 = 2', '#2 = 99999', 'G0 X[EXISTS[#1]] Y[EXISTS[#99999]] Z[EXISTS[##1]]', 'G0 A[EXISTS[##2]] B[EXISTS[#[2+3]]] C[EXISTS[#5601] + EXISTS[#5602]]'))
bad('lcnc_exists_numbered_out_of_range', 'G21 G17 G90\n#1 = 2\n#2 = 99999\nG0 X[EXISTS[###1]]\nG0 Y[EXISTS[##2]] Z[EXISTS[###2]]\nM2\n')
good('lcnc_comment_leading_blanks', prog('(   three blanks before the text)', '(\ta tab before it)', 'G0 X1 (  inline, blanks first)', '(MSG,  a message keeps its blanks)'))
good('lcnc_oword_call_comments_indirect', '(comments between the arguments of a call; o#<name> and o[expr] as the label)\nG21 G17 G90 G94 G40 G49 G80 G54\no<s> sub\nG0 X#1 Y#2\no<s> endsub\no<s> call [1] (between the arguments) [2] (and after)\n#<sub> = 7\no7 sub\nG0 X7 Z#1\no7 endsub\no#<sub> call [3]\no[#<sub>] call [4]\nM2\n')
good('lcnc_fanuc_named_program', '%\n(a Fanuc-style program named O<name>: a program number, nothing to run)\nO<Part_One>\nG21 G0 X1\nM30\n%\n')
good('lcnc_oword_return_other_label', '(return inside an if of a subroutine: the label is the if\'s, rs274 returns from the subroutine)\nG21 G17 G90 G94 G40 G49 G80 G54\no100 sub\no110 if [#1 GT 0]\no110   return [10*#1]\no110 endif\no120 if [#1 LT 0]\no120   return\no120 endif\no100 endsub [99]\no100 call [2]\nG0 X#<_value> Y#<_value_returned>\no100 call [-1]\nG0 X#<_value> Y#<_value_returned>\no100 call [0]\nG0 X#<_value> Y#<_value_returned>\nM2\n')
good('lcnc_comp_queued_calls', '(under cutter compensation rs274 queues comments, feed, coolant, spindle and dwell behind the held move; M2 issues what is held)\nG21 G17 G90 G94 G40 G49 G80 G54\nT1 M6\nG0 X-10 Y-10 Z5\nG41 G1 X0 Y0 F100\nX20 (along the bottom)\nF150\nM8\nS1000 M3\nG4 P0.5\n(MSG, messages are not held)\nY20\nM9 M5\nX0 (back)\nG0 Z2\nM2\n')
good('lcnc_cycle_polar_g91_repeats', '(G91 polar words on a canned cycle with L: each repeat adds @ to the radius and ^ to the angle of the hole before)\nG21 G17 G90 G94 G40 G49 G80 G54\nG0 X30 Y0 Z5\nG91 G81 R2 Z-8 ^45 L8 F200\nG90 G0 @10 ^30\nG91 G81 @5 R2 Z-8 L4\nG90 G0 X20 Y10\nG91 G81 @-2 ^-20 R2 Z-8 L3\nG90 G80 G0 Z20\nM2\n')
good('lcnc_cycle_tap_g18_g19', '(G84 and G74 in G18 and G19: rs274 2.9 feeds the tap with G19\'s axis order in G18 and G18\'s in G19; matched)\nG21 G90 G94 G40 G49 G80 G54\nS500 M3\nG18 G0 X10 Y5 Z5\nG98 G84 X10 Y-10 Z0 R2 F150\nG91 G99 X2 Y-4 R-1 L2\nG90 G80\nG19 M4 G0 X5 Y0 Z0\nG98 G74 Y1 Z2 X-1 R1\nG80 M5\nM2\n')
good('lcnc_comp_zero_radius', '(compensation with a zero radius runs the moves as programmed: no entry check, no corners)\nG21 G17 G90 G94 G40 G49 G80 G54 F300\nG0 X0 Y0\nG41.1 D0\nG1 X0 Y0\nX20\nY10\nX10 Y2\nG3 X5 Y7 R5\nG1 X0 Y0\nG40 G0 X-5\nG42.1 D0\nG1 X10\nG2 X20 Y0 R5\nG40 G0 X30\nM2\n')
good('lcnc_comp_shallow_corners', '(corners turning less than 0.05 rad get no arc and no endpoint change under compensation)\nG21 G17 G90 G94 G40 G49 G80 G54 F300\nG0 X-10 Y-10\nG41.1 D4\nG1 X0 Y0\nX20 Y0.5\nX40 Y0\nX60 Y-0.8\nX80 Y-0.8\nG3 X100 Y-0.4 R100\nG1 X120 Y0\nG40 G0 X130 Y-10\nM2\n')
good('lcnc_comp_reversal_at_arcs', '(a reversal onto or off an arc the tool runs outside of is a concave corner for rs274: the tool stays outside)\nG21 G17 G90 G94 G40 G49 G80 G54 F300\nG0 X-10 Y-5\nG41.1 D1\nG1 X0 Y0\nG2 X10 Y0 I5 J0\nG1 X10.2 Y8\nG1 X20 Y-10\nG2 X21.998 Y-3.222 I4.39 J2.39\nG1 X40 Y-10\nG40 G0 X50 Y0\nM2\n')
good('lcnc_comp_arc_end_radius', '(under compensation rs274 offsets an arc by its radius at the end, which may differ slightly from the start)\nG21 G17 G90 G94 G40 G49 G80 G54 F300\nG0 X-10 Y0\nG42.1 D2\nG1 X0 Y0\nG2 X20.004 Y0 I10 J0\nG2 X10 Y-10.003 I-10 J0\nG1 X-10 Y-10\nG40 G0 X-20 Y0\nM2\n')
good('lcnc_param_line', '(#<_line> is the line being read, also inside a subroutine)\nG21 G17 G90 G94 G40 G49 G80 G54\n\no1 sub\n(debug, in the sub: #<_line>)\nG0 X#<_line>\no1 endsub\n\n(debug, main: #<_line>)\nG0 Y#<_line>\no1 call\nG0 Z[#<_line> + 1]\nM2\n')
good('lcnc_param_tool_entry', '(#5401-#5410 hold the loaded tool\'s table entry in machine units, changed by M6 and by G10 L1/L10/L11 on it)\nG21 G17 G90 G94 G40 G49 G80 G54\n(debug, none: #5400 #5401 #5403 #5410)\nT2 M6\n(debug, T2: #5400 #5401 #5403 #5410)\nG10 L1 P2 X1.27 Z25.4 R3\n(debug, after L1: #5400 #5401 #5402 #5403 #5410)\nG0 X0 Y0 Z0\nG10 L10 P2 Z5\n(debug, after L10: #5403)\nG10 L1 P1 Z10\n(debug, another tool changed: #5403)\nT1 M6\n(debug, T1: #5400 #5403 #5410)\nM2\n')
good('lcnc_debug_formats', '(%d, %f and %.Nf in a DEBUG set how the parameters after them print)\nG21 G17 G90 G94 G40 G49 G80 G54\n#<v> = 2.71828182\n#1 = -0.5\n(debug, plain #<v> then %d#<v> and #1)\n(debug, %f four: #<v> #1 %.2f two: #<v>)\n(debug, 50%. %.x and %% stay)\nM2\n')
good('lcnc_comment_last_wins', '(rs274 keeps the last comment of a line only)\nG21 G17 G90 G94 G40 G49 G80 G54\n(first)(second)\nG0 X1 (during) Y2 (after the words)\n(MSG, not shown)(shown as a comment)\n(a comment)(MSG, the message wins)\n(debug, not shown #<_x>)(debug, shown #<_y>)\nM2\n')
good('lcnc_comp_entry_one_radius', '(an entry move exactly one tool radius long is taken by rs274)\nG20 G17 G90 G94 G40 G49 G80 G54 F10\nT1 M6\nG0 X0.0625 Y0\nG41 G1 X0 Y0\nG1 Y1\nX1\nG40 G0 X2 Y2\nG21 G0 X0 Y0\nG42 G1 X1.5875\nY20\nG40 G0 X30\nM2\n')
good('lcnc_param_modes', '(the read-only mode parameters of rs274 2.9)\nG21 G17 G90 G94 G40 G49 G80 G54\n(debug, start: #<_vmajor> #<_vminor> #<_ccomp> #<_units_per_minute> #<_tool_offset> #<_retract_r_plane> #<_spindle_rpm_mode> #<_ijk_absolute_mode> #<_lathe_radius_mode>)\n(debug, switches: #<_spindle_on> #<_mist> #<_flood> #<_speed_override> #<_feed_override> #<_adaptive_feed> #<_feed_hold> #<_u>)\nT1 M6\nG43 G98 G90.1 G7 G93 S1000 M3 M7\nM8 M51 P0\nM52 P1\nM53 P0\n(debug, changed: #<_tool_offset> #<_retract_old_z> #<_ijk_absolute_mode> #<_lathe_diameter_mode> #<_inverse_time> #<_spindle_cw> #<_mist> #<_flood>)\n(debug, switches: #<_speed_override> #<_adaptive_feed> #<_feed_hold>)\nG8 G91.1 G95 G49 G99 M4 M9\nM48\nM52 P0\nM53\n(debug, back: #<_units_per_rev> #<_spindle_on> #<_spindle_cw> #<_speed_override> #<_feed_override> #<_adaptive_feed> #<_feed_hold> #<_tool_offset>)\nG94 G0 X-10 Y0\nG41 G1 X0 F100\n(debug, comp: #<_ccomp>)\nG40\nG42 G1 X10\n(debug, comp: #<_ccomp>)\nG40 G0 X20\nM2\n')
good('oword_lib_lcnc_nested_sub', '(oword_lib/lcnc_nested.ngc defines o100 inside o<lcnc_nested>: rs274 2.9 runs the inner sub line as part of the call and its endsub returns)\nG21 G17 G90 G94 G40 G49 G80 G54\no<lcnc_nested> call [1] [2] [3]\nG0 X10\no<lcnc_nested> call [4] [5] [6]\nM2\n')
bad('lcnc_oword_sub_after_percent', '%\nG21 G0 X1\no2 call\n%\no2 sub\nG0 Z3\no2 endsub\n')
good('lcnc_g10_l10_rotated', '(G10 L10/L11 X or Y under a rotated coordinate system: rs274 turns the tool offset through the rotation, keeping the old offset along the other axis)\nG21 G17 G90 G94 G40 G49 G80 G54\nG10 L2 P1 X10 Y5 R30\nG10 L2 P9 R-20\nG0 X5 Y3 Z0\nT1 M6\nG43\nG10 L10 P1 X1\n(debug, L10 X: #5401 #5402)\nG10 L10 P1 Y2\n(debug, L10 Y: #5401 #5402)\nG43\nG0 X0 Y0\nG10 L10 P1 X0 Y0 Z-1\n(debug, L10 XY: #5401 #5402 #5403)\nG10 L11 P1 X2\n(debug, L11 X: #5401 #5402)\nG43\nG0 X1 Y1\nG49\nG10 L2 P1 R0\nM2\n')
# G38.x probing as the standalone rs274 runs it (never tripped), M66 with no inputs, LOG comments.
good('lcnc_probe_straight', '(G38.2 to G38.5 as rs274 runs them: the standalone probe never trips,)\n(reports its target in #5061-#5066 and leaves the tool 0.254 mm back)\nG21 G90 G17\nG0 X10 Y5 Z20\nF100\nG38.2 Z-5\n(MSG, probed Z #5063 tripped #5070)\nG91 G1 Z2\nG90\nG38.3 X30 Y15\nG1 X#5061 Y#5062\nG92 X0 Y0\nG38.4 X-8 Z10\nG38.5 Z10\nG91 G38.2 X3 Y-4\nG90 G92.1\nG20 F4\nG38.2 Z-0.5\nG0 Z1\n(LOG, a log line rs274 writes to its log file, not a comment)\nM66 P0 L1 Q5\nM66 E1\nM2\n')
bad('lcnc_probe_zero_feed', 'G21 G90\nG0 X0 Y0 Z0\nF0\nG38.2 Z-5\nM2\n')
bad('lcnc_probe_with_comp', 'G21 G90\nG0 X0 Y0 Z0\nF100\nG41.1 D1\nG1 X5\nG38.2 Z-5\nM2\n')
bad('lcnc_probe_feed_per_rev', 'G21 G90\nG0 X0 Y0 Z0\nG95 S100 F1\nG38.2 Z-5\nM2\n')
bad('lcnc_probe_to_start', 'G21 G90\nG0 X0 Y0 Z0\nF100\nG38.2 Z0\nM2\n')
bad('lcnc_m66_digital_and_analog', 'G21 G90\nG0 X0 Y0 Z0\nM66 P1 E1\nM2\n')
bad('lcnc_m66_no_input', 'G21 G90\nG0 X0 Y0 Z0\nM66 L0\nM2\n')
# G96/G97: rs274's SET_SPINDLE_MODE.
good('lcnc_spindle_css', '(G96 constant surface speed with and without a D limit, G97 back to rev/min: rs274 prints SET_SPINDLE_MODE)\nG21 G18 G90 G94 G40 G49 G80 G54\nG96 D2500 S100 M3\nG0 X10 Z1\nG1 Z-5 F200\nG97 S500\nG0 X20\nG96 S50\nG1 X5\nG20 G96 S300 D-1200\nG1 X0.5 Z0\nM2\n')
bad('lcnc_spindle_css_without_s', 'G21 G18 G90\nG96 D2000 M3\nM2\n')

# INI settings (ini/settings.ini, read by rs274 -i and oficina --ini): ORIENT_OFFSET added to
# every M19 angle, numeric entries as read-only #<_ini[section]name> (any case).
good('ini_orient_offset_and_values', '(ORIENT_OFFSET 10 is added to M19 R, or taken alone with P; INI entries read as parameters)\nG21 G17 G90 G94 G40 G49 G80 G54\n(debug, depth #<_ini[vars]depth> safe #<_ini[VARS]SAFE>)\nG0 Z#<_ini[vars]safe>\nG1 Z#<_ini[vars]depth> F100\nM19 R30\nM19 P1\nM19 R350 P2\nM3 S100\nM2\n')
bad('ini_assign_read_only', '(an INI value is a read-only parameter)\nG21 G17 G90 G94\n#<_ini[vars]depth> = 1\nM2\n')

# A parameter file (var/start.var, a copy read by rs274 -v and oficina --var-file): a G92
# offset saved with #5210 set is in force from the start; #5221 moves G54.
good('var_g92_persistence', '(a G92 offset saved in the parameter file is in force at start)\nG21 G17 G90 G94 G40 G49 G80 G54\n(debug, g92 #5210 #5211 #5212 #5213 #5214)\nG0 X0 Y0 Z0 A0\nG1 X10 F100\nG92.1\nG0 X0 Y0 Z0\nM2\n')

# M70-M73 modal state save/restore (interp_convert.cc save_settings/restore_settings): the
# restore runs the units first, then F (rounded to 0.1) S and the G codes that differ, then
# one M code per differing M group.
good('modal_m70_m72_restore', '(M70 saves the state, M72 brings units, feed, speed, distance, plane, feed mode, path mode, spindle and coolant back)\nG21 G17 G90 G94 G40 G49 G80 G54 G64 P0.05\nF123.456 S1500 M3 M8\nG0 X1 Y1 Z1\nM70\nG20 G91 G18 G93 G61 G55 F2 S300 M4 M9\nM7\nG1 X0.1 F10\nM72\nG1 X5 Y5\nM72\nG0 X0\nM71\nM2\n')
good('modal_m73_restore_on_return', '(M73 in a subroutine: the caller state comes back on endsub and on return)\nG21 G17 G90 G94 G40 G49 G80 G54\no<sub1> sub\nM73\nG20 G91 F3 S200\nG1 X0.5\no<inner> if [#1 GT 0]\no<sub1> return\no<inner> endif\nG1 Y0.5\no<sub1> endsub\nF250 S1000 M3\nG0 X0 Y0 Z0\no<sub1> call [0]\nG1 X10\no<sub1> call [1]\nG1 Y10\nM2\n')
bad('modal_m72_after_m71', '(M71 forgets the saved state: M72 has nothing to restore)\nG21 G17 G90 G94\nM70\nF100\nM71\nM72\nM2\n')


def write_all():
    for sub in ("", "bad"):
        d = os.path.join(ROOT, sub)
        os.makedirs(d, exist_ok=True)
        for f in os.listdir(d):
            if f.endswith(".ngc"):
                os.remove(os.path.join(d, f))
    for name, text in GOOD.items():
        with open(os.path.join(ROOT, name + ".ngc"), "w") as f:
            f.write(text)
    for name, text in BAD.items():
        with open(os.path.join(ROOT, "bad", name + ".ngc"), "w") as f:
            f.write(text)
    print(f"wrote {len(GOOD)} good and {len(BAD)} bad programs under {os.path.normpath(ROOT)}")


def write_only(prefix):
    """Write the programs whose name starts with `prefix`, leaving the rest of the corpus
    (hand-written programs included) as it is."""
    for sub, progs in (("", GOOD), ("bad", BAD)):
        for name, text in progs.items():
            if name.startswith(prefix):
                with open(os.path.join(ROOT, sub, name + ".ngc"), "w") as f:
                    f.write(text)


if __name__ == "__main__":
    import sys

    if len(sys.argv) > 2 and sys.argv[1] == "--only":
        write_only(sys.argv[2])
    else:
        write_all()
