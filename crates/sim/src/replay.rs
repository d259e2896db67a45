//! Canonical operations → material removal.

use oficina_cam::Tool;
use oficina_cam::{sweep_arc, sweep_line};
use oficina_canon::{from_arc_frame, to_arc_frame, Canon, CanonOp, Plane};
use oficina_geom::{chord_count, Helix};
use oficina_io::Heightmap;
use std::borrow::Borrow;
use std::collections::HashMap;

/// Why the simulator cannot replay a program.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SimError {
    /// A move uses a tool the simulator has no shape for.
    #[error("line {line}: motion with tool {tool}, which the simulator was not given")]
    UnknownTool {
        /// Source line.
        line: u32,
        /// Tool number.
        tool: u32,
    },
    /// A move comes before any tool change.
    #[error("line {line}: motion before any tool change; the simulator needs to know the tool")]
    NoTool {
        /// Source line.
        line: u32,
    },
}

/// Replays `ops` on `stock`, starting at `start` (mm, machine coordinates). Rapids cut too:
/// a rapid through material is exactly what the simulator must catch.
///
/// The tool in the spindle: `M6` loads it; without a changer (grbl) the operator loads the
/// first tool named by `T` before starting and each later one at the program stop (`M0`,
/// `M1`) that follows its `T`.
pub fn replay<B: Borrow<Canon>>(
    ops: impl IntoIterator<Item = B>,
    tools: &HashMap<u32, Tool>,
    stock: &mut Heightmap,
    start: [f64; 3],
) -> Result<[f64; 3], SimError> {
    replay_watched(ops, tools, stock, start, [0.0, 0.0], |_, _| {})
}

/// What a move is, for a watcher of [`replay_watched`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MoveKind {
    /// `G0`.
    Rapid,
    /// A straight feed.
    Feed,
    /// An arc (any plane).
    Arc,
    /// A rigid tap, in and back out.
    Tap,
}

/// A move about to be cut, in grid coordinates (program XY minus the grid's origin).
#[derive(Clone, Copy, Debug)]
pub struct Move<'a> {
    /// Source line.
    pub line: u32,
    /// What kind of move.
    pub kind: MoveKind,
    /// The tool in the spindle.
    pub tool: &'a Tool,
    /// Tool tip before the move.
    pub from: [f64; 3],
    /// Tool tip after it.
    pub to: [f64; 3],
}

/// [`replay`] on a grid whose point (0, 0) is at program XY `origin`; `watch` sees each
/// move and the stock just before the move is cut (how a rapid into material is caught
/// without a second material-removal).
pub fn replay_watched<B: Borrow<Canon>>(
    ops: impl IntoIterator<Item = B>,
    tools: &HashMap<u32, Tool>,
    stock: &mut Heightmap,
    start: [f64; 3],
    origin: [f64; 2],
    mut watch: impl FnMut(&Move, &Heightmap),
) -> Result<[f64; 3], SimError> {
    let grid = |p: [f64; 3]| [p[0] - origin[0], p[1] - origin[1], p[2]];
    let mut pos = grid(start);
    // Stock only goes down: its highest point now bounds it for the whole replay.
    let ceiling = stock.z.iter().copied().fold(f32::MIN, f32::max) as f64;
    let mut tool: Option<&Tool> = None;
    let mut selected: Option<u32> = None;
    let lookup = |n: u32, line: u32| tools.get(&n).ok_or(SimError::UnknownTool { line, tool: n });
    for c in ops {
        let c = c.borrow();
        let seen = |kind, tool, to| Move {
            line: c.line,
            kind,
            tool,
            from: pos,
            to,
        };
        match &c.op {
            CanonOp::ChangeTool(n) => {
                tool = Some(lookup(*n, c.line)?);
                selected = None;
            }
            CanonOp::SelectTool(n) if tool.is_none() => tool = Some(lookup(*n, c.line)?),
            CanonOp::SelectTool(n) => selected = Some(*n),
            CanonOp::ProgramStop | CanonOp::OptionalProgramStop => {
                if let Some(n) = selected.take() {
                    tool = Some(lookup(n, c.line)?);
                }
            }
            CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => {
                let t = tool.ok_or(SimError::NoTool { line: c.line })?;
                let kind = match c.op {
                    CanonOp::StraightTraverse { .. } => MoveKind::Rapid,
                    _ => MoveKind::Feed,
                };
                let to = grid([to.x, to.y, to.z]);
                watch(&seen(kind, t, to), stock);
                if let Some(t) = touching(t, ceiling - pos[2].min(to[2]), stock.pixel) {
                    sweep_line(stock, &t, pos, to);
                }
                pos = to;
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
                rotation,
            } => {
                let t = tool.ok_or(SimError::NoTool { line: c.line })?;
                let to = grid([end.x, end.y, end.z]);
                watch(&seen(MoveKind::Arc, t, to), stock);
                // An XZ/YZ arc may dip below both ends: no narrowing for those.
                let below = match plane {
                    Plane::XY => ceiling - pos[2].min(to[2]),
                    _ => f64::INFINITY,
                };
                let Some(t) = touching(t, below, stock.pixel) else {
                    pos = to;
                    continue;
                };
                let t = &t;
                if *plane == Plane::XY {
                    let center = [center[0] - origin[0], center[1] - origin[1]];
                    sweep_arc(stock, t, pos, to, center, *turns > 0);
                } else {
                    // Chords in the arc's own frame (from program coordinates, where its
                    // centre is given), swept on the grid.
                    let program = |p: [f64; 3]| [p[0] + origin[0], p[1] + origin[1], p[2]];
                    let (a, b) = (
                        to_arc_frame(program(pos), *rotation),
                        to_arc_frame(program(to), *rotation),
                    );
                    let mut from = pos;
                    for p in arc_chords(*plane, a, b, *center, *turns, CHORD_TOLERANCE) {
                        let p = grid(from_arc_frame(p, *rotation));
                        sweep_line(stock, t, from, p);
                        from = p;
                    }
                }
                pos = to;
            }
            // A rigid tap cuts in to its end and back out along the same line.
            CanonOp::RigidTap { to } => {
                let t = tool.ok_or(SimError::NoTool { line: c.line })?;
                let to = grid([to.x, to.y, to.z]);
                watch(&seen(MoveKind::Tap, t, to), stock);
                sweep_line(stock, t, pos, to);
                sweep_line(stock, t, to, pos);
            }
            _ => {}
        }
    }
    Ok([pos[0] + origin[0], pos[1] + origin[1], pos[2]])
}

