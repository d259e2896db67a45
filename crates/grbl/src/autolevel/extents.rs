//! The XY extents of a program's feed moves, as the interpreter reads it: the area a height
//! map must cover.

use super::grid::Area;
use oficina_canon::CanonOp;
use oficina_gcode::{Dialect, RunOptions, Severity};
use oficina_geom::Helix;

/// The rectangle holding every feed move (arcs by their swept box) of `text`, work mm. A
/// feed move from before the first positioned move starts nowhere known: only its end counts.
pub fn feed_area(text: &str, dialect: Dialect) -> Result<Area, String> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut add = |p: [f64; 3]| {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    };
    let mut at: Option<[f64; 3]> = None;
    let opts = RunOptions {
        dialect,
        ..RunOptions::default()
    };
    // M6 (which grbl's sender handles, never grbl) moves nothing: read without it.
    let view = crate::sender_view(text.as_bytes(), &crate::ToolChange::default()).0;
    let text = String::from_utf8_lossy(&view);
    let diags = oficina_gcode::run_text(&text, &opts, &mut |c| match c.op {
        CanonOp::StraightTraverse { to } => at = Some([to.x, to.y, to.z]),
        CanonOp::StraightFeed { to } => {
            let to = [to.x, to.y, to.z];
            if let Some(a) = at {
                add(a);
            }
            add(to);
            at = Some(to);
        }
        CanonOp::ArcFeed {
            plane,
            end,
            center,
            turns,
            ..
        } => {
            let to = [end.x, end.y, end.z];
            match at {
                Some(a) => {
                    let (l, h) = Helix::new(plane, a, to, center, turns).extents();
                    add(l);
                    add(h);
                }
                None => add(to),
            }
            at = Some(to);
        }
        _ => {}
    });
    if let Some(d) = diags.iter().find(|d| d.severity == Severity::Error) {
        return Err(format!("line {}: {}", d.span.line, d.message));
    }
    if lo[0] > hi[0] {
        return Err("the program has no feed moves: nothing to probe under".into());
    }
    Ok(Area { min: lo, max: hi })
}
