//! Raster finishing on a mesh: rows at an angle, each a polyline of cutter locations that
//! never dips into the model between samples, joined by links that follow the surface too.
//!
//! Along a row the CL height is sampled every `step`; wherever the CL at the middle of two
//! neighbours differs from their chord by more than `tolerance` the interval is halved
//! (down to 1 µm), so a straight feed between kept points passes within `tolerance` of the
//! exact CL at every sample. The polyline is then thinned (Douglas–Peucker) to the same
//! tolerance.

use super::DropCutter;
use crate::Move;
use rayon::prelude::*;

/// A raster finishing pass (mm, degrees).
#[derive(Clone, Debug)]
pub struct Raster {
    /// Row direction, degrees from +X (0: rows along X, 90: along Y).
    pub angle: f64,
    /// Distance between rows.
    pub stepover: f64,
    /// Sample spacing along a row before refinement.
    pub step: f64,
    /// Largest deviation of a straight feed from the exact CL.
    pub tolerance: f64,
    /// Lowest tip height (the stock's bottom): the CL where the mesh is out of reach.
    pub floor: f64,
    /// The region the tool centre sweeps: min x, min y, max x, max y.
    pub region: [f64; 4],
}

/// The rows of `r` as CL polylines, alternate rows reversed (zig-zag), on all cores.
pub fn raster(dc: &DropCutter, r: &Raster) -> Vec<Vec<[f64; 3]>> {
    let (s, c) = r.angle.to_radians().sin_cos();
    // Row frame: u along the rows, v across; the region's corners bound both.
    let corners = [
        [r.region[0], r.region[1]],
        [r.region[2], r.region[1]],
        [r.region[0], r.region[3]],
        [r.region[2], r.region[3]],
    ];
    let v: Vec<f64> = corners.iter().map(|p| -s * p[0] + c * p[1]).collect();
    let (v0, v1) = (
        v.iter().copied().fold(f64::INFINITY, f64::min),
        v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
    );
    let n = ((v1 - v0) / r.stepover).ceil().max(0.0) as usize + 1;
    let spacing = if n > 1 {
        (v1 - v0) / (n - 1) as f64
    } else {
        0.0
    };
    let mut rows: Vec<Vec<[f64; 3]>> = (0..n)
        .into_par_iter()
        .filter_map(|i| {
            let vv = v0 + i as f64 * spacing;
            let (a, b) = clip_row(r.region, [c, s], [-s * vv, c * vv])?;
            let mut pts = follow(dc, r, a, b);
            if i % 2 == 1 {
                pts.reverse();
            }
            Some(pts)
        })
        .collect();
    rows.retain(|p| !p.is_empty());
    rows
}

/// The part of the line `o + t·d` inside the rectangle, as its two ends.
fn clip_row(rect: [f64; 4], d: [f64; 2], o: [f64; 2]) -> Option<([f64; 2], [f64; 2])> {
    let (mut t0, mut t1) = (f64::NEG_INFINITY, f64::INFINITY);
    for k in 0..2 {
        let (lo, hi) = (rect[k], rect[k + 2]);
        if d[k].abs() < 1e-12 {
            if o[k] < lo - 1e-9 || o[k] > hi + 1e-9 {
                return None;
            }
        } else {
            let (a, b) = ((lo - o[k]) / d[k], (hi - o[k]) / d[k]);
            t0 = t0.max(a.min(b));
            t1 = t1.min(a.max(b));
        }
    }
    (t1 > t0).then(|| {
        (
            [o[0] + t0 * d[0], o[1] + t0 * d[1]],
            [o[0] + t1 * d[0], o[1] + t1 * d[1]],
        )
    })
}

fn cl(dc: &DropCutter, r: &Raster, p: [f64; 2]) -> [f64; 3] {
    [
        p[0],
        p[1],
        dc.drop(p[0], p[1]).unwrap_or(r.floor).max(r.floor),
    ]
}

