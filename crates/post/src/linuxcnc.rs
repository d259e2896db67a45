//! LinuxCNC (RS274/NGC): the [`Post`] defaults (the RS274 skeleton in `rs274.rs`) plus
//! G81/G82/G83 drilling, G61/G64 and G41/G42 compensation.

use crate::emit::Emitter;
use crate::format::push_decimal;
use crate::Post;
use oficina_cam::{CompSide, Drill, PathMode};
use std::io;

pub(crate) struct LinuxCnc;

impl Post for LinuxCnc {
    /// G99 (back to R) G81, G82 with P seconds, or G83 with Q pecks.
    fn drill(&self, e: &mut Emitter, d: &Drill) -> io::Result<()> {
        let code = match (d.peck, d.dwell > 0.0) {
            (Some(q), _) if q > 0.0 => "G83",
            (_, true) => "G82",
            _ => "G81",
        };
        let f = e.format;
        let mut s = format!("G99 {code}");
        f.push_word(&mut s, 'X', f.length(d.at[0]));
        f.push_word(&mut s, 'Y', f.length(d.at[1]));
        f.push_word(&mut s, 'Z', f.length(d.bottom));
        f.push_word(&mut s, 'R', f.length(d.r));
        if let Some(q) = d.peck.filter(|q| *q > 0.0) {
            f.push_word(&mut s, 'Q', f.length(q));
        }
        if d.dwell > 0.0 {
            s.push_str(" P");
            push_decimal(&mut s, d.dwell, 4);
        }
        let feed = f.length(d.feed * 60.0);
        s.push_str(" F");
        push_decimal(&mut s, feed, 4);
        e.block(&s)?;
        e.set_feed_written(feed);
        e.pos = [d.at[0], d.at[1], d.r];
        Ok(())
    }

    fn path_mode(&self, e: &mut Emitter, mode: PathMode) -> io::Result<()> {
        e.block(match mode {
            PathMode::ExactStop => "G61",
            PathMode::Continuous => "G64",
        })
    }

    /// G41/G42 D n on a block of its own: the next move is the entry move.
    fn comp(&self, e: &mut Emitter, comp: Option<(CompSide, u32)>) -> io::Result<()> {
        e.block(&match comp {
            Some((CompSide::Left, d)) => format!("G41 D{d}"),
            Some((CompSide::Right, d)) => format!("G42 D{d}"),
            None => "G40".into(),
        })
    }
}
