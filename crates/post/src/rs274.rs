//! The RS274 skeleton every G-code post starts from, and that [`crate::Post`]'s defaults
//! write: G0–G3 words, the modal set-up line, spindle on, and the end of program. Dialect
//! files override only what their control does differently.

use crate::emit::{Emitter, MotionWords};
use crate::format::{push_decimal, Units};
use oficina_cam::{Operation, Toolpath};
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

/// Safe Z, spindle off, M30.
pub(crate) fn end(e: &mut Emitter, tp: &Toolpath) -> io::Result<()> {
    e.rapid_z(tp.safe_z)?;
    e.block("M5")?;
    e.block("M30")
}