/// The part of `tool` that can touch stock when its tip is at most `below` mm under the
/// stock's highest point: `None` when the tip stays above it (nothing is cut, every profile
/// being ≥ 0); for a V bit only the cone out to ρ = below·tan(θ/2) (plus a pixel), which
/// stamps the same stock as the whole bit in far fewer cells; otherwise the tool itself.
fn touching(tool: &Tool, below: f64, pixel: f64) -> Option<std::borrow::Cow<'_, Tool>> {
    use std::borrow::Cow;
    if below <= 0.0 {
        return None;
    }
    match tool.shape {
        oficina_cam::CutterShape::V { angle } if below < tool.flute_length => {
            let r = below * (angle.to_radians() / 2.0).tan() + pixel;
            if r >= tool.reach_radius() {
                return Some(Cow::Borrowed(tool));
            }
            Some(Cow::Owned(Tool {
                diameter: 2.0 * r,
                shank_diameter: 2.0 * r,
                ..tool.clone()
            }))
        }
        _ => Some(Cow::Borrowed(tool)),
    }
}

/// Chord height (mm) allowed when arcs in the XZ and YZ planes are cut into straight pieces:
/// far below the 1 µm the reports resolve.
const CHORD_TOLERANCE: f64 = 1e-4;

/// End points of chords along an arc in `plane` (G18/G19 arcs, such as image-to-gcode's
/// entry and fitted moves), none further than `tol` from the arc.
pub(crate) fn arc_chords(
    plane: Plane,
    from: [f64; 3],
    to: [f64; 3],
    center: [f64; 2],
    turns: i32,
    tol: f64,
) -> Vec<[f64; 3]> {
    let helix = Helix::new(plane, from, to, center, turns);
    // Bounded: at most one chord per 0.01° whatever the radius.
    let count = chord_count(helix.arc.radius, helix.arc.sweep, tol)
        .min(36_000 * (turns.unsigned_abs() as usize).max(1));
    (1..=count)
        .map(|k| {
            if k == count {
                to
            } else {
                helix.point_at(k as f64 / count as f64)
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_rigid_tap_cuts_to_its_depth_and_ends_where_it_started() {
        use oficina_canon::{Canon, Pos};
        let tool = oficina_cam::Tool::new(oficina_cam::CutterShape::Flat, 4.0).unwrap();
        let tools = HashMap::from([(1, tool)]);
        let mut stock = Heightmap::flat(41, 41, 0.5, 0.0);
        let ops: Vec<Canon> = [
            CanonOp::ChangeTool(1),
            CanonOp::StraightTraverse {
                to: Pos::xyz(10.0, 10.0, 2.0),
            },
            CanonOp::StartSpeedFeedSync { pitch: 1.0 },
            CanonOp::RigidTap {
                to: Pos::xyz(10.0, 10.0, -8.0),
            },
            CanonOp::StopSpeedFeedSync,
        ]
        .into_iter()
        .map(|op| Canon { line: 1, op })
        .collect();
        let end = replay(&ops, &tools, &mut stock, [0.0, 0.0, 5.0]).unwrap();
        assert_eq!(end, [10.0, 10.0, 2.0]);
        assert!(
            (stock.at(20, 20) + 8.0).abs() < 1e-6,
            "{}",
            stock.at(20, 20)
        );
        // 4 mm from the axis, outside the 2 mm radius: untouched.
        assert_eq!(stock.at(28, 20), 0.0);
    }

    #[test]
    fn xz_arc_chords_stay_on_the_circle() {
        // G18 half circle from X0 Z0 to X10 Z0 about X5 Z0, bulging down (clockwise seen
        // from +Y in (Z, X) coordinates is counter-clockwise there: check both ends).
        for turns in [1, -1] {
            let pts = arc_chords(
                Plane::XZ,
                [0.0, 2.0, 0.0],
                [10.0, 2.0, 0.0],
                [0.0, 5.0],
                turns,
                1e-4,
            );
            assert_eq!(*pts.last().unwrap(), [10.0, 2.0, 0.0]);
            let mid = pts[pts.len() / 2];
            assert!((mid[2].abs() - 5.0).abs() < 1e-3, "{mid:?}");
            for p in &pts {
                assert!(((p[0] - 5.0).hypot(p[2]) - 5.0).abs() < 1e-9);
                assert_eq!(p[1], 2.0);
            }
        }
    }
}
