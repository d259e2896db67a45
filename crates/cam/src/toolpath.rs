//! The machine-neutral toolpath: operations (one tool, spindle and feeds each) made of
//! rapid, line, arc and dwell moves. Relief, profile, pocket and sole CAM all produce this;
//! post-processors turn it into a dialect, and [`Toolpath::canon`] into canonical operations.

use crate::tool::Tool;
use oficina_canon::{Canon, CanonOp, PathControlMode, Plane, Pos, SpindleDir};

/// One tool-centre move of a toolpath (lengths mm, feeds mm/s).
#[derive(Clone, Debug, PartialEq)]
pub enum Move {
    /// Rapid to `to`.
    Rapid {
        /// End point.
        to: [f64; 3],
    },
    /// Straight feed at `feed` mm/s.
    Line {
        /// End point.
        to: [f64; 3],
        /// Feed, mm/s.
        feed: f64,
    },
    /// Arc in the XY plane about `center` (X, Y), helical when Z changes.
    Arc {
        /// End point.
        to: [f64; 3],
        /// Centre (X, Y).
        center: [f64; 2],
        /// Counter-clockwise (G3) rather than clockwise (G2).
        ccw: bool,
        /// Feed, mm/s.
        feed: f64,
    },
    /// Seconds.
    Dwell(f64),
    /// One drilled hole: a canned cycle where the control has them (G81/G82/G83), the same
    /// moves written out where it has not ([`Drill::moves`] says what they are).
    Drill(Drill),
    /// Corner behaviour from here on (G61/G64, Sinumerik G60/G64).
    PathMode(PathMode),
    /// Cutter radius compensation from here on: the control keeps the tool on `side` of
    /// the programmed path (G41 left, G42 right) by the radius in tool register D, or off
    /// (G40). Moves in between are the part outline, not the tool centre.
    Comp(Option<(CompSide, u32)>),
}

/// Side of the programmed path the tool is kept on, looking along the travel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CompSide {
    /// G41.
    Left,
    /// G42.
    Right,
}

/// A drilling cycle at one point, retracting to the R plane after the hole (LinuxCNC G99).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Drill {
    /// Hole centre (X, Y).
    pub at: [f64; 2],
    /// Z of the hole bottom.
    pub bottom: f64,
    /// Z of the R plane: rapids stop here, the feed starts here, the tool returns here.
    pub r: f64,
    /// Depth of each peck (G83); `None` drills in one feed.
    pub peck: Option<f64>,
    /// Seconds at the bottom (G82); 0 for none.
    pub dwell: f64,
    /// Feed, mm/s.
    pub feed: f64,
}

/// How the control treats block joints.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathMode {
    /// Stop exactly at each block end: sharp corners (G61, Sinumerik G60).
    ExactStop,
    /// Blend through joints without slowing: no dwell marks on a contour (G64).
    Continuous,
}

/// LinuxCNC's G83 rapids back down to this far (0.010 inch) above the last peck's bottom.
pub(crate) const PECK_CLEARANCE: f64 = 0.254;

impl Drill {
    /// The cycle as plain moves from `from`, as LinuxCNC executes it under G99: up to R if
    /// below it, rapid over the hole, rapid down to R, feed to the bottom (in pecks, each
    /// followed by a rapid out to R and back down to [`PECK_CLEARANCE`] above the cut), dwell,
    /// rapid back to R.
    pub fn moves(&self, from: [f64; 3]) -> Vec<Move> {
        let [x, y] = self.at;
        let mut out = Vec::new();
        if from[2] < self.r {
            out.push(Move::Rapid {
                to: [from[0], from[1], self.r],
            });
        }
        let z0 = from[2].max(self.r);
        out.push(Move::Rapid { to: [x, y, z0] });
        if z0 != self.r {
            out.push(Move::Rapid { to: [x, y, self.r] });
        }
        match self.peck {
            Some(q) if q > 0.0 => {
                let mut depth = self.r;
                loop {
                    let next = (depth - q).max(self.bottom);
                    out.push(Move::Line {
                        to: [x, y, next],
                        feed: self.feed,
                    });
                    depth = next;
                    if depth <= self.bottom {
                        break;
                    }
                    out.push(Move::Rapid { to: [x, y, self.r] });
                    out.push(Move::Rapid {
                        to: [x, y, depth + PECK_CLEARANCE],
                    });
                }
            }
            _ => out.push(Move::Line {
                to: [x, y, self.bottom],
                feed: self.feed,
            }),
        }
        if self.dwell > 0.0 {
            out.push(Move::Dwell(self.dwell));
        }
        out.push(Move::Rapid { to: [x, y, self.r] });
        out
    }
}

