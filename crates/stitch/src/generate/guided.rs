//! Guided fill (Ink/Stitch's `guided_fill`): the rows follow a guide line instead of a fixed
//! angle. Row k is the guide, lengthened at both ends past the shape, moved k row spacings
//! sideways: shifted as a whole across its start-to-end direction (strategy 0, "copy", the
//! default) or offset point by point along its normals (strategy 1, "parallel offset": every
//! row the same distance from the guide). Each row is cut by the shape into pieces, needle
//! points along it every stitch length from a grid that shifts row by row (the tatami's
//! stagger), corners kept; the pieces are then joined as tatami sections are.

use super::fill::{approach, join_sections, leave, row_points, FillParams, Run};
use oficina_geom::{Point, Region, Vec2};

/// A corner of a row sharper than this (radians) is a needle point.
const CORNER: f64 = 0.35;

/// The guided fill of `region` along `guide` (mm), from the row end nearest `start` to the
/// one nearest `end` when given. None when the guide has no length.
pub(super) fn guided(
    region: &Region,
    guide: &[Point],
    p: &FillParams,
    parallel: bool,
    start: Option<Point>,
    end: Option<Point>,
) -> Option<Vec<Run>> {
    let g = dedup(guide);
    if g.len() < 2 {
        return None;
    }
    let (lo, hi) = bounds(region)?;
    let diag = lo.distance(hi);
    if !(diag > 0.0 && diag.is_finite()) || g.iter().any(|q| !(q.x.is_finite() && q.y.is_finite()))
    {
        return None;
    }
    // Lengthened along its end directions so every row crosses the whole shape.
    let (u0, u1) = (
        (g[1] - g[0]).normalize(),
        (g[g.len() - 1] - g[g.len() - 2]).normalize(),
    );
    let mut line = vec![g[0] - u0 * diag];
    line.extend(g.iter().copied());
    line.push(g[g.len() - 1] + u1 * diag);
    let chord = (g[g.len() - 1] - g[0]).normalize();
    let side = if chord.is_finite() {
        chord.turn_90()
    } else {
        u0.turn_90()
    };
    let normals = normals(&line);
    // The rows that may cross the shape. Parallel offsets: from the shape's nearest to its
    // farthest point from the guide (a guide far away makes no rows on the way). Copies: the
    // shifts that bring some point of the guide onto some point of the shape.
    let vertices: Vec<Point> = region
        .outer
        .iter()
        .map(|q| Point::new(q[0], q[1]))
        .collect();
    let ks: Vec<i64> = if parallel {
        let d: Vec<f64> = vertices.iter().map(|c| distance_to(&line, *c)).collect();
        let reach = d.iter().copied().fold(0.0, f64::max);
        let near = if line.iter().any(|&q| contains(region, q)) {
            0.0
        } else {
            d.iter().copied().fold(f64::INFINITY, f64::min)
        };
        let k_max = (reach / p.spacing).ceil() as i64 + 1;
        let k_min = ((near / p.spacing).floor() as i64 - 1).max(0);
        (-k_max..=-k_min).chain(k_min.max(1)..=k_max).collect()
    } else {
        let span = |pts: &[Point]| {
            pts.iter()
                .map(|q| q.to_vec2().dot(side))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
                    (a.min(x), b.max(x))
                })
        };
        let ((v0, v1), (q0, q1)) = (span(&vertices), span(&line));
        ((((v0 - q1) / p.spacing).floor() as i64 - 1)..=(((v1 - q0) / p.spacing).ceil() as i64 + 1))
            .collect()
    };
    let k_off = ks.iter().copied().min().unwrap_or(0);
    let mut pieces: Vec<Vec<Point>> = Vec::new();
    for k in ks {
        let d = k as f64 * p.spacing;
        let row: Vec<Point> = if parallel {
            line.iter()
                .zip(&normals)
                .map(|(&q, &n)| q + n * d)
                .collect()
        } else {
            line.iter().map(|&q| q + side * d).collect()
        };
        for piece in clip(&row, region) {
            pieces.push(stitch(&piece, (k - k_off) as usize, p));
        }
    }
    pieces.retain(|q| q.len() >= 2);
    if pieces.is_empty() {
        return Some(Vec::new());
    }
    // The piece with the end nearest the start command first, oriented from there; the one
    // nearest the end command last.
    let first = start.map(|q| approach(q, take(&mut pieces, q, true), region, p));
    let last = end
        .filter(|_| !pieces.is_empty())
        .map(|q| leave(take(&mut pieces, q, false), q, region, p));
    Some(join_sections(first, pieces, last, region, p))
}

