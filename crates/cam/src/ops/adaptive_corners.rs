//! Sharp inside corners of a pocket, cleared by the contour pass on its way round.
//!
//! At a sharp corner the tool-centre boundary has a convex vertex c0, the position touching
//! both walls. Its disc holds a sliver no other position reaches, so whatever comes last
//! into the corner meets the uncut arc between the walls (53° for a 90° corner as the
//! walk measures it, more the further off c0 it still is). The clearing cannot get there
//! (the arc alone nearly fills its target), and a contour arriving along one wall meets it
//! together with the strip of the wall ahead (66–71° at a 60° maximum). Here the corner is
//! taken by straight sweeps from wall to wall, across the bisector, each a little nearer c0:
//! a sweep's ends, c0 + s·e1 and c0 + s·e2, lie on the two walls' centre lines, so the
//! sweeps are parallel, d = Δs·cos(α/2) apart for an interior angle α, and each cuts a strip
//! about d thick (acos(1 − d/r) on the way across) while the corner's arc stays beside the
//! tool rather than ahead of it. The last move goes into c0 from a sweep d away; the contour
//! then finds the corner cleared.

use super::adaptive_model::{Model, Rings};
use super::chain::inside;

/// Distance between successive sweeps, as a fraction of the tool radius: r/24 = 0.125 mm
/// for a 6 mm tool, about one cell of the walk (0.12 mm); twice that lets the corner's arc
/// and the strip ahead add up past 65° in the last sweeps.
const SPACING: f64 = 1.0 / 24.0;
/// Interior angles (degrees) at or above this are not corners (flattened arcs turn less).
const FLATTEST: f64 = 160.0;

/// The contour pass `order` (a closed path along `rings`, the tool-centre boundary) with a
/// zigzag spliced in before every sharp convex corner that still has material about it:
/// the contour arrives along one wall to the first sweep that meets material, zigzags
/// into the corner and leaves along the other wall. The model is cut along the whole pass,
/// so each corner's sweeps start where the contour so far left material.
pub(super) fn with_corner_sweeps(
    model: &mut Model,
    rings: &Rings,
    order: &[[f64; 2]],
) -> Vec<[f64; 2]> {
    let mut out = vec![order[0]];
    for k in 1..order.len() {
        let c0 = order[k];
        if k + 1 < order.len() {
            if let Some(zigzag) = sweeps(model, rings, c0, order[k - 1], order[k + 1]) {
                for &p in &zigzag {
                    let from = out[out.len() - 1];
                    cut_along(model, from, p);
                    out.push(p);
                }
                continue;
            }
        }
        cut_along(model, out[out.len() - 1], c0);
        out.push(c0);
    }
    out
}

/// The zigzag into corner `c0`, arrived at from `prev` and left towards `next`, from the
/// first sweep (furthest out, s ≤ r) that meets material, ending in `c0`; `None` when `c0`
/// is no sharp convex corner or nothing is left about it.
fn sweeps(
    model: &Model,
    rings: &Rings,
    c0: [f64; 2],
    prev: [f64; 2],
    next: [f64; 2],
) -> Option<Vec<[f64; 2]>> {
    let unit = |p: [f64; 2]| {
        let (dx, dy) = (p[0] - c0[0], p[1] - c0[1]);
        let l = dx.hypot(dy);
        (l > 0.0).then(|| ([dx / l, dy / l], l))
    };
    let ((e1, l1), (e2, l2)) = (unit(prev)?, unit(next)?);
    let alpha = (e1[0] * e2[0] + e1[1] * e2[1]).clamp(-1.0, 1.0).acos();
    if alpha.to_degrees() >= FLATTEST {
        return None;
    }
    // Convex for the region: the wedge between the edges is inside it.
    let bis = [e1[0] + e2[0], e1[1] + e2[1]];
    let bl = bis[0].hypot(bis[1]);
    let probe = 0.05 * model.r / bl;
    if !inside(rings, [c0[0] + probe * bis[0], c0[1] + probe * bis[1]]) {
        return None;
    }
    let ds = SPACING * model.r / (alpha / 2.0).cos();
    let s_max = model.r.min(l1).min(l2);
    let at = |e: [f64; 2], s: f64| [c0[0] + s * e[0], c0[1] + s * e[1]];
    let levels: Vec<f64> = (0..)
        .map(|k| s_max - k as f64 * ds)
        .take_while(|&s| s > 0.0)
        .collect();
    let first = levels
        .iter()
        .position(|&s| !model.free_along(at(e1, s), at(e2, s)))?;
    let mut pts = Vec::with_capacity(2 * levels.len() + 2);
    // In from the last sweep that touched nothing: the tool enters the corner where it is
    // free (a link over the top goes down there).
    if first > 0 {
        pts.push(at(e1, levels[first - 1]));
    }
    for (k, &s) in levels[first..].iter().enumerate() {
        let (a, b) = (at(e1, s), at(e2, s));
        if k % 2 == 0 {
            pts.extend([a, b]);
        } else {
            pts.extend([b, a]);
        }
    }
    pts.push(c0);
    Some(pts)
}

fn cut_along(model: &mut Model, a: [f64; 2], b: [f64; 2]) {
    for q in model.along(a, b).collect::<Vec<_>>() {
        model.stamp(q);
    }
}
