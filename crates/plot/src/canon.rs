//! A plot as canonical operations (machine coordinates), for the planner's time estimate
//! without going through G-code text.

use oficina_canon::{Canon, CanonOp, Pos};
use oficina_motion::Profile;

use crate::machine::{arm_limited_feed, PenLift, PenMachine};
use crate::strokes::Plot;

/// Pen up and down are Z moves when the pen is on Z; a servo or command lift costs only its
/// dwell here.
pub fn to_canon(plot: &Plot, m: &PenMachine, profile: &Profile) -> Vec<Canon> {
    let off = profile.work_offset;
    let (down, up) = match m.lift {
        PenLift::Z { down, up } => (down + off[2], up + off[2]),
        _ => (profile.start[2], profile.start[2]),
    };
    let mut ops = Vec::new();
    let mut line = 0u32;
    let mut push = |op: CanonOp| {
        line += 1;
        ops.push(Canon { line, op });
    };
    let at = |x: f64, y: f64, z: f64| Pos::xyz(x + off[0], y + off[1], z);
    let lift = |push: &mut dyn FnMut(CanonOp), x: f64, y: f64, z: f64, feed: bool| {
        let to = at(x, y, z);
        push(if feed {
            CanonOp::StraightFeed { to }
        } else {
            CanonOp::StraightTraverse { to }
        });
        if m.lift_dwell > 0.0 {
            push(CanonOp::Dwell(m.lift_dwell));
        }
    };
    let start = profile.start;
    lift(&mut push, start[0] - off[0], start[1] - off[1], up, false);
    for pen in &plot.pens {
        for s in &pen.strokes {
            push(CanonOp::StraightTraverse {
                to: at(s[0].x, s[0].y, up),
            });
            push(CanonOp::SetFeedRate(m.draw_feed));
            lift(&mut push, s[0].x, s[0].y, down, true);
            push(CanonOp::SetFeedRate(arm_limited_feed(
                profile,
                s,
                m.draw_feed,
            )));
            for p in &s[1..] {
                push(CanonOp::StraightFeed {
                    to: at(p.x, p.y, down),
                });
            }
            let l = s.last().unwrap();
            lift(&mut push, l.x, l.y, up, false);
        }
    }
    push(CanonOp::StraightTraverse {
        to: at(m.home.x, m.home.y, up),
    });
    push(CanonOp::ProgramEnd);
    ops
}