/// Takes the piece with an end nearest `q`, oriented to start there (`first`) or end there.
fn take(pieces: &mut Vec<Vec<Point>>, q: Point, first: bool) -> Vec<Point> {
    let (mut best, mut rev, mut d) = (0, false, f64::INFINITY);
    for (i, pc) in pieces.iter().enumerate() {
        for (e, r) in [(pc[0], !first), (pc[pc.len() - 1], first)] {
            if e.distance(q) < d {
                (best, rev, d) = (i, r, e.distance(q));
            }
        }
    }
    let mut pc = pieces.remove(best);
    if rev {
        pc.reverse();
    }
    pc
}

fn dedup(points: &[Point]) -> Vec<Point> {
    let mut v: Vec<Point> = Vec::with_capacity(points.len());
    for &q in points {
        if v.last().is_none_or(|l| l.distance(q) > 1e-6) {
            v.push(q);
        }
    }
    v
}

fn bounds(region: &Region) -> Option<(Point, Point)> {
    let b = oficina_geom::bounds(region.outer.iter().copied())?;
    Some((Point::new(b.x0, b.y0), Point::new(b.x1, b.y1)))
}

/// Unit normals (left of the direction of travel) at each vertex, mitred: a vertex's normal is
/// lengthened so the offset edges stay `d` from the line (capped where the turn is sharp).
fn normals(line: &[Point]) -> Vec<Vec2> {
    let n = line.len();
    let edge = |i: usize| (line[i + 1] - line[i]).normalize().turn_90();
    (0..n)
        .map(|i| {
            if i == 0 {
                edge(0)
            } else if i == n - 1 {
                edge(n - 2)
            } else {
                let (a, b) = (edge(i - 1), edge(i));
                let m = (a + b).normalize();
                let c = m.dot(a).max(0.25);
                if m.is_finite() {
                    m / c
                } else {
                    a
                }
            }
        })
        .collect()
}

