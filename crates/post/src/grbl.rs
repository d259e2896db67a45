//! grbl 1.1: the [`Post`] defaults (the RS274 skeleton) except: no canned cycles and no G64
//! (cycles are written out as moves); tool changes are an M0 pause unless the machine handles
//! M6.

use crate::emit::Emitter;
use crate::{rs274, Post, ToolChange};
use oficina_cam::PathMode;
use std::io;

pub(crate) struct Grbl;

impl Post for Grbl {
    /// `T n M6` where the machine handles it; otherwise an M0 pause with a message (the
    /// first tool is loaded before the program starts).
    fn load_tool(&self, e: &mut Emitter, c: &ToolChange) -> io::Result<()> {
        let op = c.op;
        if c.opts.allow_m6 {
            return rs274::m6(e, op);
        }
        if c.previous.is_some() {
            e.block("M5")?;
            e.block(&format!(
                "(MSG, Change to T{}: {}, set Z zero, then resume)",
                op.tool_number,
                op.tool.spec()
            ))?;
            // grbl accepts and ignores T; it names the tool for readers and simulators.
            e.block(&format!("T{}", op.tool_number))?;
            e.block("M0")
        } else {
            e.comment(&format!(
                "load T{} ({}) and set Z zero on the stock top before starting",
                op.tool_number,
                op.tool.spec()
            ))?;
            e.block(&format!("T{}", op.tool_number))
        }
    }

    /// grbl has G61 only (and it is the default): the mode is noted, not written.
    fn path_mode(&self, e: &mut Emitter, mode: PathMode) -> io::Result<()> {
        e.comment(&format!(
            "path mode {mode:?}: grbl always blends by junction deviation"
        ))
    }
}
