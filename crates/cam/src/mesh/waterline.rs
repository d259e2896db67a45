//! Waterline finishing: the closed loops a tool traces with its tip at one height, touching
//! the mesh (OpenCAMLib's `Waterline`, derived anew from drop-cutter).
//!
//! With the tip at height `z` over XY point `p` the tool is inside the model exactly where
//! the drop-cutter height `d(p)` is above `z` (it would have to stop higher). So the loop at
//! `z` is the level curve `d(p) = z`. `d` is sampled once on a square grid (it does not depend
//! on `z`, so every level reuses it); marching squares finds the grid edges the curve
//! crosses, bisection places each crossing on its edge, and wherever the straight move
//! between two loop points would dip into the model by more than the tolerance
//! (`d(midpoint) > z + tolerance`) the exact curve point across the chord is inserted. Every
//! point kept is on the outside (`d ≤ z`): the tool touches without cutting.

use super::DropCutter;
use rayon::prelude::*;
use std::collections::HashMap;

/// The drop-cutter heights on a square grid, shared by every level.
pub struct ContactGrid {
    origin: [f64; 2],
    step: f64,
    nx: usize,
    ny: usize,
    /// Tip heights, `NEG_INFINITY` where no triangle is in reach.
    d: Vec<f64>,
}

impl ContactGrid {
    /// Bytes a grid of `step` over `region` (min x, min y, max x, max y) takes.
    pub fn bytes_estimate(region: [f64; 4], step: f64) -> u64 {
        let (nx, ny) = Self::size(region, step);
        (nx as u64).saturating_mul(ny as u64).saturating_mul(8)
    }

    fn size(region: [f64; 4], step: f64) -> (usize, usize) {
        let n = |a: f64, b: f64| ((b - a) / step).ceil().max(0.0) as usize + 2;
        (n(region[0], region[2]), n(region[1], region[3]))
    }

    /// Drops the tool on every node `step` apart over `region`, grown by one step so every
    /// loop closes inside the grid (check [`ContactGrid::bytes_estimate`] first).
    pub fn new(dc: &DropCutter, region: [f64; 4], step: f64) -> ContactGrid {
        let origin = [region[0] - step, region[1] - step];
        let (nx, ny) = Self::size(region, step);
        let (nx, ny) = (nx + 1, ny + 1);
        let d = (0..ny)
            .into_par_iter()
            .flat_map_iter(|j| {
                (0..nx).map(move |i| {
                    let p = [origin[0] + i as f64 * step, origin[1] + j as f64 * step];
                    dc.drop(p[0], p[1]).unwrap_or(f64::NEG_INFINITY)
                })
            })
            .collect();
        ContactGrid {
            origin,
            step,
            nx,
            ny,
            d,
        }
    }

    /// The spacing of the nodes, mm.
    pub fn step(&self) -> f64 {
        self.step
    }

    fn at(&self, i: usize, j: usize) -> f64 {
        self.d[j * self.nx + i]
    }

    fn xy(&self, i: usize, j: usize) -> [f64; 2] {
        [
            self.origin[0] + i as f64 * self.step,
            self.origin[1] + j as f64 * self.step,
        ]
    }

    /// The highest tip height on the grid (`None` when the tool reaches nothing).
    pub fn top(&self) -> Option<f64> {
        let t = self.d.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        t.is_finite().then_some(t)
    }

    /// The steepest slope of the tip-height surface at the node nearest `p`, as the angle
    /// from horizontal in degrees (central differences; the floor counts as flat). For a
    /// ball the tip surface's normal is the contact's, so this is the model's slope there.
    pub fn slope_at(&self, p: [f64; 2], floor: f64) -> f64 {
        let i = ((p[0] - self.origin[0]) / self.step).round();
        let j = ((p[1] - self.origin[1]) / self.step).round();
        let i = (i.max(1.0) as usize).min(self.nx - 2);
        let j = (j.max(1.0) as usize).min(self.ny - 2);
        let v = |i: usize, j: usize| self.at(i, j).max(floor);
        let gx = (v(i + 1, j) - v(i - 1, j)) / (2.0 * self.step);
        let gy = (v(i, j + 1) - v(i, j - 1)) / (2.0 * self.step);
        gx.hypot(gy).atan().to_degrees()
    }
}