/// Distance from `q` to the polyline `line`.
pub(super) fn distance_to(line: &[Point], q: Point) -> f64 {
    line.windows(2)
        .map(|w| {
            let v = w[1] - w[0];
            let l2 = v.hypot2();
            let t = if l2 > 0.0 {
                ((q - w[0]).dot(v) / l2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            w[0].lerp(w[1], t).distance(q)
        })
        .fold(f64::INFINITY, f64::min)
}

/// Whether `q` is inside the region (even-odd over its rings).
fn contains(region: &Region, q: Point) -> bool {
    let mut inside = false;
    for r in std::iter::once(&region.outer).chain(region.holes.iter()) {
        for i in 0..r.len() {
            let (a, b) = (r[i], r[(i + 1) % r.len()]);
            if (a[1] <= q.y) != (b[1] <= q.y)
                && q.x < a[0] + (q.y - a[1]) / (b[1] - a[1]) * (b[0] - a[0])
            {
                inside = !inside;
            }
        }
    }
    inside
}

/// The parts of `line` inside the region, each as (arc length along `line`, point) pairs.
fn clip(line: &[Point], region: &Region) -> Vec<Vec<(f64, Point)>> {
    let rings: Vec<&Vec<[f64; 2]>> = std::iter::once(&region.outer)
        .chain(region.holes.iter())
        .collect();
    let mut out: Vec<Vec<(f64, Point)>> = Vec::new();
    let mut cur: Vec<(f64, Point)> = Vec::new();
    let mut s0 = 0.0;
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        let len = a.distance(b);
        let mut ts = vec![0.0, 1.0];
        for r in &rings {
            for i in 0..r.len() {
                let (p, q) = (r[i], r[(i + 1) % r.len()]);
                let (p, q) = (Point::new(p[0], p[1]), Point::new(q[0], q[1]));
                let (d, e) = (b - a, q - p);
                let den = d.cross(e);
                if den.abs() < 1e-12 {
                    continue;
                }
                let t = (p - a).cross(e) / den;
                let u = (p - a).cross(d) / den;
                if (0.0..=1.0).contains(&t) && (0.0..=1.0).contains(&u) {
                    ts.push(t);
                }
            }
        }
        ts.sort_by(f64::total_cmp);
        for t in ts.windows(2) {
            if t[1] - t[0] < 1e-12 {
                continue;
            }
            let mid = a.lerp(b, (t[0] + t[1]) / 2.0);
            let (pa, pb) = (a.lerp(b, t[0]), a.lerp(b, t[1]));
            let (sa, sb) = (s0 + t[0] * len, s0 + t[1] * len);
            if contains(region, mid) {
                if cur.last().is_none_or(|l| (l.0 - sa).abs() > 1e-9) {
                    if cur.len() >= 2 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur = vec![(sa, pa)];
                }
                cur.push((sb, pb));
            } else if cur.len() >= 2 {
                out.push(std::mem::take(&mut cur));
            } else {
                cur.clear();
            }
        }
        s0 += len;
    }
    if cur.len() >= 2 {
        out.push(cur);
    }
    out
}

/// Needle points along a clipped piece of row `row`: its ends, the row's staggered grid of
/// stitch lengths in between, and its corners.
fn stitch(piece: &[(f64, Point)], row: usize, p: &FillParams) -> Vec<Point> {
    let (s0, s1) = (piece[0].0, piece[piece.len() - 1].0);
    let mut at: Vec<f64> = row_points((s0, s1), row, false, p);
    for i in 1..piece.len().saturating_sub(1) {
        let (u, v) = (piece[i].1 - piece[i - 1].1, piece[i + 1].1 - piece[i].1);
        if v.cross(u).atan2(u.dot(v)).abs() > CORNER {
            at.push(piece[i].0);
        }
    }
    at.sort_by(f64::total_cmp);
    at.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    let mut j = 0;
    at.iter()
        .map(|&s| {
            while j + 2 < piece.len() && piece[j + 1].0 < s {
                j += 1;
            }
            let ((sa, a), (sb, b)) = (piece[j], piece[j + 1]);
            let t = if sb > sa { (s - sa) / (sb - sa) } else { 0.0 };
            a.lerp(b, t.clamp(0.0, 1.0))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_is_cut_where_it_crosses_a_hole() {
        let r = Region {
            outer: vec![[0.0, 0.0], [30.0, 0.0], [30.0, 10.0], [0.0, 10.0]],
            holes: vec![vec![[10.0, 2.0], [10.0, 8.0], [20.0, 8.0], [20.0, 2.0]]],
        };
        let line = [Point::new(-5.0, 5.0), Point::new(35.0, 5.0)];
        let parts = clip(&line, &r);
        let spans: Vec<(f64, f64)> = parts
            .iter()
            .map(|p| (p[0].1.x, p[p.len() - 1].1.x))
            .collect();
        assert_eq!(spans.len(), 2, "{spans:?}");
        assert!((spans[0].0 - 0.0).abs() < 1e-9 && (spans[0].1 - 10.0).abs() < 1e-9);
        assert!((spans[1].0 - 20.0).abs() < 1e-9 && (spans[1].1 - 30.0).abs() < 1e-9);
    }
}
