//! The machine-neutral toolpath: operations (one tool, spindle and feeds each) made of
//! rapid, line, arc and dwell moves. Relief, profile, pocket and sole CAM all produce this;
//! post-processors turn it into a dialect, and [`Toolpath::canon`] into canonical operations.

use crate::tool::Tool;
use oficina_canon::{Canon, CanonOp, Plane, Pos, SpindleDir};

#[derive(Clone, Debug, PartialEq)]
pub enum Move {
    Rapid {
        to: [f64; 3],
    },
    /// Straight feed at `feed` mm/s.
    Line {
        to: [f64; 3],
        feed: f64,
    },
    /// Arc in the XY plane about `center` (X, Y), helical when Z changes.
    Arc {
        to: [f64; 3],
        center: [f64; 2],
        ccw: bool,
        feed: f64,
    },
    /// Seconds.
    Dwell(f64),
}

#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    pub name: String,
    pub tool_number: u32,
    pub tool: Tool,
    pub spindle_rpm: f64,
    pub moves: Vec<Move>,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Toolpath {
    /// Z (mm) clear of the stock and clamps; retracts and tool changes happen here.
    pub safe_z: f64,
    pub operations: Vec<Operation>,
}

impl Move {
    pub fn end(&self) -> Option<[f64; 3]> {
        match *self {
            Move::Rapid { to } | Move::Line { to, .. } | Move::Arc { to, .. } => Some(to),
            Move::Dwell(_) => None,
        }
    }
}

impl Toolpath {
    /// The canonical operations this toolpath means, starting from the machine at `safe_z`
    /// above the origin. Used to feed the simulator and the estimator without text; it must
    /// agree with what the post-processors print (tested there).
    pub fn canon(&self) -> Vec<Canon> {
        let mut out = Vec::new();
        let mut push = |op| out.push(Canon { line: 0, op });
        let mut current_tool = None;
        for op in &self.operations {
            if current_tool != Some(op.tool_number) {
                push(CanonOp::SelectTool(op.tool_number));
                push(CanonOp::ChangeTool(op.tool_number));
                current_tool = Some(op.tool_number);
            }
            push(CanonOp::SetSpindleSpeed(op.spindle_rpm));
            push(CanonOp::StartSpindle(SpindleDir::Clockwise));
            for m in &op.moves {
                match *m {
                    Move::Rapid { to } => push(CanonOp::StraightTraverse { to: pos(to) }),
                    Move::Line { to, feed } => {
                        push(CanonOp::SetFeedRate(feed * 60.0));
                        push(CanonOp::StraightFeed { to: pos(to) });
                    }
                    Move::Arc {
                        to,
                        center,
                        ccw,
                        feed,
                    } => {
                        push(CanonOp::SetFeedRate(feed * 60.0));
                        push(CanonOp::ArcFeed {
                            plane: Plane::XY,
                            end: pos(to),
                            center,
                            turns: if ccw { 1 } else { -1 },
                        });
                    }
                    Move::Dwell(s) => push(CanonOp::Dwell(s)),
                }
            }
        }
        push(CanonOp::StopSpindle);
        push(CanonOp::ProgramEnd);
        out
    }

    /// Number of motion moves.
    pub fn move_count(&self) -> usize {
        self.operations
            .iter()
            .map(|o| o.moves.iter().filter(|m| m.end().is_some()).count())
            .sum()
    }
}

fn pos(p: [f64; 3]) -> Pos {
    Pos::xyz(p[0], p[1], p[2])
}