/// The closed loops at tip height `z` (first point repeated last), each point within
/// `tolerance` of the exact curve and every straight move between them within `tolerance`
/// of cutting (the depth the model would be cut, measured as drop-cutter height).
pub fn loops_at(dc: &DropCutter, g: &ContactGrid, z: f64, tolerance: f64) -> Vec<Vec<[f64; 3]>> {
    let inside = |v: f64| v > z;
    // Grid edge ids: 2·node for the edge to +X, 2·node + 1 for the edge to +Y.
    let node = |i: usize, j: usize| j * g.nx + i;
    let mut crossing: Vec<(usize, [usize; 2], [usize; 2])> = Vec::new();
    for j in 0..g.ny {
        for i in 0..g.nx {
            let a = inside(g.at(i, j));
            if i + 1 < g.nx && a != inside(g.at(i + 1, j)) {
                crossing.push((2 * node(i, j), [i, j], [i + 1, j]));
            }
            if j + 1 < g.ny && a != inside(g.at(i, j + 1)) {
                crossing.push((2 * node(i, j) + 1, [i, j], [i, j + 1]));
            }
        }
    }
    if crossing.is_empty() {
        return Vec::new();
    }
    let precision = (tolerance / 10.0).max(1e-6);
    let points: HashMap<usize, [f64; 2]> = crossing
        .par_iter()
        .map(|&(id, a, b)| {
            let (pa, pb) = (g.xy(a[0], a[1]), g.xy(b[0], b[1]));
            let p = if inside(g.at(a[0], a[1])) {
                to_curve(dc, z, pa, pb, precision)
            } else {
                to_curve(dc, z, pb, pa, precision)
            };
            (id, p)
        })
        .collect();
    // Marching squares: each cell the curve crosses gives one segment, or two at a saddle.
    let mut next: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut link = |a: usize, b: usize| {
        next.entry(a).or_default().push(b);
        next.entry(b).or_default().push(a);
    };
    for j in 0..g.ny - 1 {
        for i in 0..g.nx - 1 {
            // Around the cell: bottom, right, top, left.
            let edges = [
                2 * node(i, j),
                2 * node(i + 1, j) + 1,
                2 * node(i, j + 1),
                2 * node(i, j) + 1,
            ];
            let cut: Vec<usize> = edges
                .iter()
                .copied()
                .filter(|e| points.contains_key(e))
                .collect();
            match cut.len() {
                2 => link(cut[0], cut[1]),
                4 => {
                    // Saddle: the bottom-right corner is cut off alone unless the centre is
                    // on its side.
                    let c = g.xy(i, j);
                    let h = g.step / 2.0;
                    let centre = dc.drop(c[0] + h, c[1] + h).unwrap_or(f64::NEG_INFINITY);
                    if inside(g.at(i + 1, j)) != inside(centre) {
                        link(cut[0], cut[1]);
                        link(cut[2], cut[3]);
                    } else {
                        link(cut[3], cut[0]);
                        link(cut[1], cut[2]);
                    }
                }
                _ => {}
            }
        }
    }
    // Walk the graph: every crossing has two neighbours, so the walks are closed loops.
    let mut seen: HashMap<usize, bool> = HashMap::new();
    let mut loops: Vec<Vec<[f64; 2]>> = Vec::new();
    let mut starts: Vec<usize> = next.keys().copied().collect();
    starts.sort_unstable();
    for s in starts {
        if seen.contains_key(&s) {
            continue;
        }
        let (mut prev, mut cur) = (usize::MAX, s);
        let mut lp = Vec::new();
        loop {
            seen.insert(cur, true);
            lp.push(points[&cur]);
            let n = &next[&cur];
            let to = n
                .iter()
                .copied()
                .find(|&e| e != prev && !seen.contains_key(&e));
            match to {
                Some(e) => {
                    prev = cur;
                    cur = e;
                }
                None => break,
            }
        }
        if lp.len() >= 3 {
            lp.push(lp[0]);
            loops.push(lp);
        }
    }
    loops
        .into_par_iter()
        .map(|lp| {
            // The crossings are a grid step apart even along straight stretches: keep those
            // that bend the loop by more than half the tolerance (the dropped ones are within
            // that of the chord, in XY, so on the outside or that little inside), then
            // tighten the chords that still dip.
            let lp = thin_loop(&lp, tolerance / 2.0);
            let mut out = vec![lp[0]];
            for w in lp.windows(2) {
                tighten(dc, z, w[0], w[1], tolerance, g.step, 0, &mut out);
                out.push(w[1]);
            }
            out.into_iter().map(|p| [p[0], p[1], z]).collect()
        })
        .collect()
}