/// The moves of one tool: what a post writes between tool changes.
#[derive(Clone, Debug, PartialEq)]
pub struct Operation {
    /// The operation's name, written as a comment.
    pub name: String,
    /// Tool number in the program.
    pub tool_number: u32,
    /// The cutter.
    pub tool: Tool,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
    /// The moves in order.
    pub moves: Vec<Move>,
}

/// A whole job: operations in order, machine-neutral.
#[derive(Clone, Debug, PartialEq)]
pub struct Toolpath {
    /// Z (mm) clear of the stock and clamps; retracts and tool changes happen here.
    pub safe_z: f64,
    /// The operations in cutting order.
    pub operations: Vec<Operation>,
}

impl Move {
    /// Where the move leaves the tool; `None` for moves that do not move it.
    pub fn end(&self) -> Option<[f64; 3]> {
        match *self {
            Move::Rapid { to } | Move::Line { to, .. } | Move::Arc { to, .. } => Some(to),
            Move::Dwell(_) | Move::PathMode(_) | Move::Comp(_) => None,
            Move::Drill(d) => Some([d.at[0], d.at[1], d.r]),
        }
    }
}

impl Toolpath {
    /// Each tool number the operations use, with its tool: what the simulator needs to cut
    /// with the right cutter when it replays the program.
    pub fn tools(&self) -> std::collections::HashMap<u32, Tool> {
        self.operations
            .iter()
            .map(|o| (o.tool_number, o.tool.clone()))
            .collect()
    }

    /// The canonical operations this toolpath means, starting from the machine at `safe_z`
    /// above the origin. Used to feed the simulator and the estimator without text; it must
    /// agree with what the post-processors print (tested there).
    pub fn canon(&self) -> Vec<Canon> {
        let mut out = Vec::new();
        let mut push = |op| out.push(Canon { line: 0, op });
        let mut current_tool = None;
        let mut at = [0.0, 0.0, self.safe_z];
        for op in &self.operations {
            if current_tool != Some(op.tool_number) {
                push(CanonOp::SelectTool(op.tool_number));
                push(CanonOp::ChangeTool(op.tool_number));
                current_tool = Some(op.tool_number);
            }
            push(CanonOp::SetSpindleSpeed(op.spindle_rpm));
            push(CanonOp::StartSpindle(SpindleDir::Clockwise));
            let plain;
            (plain, at) = plain_moves(&op.moves, at);
            for m in plain {
                match m {
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
                            rotation: 0.0,
                        });
                    }
                    Move::Dwell(s) => push(CanonOp::Dwell(s)),
                    Move::PathMode(mode) => push(CanonOp::SetMotionControlMode {
                        mode: match mode {
                            PathMode::ExactStop => PathControlMode::ExactPath,
                            PathMode::Continuous => PathControlMode::Continuous,
                        },
                        tolerance: 0.0,
                    }),
                    // Expanded into plain moves above.
                    Move::Drill(_) => {}
                    // The moves stay the programmed ones: only a control (or the
                    // interpreter reading the posted text) knows the radius in D.
                    Move::Comp(_) => {}
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

/// `moves` with every [`Move::Drill`] written out as the moves it makes, starting at
/// `from`; also returns where they end.
pub(crate) fn plain_moves(moves: &[Move], from: [f64; 3]) -> (Vec<Move>, [f64; 3]) {
    let mut at = from;
    let mut out = Vec::with_capacity(moves.len());
    for m in moves {
        match m {
            Move::Drill(d) => out.extend(d.moves(at)),
            m => out.push(m.clone()),
        }
        if let Some(to) = m.end() {
            at = to;
        }
    }
    (out, at)
}

fn pos(p: [f64; 3]) -> Pos {
    Pos::xyz(p[0], p[1], p[2])
}
