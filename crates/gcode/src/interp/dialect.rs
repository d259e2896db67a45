//! The two dialects beside LinuxCNC's.
//!
//! grbl 1.1 (gcode.c, report.c): the same interpreter, but only grbl's G/M set is accepted
//! and errors carry grbl's `error:N` numbers and texts. The motion mode at power-up is G0,
//! as in grbl. Probing (G38.2 to G38.5) is checked as grbl checks it (feed, axis words, a
//! target that is not the current point) and then runs as a straight feed to the target:
//! Oficina's machines have no probe input, so a probe never trips and the move ends at the
//! target; the motion mode afterwards is G1.
//!
//! Legacy 2006 (seed 002, §3): G90/G91 are themselves linear feed moves (absolute /
//! incremental), I J are absolute arc centres, motion codes are modal, G0 is a rapid.

use super::words::{g_group as G, m_group as M, unknown_g, DecodeError, DecodeFault, Decoded};
use super::Interpreter;
use crate::diag::Diagnostic;
use oficina_canon::FeedMode;

/// grbl's text for an error number (the one table, [`crate::grbl_errors`]).
pub(crate) fn grbl_text(code: u16) -> &'static str {
    crate::grbl_errors::error_text(code).map_or("", |(_, text)| text)
}

/// Attach grbl's number and text to a diagnostic.
pub(crate) fn grbl_error(d: Diagnostic, code: u16) -> Diagnostic {
    let help = match &d.help {
        Some(h) => format!("grbl error:{code}: {} ({h})", grbl_text(code)),
        None => format!("grbl error:{code}: {}", grbl_text(code)),
    };
    let mut d = d.with_code(code);
    d.help = Some(help);
    d
}

/// G codes grbl calls axis commands (gcode.c's `axis_command`): motion G0 G1 G2 G3 G38.x and
/// the non-modal G10 G28 G30 G92, in tenths.
fn grbl_axis_command(tenths: u16) -> bool {
    matches!(tenths, 0 | 10 | 20 | 30 | 100 | 280 | 300 | 920 | 382..=385)
}

/// A decoding error in grbl's numbering, chosen by what the decoder found. gcode.c meets a
/// second axis command before it checks modal groups: `G0 G1` is error 24, not 21.
pub(crate) fn grbl_code_for_decode(e: DecodeError) -> Diagnostic {
    let code = match e.fault {
        DecodeFault::SameModalGroup {
            letter: 'G',
            first,
            second,
        } if grbl_axis_command(first) && grbl_axis_command(second) => 24,
        DecodeFault::SameModalGroup { .. } => 21,
        DecodeFault::RepeatedWord => 25,
        DecodeFault::Unsupported => 20,
    };
    grbl_error(e.diag, code)
}

fn unsupported(span: crate::diag::Span, what: String, hint: Option<&str>) -> Diagnostic {
    let d = Diagnostic::error(span, what);
    grbl_error(
        match hint {
            Some(h) => d.with_help(h),
            None => d,
        },
        20,
    )
}

/// What usually puts a G code grbl refuses (`tenths`, of modal `group`) into a program, and
/// what to do: most come from a post-processor written for another control.
fn post_hint_g(group: usize, tenths: u16) -> Option<&'static str> {
    Some(match (group, tenths) {
        (G::CONTROL, 640 | 641) => {
            "a LinuxCNC post; grbl has no path blending mode: remove it or choose a grbl post"
        }
        (G::CONTROL, 611) => {
            "exact-path mode is LinuxCNC's; grbl always follows the path: remove it or choose a grbl post"
        }
        (G::TOOL_LENGTH, 430 | 432) => {
            "tool length offsets from a tool table (a LinuxCNC or Fanuc post); grbl has only G43.1 Z…: remove it and touch off each tool, or choose a grbl post"
        }
        (G::CUTTER_COMP, _) => {
            "grbl has no cutter radius compensation: let the CAM offset the path (compensation \"in computer\") or choose a grbl post"
        }
        (G::MOTION, 730..=890) => {
            "grbl has no canned cycles: have the post expand drilling into G0/G1 moves (a grbl post does)"
        }
        (G::MOTION, 50..=53) => "splines are LinuxCNC's: have the CAM write arcs and lines",
        (G::RETRACT, _) => {
            "a canned-cycle retract mode (a LinuxCNC or Fanuc post); grbl has no canned cycles: remove it or choose a grbl post"
        }
        (G::FEED_MODE, 950) => "feed per revolution is a lathe's; grbl feeds per minute (G94) or inverse time (G93)",
        (G::NON_MODAL, 520) => "G52 local offsets are LinuxCNC's: use G92 or a work offset G54…G59",
        (G::DISTANCE, _) | (G::ARC_DISTANCE, 901) => {
            "grbl takes I J K as offsets from the start (G91.1) only: choose a post with incremental arc centres"
        }
        _ => return None,
    })
}

