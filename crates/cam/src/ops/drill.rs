//! Holes at the centres of the drawing's circles, as canned cycles, nearest first.

use super::{Cut, OpError};
use crate::{Drill, Move, Operation};
use oficina_geom::Path;

/// How holes are drilled: pecks and dwell.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrillParams {
    /// Peck depth, mm (None: one feed to the bottom; G83 when set).
    pub peck: Option<f64>,
    /// Seconds at the bottom (G82).
    pub dwell: f64,
}

/// How far a hole's outline may stray from its circle: 0.5 % of the radius, at most 0.02 mm.
/// A 24-gon's vertices lie on the circle; an SVG circle's four Béziers within 0.03 %.
fn hole_tolerance(radius: f64) -> f64 {
    (0.005 * radius).min(0.02)
}

/// The centre of every closed path that is a circle however it was drawn (a CIRCLE, arcs
/// about one centre, a many-sided polygon, a spline, Béziers): `Path::fit_circle` within
/// [`hole_tolerance`].
pub(super) fn hole_centres(paths: &[Path]) -> Vec<[f64; 2]> {
    paths
        .iter()
        .filter_map(|p| p.fit_circle())
        .filter(|c| c.deviation <= hole_tolerance(c.radius))
        .map(|c| [c.center.x, c.center.y])
        .collect()
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
