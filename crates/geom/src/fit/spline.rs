//! The seed's polyline methods (App. B): Bézier from groups of four points, the clamped
//! cubic B-spline, and local four-point interpolation; and the 0.004 rad collinear merge.

use crate::drawing::{Path, Segment};
use kurbo::{CubicBez, Point};

/// Bézier as the seed implemented it: cubic pieces over p(3k) … p(3k+3), so the curve passes
/// through every third point and the end tangents are 3(p1 − p0), 3(p3 − p2) (eq. b.3); no
/// tangent continuity between pieces. The closed contour ends where it starts; a last group
/// short of points repeats its end.
pub fn bezier_seed(ctrl: &[Point]) -> Path {
    let mut p = ctrl.to_vec();
    if p.len() < 2 {
        return Path::new(vec![], true);
    }
    p.push(p[0]);
    let mut segs = Vec::new();
    let mut k = 0;
    while k + 1 < p.len() {
        let g = |i: usize| p[(k + i).min(p.len() - 1)];
        segs.push(Segment::Cubic(CubicBez::new(g(0), g(1), g(2), g(3))));
        k += 3;
    }
    Path::new(segs, true)
}

/// Clamped (open-uniform) cubic B-spline on the control points, closed by repeating the
/// first: knots [0,0,0,0,1,2,…,m,m,m,m], which is exactly the seed's special first/second and
/// mirrored last sections (eq. b.13–b.17). `per_span` samples per knot span, by de Boor.
pub fn bspline_clamped(ctrl: &[Point], per_span: usize) -> Vec<Point> {
    let mut p = ctrl.to_vec();
    if p.len() < 4 {
        return p;
    }
    p.push(p[0]);
    let n = p.len();
    let m = n - 3; // spans
    let knot = |i: usize| -> f64 { (i as f64 - 3.0).clamp(0.0, m as f64) };
    let eval = |u: f64| -> Point {
        // Span s with knot(s) ≤ u < knot(s+1), s in 3..n-1.
        let s = ((u.floor() as usize) + 3).min(n - 1);
        let mut d: Vec<Point> = (0..4).map(|j| p[s - 3 + j]).collect();
        for r in 1..=3 {
            for j in (r..=3).rev() {
                let i = s - 3 + j;
                let (a, b) = (knot(i), knot(i + 4 - r));
                let alpha = if b > a { (u - a) / (b - a) } else { 0.0 };
                d[j] = d[j - 1].lerp(d[j], alpha);
            }
        }
        d[3]
    };
    let per = per_span.max(1);
    let mut out: Vec<Point> = (0..m * per).map(|k| eval(k as f64 / per as f64)).collect();
    out.push(p[n - 1]);
    out
}

/// Interpolation through every point: over each interval p(i) → p(i+1), the cubic through
/// p(i−1), p(i), p(i+1), p(i+2) at nodes u = −1, 0, 1, 2 (Lagrange, eq. b.19–b.22 applied
/// four points at a time), closed round the contour.
pub fn interpolate_local(ctrl: &[Point], per_span: usize) -> Vec<Point> {
    let n = ctrl.len();
    if n < 4 {
        return ctrl.to_vec();
    }
    let per = per_span.max(1);
    let mut out = Vec::with_capacity(n * per + 1);
    for i in 0..n {
        let q = [
            ctrl[(i + n - 1) % n],
            ctrl[i],
            ctrl[(i + 1) % n],
            ctrl[(i + 2) % n],
        ];
        for k in 0..per {
            let u = k as f64 / per as f64;
            let w = [
                -u * (u - 1.0) * (u - 2.0) / 6.0,
                (u + 1.0) * (u - 1.0) * (u - 2.0) / 2.0,
                -(u + 1.0) * u * (u - 2.0) / 2.0,
                (u + 1.0) * u * (u - 1.0) / 6.0,
            ];
            let x = (0..4).map(|j| w[j] * q[j].x).sum();
            let y = (0..4).map(|j| w[j] * q[j].y).sum();
            out.push(Point::new(x, y));
        }
    }
    out.push(ctrl[0]);
    out
}

/// Merges consecutive segments whose direction changes less than `angle` (the seed's first
/// cleaning pass, 0.004 rad): a vertex is dropped when the line from the last kept vertex
/// turns less than `angle` into the next segment.
pub fn merge_collinear(pts: &[Point], angle: f64) -> Vec<Point> {
    if pts.len() < 3 {
        return pts.to_vec();
    }
    let mut out = vec![pts[0]];
    for i in 1..pts.len() - 1 {
        let last = *out.last().unwrap();
        let a = pts[i] - last;
        let b = pts[i + 1] - pts[i];
        if a.hypot() < 1e-12 {
            continue;
        }
        let turn = a.cross(b).atan2(a.dot(b)).abs();
        if turn >= angle {
            out.push(pts[i]);
        }
    }
    out.push(*pts.last().unwrap());
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use kurbo::ParamCurve;

    fn square() -> Vec<Point> {
        vec![
            Point::new(0.0, 0.0),
            Point::new(10.0, 0.0),
            Point::new(10.0, 10.0),
            Point::new(0.0, 10.0),
            Point::new(-5.0, 5.0),
        ]
    }

    #[test]
    fn clamped_bspline_matches_the_seeds_first_section_basis() {
        // Seed eq. b.14: first section B1' = (1−u)³, B2' = 21u³/12 − 9u²/2 + 3u,
        // B3' = −11u³/12 + 3u²/2, B4' = u³/6, on p0..p3.
        let p = square();
        let s = bspline_clamped(&p, 4);
        assert_eq!(s[0], p[0], "starts at the first point");
        assert_eq!(*s.last().unwrap(), p[0], "closed");
        let u: f64 = 0.5;
        let b = [
            (1.0 - u).powi(3),
            21.0 * u.powi(3) / 12.0 - 4.5 * u * u + 3.0 * u,
            -11.0 * u.powi(3) / 12.0 + 1.5 * u * u,
            u.powi(3) / 6.0,
        ];
        let want = Point::new(
            (0..4).map(|j| b[j] * p[j].x).sum(),
            (0..4).map(|j| b[j] * p[j].y).sum(),
        );
        assert!(s[2].distance(want) < 1e-12, "{:?} vs {want:?}", s[2]);
    }

    #[test]
    fn interpolation_passes_through_every_point_and_bezier_through_every_third() {
        let p = square();
        let s = interpolate_local(&p, 8);
        for (k, q) in p.iter().enumerate() {
            assert!(s[k * 8].distance(*q) < 1e-12);
        }
        let b = bezier_seed(&p);
        assert_eq!(b.segments[0].start(), p[0]);
        assert_eq!(b.segments[0].end(), p[3]);
        assert_eq!(b.segments.last().unwrap().end(), p[0]);
        let Segment::Cubic(c) = b.segments[0] else {
            panic!()
        };
        assert_eq!(c.eval(0.0), p[0]);
    }

    #[test]
    fn collinear_merge_uses_the_angle() {
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(1.0, 0.001),
            Point::new(2.0, 0.0),
            Point::new(2.0, 5.0),
        ];
        assert_eq!(merge_collinear(&pts, 0.004).len(), 3);
        assert_eq!(merge_collinear(&pts, 0.0001).len(), 4);
    }
}
