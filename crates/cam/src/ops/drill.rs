//! Holes at the centres of the drawing's circles, as canned cycles, nearest first.

use super::{Cut, OpError};
use crate::{Drill, Move, Operation};
use oficina_geom::{Path, Segment};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrillParams {
    /// Peck depth, mm (None: one feed to the bottom; G83 when set).
    pub peck: Option<f64>,
    /// Seconds at the bottom (G82).
    pub dwell: f64,
}

/// The centre of every closed path made of arcs only (circles, as SVG and DXF give them).
pub fn hole_centres(paths: &[Path]) -> Vec<[f64; 2]> {
    paths
        .iter()
        .filter(|p| p.closed && !p.segments.is_empty())
        .filter_map(|p| {
            let mut c = None;
            for s in &p.segments {
                match s {
                    Segment::Arc(a) => {
                        let here = [a.center.x, a.center.y];
                        match c {
                            None => c = Some(here),
                            Some(k) if (k[0] - here[0]).hypot(k[1] - here[1]) < 1e-6 => {}
                            Some(_) => return None,
                        }
                    }
                    _ => return None,
                }
            }
            c
        })
        .collect()
}

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
    Ok(Operation {
        name: name.into(),
        tool_number: cut.tool_number,
        tool: cut.tool.clone(),
        spindle_rpm: cut.spindle_rpm,
        moves,
    })
}
