//! One job operation → its cam operation and the region it may cut (for the stock check),
//! reusing the single-operation ops of `oficina mill`.

use super::model::{ChamferSide, Dogbone, JobOp, OpKind};
use super::select::Shape;
use crate::mill::{EntryKind, PocketStrategy};
use oficina_cam::ops::{
    adaptive, allowed_region, chamfer, chamfer_regions, dogbones, groove_region, half_tan,
    operation, AdaptiveParams, ChamferParams, Comp, Cut, DrillParams, Entry, MillOp, Notch,
    PocketParams, ProfileParams, Side, Strategy, Tabs, VCarveParams, DEFAULT_LEAD_IN,
};
use oficina_cam::{Operation, Tool, ToolFeeds};
use oficina_geom::Path;
use oficina_sim::Design;

/// What the job fixes for every operation.
pub(crate) struct Frame {
    /// Retraction plane, mm.
    pub clear_z: f64,
    /// Stock thickness, mm.
    pub thickness: f64,
}

/// An operation made: its moves, its allowed regions (`None`: on the line, not checked)
/// and its depth.
pub(crate) struct Built {
    /// The moves.
    pub operation: Operation,
    /// Where it may cut.
    pub designs: Option<Vec<Design>>,
    /// Depth reached, mm.
    pub depth: f64,
}

/// Builds `op` on `shapes` with tool `number`/`tool` at `feeds`.
pub(crate) fn build(
    name: &str,
    op: &JobOp,
    shapes: &[&Shape],
    number: u32,
    tool: &Tool,
    feeds: &ToolFeeds,
    frame: &Frame,
) -> Result<Built, String> {
    let d = tool.diameter;
    let angle = op.ramp_angle.unwrap_or(3.0);
    let entry = match op.entry.unwrap_or(EntryKind::Ramp) {
        EntryKind::Plunge => Entry::Plunge,
        EntryKind::Ramp => Entry::Ramp { angle },
        EntryKind::Helix => Entry::Helix {
            radius: d / 3.0,
            angle,
        },
    };
    let depth = match (op.kind, op.depth) {
        (OpKind::Chamfer, Some(_)) => {
            return Err("depth: a chamfer's depth comes from its width; give width".into())
        }
        (OpKind::Chamfer, None) => 1.0,
        (_, Some(depth)) => depth,
        (_, None) => return Err("depth: missing (mm below the stock top)".into()),
    };
    if depth > frame.thickness + 2.0 {
        return Err(format!(
            "depth = {depth}: more than 2 mm below the stock's {} mm",
            frame.thickness
        ));
    }
    let mut cut = Cut {
        tool_number: number,
        tool: tool.clone(),
        spindle_rpm: feeds.rpm,
        feed: feeds.feed / 60.0,
        plunge_feed: feeds.plunge_feed / 60.0,
        top: 0.0,
        depth,
        stepdown: op.stepdown.unwrap_or((d / 2.0).min(depth)),
        clear_z: frame.clear_z,
        entry,
    };
    let mut paths: Vec<Path> = shapes.iter().map(|s| s.path.clone()).collect();
    let notch = match &op.dogbone {
        None | Some(Dogbone::On(false)) => None,
        Some(Dogbone::On(true)) => Some(Notch::Bisector),
        Some(Dogbone::Style(s)) if s == "t-bone" => Some(Notch::LongerSide),
        Some(Dogbone::Style(s)) => {
            return Err(format!("dogbone = {s:?}: write true, false or \"t-bone\""))
        }
    };
    if let Some(notch) = notch {
        if !matches!(op.kind, OpKind::Pocket | OpKind::ProfileIn) {
            return Err("dogbone: only pocket and profile-in have inside corners to notch".into());
        }
        paths = dogbones(&paths, d / 2.0, notch).map_err(|e| format!("dogbone: {e}"))?;
    }
    let allowance = op.allowance.unwrap_or(0.2);
    let profile = |side| {
        MillOp::Profile(ProfileParams {
            side,
            allowance: if side == Side::On { 0.0 } else { allowance },
            tabs: op.tabs.map(|t| Tabs {
                count: t.count,
                width: t.width,
                height: t.height,
            }),
            lead_out: op.lead_out.unwrap_or(0.0),
            lead_in: op.lead_in.unwrap_or(d / 2.0 * DEFAULT_LEAD_IN),
            comp: Comp::Computer,
        })
    };
    let mill_op = match op.kind {
        OpKind::ProfileIn => profile(Side::Inside),
        OpKind::ProfileOut => profile(Side::Outside),
        OpKind::ProfileOn | OpKind::Engrave => profile(Side::On),
        OpKind::Pocket => MillOp::Pocket(PocketParams {
            strategy: match op.strategy.unwrap_or(PocketStrategy::Offset) {
                PocketStrategy::Offset => Strategy::Offset,
                PocketStrategy::Zigzag => Strategy::ZigZag,
            },
            stepover: op.stepover.unwrap_or(0.6 * d),
            allowance,
        }),
        OpKind::Drill => MillOp::Drill(DrillParams {
            peck: op.peck,
            dwell: op.dwell.unwrap_or(0.0),
        }),
        OpKind::Vcarve => MillOp::VCarve(VCarveParams {
            leftover: op.leftover.unwrap_or(0.05),
        }),
        OpKind::Chamfer => return build_chamfer(name, op, shapes, cut),
        // Cleared like a pocket (the same region may be cut), at a bounded engagement.
        OpKind::Adaptive => MillOp::Pocket(PocketParams {
            strategy: Strategy::Offset,
            stepover: op.stepover.unwrap_or(d),
            allowance: op.stock_to_leave.unwrap_or(0.0),
        }),
    };
    if op.tabs.is_some() && !matches!(op.kind, OpKind::ProfileOut | OpKind::ProfileIn) {
        return Err("tabs: only profile-out and profile-in leave tabs".into());
    }
    let made = if op.kind == OpKind::Adaptive {
        let params = AdaptiveParams {
            max_engagement: op.max_engagement.unwrap_or(90.0),
            stepover: op.stepover.unwrap_or(d),
            stock_to_leave: op.stock_to_leave.unwrap_or(0.0),
        };
        adaptive(name, &paths, &cut, &params)
    } else {
        operation(&paths, &cut, &mill_op)
    };
    let mut operation = made.map_err(|e| e.to_string())?;
    operation.name = name.to_string();
    let slope = match mill_op {
        MillOp::VCarve(_) => 1.0 / half_tan(&cut).map_err(|e| e.to_string())?,
        _ => 0.0,
    };
    cut.depth = depth;
    let region = match op.kind {
        // On the line: within the tool radius of it.
        OpKind::ProfileOn | OpKind::Engrave => Some((
            groove_region(&paths, d / 2.0).map_err(|e| e.to_string())?,
            true,
        )),
        _ => allowed_region(&paths, &mill_op).map_err(|e| e.to_string())?,
    };
    let designs = region.map(|(rings, cut_inside)| {
        vec![Design {
            rings,
            cut_inside,
            top: 0.0,
            floor: cut.bottom(),
            slope,
        }]
    });
    Ok(Built {
        operation,
        designs,
        depth,
    })
}

