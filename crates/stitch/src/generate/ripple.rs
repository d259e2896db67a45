//! Ripple stitch (Ink/Stitch's `ripple_stitch`), as its `ripple_stitch.py` builds it: copies
//! of the drawn line, sewn one after another as one running line.
//! - One line: each of its points (the line cut into running stitches first) is joined to a
//!   target (the `ripple_target` command, else the centre of the line's convex hull) and the
//!   copies are the points a step further along those joins; with a guide line the copies
//!   are moved along the guide instead, scaled from `scale_start` to `scale_end` %.
//!   A closed line makes one more copy and then a spiral: along each copy the points slide
//!   from that copy to the next, so copy j ends where copy j + 1 begins — `line_count` turns.
//! - Two or more subpaths (a satin's rails): copies between the two rails, from the first to
//!   the second.
//!
//! Steps run 0..1 in equal parts raised to `exponent` (mirrored with `flip_exponent`); the
//! count is `line_count` or, with `min_line_dist_mm`, the shortest join over that distance
//! (kept odd or even as the line count is, so the end stays on the same side). Open copies
//! go back and forth (`flip_copies`); `skip_start` / `skip_end` drop copies (ignored when
//! they would drop them all); `reverse` sews it from the other end.

use super::running::running;
use super::satin;
use crate::inkstitch::RippleParams;
use oficina_geom::Point;

/// The ripple's line (before its running stitches): `lines` the element's subpaths (closed
/// ones with their first point repeated), `len` the running stitch length.
pub(super) fn ripple(
    lines: &[Vec<Point>],
    r: &RippleParams,
    len: f64,
    target: Option<Point>,
    guide: Option<&[Point]>,
) -> Vec<Point> {
    // With a grid the line is cut at the grid's size (the grid's lines join those points).
    let step = if r.grid_size > 0.0 {
        r.grid_size.max(0.1)
    } else {
        len
    };
    let (copies, linear) = if lines.len() >= 2 {
        (between_rails(&lines[0], &lines[1], r), true)
    } else {
        let line = &lines[0];
        let closed = line.len() > 2 && line[0].distance(line[line.len() - 1]) < 0.05;
        let outline = running(line, step);
        let mut copies = match guide.filter(|g| g.len() >= 2) {
            Some(g) => along_guide(&outline, g, r, closed),
            None => {
                let t = target.unwrap_or_else(|| hull_centroid(&outline));
                let shortest = outline
                    .iter()
                    .map(|q| q.distance(t))
                    .fold(f64::INFINITY, f64::min);
                let n = count(r, shortest, closed);
                steps(n, r)
                    .iter()
                    .map(|&s| outline.iter().map(|&q| q.lerp(t, s)).collect())
                    .collect()
            }
        };
        if closed {
            copies = spiral(&copies);
        }
        (copies, !closed)
    };
    let (mut a, mut b) = (r.skip_start as usize, r.skip_end as usize);
    if a + b >= copies.len() {
        (a, b) = (0, 0);
    }
    let mut out: Vec<Point> = Vec::new();
    for (i, copy) in copies[a..copies.len() - b].iter().enumerate() {
        if linear && r.flip_copies && i % 2 == 1 {
            out.extend(copy.iter().rev());
        } else {
            out.extend(copy.iter());
        }
    }
    if r.reverse {
        out.reverse();
    }
    if r.grid_size > 0.0 {
        let g = grid(&copies[a..copies.len() - b], out.last().copied());
        out.extend(g);
    }
    if r.grid_first {
        out.reverse();
    }
    out
}