/// The CL polyline from `a` to `b` (XY), refined and thinned to the tolerance.
fn follow(dc: &DropCutter, r: &Raster, a: [f64; 2], b: [f64; 2]) -> Vec<[f64; 3]> {
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let n = (len / r.step).ceil().max(1.0) as usize;
    let at = |i: usize| {
        let t = i as f64 / n as f64;
        [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
    };
    let mut dense = vec![cl(dc, r, at(0))];
    for i in 1..=n {
        let q = cl(dc, r, at(i));
        let p = *dense.last().unwrap_or(&q);
        refine(dc, r, p, q, 0, &mut dense);
        dense.push(q);
    }
    let mut keep = vec![false; dense.len()];
    thin(&dense, r.tolerance, 0, dense.len() - 1, &mut keep);
    dense
        .into_iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(p))
        .collect()
}

/// Pushes the points between `p` and `q` needed for the chord to stay within tolerance.
fn refine(
    dc: &DropCutter,
    r: &Raster,
    p: [f64; 3],
    q: [f64; 3],
    depth: u32,
    out: &mut Vec<[f64; 3]>,
) {
    let m = cl(dc, r, [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0]);
    let off = m[2] - (p[2] + q[2]) / 2.0;
    let len = (q[0] - p[0]).hypot(q[1] - p[1]);
    if off.abs() <= r.tolerance || depth >= 20 || len < 1e-3 {
        return;
    }
    refine(dc, r, p, m, depth + 1, out);
    out.push(m);
    refine(dc, r, m, q, depth + 1, out);
}

/// Douglas–Peucker on the vertical deviation from the chord: keeps `lo`, `hi` and whatever
/// is needed for every point to be within `tol` of its chord.
fn thin(p: &[[f64; 3]], tol: f64, lo: usize, hi: usize, keep: &mut [bool]) {
    keep[lo] = true;
    keep[hi] = true;
    if hi <= lo + 1 {
        return;
    }
    let (a, b) = (p[lo], p[hi]);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    let mut worst = (0.0, lo);
    for (i, q) in p.iter().enumerate().take(hi).skip(lo + 1) {
        let t = if len > 0.0 {
            (q[0] - a[0]).hypot(q[1] - a[1]) / len
        } else {
            0.5
        };
        let dz = (q[2] - (a[2] + t * (b[2] - a[2]))).abs();
        if dz > worst.0 {
            worst = (dz, i);
        }
    }
    if worst.0 > tol {
        thin(p, tol, lo, worst.1, keep);
        thin(p, tol, worst.1, hi, keep);
    }
}

/// One continuous finishing pass: rapid above the first row, plunge, the rows joined by
/// links that follow the CL surface, retract to `safe_z`. Feeds mm/s.
pub fn finishing_moves(
    dc: &DropCutter,
    r: &Raster,
    rows: &[Vec<[f64; 3]>],
    safe_z: f64,
    feed: f64,
    plunge: f64,
) -> Vec<Move> {
    let mut moves = Vec::new();
    let Some(first) = rows.first().and_then(|row| row.first()) else {
        return moves;
    };
    moves.push(Move::Rapid {
        to: [first[0], first[1], safe_z],
    });
    moves.push(Move::Line {
        to: *first,
        feed: plunge,
    });
    let links: Vec<Vec<[f64; 3]>> = rows
        .par_windows(2)
        .map(|w| {
            let (a, b) = (w[0][w[0].len() - 1], w[1][0]);
            follow(dc, r, [a[0], a[1]], [b[0], b[1]])
        })
        .collect();
    for (i, row) in rows.iter().enumerate() {
        if i > 0 {
            for p in &links[i - 1][1..] {
                moves.push(Move::Line { to: *p, feed });
            }
        }
        for p in &row[1..] {
            moves.push(Move::Line { to: *p, feed });
        }
    }
    if let Some(Move::Line { to, .. }) = moves.last().cloned() {
        moves.push(Move::Rapid {
            to: [to[0], to[1], safe_z],
        });
    }
    moves
}
