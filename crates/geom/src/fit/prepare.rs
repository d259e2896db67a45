//! Cleaning digitised contours before fitting: duplicates and jitter out, counter-clockwise,
//! the closing repeat dropped; Douglas–Peucker simplification; resampling by arc length.

use kurbo::{Line, ParamCurveNearest, Point};

/// Drops repeated points (closer than `min_step`), the closing repeat of the first point, and
/// smooths jitter with one Laplacian pass whose moves are capped at `max_move`: a point moves
/// halfway towards the midpoint of its neighbours, never more than the cap. Returns the
/// contour counter-clockwise.
pub fn denoise(points: &[Point], min_step: f64, max_move: f64) -> Vec<Point> {
    let mut pts: Vec<Point> = Vec::with_capacity(points.len());
    for &p in points {
        if !p.is_finite() {
            continue;
        }
        if pts.last().is_none_or(|q: &Point| q.distance(p) > min_step) {
            pts.push(p);
        }
    }
    while pts.len() > 2 && pts[0].distance(*pts.last().unwrap()) <= min_step {
        pts.pop();
    }
    let n = pts.len();
    if n >= 5 && max_move > 0.0 {
        let orig = pts.clone();
        for i in 0..n {
            let mid = orig[(i + n - 1) % n].midpoint(orig[(i + 1) % n]);
            let mv = (mid - orig[i]) * 0.5;
            let len = mv.hypot();
            let mv = if len > max_move {
                mv * (max_move / len)
            } else {
                mv
            };
            pts[i] = orig[i] + mv;
        }
    }
    if signed_area(&pts) < 0.0 {
        pts.reverse();
        // Keep the first point first.
        pts.rotate_right(1);
    }
    pts
}

/// Shoelace area of a closed point list, > 0 counter-clockwise.
pub fn signed_area(p: &[Point]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| p[i].to_vec2().cross(p[(i + 1) % n].to_vec2()))
        .sum::<f64>()
        / 2.0
}

/// Douglas–Peucker on an open polyline: keeps the ends and every point needed to stay
/// within `tol`.
pub fn simplify_open(points: &[Point], tol: f64) -> Vec<Point> {
    if points.len() < 3 {
        return points.to_vec();
    }
    let mut keep = vec![false; points.len()];
    keep[0] = true;
    *keep.last_mut().unwrap() = true;
    let mut stack = vec![(0, points.len() - 1)];
    while let Some((a, b)) = stack.pop() {
        if b <= a + 1 {
            continue;
        }
        let l = Line::new(points[a], points[b]);
        let (mut worst, mut at) = (0.0, a);
        for (i, p) in points.iter().enumerate().take(b).skip(a + 1) {
            let d = l.nearest(*p, 1e-9).distance_sq;
            if d > worst {
                worst = d;
                at = i;
            }
        }
        if worst.sqrt() > tol {
            keep[at] = true;
            stack.push((a, at));
            stack.push((at, b));
        }
    }
    points
        .iter()
        .zip(keep)
        .filter(|(_, k)| *k)
        .map(|(p, _)| *p)
        .collect()
}

/// Douglas–Peucker on a closed contour (split at the point farthest from the first).
pub fn simplify_closed(points: &[Point], tol: f64) -> Vec<Point> {
    if points.len() < 4 {
        return points.to_vec();
    }
    let far = (0..points.len())
        .max_by(|&i, &j| {
            points[0]
                .distance(points[i])
                .total_cmp(&points[0].distance(points[j]))
        })
        .unwrap();
    let mut a = simplify_open(&points[..=far], tol);
    let mut tail: Vec<Point> = points[far..].to_vec();
    tail.push(points[0]);
    let b = simplify_open(&tail, tol);
    a.pop();
    a.extend_from_slice(&b[..b.len() - 1]);
    a
}

/// `n` points evenly spaced by arc length round a closed contour, starting at its first.
pub fn resample_closed(points: &[Point], n: usize) -> Vec<Point> {
    let m = points.len();
    if m < 2 || n == 0 {
        return points.to_vec();
    }
    let seg: Vec<f64> = (0..m)
        .map(|i| points[i].distance(points[(i + 1) % m]))
        .collect();
    let total: f64 = seg.iter().sum();
    let mut out = Vec::with_capacity(n);
    let (mut i, mut acc) = (0, 0.0);
    for k in 0..n {
        let s = total * k as f64 / n as f64;
        while i < m - 1 && acc + seg[i] < s {
            acc += seg[i];
            i += 1;
        }
        let t = if seg[i] > 0.0 {
            ((s - acc) / seg[i]).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(points[i].lerp(points[(i + 1) % m], t));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn denoise_drops_repeats_and_makes_ccw() {
        let cw = [
            Point::new(0.0, 0.0),
            Point::new(0.0, 0.0),
            Point::new(0.0, 10.0),
            Point::new(10.0, 10.0),
            Point::new(10.0, 0.0),
            Point::new(0.0, 0.0),
        ];
        let d = denoise(&cw, 1e-6, 0.0);
        assert_eq!(d.len(), 4);
        assert!(signed_area(&d) > 0.0);
        assert_eq!(d[0], Point::new(0.0, 0.0));
    }

    #[test]
    fn simplify_keeps_corners_within_tolerance() {
        let mut pts = Vec::new();
        for i in 0..10 {
            pts.push(Point::new(i as f64, 0.0));
        }
        for i in 0..10 {
            pts.push(Point::new(10.0, i as f64));
        }
        for i in 0..10 {
            pts.push(Point::new(10.0 - i as f64, 10.0));
        }
        for i in 0..10 {
            pts.push(Point::new(0.0, 10.0 - i as f64));
        }
        let s = simplify_closed(&pts, 0.01);
        assert_eq!(s.len(), 4, "{s:?}");
        let r = resample_closed(&s, 8);
        assert_eq!(r.len(), 8);
        assert!(r[1].distance(Point::new(5.0, 0.0)) < 1e-9);
    }
}