/// The grid: through each point of the line, across the copies; every other one reversed,
/// starting at the corner nearest `from` (where the copies ended).
fn grid(copies: &[Vec<Point>], from: Option<Point>) -> Vec<Point> {
    let n = copies.iter().map(Vec::len).min().unwrap_or(0);
    let mut lines: Vec<Vec<Point>> = (0..n)
        .map(|i| copies.iter().map(|c| c[i]).collect())
        .collect();
    if lines.is_empty() || lines[0].is_empty() {
        return Vec::new();
    }
    if let Some(q) = from {
        let (first, last) = (&lines[0], &lines[lines.len() - 1]);
        let corners = [
            first[0],
            first[first.len() - 1],
            last[0],
            last[last.len() - 1],
        ];
        let k = (0..4)
            .min_by(|&i, &j| corners[i].distance(q).total_cmp(&corners[j].distance(q)))
            .unwrap_or(0);
        if k == 2 || k == 3 {
            lines.reverse();
        }
        if k == 1 || k == 3 {
            lines.iter_mut().for_each(|l| l.reverse());
        }
    }
    lines
        .into_iter()
        .enumerate()
        .flat_map(|(i, mut l)| {
            if i % 2 == 1 {
                l.reverse();
            }
            l
        })
        .collect()
}

/// `n` steps from 0 to 1 (both included), raised to the exponent, mirrored when flipped.
fn steps(n: usize, r: &RippleParams) -> Vec<f64> {
    let n = n.max(2);
    let mut s: Vec<f64> = (0..n)
        .map(|i| (i as f64 / (n - 1) as f64).powf(r.exponent))
        .collect();
    if r.flip_exponent {
        s = s.iter().rev().map(|x| 1.0 - x).collect();
    }
    s
}

/// How many copies: `line_count`, or the shortest join over `min_line_dist` (its parity
/// kept as the line count's); a closed line one more (the spiral joins copy to copy).
fn count(r: &RippleParams, shortest: f64, closed: bool) -> usize {
    let mut n = r.line_count as usize;
    if let Some(d) = r.min_line_dist {
        n = (shortest / d).ceil() as usize;
        if n % 2 != r.line_count as usize % 2 {
            n = n.saturating_sub(1);
        }
    }
    // As many as Ink/Stitch's dialog allows (the design's stitch estimate bounds the rest).
    n.clamp(1, 10_000) + usize::from(closed)
}

/// Copies between two rails, from the first to the second (the rails paired point by point).
fn between_rails(a: &[Point], b: &[Point], r: &RippleParams) -> Vec<Vec<Point>> {
    let la: f64 = a.windows(2).map(|w| w[0].distance(w[1])).sum();
    let lb: f64 = b.windows(2).map(|w| w[0].distance(w[1])).sum();
    // Pairs every 0.2 mm, or at the grid's size (its lines join the pairs).
    let step = if r.grid_size > 0.0 {
        r.grid_size.max(0.1)
    } else {
        0.2
    };
    let m = ((la.max(lb) / step - 1e-6).ceil() as usize + 1).clamp(2, 100_000);
    let (a, mut b) = (satin::resample(a, m), satin::resample(b, m));
    if a[0].distance(b[0]) > a[0].distance(b[m - 1]) {
        b.reverse(); // drawn the other way round
    }
    let shortest = a
        .iter()
        .zip(&b)
        .map(|(x, y)| x.distance(*y))
        .fold(f64::INFINITY, f64::min);
    steps(count(r, shortest, false), r)
        .iter()
        .map(|&s| a.iter().zip(&b).map(|(x, y)| x.lerp(*y, s)).collect())
        .collect()
}

