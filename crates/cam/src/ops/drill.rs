//! Holes at the centres of the drawing's circles, as canned cycles, nearest first.

use super::{Cut, OpError};
use crate::{Drill, Move, Operation};
use oficina_geom::{Path, Segment};

/// How holes are drilled: pecks and dwell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrillParams {
    /// Peck depth, mm (None: one feed to the bottom; G83 when set).
    pub peck: Option<f64>,
    /// Seconds at the bottom (G82).
    pub dwell: f64,
}

/// The centre of every closed path that is a circle: arcs about one centre (DXF CIRCLE), or
/// any closed curve whose points all lie within 0.5 % (and 0.02 mm) of one radius about their
/// mean (SVG circles arrive as four cubic Béziers).
pub(super) fn hole_centres(paths: &[Path]) -> Vec<[f64; 2]> {
    paths
        .iter()
        .filter(|p| p.closed && !p.segments.is_empty())
        .filter_map(circle_centre)
        .collect()
}

fn circle_centre(p: &Path) -> Option<[f64; 2]> {
    let arcs: Vec<_> = p
        .segments
        .iter()
        .map(|s| match s {
            Segment::Arc(a) => Some(a.center),
            _ => None,
        })
        .collect();
    if let Some(Some(c)) = arcs.first() {
        if arcs
            .iter()
            .all(|a| a.is_some_and(|k| k.distance(*c) < 1e-6))
        {
            return Some([c.x, c.y]);
        }
    }
    let pts = p.flatten(0.001);
    if pts.len() < 8 {
        return None;
    }
    let n = pts.len() as f64;
    let c = pts
        .iter()
        .fold((0.0, 0.0), |a, q| (a.0 + q.x / n, a.1 + q.y / n));
    let radii: Vec<f64> = pts.iter().map(|q| (q.x - c.0).hypot(q.y - c.1)).collect();
    let (lo, hi) = radii
        .iter()
        .fold((f64::MAX, 0.0f64), |(lo, hi), &r| (lo.min(r), hi.max(r)));
    (hi > 0.0 && hi - lo <= (0.005 * hi).min(0.02)).then_some([c.0, c.1])
}

/// Drills every circle of `paths` at its centre with `cut`'s tool and depth.
pub fn drill(name: &str, paths: &[Path], cut: &Cut, p: &DrillParams) -> Result<Operation, OpError> {
    cut.validate()?;
    if let Some(q) = p.peck {
        if !(q.is_finite() && q > 0.0) {
            return Err(OpError::Invalid(format!("peck {q} mm must be above 0")));
        }
    }
    if !(p.dwell.is_finite() && p.dwell >= 0.0) {
        return Err(OpError::Invalid("dwell must be 0 s or more".into()));
    }
    let mut holes = hole_centres(paths);
    if holes.is_empty() {
        return Err(OpError::Empty(
            "no circle in the drawing to drill at its centre".into(),
        ));
    }
    let mut moves = vec![];
    let mut at = [0.0, 0.0];
    while !holes.is_empty() {
        let k = (0..holes.len())
            .min_by(|&i, &j| {
                let d = |h: [f64; 2]| (h[0] - at[0]).hypot(h[1] - at[1]);
                d(holes[i]).total_cmp(&d(holes[j]))
            })
            .expect("not empty");
        let h = holes.swap_remove(k);
        moves.push(Move::Drill(Drill {
            at: h,
            bottom: cut.bottom(),
            r: cut.top + super::RAPID_GAP.max(cut.clear_z - cut.top).min(2.0),
            peck: p.peck,
            dwell: p.dwell,
            feed: cut.plunge_feed,
        }));
        at = h;
    }
    moves.push(Move::Rapid {
        to: [at[0], at[1], cut.clear_z],
    });
    Ok(cut.operation(name, moves))
}