/// Douglas–Peucker in XY on a closed loop (first point repeated last), split at its start
/// and the point farthest from it.
fn thin_loop(lp: &[[f64; 2]], tol: f64) -> Vec<[f64; 2]> {
    let n = lp.len();
    if n < 4 {
        return lp.to_vec();
    }
    let d = |p: [f64; 2]| (p[0] - lp[0][0]).hypot(p[1] - lp[0][1]);
    let far = (1..n - 1)
        .max_by(|&i, &j| d(lp[i]).total_cmp(&d(lp[j])))
        .unwrap_or(n / 2);
    let mut keep = vec![false; n];
    thin_xy(lp, tol, 0, far, &mut keep);
    thin_xy(lp, tol, far, n - 1, &mut keep);
    lp.iter()
        .zip(keep)
        .filter_map(|(p, k)| k.then_some(*p))
        .collect()
}

fn thin_xy(p: &[[f64; 2]], tol: f64, lo: usize, hi: usize, keep: &mut [bool]) {
    keep[lo] = true;
    keep[hi] = true;
    if hi <= lo + 1 {
        return;
    }
    let (a, b) = (p[lo], p[hi]);
    let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
    let len = ux.hypot(uy);
    let off = |q: [f64; 2]| {
        let (vx, vy) = (q[0] - a[0], q[1] - a[1]);
        if len > 0.0 {
            (ux * vy - uy * vx).abs() / len
        } else {
            vx.hypot(vy)
        }
    };
    let (worst, i) = (lo + 1..hi)
        .map(|i| (off(p[i]), i))
        .fold((0.0, lo), |m, x| if x.0 > m.0 { x } else { m });
    if worst > tol {
        thin_xy(p, tol, lo, i, keep);
        thin_xy(p, tol, i, hi, keep);
    }
}

/// Bisection from `a` (inside) to `b` (outside) to within `precision`; the outside end.
fn to_curve(dc: &DropCutter, z: f64, mut a: [f64; 2], mut b: [f64; 2], precision: f64) -> [f64; 2] {
    for _ in 0..60 {
        if (b[0] - a[0]).hypot(b[1] - a[1]) <= precision {
            break;
        }
        let m = [(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0];
        if dc.drop(m[0], m[1]).is_some_and(|d| d > z) {
            a = m;
        } else {
            b = m;
        }
    }
    b
}

/// Pushes the curve points needed between `p` and `q` so no straight move between kept
/// points dips more than `tol` into the model (checked at midpoints, down to 1 µm chords).
#[allow(clippy::too_many_arguments)]
fn tighten(
    dc: &DropCutter,
    z: f64,
    p: [f64; 2],
    q: [f64; 2],
    tol: f64,
    reach: f64,
    depth: u32,
    out: &mut Vec<[f64; 2]>,
) {
    let m = [(p[0] + q[0]) / 2.0, (p[1] + q[1]) / 2.0];
    let len = (q[0] - p[0]).hypot(q[1] - p[1]);
    let dips = dc.drop(m[0], m[1]).is_some_and(|d| d > z + tol);
    if !dips || depth >= 12 || len < 1e-3 {
        return;
    }
    // Out of the model across the chord, on whichever side it is nearer.
    let n = [-(q[1] - p[1]) / len, (q[0] - p[0]) / len];
    let mut out_at = None;
    let mut d = tol.max(1e-4);
    while d <= reach && out_at.is_none() {
        for s in [1.0, -1.0] {
            let t = [m[0] + s * d * n[0], m[1] + s * d * n[1]];
            if !dc.drop(t[0], t[1]).is_some_and(|v| v > z) {
                out_at = Some(t);
                break;
            }
        }
        d *= 2.0;
    }
    let Some(t) = out_at else { return };
    let c = to_curve(dc, z, m, t, (tol / 10.0).max(1e-6));
    tighten(dc, z, p, c, tol, reach, depth + 1, out);
    out.push(c);
    tighten(dc, z, c, q, tol, reach, depth + 1, out);
}