/// Copies of `outline` moved along the guide from its start, each scaled about its place on
/// the guide from `scale_start` to `scale_end` percent and, with `rotate_ripples`, turned
/// about it by the guide's direction there (from the copy before) against its start's.
fn along_guide(outline: &[Point], g: &[Point], r: &RippleParams, closed: bool) -> Vec<Vec<Point>> {
    let total: f64 = g.windows(2).map(|w| w[0].distance(w[1])).sum();
    let n = count(r, total, closed);
    let at = |s: f64| {
        let mut acc = 0.0;
        for w in g.windows(2) {
            let l = w[0].distance(w[1]);
            if acc + l >= s && l > 0.0 {
                return w[0].lerp(w[1], ((s - acc) / l).clamp(0.0, 1.0));
            }
            acc += l;
        }
        g[g.len() - 1]
    };
    let dir = |a: Point, b: Point| (b.y - a.y).atan2(b.x - a.x);
    let start = dir(g[0], at(0.1_f64.min(total)));
    let k = n.max(2);
    let places: Vec<Point> = steps(n, r).iter().map(|&s| at(s * total)).collect();
    places
        .iter()
        .enumerate()
        .map(|(i, &c)| {
            let shift = c - g[0];
            let f = i as f64 / (k - 1) as f64;
            let scale = (r.scale_start + (r.scale_end - r.scale_start) * f) / 100.0;
            let turn = if r.rotate && i > 0 && places[i - 1].distance(c) > 1e-9 {
                dir(places[i - 1], c) - start
            } else {
                0.0
            };
            let (sin, cos) = turn.sin_cos();
            outline
                .iter()
                .map(|&q| {
                    let v = (q + shift - c) * scale;
                    c + oficina_geom::Vec2::new(v.x * cos - v.y * sin, v.x * sin + v.y * cos)
                })
                .collect()
        })
        .collect()
}

/// Closed copies made one spiral: along copy j the points slide from copy j to copy j + 1.
fn spiral(copies: &[Vec<Point>]) -> Vec<Vec<Point>> {
    copies
        .windows(2)
        .map(|w| {
            let n = w[0].len();
            (0..n)
                .map(|i| w[0][i].lerp(w[1][i], i as f64 / (n - 1).max(1) as f64))
                .collect()
        })
        .collect()
}

/// The centroid of the convex hull of `pts` (Ink/Stitch's default ripple target).
fn hull_centroid(pts: &[Point]) -> Point {
    let mut p: Vec<Point> = pts.to_vec();
    p.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    p.dedup_by(|a, b| a.distance(*b) < 1e-9);
    if p.len() < 3 {
        let n = p.len().max(1) as f64;
        let s = p.iter().fold((0.0, 0.0), |s, q| (s.0 + q.x, s.1 + q.y));
        return Point::new(s.0 / n, s.1 / n);
    }
    let cross = |o: Point, a: Point, b: Point| (a - o).cross(b - o);
    let mut hull: Vec<Point> = Vec::new();
    for pass in 0..2 {
        let start = hull.len();
        let iter: Box<dyn Iterator<Item = &Point>> = if pass == 0 {
            Box::new(p.iter())
        } else {
            Box::new(p.iter().rev())
        };
        for &q in iter {
            while hull.len() >= start + 2
                && cross(hull[hull.len() - 2], hull[hull.len() - 1], q) <= 0.0
            {
                hull.pop();
            }
            hull.push(q);
        }
        hull.pop();
    }
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..hull.len() {
        let (u, v) = (hull[i], hull[(i + 1) % hull.len()]);
        let c = u.x * v.y - v.x * u.y;
        a += c;
        cx += (u.x + v.x) * c;
        cy += (u.y + v.y) * c;
    }
    if a.abs() < 1e-12 {
        // Points on a line: the middle of the line (a line's centroid).
        let n = hull.len() as f64;
        let s = hull.iter().fold((0.0, 0.0), |s, q| (s.0 + q.x, s.1 + q.y));
        return Point::new(s.0 / n, s.1 / n);
    }
    Point::new(cx / (3.0 * a), cy / (3.0 * a))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_hull_centroid_of_a_square_with_an_inner_point_is_its_centre() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(4.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(4.0, 4.0),
            Point::new(0.0, 4.0),
        ];
        let c = hull_centroid(&pts);
        assert!(c.distance(Point::new(2.0, 2.0)) < 1e-9, "{c:?}");
    }
}
