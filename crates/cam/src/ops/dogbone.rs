//! Dogbone fillets: a round end mill leaves its radius in every inside corner of a pocket
//! or a hole, where a square tenon will not go. A dogbone adds to the shape a circle of the
//! tool's radius (a little more) through each such corner, centred on the corner's
//! bisector, so the pocket and profile offsets carry the tool right into it.

use super::OpError;
use oficina_geom::{boolean, simplify, Area, BoolOp, Fill, Path, Point, Ring};

/// Corners turning by less than this (degrees) are left alone: flattened arcs, near-
/// straight joints.
const MIN_TURN_DEG: f64 = 20.0;
/// The notch is a tenth wider than the tool: the tool moves about in it instead of fitting
/// it exactly, which its polygon and the offsets could not hold to the check's thousandth.
const NOTCH_SCALE: f64 = 1.1;
/// Sides of each notch's polygon.
const NOTCH_SIDES: usize = 64;

/// Where a corner's notch goes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Notch {
    /// On the corner's bisector (a dogbone).
    Bisector,
    /// Along the longer side past the corner (a T-bone): the short side's wall stays
    /// straight all along, for a tenon seen from that side.
    LongerSide,
}

/// `paths`' closed shapes (nested: islands are material) with a notch of `tool_radius` at
/// every inside corner of the region between them, as closed polylines.
pub fn dogbones(paths: &[Path], tool_radius: f64, notch: Notch) -> Result<Vec<Path>, OpError> {
    if !(tool_radius.is_finite() && tool_radius > 0.0) {
        return Err(OpError::Invalid(format!(
            "dogbones need a tool radius above 0 (got {tool_radius})"
        )));
    }
    let geo = |e: oficina_geom::PolygonError| OpError::Geometry(e.to_string());
    let mut rings: Vec<Ring> = Vec::new();
    let mut notches: Vec<Ring> = Vec::new();
    for area in Area::from_paths(paths) {
        let region = area.to_region(1e-3);
        for ring in std::iter::once(&region.outer).chain(region.holes.iter()) {
            // The region lies left of every ring (outer CCW, holes CW): a left turn is a
            // corner the tool cannot fill.
            let n = ring.len();
            for i in 0..n {
                let (a, v, b) = (ring[(i + n - 1) % n], ring[i], ring[(i + 1) % n]);
                let (l1, l2) = (
                    (v[0] - a[0]).hypot(v[1] - a[1]),
                    (b[0] - v[0]).hypot(b[1] - v[1]),
                );
                let d1 = unit([v[0] - a[0], v[1] - a[1]]);
                let d2 = unit([b[0] - v[0], b[1] - v[1]]);
                let (Some(d1), Some(d2)) = (d1, d2) else {
                    continue;
                };
                let cross = d1[0] * d2[1] - d1[1] * d2[0];
                let turn = cross.atan2(d1[0] * d2[0] + d1[1] * d2[1]).to_degrees();
                if turn < MIN_TURN_DEG {
                    continue;
                }
                // The centre: a tool radius in along the bisector, or on the longer side's
                // offset line level with the corner (left normal: the region's side).
                let bis = match notch {
                    Notch::Bisector => match unit([d2[0] - d1[0], d2[1] - d1[1]]) {
                        Some(b) => b,
                        None => continue,
                    },
                    Notch::LongerSide => {
                        let d = if l1 >= l2 { d1 } else { d2 };
                        [-d[1], d[0]]
                    }
                };
                let c = [v[0] + bis[0] * tool_radius, v[1] + bis[1] * tool_radius];
                notches.push(circle(c, tool_radius * NOTCH_SCALE));
            }
            rings.push(ring.clone());
        }
    }
    if rings.is_empty() {
        return Err(OpError::Empty("no closed shape to add dogbones to".into()));
    }
    // Overlapping notches first become one shape, then join the drawing's.
    let notch_rings: Vec<Ring> = simplify(&notches, Fill::NonZero)
        .map_err(geo)?
        .into_iter()
        .flat_map(|r| std::iter::once(r.outer).chain(r.holes))
        .collect();
    let joined = boolean(&rings, &notch_rings, BoolOp::Union, Fill::EvenOdd).map_err(geo)?;
    Ok(joined
        .iter()
        .flat_map(|r| std::iter::once(&r.outer).chain(r.holes.iter()))
        .map(|ring| {
            let pts: Vec<Point> = ring.iter().map(|p| Point::new(p[0], p[1])).collect();
            Path::polyline(&pts, true)
        })
        .collect())
}

fn unit(v: [f64; 2]) -> Option<[f64; 2]> {
    let l = v[0].hypot(v[1]);
    (l > 1e-9).then(|| [v[0] / l, v[1] / l])
}

/// A counter-clockwise polygon round `c` whose sides stay outside radius `r · cos(π/n)`.
fn circle(c: [f64; 2], r: f64) -> Ring {
    (0..NOTCH_SIDES)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / NOTCH_SIDES as f64;
            [c[0] + r * a.cos(), c[1] + r * a.sin()]
        })
        .collect()
}
