//! Canonical operations → material removal.

use oficina_cam::stock::{sweep_arc, sweep_line};
use oficina_cam::Tool;
use oficina_canon::{Canon, CanonOp, Plane};
use oficina_io::Heightmap;
use std::collections::HashMap;

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SimError {
    #[error("line {line}: motion with tool {tool}, which the simulator was not given")]
    UnknownTool { line: u32, tool: u32 },
    #[error("line {line}: motion before any tool change; the simulator needs to know the tool")]
    NoTool { line: u32 },
    #[error("line {line}: arcs outside the XY plane are not simulated on a height field")]
    ArcPlane { line: u32 },
}

/// Replays `ops` on `stock`, starting at `start` (mm, machine coordinates). Rapids cut too:
/// a rapid through material is exactly what the simulator must catch.
///
/// The tool in the spindle: `M6` loads it; without a changer (grbl) the operator loads the
/// first tool named by `T` before starting and each later one at the program stop (`M0`,
/// `M1`) that follows its `T`.
pub fn replay<'a>(
    ops: impl IntoIterator<Item = &'a Canon>,
    tools: &HashMap<u32, Tool>,
    stock: &mut Heightmap,
    start: [f64; 3],
) -> Result<[f64; 3], SimError> {
    let mut pos = start;
    let mut tool: Option<&Tool> = None;
    let mut selected: Option<u32> = None;
    let lookup = |n: u32, line: u32| tools.get(&n).ok_or(SimError::UnknownTool { line, tool: n });
    for c in ops {
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
                let to = [to.x, to.y, to.z];
                sweep_line(stock, t, pos, to);
                pos = to;
            }
            CanonOp::ArcFeed {
                plane,
                end,
                center,
                turns,
            } => {
                if *plane != Plane::XY {
                    return Err(SimError::ArcPlane { line: c.line });
                }
                let t = tool.ok_or(SimError::NoTool { line: c.line })?;
                let to = [end.x, end.y, end.z];
                sweep_arc(stock, t, pos, to, *center, *turns > 0);
                pos = to;
            }
            _ => {}
        }
    }
    Ok(pos)
}