/// A chamfer: parts (even nesting depth) from outside, holes (odd) from inside, unless the
/// op says which side.
fn build_chamfer(name: &str, op: &JobOp, shapes: &[&Shape], mut cut: Cut) -> Result<Built, String> {
    if !matches!(cut.tool.shape, oficina_cam::CutterShape::V { .. }) {
        return Err(format!(
            "tool: a chamfer needs a V bit (v:DIAMETER:ANGLE), not {}",
            cut.tool.spec()
        ));
    }
    // Passes of half the bit's diameter unless asked: a chamfer is usually one pass.
    cut.stepdown = op.stepdown.unwrap_or(cut.tool.diameter / 2.0);
    let p = ChamferParams {
        width: op
            .width
            .ok_or("width: missing (the chamfer's width on the top face, mm)")?,
        tip_offset: op.tip_offset.unwrap_or(0.0),
    };
    let closed: Vec<&Shape> = shapes.iter().copied().filter(|s| s.path.closed).collect();
    let is_hole = |s: &Shape| match op.side {
        Some(ChamferSide::In) => true,
        Some(ChamferSide::Out) => false,
        None => s.depth % 2 == 1,
    };
    let holes: Vec<Path> = closed
        .iter()
        .filter(|s| is_hole(s))
        .map(|s| s.path.clone())
        .collect();
    let parts: Vec<Path> = closed
        .iter()
        .filter(|s| !is_hole(s))
        .map(|s| s.path.clone())
        .collect();
    let depth = p.depth(&cut).map_err(|e| e.to_string())?;
    let slope = 1.0 / half_tan(&cut).map_err(|e| e.to_string())?;
    let mut operation = chamfer(name, &parts, &holes, &cut, &p).map_err(|e| e.to_string())?;
    operation.name = name.to_string();
    let designs = chamfer_regions(&parts, &holes, &p)
        .map_err(|e| e.to_string())?
        .into_iter()
        .map(|(rings, cut_inside)| Design {
            rings,
            cut_inside,
            top: 0.0,
            floor: -depth,
            slope,
        })
        .collect();
    Ok(Built {
        operation,
        designs: Some(designs),
        depth,
    })
}
