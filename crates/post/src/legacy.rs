//! The seed 002 controller (2006, digest §3): `G0` rapid, `G90` the absolute feed move
//! (there is no G01), `G2`/`G3` with I J as the absolute centre, motion modal, no F (the
//! machine runs at its configured feed, noted in the header), no spindle or tool words.
//! Drills are written as moves and dwells as comments: the control has neither.

use crate::emit::{Emitter, MotionWords};
use crate::format::{Format, Numbers, Units};
use crate::{Post, PostOptions, ToolChange};
use oficina_cam::{Move, Operation, PathMode, Toolpath};
use std::io;

pub(crate) struct Legacy;

const WORDS: MotionWords = MotionWords {
    rapid: "G0",
    line: "G90",
    cw: "G2",
    ccw: "G3",
    absolute_centres: true,
    feed_words: false,
    integer_feed: false,
};

impl Post for Legacy {
    fn words(&self) -> MotionWords {
        WORDS
    }

    fn default_format(&self) -> Format {
        // The seed's programs carry real numbers; 3 decimals is 1 µm.
        Format {
            numbers: Numbers::Decimal { places: 3 },
            ..Format::DEFAULT
        }
    }

    fn check_format(&self, format: &Format) -> Result<(), String> {
        format.validate()?;
        if format.units != Units::Mm {
            return Err("the legacy-2006 control has no unit word: millimetres only".into());
        }
        if matches!(format.numbers, Numbers::Integer { .. }) {
            return Err("the legacy-2006 control reads real numbers, not integer words".into());
        }
        Ok(())
    }

    fn prologue(&self, e: &mut Emitter, tp: &Toolpath, opts: &PostOptions) -> io::Result<()> {
        crate::title_and_settings(e, opts)?;
        let feeds: Vec<f64> = tp
            .operations
            .iter()
            .flat_map(|o| &o.moves)
            .filter_map(|m| match m {
                Move::Line { feed, .. } | Move::Arc { feed, .. } => Some(*feed * 60.0),
                Move::Drill(d) => Some(d.feed * 60.0),
                _ => None,
            })
            .collect();
        let slowest = feeds.iter().copied().fold(f64::INFINITY, f64::min);
        if slowest.is_finite() {
            e.comment(&format!(
                "post = legacy-2006: set the machine feed to {} mm/min [slowest feed of the job]",
                crate::format::num(slowest, 0)
            ))?;
        }
        Ok(())
    }

    /// No tool words: the operator stops the machine and changes the tool.
    fn load_tool(&self, e: &mut Emitter, c: &ToolChange) -> io::Result<()> {
        e.comment(&format!(
            "stop here: load T{} ({}), set Z zero, then start the next part",
            c.op.tool_number,
            c.op.tool.spec()
        ))
    }

    fn spindle(&self, e: &mut Emitter, _tp: &Toolpath, op: &Operation, _: bool) -> io::Result<()> {
        e.comment(&format!("spindle {} rpm", op.spindle_rpm))
    }

    fn dwell(&self, e: &mut Emitter, seconds: f64) -> io::Result<()> {
        e.comment(&format!("dwell {seconds} s: the control has none"))
    }

    fn path_mode(&self, _e: &mut Emitter, _mode: PathMode) -> io::Result<()> {
        Ok(())
    }

    /// The program just stops at safe Z: no spindle word, no M30.
    fn end_program(&self, _e: &mut Emitter) -> io::Result<()> {
        Ok(())
    }
}
