//! Finishing by slope: raster rows where the model is flat enough, waterline loops where it
//! is steep, each kept by the slope of the tip-height surface under it.
//!
//! Waterline levels are `dz = stepover · sin(limit)` apart: on a wall of slope `θ ≥ limit`
//! two levels are `dz / sin θ ≤ stepover` apart along the surface, as raster rows are on
//! the flats (`stepover / cos θ` along a slope below the limit). The two sides overlap by
//! [`OVERLAP`] degrees so the seam between them is finished twice rather than not at all.

use super::waterline::{loops_at, ContactGrid};
use super::DropCutter;

/// How the finishing pass covers the model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Strategy {
    /// Raster rows everywhere.
    Raster,
    /// Waterline loops everywhere (flats between levels are left).
    Waterline,
    /// Raster on slopes below the limit, waterline above.
    Mix,
}

impl std::str::FromStr for Strategy {
    type Err = String;
    fn from_str(s: &str) -> Result<Strategy, String> {
        match s {
            "raster" => Ok(Strategy::Raster),
            "waterline" => Ok(Strategy::Waterline),
            "mix" => Ok(Strategy::Mix),
            _ => Err(format!(
                "unknown finishing strategy '{s}' (raster, waterline, mix)"
            )),
        }
    }
}

/// Degrees by which the raster's and the waterline's slopes overlap at the seam.
pub const OVERLAP: f64 = 5.0;

/// The waterline spacing for walls of `limit` degrees and steeper.
pub fn level_spacing(stepover: f64, limit: f64) -> f64 {
    stepover * limit.to_radians().sin()
}

/// Waterline loops every [`level_spacing`] from the top of the tip-height surface down to
/// (not including) `floor`; with `min_slope`, only the stretches steeper than it, cut into
/// open pieces. Pieces are ordered top down, each level's nearest first.
pub fn waterline_pieces(
    dc: &DropCutter,
    g: &ContactGrid,
    floor: f64,
    dz: f64,
    tolerance: f64,
    min_slope: Option<f64>,
) -> Vec<Vec<[f64; 3]>> {
    let Some(top) = g.top() else {
        return Vec::new();
    };
    let mut out: Vec<Vec<[f64; 3]>> = Vec::new();
    let mut k = 1;
    loop {
        let z = top - k as f64 * dz;
        if z <= floor + 1e-6 {
            break;
        }
        let mut level = Vec::new();
        for lp in loops_at(dc, g, z, tolerance) {
            match min_slope {
                None => level.push(lp),
                Some(s) => level.extend(split(&lp, g.step(), |p| g.slope_at(p, floor) >= s)),
            }
        }
        out.extend(nearest_first(
            level,
            out.last().and_then(|p| p.last()).copied(),
        ));
        k += 1;
    }
    out
}

/// The stretches of a polyline where `keep` holds, judged every `step` mm along each move
/// (a thinned row may cross a whole flat in one move): a move is cut where `keep` changes,
/// at a point on the move itself, so the pieces trace the same safe chords. Only the
/// path's own vertices and the cut points are kept: the samples between them lie on the
/// chord and would only add moves (they made the mix's programs several times longer).
pub fn split(path: &[[f64; 3]], step: f64, keep: impl Fn([f64; 2]) -> bool) -> Vec<Vec<[f64; 3]>> {
    let mut out = Vec::new();
    let mut cur: Vec<[f64; 3]> = Vec::new();
    let Some(&first) = path.first() else {
        return out;
    };
    let mut inside = keep([first[0], first[1]]);
    if inside {
        cur.push(first);
    }
    for w in path.windows(2) {
        let (a, b) = (w[0], w[1]);
        let n = ((b[0] - a[0]).hypot(b[1] - a[1]) / step).ceil().max(1.0) as usize;
        // The last sample seen, kept if a piece ends after it.
        let mut last = a;
        for i in 1..=n {
            let p = if i == n {
                b
            } else {
                let t = i as f64 / n as f64;
                std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
            };
            let now = keep([p[0], p[1]]);
            if now && !inside {
                cur.push(p);
            } else if !now && inside {
                if cur.last() != Some(&last) {
                    cur.push(last);
                }
                out.push(std::mem::take(&mut cur));
            } else if now && i == n && cur.last() != Some(&p) {
                cur.push(p);
            }
            inside = now;
            last = p;
        }
    }
    out.push(cur);
    out.retain(|p| p.len() >= 2);
    out
}

/// Raster rows kept where the slope is at most `max_slope`.
pub fn flat_pieces(
    rows: &[Vec<[f64; 3]>],
    g: &ContactGrid,
    floor: f64,
    max_slope: f64,
) -> Vec<Vec<[f64; 3]>> {
    rows.iter()
        .flat_map(|r| split(r, g.step(), |p| g.slope_at(p, floor) <= max_slope))
        .collect()
}

/// Greedy order: from `from`, the piece whose start or end is nearest, reversed if its end.
fn nearest_first(mut pieces: Vec<Vec<[f64; 3]>>, from: Option<[f64; 3]>) -> Vec<Vec<[f64; 3]>> {
    let mut out = Vec::with_capacity(pieces.len());
    let mut at = from.or_else(|| pieces.first().map(|p| p[0]));
    while let Some(a) = at {
        let d = |p: &[f64; 3]| (p[0] - a[0]).hypot(p[1] - a[1]);
        let best = pieces
            .iter()
            .enumerate()
            .map(|(i, p)| {
                let (s, e) = (d(&p[0]), d(&p[p.len() - 1]));
                (s.min(e), i, e < s)
            })
            .min_by(|x, y| x.0.total_cmp(&y.0));
        let Some((_, i, rev)) = best else { break };
        let mut p = pieces.swap_remove(i);
        if rev {
            p.reverse();
        }
        at = p.last().copied();
        out.push(p);
    }
    out
}
