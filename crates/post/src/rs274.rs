//! The RS274 skeleton every G-code post starts from, and that [`crate::Post`]'s defaults
//! write: G0–G3 words, the modal set-up line, `T n M6`, spindle on, and the end of program. Dialect
//! files override only what their control does differently.

use crate::emit::{Emitter, MotionWords};
use crate::format::{push_decimal, Units};
use oficina_cam::Operation;
use std::io;

/// G0 G1 G2 G3, I J from the start, F words.
pub(crate) const RS274_WORDS: MotionWords = MotionWords {
    rapid: "G0",
    line: "G1",
    cw: "G2",
    ccw: "G3",
    absolute_centres: false,
    feed_words: true,
    integer_feed: false,
};

/// "G21 G90 G94 G17" (G20 in inches): the modal state every rs274 program sets first.
pub(crate) fn modal_setup(e: &mut Emitter) -> io::Result<()> {
    let units = match e.format.units {
        Units::Mm => "G21",
        Units::Inch => "G20",
    };
    e.block(&format!("{units} G90 G94 G17"))
}

/// Spindle on; the same block in LinuxCNC and grbl.
pub(crate) fn spindle_on(e: &mut Emitter, op: &Operation) -> io::Result<()> {
    let mut s = String::from("S");
    push_decimal(&mut s, op.spindle_rpm, 4);
    s.push_str(" M3");
    e.block(&s)
}

/// `T n M6`: the tool change of LinuxCNC (and grbl where the machine handles M6).
pub(crate) fn m6(e: &mut Emitter, op: &Operation) -> io::Result<()> {
    e.block(&format!("T{} M6", op.tool_number))
}

/// Spindle off, M30.
pub(crate) fn end(e: &mut Emitter) -> io::Result<()> {
    e.block("M5")?;
    e.block("M30")
}
