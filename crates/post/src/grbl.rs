//! grbl 1.1: the [`Post`] defaults (the RS274 skeleton) except: no canned cycles and no G64
//! (cycles are written out as moves); tool changes are an M0 pause unless the machine handles
//! M6.

use crate::emit::Emitter;
use crate::linuxcnc::m6_change;
use crate::{Post, PostOptions};
use oficina_cam::{Operation, PathMode, Toolpath};
use std::io;

pub(crate) struct Grbl;

impl Post for Grbl {
    fn tool_change(
        &self,
        e: &mut Emitter,
        tp: &Toolpath,
        opts: &PostOptions,
        op: &Operation,
        previous: Option<u32>,
    ) -> io::Result<()> {
        if opts.allow_m6 {
            return m6_change(e, tp, op, previous);
        }
        if previous.is_some() {
            e.rapid_z(tp.safe_z)?;
            e.block("M5")?;
            e.block(&format!(
                "(MSG, Change to T{}: {}, set Z zero, then resume)",
                op.tool_number,
                op.tool.spec()
            ))?;
            // grbl accepts and ignores T; it names the tool for readers and simulators.
            e.block(&format!("T{}", op.tool_number))?;
            e.block("M0")?;
        } else {
            e.comment(&format!(
                "load T{} ({}) and set Z zero on the stock top before starting",
                op.tool_number,
                op.tool.spec()
            ))?;
            e.block(&format!("T{}", op.tool_number))?;
            e.rapid_z(tp.safe_z)?;
        }
        Ok(())
    }

    /// grbl has G61 only (and it is the default): the mode is noted, not written.
    fn path_mode(&self, e: &mut Emitter, mode: PathMode) -> io::Result<()> {
        e.comment(&format!(
            "path mode {mode:?}: grbl always blends by junction deviation"
        ))
    }
}
