//! Checking a 2.5D milling program against its drawing: the program, as the interpreter
//! read it, is replayed on a flat stock; the design is the stock top with the regions the
//! operation may cut lowered to the floor. Gouge = stock below the design (a cut outside
//! the allowed region or below the floor); leftover = stock above it.

use crate::replay::{replay, SimError};
use crate::report::{compare, ideal_surface, Report};
use oficina_cam::Tool;
use oficina_canon::{Canon, CanonOp, Pos};
use oficina_io::Heightmap;
use std::collections::HashMap;

/// What may be cut: the inside of `rings` (even–odd) or their outside, down to `floor`.
#[derive(Clone, Debug, PartialEq)]
pub struct Design {
    /// Closed outlines, mm (X, Y).
    pub rings: Vec<Vec<[f64; 2]>>,
    /// Cut inside the rings (a pocket) rather than outside (a profile's part).
    pub cut_inside: bool,
    /// Stock top, mm.
    pub top: f64,
    /// Design floor, mm.
    pub floor: f64,
    /// Walls that slope down from the rings by this many mm per mm inwards (a V-carving:
    /// 1 / tan(half angle)), down to `floor`; 0: vertical walls.
    pub slope: f64,
}

/// Result of a check, with the grids for previews.
pub struct MillCheck {
    /// How the stock compares with the design.
    pub report: Report,
    /// The simulated stock.
    pub stock: Heightmap,
    /// The design as a height field on the same grid.
    pub design: Heightmap,
    /// Where grid point (0, 0) is in program coordinates.
    pub origin: [f64; 2],
}

/// Largest grid the check builds (about 64 MB of f32 per map): a bigger drawing gets a
/// coarser pixel rather than an allocation without bound.
pub(crate) const MAX_PIXELS: usize = 16_000_000;

/// Replays `canon` over the drawing's extent plus `margin` mm at `pixel` mm (coarsened if
/// the grid would pass [`MAX_PIXELS`]) and compares with `design`. `last_tool` judges the
/// scallops (what that tool can reach).
pub fn check_mill(
    canon: &[Canon],
    tools: &HashMap<u32, Tool>,
    designs: &[Design],
    mut pixel: f64,
    margin: f64,
    start_z: f64,
    last_tool: &Tool,
) -> Result<MillCheck, SimError> {
    let (x0, y0, x1, y1) = oficina_geom::bounds(
        designs
            .iter()
            .flat_map(|d| d.rings.iter().flatten().copied()),
    )
    .map_or((0.0, 0.0, 1.0, 1.0), |b| (b.x0, b.y0, b.x1, b.y1));
    let (x0, y0) = (x0 - margin, y0 - margin);
    let (w_mm, h_mm) = (x1 + margin - x0, y1 + margin - y0);
    while (w_mm / pixel) * (h_mm / pixel) > MAX_PIXELS as f64 {
        pixel *= 1.5;
    }
    let width = (w_mm / pixel).ceil() as usize + 1;
    let height = (h_mm / pixel).ceil() as usize + 1;
    let top = designs.first().map_or(0.0, |d| d.top);
    let mut d = Heightmap::flat(width, height, pixel, top as f32);
    // The cuts each design allows, together: the lowest of them at every point.
    for design in designs {
        let one = design_map(design, [x0, y0], [w_mm, width as f64, height as f64], pixel);
        for (v, o) in d.z.iter_mut().zip(one) {
            *v = v.min(o);
        }
    }
    let shifted = shift(canon, [-x0, -y0]);
    let mut stock = Heightmap::flat(width, height, pixel, top as f32);
    replay(&shifted, tools, &mut stock, [-x0, -y0, start_z])?;
    let ideal = ideal_surface(&d, last_tool);
    let mut report = compare(&stock, &d, &ideal);
    report.gouge_at = [report.gouge_at[0] + x0, report.gouge_at[1] + y0];
    Ok(MillCheck {
        report,
        stock,
        design: d,
        origin: [x0, y0],
    })
}