/// [`post_hint_g`] for M codes.
fn post_hint_m(group: usize, code: u16) -> Option<&'static str> {
    Some(match (group, code) {
        (M::OVERRIDE, _) => {
            "override switches are LinuxCNC's; grbl's overrides are real-time commands: remove it"
        }
        (M::SPINDLE, 19) => "spindle orientation is LinuxCNC's: remove it",
        _ => return None,
    })
}

/// Reject what grbl 1.1 rejects before the common interpreter sees the block.
pub(crate) fn check_grbl(interp: &Interpreter, d: &mut Decoded) -> Result<(), Diagnostic> {
    for (group, code) in d.g.iter().enumerate() {
        let Some(c) = code else { continue };
        let ok = match group {
            G::NON_MODAL => matches!(c.tenths, 40 | 100 | 280 | 281 | 300 | 301 | 530 | 920 | 921),
            G::MOTION => matches!(c.tenths, 0 | 10 | 20 | 30 | 382..=385 | 800),
            G::ARC_DISTANCE => c.tenths == 911,
            G::FEED_MODE => matches!(c.tenths, 930 | 940),
            G::CUTTER_COMP => c.tenths == 400,
            G::TOOL_LENGTH => matches!(c.tenths, 431 | 490),
            G::RETRACT | G::SPINDLE_MODE => false,
            G::CONTROL => c.tenths == 610,
            G::COORD_SYSTEM => {
                if c.tenths > 590 {
                    return Err(grbl_error(
                        Diagnostic::error(
                            c.span,
                            format!("G{} is not supported by grbl", c.tenths as f64 / 10.0),
                        ),
                        29,
                    ));
                }
                true
            }
            _ => true,
        };
        if !ok {
            return Err(unsupported(
                c.span,
                format!("G{} is not supported by grbl", c.tenths as f64 / 10.0),
                post_hint_g(group, c.tenths),
            ));
        }
    }
    for (group, code) in d.m.iter().enumerate() {
        let Some(c) = code else { continue };
        let ok = match group {
            M::STOP => matches!(c.tenths, 0 | 1 | 2 | 30),
            M::SPINDLE => matches!(c.tenths, 3..=5),
            M::COOLANT => true,
            _ => false,
        };
        if !ok {
            return Err(unsupported(
                c.span,
                format!("M{} is not supported by grbl", c.tenths),
                post_hint_m(group, c.tenths),
            ));
        }
    }
    if d.g_in(G::NON_MODAL) == Some(100) {
        // gcode.c checks the axis words of G10 before its L and P words.
        if !d.any_axis() {
            return Err(grbl_error(
                Diagnostic::error(
                    d.g_span(G::NON_MODAL),
                    "G10 without axis words: nothing to set",
                ),
                26,
            ));
        }
        let (Some(l), Some(p)) = (d.get('L'), d.get('P')) else {
            let missing = if d.has('L') { 'P' } else { 'L' };
            return Err(grbl_error(
                Diagnostic::error(
                    d.g_span(G::NON_MODAL),
                    format!("G10 without an {missing} word"),
                ),
                28,
            ));
        };
        if p.trunc() > 6.0 {
            return Err(grbl_error(
                Diagnostic::error(
                    d.span_of('P'),
                    format!("G10 P{p}: grbl has six work coordinate systems (P0 to P6)"),
                ),
                29,
            ));
        }
        if l != 2.0 && l != 20.0 {
            return Err(unsupported(
                d.span_of('L'),
                "grbl supports G10 L2 and L20 only".into(),
                None,
            ));
        }
        if l == 2.0 && d.has('R') {
            return Err(unsupported(
                d.span_of('R'),
                "G10 L2 R (a rotation) is not supported by grbl".into(),
                None,
            ));
        }
    }
    for l in ['A', 'B', 'C', 'D', 'E', 'H', 'Q'] {
        if d.has(l) {
            return Err(grbl_error(
                Diagnostic::error(d.span_of(l), format!("{l} word is not used by grbl")),
                if "ABCE".contains(l) { 20 } else { 36 },
            ));
        }
    }
    if let Some(t) = d.get('T') {
        if t > 255.0 {
            return Err(grbl_error(
                Diagnostic::error(
                    d.span_of('T'),
                    format!("tool number {t} is over grbl's 255"),
                ),
                38,
            ));
        }
    }
    // Arcs: grbl wants an axis word in the plane and, in the offset form, an offset in it.
    let axes_taken = matches!(d.g_in(G::NON_MODAL), Some(100 | 280 | 300 | 920))
        || d.g_in(G::TOOL_LENGTH) == Some(431);
    let motion = d
        .g_in(G::MOTION)
        .map(super::state::Motion::from_tenths)
        .unwrap_or(interp.modal.motion);
    if matches!(
        motion,
        super::state::Motion::Clockwise | super::state::Motion::CounterClockwise
    ) && !axes_taken
        && (d.any_axis() || d.g[G::MOTION].is_some())
    {
        let (a0, a1, _) = interp.modal.plane.axes();
        let (l0, l1) = (super::AXES[a0], super::AXES[a1]);
        if !d.any_axis() {
            return Err(grbl_error(
                Diagnostic::error(d.g_span(G::MOTION), "arc without axis words"),
                26,
            ));
        }
        if !d.has(l0) && !d.has(l1) {
            return Err(grbl_error(
                Diagnostic::error(
                    d.g_span(G::MOTION),
                    format!("arc without {l0} or {l1} word"),
                ),
                32,
            ));
        }
        // gcode.c consumes I, J and K alike in the offset form (`bit_false(value_words,
        // I|J|K)`) and uses the two of the plane: the third, which posts such as FreeCAD's
        // write on every arc (`K0.000` in G17), is read and ignored.
        if !d.has('R') {
            let off = ['I', 'J', 'K'][interp.modal.plane.axes().2];
            d.values[super::words::slot(off)] = None;
        }
    }
    if let Some(probe) = d.g[G::MOTION].filter(|c| (382..=385).contains(&c.tenths)) {
        check_grbl_probe(interp, d)?;
        // No probe input to trip: the probe is a feed to its target.
        d.g[G::MOTION] = Some(super::words::Code {
            tenths: 10,
            span: probe.span,
        });
    }
    Ok(())
}

