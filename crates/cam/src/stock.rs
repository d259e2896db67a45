//! Material removal on a height-field stock: the tool is stamped along every move at a
//! fraction of a pixel, each grid point lowered to the tool's lower surface above it.
//! The CAM uses it to know what a pass left for the next tool; the simulator to verify.

use crate::tool::Tool;
use crate::toolpath::Move;
use oficina_io::Heightmap;

/// Positions per pixel of travel where the tool is stamped.
pub(crate) const STAMPS_PER_PIXEL: f64 = 4.0;

/// Lowers `stock` to the tool tip at `(x, y, z)` (mm).
pub(crate) fn stamp(stock: &mut Heightmap, tool: &Tool, x: f64, y: f64, z: f64) {
    let px = stock.pixel;
    let reach = tool.reach_radius();
    let (x0, x1) = (
        ((x - reach) / px).ceil().max(0.0),
        ((x + reach) / px).floor(),
    );
    let (y0, y1) = (
        ((y - reach) / px).ceil().max(0.0),
        ((y + reach) / px).floor(),
    );
    if x1 < 0.0 || y1 < 0.0 {
        return;
    }
    let (x1, y1) = (
        x1.min(stock.width as f64 - 1.0),
        y1.min(stock.height as f64 - 1.0),
    );
    if x0 > x1 || y0 > y1 {
        return;
    }
    for iy in y0 as usize..=y1 as usize {
        let dy = iy as f64 * px - y;
        for ix in x0 as usize..=x1 as usize {
            let dx = ix as f64 * px - x;
            if let Some(lift) = tool.profile((dx * dx + dy * dy).sqrt()) {
                let cell = &mut stock.z[iy * stock.width + ix];
                let bottom = (z + lift) as f32;
                if bottom < *cell {
                    *cell = bottom;
                }
            }
        }
    }
}

/// Sweeps the tool along a straight move.
pub fn sweep_line(stock: &mut Heightmap, tool: &Tool, from: [f64; 3], to: [f64; 3]) {
    let len_xy = ((to[0] - from[0]).powi(2) + (to[1] - from[1]).powi(2)).sqrt();
    let steps = ((len_xy / stock.pixel * STAMPS_PER_PIXEL).ceil() as usize).max(1);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        stamp(
            stock,
            tool,
            from[0] + (to[0] - from[0]) * t,
            from[1] + (to[1] - from[1]) * t,
            from[2] + (to[2] - from[2]) * t,
        );
    }
}

/// Sweeps the tool along an XY arc (helical if Z changes) from `from` about `center`.
pub fn sweep_arc(
    stock: &mut Heightmap,
    tool: &Tool,
    from: [f64; 3],
    to: [f64; 3],
    center: [f64; 2],
    ccw: bool,
) {
    let a0 = (from[1] - center[1]).atan2(from[0] - center[0]);
    let mut a1 = (to[1] - center[1]).atan2(to[0] - center[0]);
    let r = ((from[0] - center[0]).powi(2) + (from[1] - center[1]).powi(2)).sqrt();
    if ccw && a1 <= a0 {
        a1 += std::f64::consts::TAU;
    } else if !ccw && a1 >= a0 {
        a1 -= std::f64::consts::TAU;
    }
    let sweep = a1 - a0;
    let steps = ((sweep.abs() * r / stock.pixel * STAMPS_PER_PIXEL).ceil() as usize).max(1);
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let a = a0 + sweep * t;
        stamp(
            stock,
            tool,
            center[0] + r * a.cos(),
            center[1] + r * a.sin(),
            from[2] + (to[2] - from[2]) * t,
        );
    }
}

/// Applies a list of moves starting at `start`; returns the end position.
pub fn apply_moves(
    stock: &mut Heightmap,
    tool: &Tool,
    start: [f64; 3],
    moves: &[Move],
) -> [f64; 3] {
    let mut pos = start;
    for m in moves {
        match *m {
            Move::Rapid { to } | Move::Line { to, .. } => {
                sweep_line(stock, tool, pos, to);
                pos = to;
            }
            Move::Arc {
                to, center, ccw, ..
            } => {
                sweep_arc(stock, tool, pos, to, center, ccw);
                pos = to;
            }
            Move::Drill(d) => pos = apply_moves(stock, tool, pos, &d.moves(pos)),
            Move::Dwell(_) | Move::PathMode(_) | Move::Comp(_) => {}
        }
    }
    pos
}