/// One design on the grid at `origin`, `pixel` mm, `[width mm, columns, rows]`.
fn design_map(design: &Design, origin: [f64; 2], size: [f64; 3], pixel: f64) -> Vec<f32> {
    let [x0, y0] = origin;
    let (w_mm, width, height) = (size[0], size[1] as usize, size[2] as usize);
    let mut d = Heightmap::flat(width, height, pixel, design.top as f32);
    // Scanline fill: per row, the crossings of every ring edge.
    let low = design.floor as f32;
    for iy in 0..height {
        let y = y0 + iy as f64 * pixel;
        let mut xs = Vec::new();
        for r in &design.rings {
            let n = r.len();
            for i in 0..n {
                let (a, b) = (r[i], r[(i + 1) % n]);
                if (a[1] > y) != (b[1] > y) {
                    xs.push(a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]));
                }
            }
        }
        xs.sort_by(f64::total_cmp);
        let row = &mut d.z[iy * width..(iy + 1) * width];
        let mut fill = |from: f64, to: f64| {
            let a = ((from - x0) / pixel).ceil().max(0.0) as usize;
            let b = (((to - x0) / pixel).floor() + 1.0).clamp(0.0, width as f64) as usize;
            for v in row.iter_mut().take(b).skip(a) {
                *v = low;
            }
        };
        if design.cut_inside {
            for c in xs.chunks_exact(2) {
                fill(c[0], c[1]);
            }
        } else {
            let mut from = x0 - 1.0;
            for c in xs.chunks_exact(2) {
                fill(from, c[0]);
                from = c[1];
            }
            fill(from, x0 + w_mm + 1.0);
        }
    }
    if design.slope > 0.0 && design.top > design.floor {
        slope_walls(design, &mut d, origin);
    }
    d.z
}

/// Raises the lowered points of `d` to `top − slope · distance to the nearest ring edge`
/// where that is above the floor: each edge visits only the points within the distance
/// `(top − floor) / slope` at which the wall meets the floor.
fn slope_walls(design: &Design, d: &mut Heightmap, origin: [f64; 2]) {
    let reach = (design.top - design.floor) / design.slope;
    let low = design.floor as f32;
    let px = d.pixel;
    let mut dist = vec![reach; d.z.len()];
    for r in &design.rings {
        let n = r.len();
        for i in 0..n {
            let (a, b) = (r[i], r[(i + 1) % n]);
            let gx0 = (((a[0].min(b[0]) - reach - origin[0]) / px).floor().max(0.0)) as usize;
            let gy0 = (((a[1].min(b[1]) - reach - origin[1]) / px).floor().max(0.0)) as usize;
            let gx1 = (((a[0].max(b[0]) + reach - origin[0]) / px).ceil().max(0.0) as usize)
                .min(d.width.saturating_sub(1));
            let gy1 = (((a[1].max(b[1]) + reach - origin[1]) / px).ceil().max(0.0) as usize)
                .min(d.height.saturating_sub(1));
            let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
            let len2 = ex * ex + ey * ey;
            for iy in gy0..=gy1 {
                for ix in gx0..=gx1 {
                    let k = iy * d.width + ix;
                    if d.z[k] != low {
                        continue;
                    }
                    let (px_, py_) = (origin[0] + ix as f64 * px, origin[1] + iy as f64 * px);
                    let t = if len2 > 0.0 {
                        (((px_ - a[0]) * ex + (py_ - a[1]) * ey) / len2).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    let dd = (px_ - a[0] - t * ex).hypot(py_ - a[1] - t * ey);
                    if dd < dist[k] {
                        dist[k] = dd;
                    }
                }
            }
        }
    }
    for (v, dd) in d.z.iter_mut().zip(dist) {
        if *v == low {
            *v = (design.top - design.slope * dd) as f32;
        }
    }
}

/// The operations moved by `by` in X and Y (the grid starts at 0, the drawing need not).
pub(crate) fn shift(canon: &[Canon], by: [f64; 2]) -> Vec<Canon> {
    let mv = |p: &Pos| Pos {
        x: p.x + by[0],
        y: p.y + by[1],
        ..*p
    };
    canon
        .iter()
        .map(|c| {
            let op = match &c.op {
                CanonOp::StraightTraverse { to } => CanonOp::StraightTraverse { to: mv(to) },
                CanonOp::StraightFeed { to } => CanonOp::StraightFeed { to: mv(to) },
                CanonOp::ArcFeed {
                    plane: oficina_canon::Plane::XY,
                    end,
                    center,
                    turns,
                    rotation,
                } => CanonOp::ArcFeed {
                    plane: oficina_canon::Plane::XY,
                    end: mv(end),
                    center: [center[0] + by[0], center[1] + by[1]],
                    turns: *turns,
                    rotation: *rotation,
                },
                op => op.clone(),
            };
            Canon { line: c.line, op }
        })
        .collect()
}