/// grbl's G38 errors, in gcode.c's order: no feed (22), no axis words (26), a target equal
/// to the current point (33).
fn check_grbl_probe(interp: &Interpreter, d: &Decoded) -> Result<(), Diagnostic> {
    let span = d.g_span(G::MOTION);
    let inverse_time = match d.g_in(G::FEED_MODE) {
        Some(930) => true,
        Some(_) => false,
        None => interp.modal.feed_mode == FeedMode::InverseTime,
    };
    let feed = if inverse_time {
        d.get('F').unwrap_or(0.0)
    } else {
        d.get('F').unwrap_or(interp.modal.feed)
    };
    if feed == 0.0 {
        return Err(grbl_error(
            Diagnostic::error(span, "probe without a feed rate; set F"),
            22,
        ));
    }
    if !d.any_axis() {
        return Err(grbl_error(
            Diagnostic::error(span, "probe without axis words: no target"),
            26,
        ));
    }
    // The target as the block's own G90/G91 and G20/G21 make it.
    let incremental = match d.g_in(G::DISTANCE) {
        Some(t) => t == 910,
        None => interp.modal.incremental,
    };
    let k = match d.g_in(G::UNITS) {
        Some(200) => 25.4,
        Some(_) => 1.0,
        None => interp.k(),
    };
    let same = (0..3).all(|i| match d.get(super::AXES[i]) {
        Some(v) if incremental => v == 0.0,
        Some(v) => v * k == interp.pos[i],
        None => true,
    });
    if same {
        return Err(grbl_error(
            Diagnostic::error(span, "probe target is the current point"),
            33,
        ));
    }
    Ok(())
}

/// The legacy and Marlin dialects: probing is not supported (seed 002 has no G38),
/// with the message an unknown code gets.
pub(crate) fn refuse_probe(d: &Decoded) -> Result<(), Diagnostic> {
    match d.g[G::MOTION] {
        Some(c) if (382..=385).contains(&c.tenths) => {
            Err(unknown_g(c.span, f64::from(c.tenths) / 10.0))
        }
        _ => Ok(()),
    }
}

/// Rewrite a seed-002 block into its LinuxCNC meaning: `G90`/`G91` become `G1` plus the
/// distance mode (unless the block names another motion), so lines with coordinates only
/// repeat the last motion.
pub(crate) fn translate_legacy(d: &mut Decoded) {
    if let Some(dist) = d.g[G::DISTANCE] {
        if d.g[G::MOTION].is_none() {
            d.g[G::MOTION] = Some(super::words::Code {
                tenths: 10,
                span: dist.span,
            });
        }
    }
    // I and J are absolute centres in this dialect.
    d.g[G::ARC_DISTANCE] = None;
}
