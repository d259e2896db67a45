//! Biarc fitting: two tangent arcs between two points with given tangents, and a greedy fit
//! of a closed point list to as few biarcs as stay within a tolerance (the modern way to the
//! seed's "few arcs, G1" contour).

use crate::arc::{sweep_between, Arc};
use crate::drawing::{Path, Segment};
use kurbo::{Point, Vec2};

/// The arc that leaves `p` along unit tangent `t` and ends at `q` (a line if `q` lies ahead).
/// Its centre is on the normal at p: c = p + s·n with |c − q| = |s|, so s = |w|² / (2 n·w).
pub(super) fn arc_from_tangent(p: Point, t: Vec2, q: Point) -> Segment {
    let n = Vec2::new(-t.y, t.x);
    let w = q - p;
    let den = 2.0 * n.dot(w);
    if den.abs() <= 1e-9 * w.hypot() || w.hypot2() < 1e-24 {
        return Segment::line(p, q);
    }
    let s = w.hypot2() / den;
    if s.abs() > 1e6 * w.hypot() {
        return Segment::line(p, q);
    }
    let c = p + n * s;
    let a0 = (p - c).atan2();
    let sweep = sweep_between(a0, (q - c).atan2(), if s > 0.0 { 1 } else { -1 });
    Segment::Arc(Arc::new(c, s.abs(), a0, sweep))
}

/// Biarc from `p0` (unit tangent `t0`) to `p1` (unit tangent `t1`) with equal tangent legs d:
/// the joint is (p0 + d·t0 + p1 − d·t1)/2, where |(p0 + d·t0) − (p1 − d·t1)| = 2d gives
/// 2(1 − t0·t1)·d² + 2(v·t)·d − v·v = 0, v = p1 − p0, t = t0 + t1 (the positive root).
pub fn biarc(p0: Point, t0: Vec2, p1: Point, t1: Vec2) -> [Segment; 2] {
    let v = p1 - p0;
    let t = t0 + t1;
    let a = 2.0 * (1.0 - t0.dot(t1));
    let b = 2.0 * v.dot(t);
    let c = -v.hypot2();
    let d = if a.abs() < 1e-12 {
        if b.abs() < 1e-12 {
            f64::NAN
        } else {
            -c / b
        }
    } else {
        (-b + (b * b - 4.0 * a * c).max(0.0).sqrt()) / (2.0 * a)
    };
    if !(d.is_finite() && d > 0.0) {
        let m = p0.midpoint(p1);
        return [Segment::line(p0, m), Segment::line(m, p1)];
    }
    let joint = (p0 + t0 * d).midpoint(p1 - t1 * d);
    let first = arc_from_tangent(p0, t0, joint);
    let second = arc_from_tangent(p1, -t1, joint).reversed();
    [first, second]
}

/// Tangent at each point of a closed contour: that of the circle through it and its two
/// neighbours (the chord direction where they are collinear).
fn tangents(pts: &[Point]) -> Vec<Vec2> {
    let n = pts.len();
    (0..n)
        .map(|i| {
            let (a, p, b) = (pts[(i + n - 1) % n], pts[i], pts[(i + 1) % n]);
            let chord = (b - a).normalize();
            match crate::arc::circumcenter(a, p, b) {
                Some(c) => {
                    let r = (p - c).normalize();
                    let t = Vec2::new(-r.y, r.x);
                    if t.dot(chord) >= 0.0 {
                        t
                    } else {
                        -t
                    }
                }
                None => chord,
            }
        })
        .collect()
}

/// Fits a closed contour with biarcs through some of its points, each biarc spanning as many
/// points as stay within `tol` of it (and at most `max_span`).
pub fn fit_biarcs(pts: &[Point], tol: f64) -> Path {
    let n = pts.len();
    if n < 3 {
        return Path::polyline(pts, true);
    }
    let tan = tangents(pts);
    let max_span = n.min(400);
    let fits = |i: usize, j: usize| -> Option<[Segment; 2]> {
        let (p, q) = (pts[i % n], pts[j % n]);
        let b = biarc(p, tan[i % n], q, tan[j % n]);
        let ok = (i + 1..j).all(|k| {
            let x = pts[k % n];
            b[0].distance(x).min(b[1].distance(x)) <= tol
        });
        ok.then_some(b)
    };
    let mut segs = Vec::new();
    let mut i = 0;
    while i < n {
        let mut best = (i + 1, fits(i, i + 1).expect("no interior points"));
        let mut j = i + 2;
        while j <= n && j - i <= max_span {
            match fits(i, j) {
                Some(b) => best = (j, b),
                None => break,
            }
            j += 1;
        }
        for s in best.1 {
            if s.length() > 1e-12 {
                segs.push(s);
            }
        }
        i = best.0;
    }
    Path::new(segs, true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn biarc_is_g1_and_reproduces_a_circle() {
        // Quarter of a unit circle: the biarc is two arcs of radius 1.
        let b = biarc(
            Point::new(1.0, 0.0),
            Vec2::new(0.0, 1.0),
            Point::new(0.0, 1.0),
            Vec2::new(-1.0, 0.0),
        );
        for s in &b {
            let Segment::Arc(a) = s else { panic!("{s:?}") };
            assert!((a.radius - 1.0).abs() < 1e-9 && a.center.distance(Point::ORIGIN) < 1e-9);
        }
        assert!(b[0].end().distance(b[1].start()) < 1e-12);
        // An S: tangents parallel, points offset.
        let s = biarc(
            Point::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Point::new(10.0, 2.0),
            Vec2::new(1.0, 0.0),
        );
        let (Segment::Arc(a), Segment::Arc(b)) = (s[0], s[1]) else {
            panic!()
        };
        assert!(a.sweep > 0.0 && b.sweep < 0.0, "turns left then right");
        assert!(a.tangent_at(1.0).dot(b.tangent_at(0.0)) > 1.0 - 1e-9);
        assert!(b.end().distance(Point::new(10.0, 2.0)) < 1e-9);
    }

    #[test]
    fn a_circle_of_many_points_needs_few_biarcs() {
        let pts: Vec<Point> = (0..200)
            .map(|k| {
                let t = TAU * k as f64 / 200.0;
                Point::new(30.0 * t.cos(), 30.0 * t.sin())
            })
            .collect();
        let p = fit_biarcs(&pts, 0.01);
        assert!(p.segments.len() <= 8, "{} segments", p.segments.len());
        let dev = pts.iter().map(|q| p.distance(*q)).fold(0.0, f64::max);
        assert!(dev < 0.01);
    }
}
