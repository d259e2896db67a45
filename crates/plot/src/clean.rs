//! Cleaning strokes: Ramer–Douglas–Peucker simplification and removal of duplicates.

use oficina_geom::Point;
use std::collections::HashSet;

use crate::strokes::Stroke;

/// Distance from `p` to the segment a–b.
fn seg_distance(p: Point, a: Point, b: Point) -> f64 {
    let ab = b - a;
    let len2 = ab.hypot2();
    if len2 == 0.0 {
        return p.distance(a);
    }
    let t = ((p - a).dot(ab) / len2).clamp(0.0, 1.0);
    p.distance(a + ab * t)
}

/// Ramer–Douglas–Peucker: keeps the fewest points such that every dropped point lies within
/// `tol` of the kept polyline. Iterative (a stack of spans), so long strokes cannot overflow.
pub fn simplify(s: &[Point], tol: f64) -> Stroke {
    if s.len() < 3 || tol <= 0.0 {
        return s.to_vec();
    }
    let mut keep = vec![false; s.len()];
    keep[0] = true;
    keep[s.len() - 1] = true;
    let mut spans = vec![(0usize, s.len() - 1)];
    while let Some((a, b)) = spans.pop() {
        let (mut worst, mut at) = (0.0, 0);
        for i in a + 1..b {
            let d = seg_distance(s[i], s[a], s[b]);
            if d > worst {
                worst = d;
                at = i;
            }
        }
        if worst > tol {
            keep[at] = true;
            spans.push((a, at));
            spans.push((at, b));
        }
    }
    s.iter()
        .zip(&keep)
        .filter(|(_, &k)| k)
        .map(|(p, _)| *p)
        .collect()
}

/// Drops strokes that repeat an earlier one (same points within `tol`, either direction).
/// Returns how many were dropped.
pub fn dedupe(strokes: &mut Vec<Stroke>, tol: f64) -> usize {
    let q = if tol > 0.0 { tol } else { 1e-9 };
    let key = |s: &Stroke| -> Vec<(i64, i64)> {
        let k: Vec<(i64, i64)> = s
            .iter()
            .map(|p| ((p.x / q).round() as i64, (p.y / q).round() as i64))
            .collect();
        let r: Vec<(i64, i64)> = k.iter().rev().copied().collect();
        k.min(r)
    };
    let mut seen = HashSet::with_capacity(strokes.len());
    let before = strokes.len();
    strokes.retain(|s| seen.insert(key(s)));
    before - strokes.len()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simplify_keeps_every_dropped_point_within_tolerance() {
        let pts: Vec<Point> = (0..200)
            .map(|i| {
                let t = i as f64 / 199.0 * std::f64::consts::PI;
                Point::new(50.0 * t.cos(), 50.0 * t.sin())
            })
            .collect();
        let s = simplify(&pts, 0.1);
        assert!(s.len() < 60 && s.len() > 5, "{}", s.len());
        for p in &pts {
            let d = s
                .windows(2)
                .map(|w| seg_distance(*p, w[0], w[1]))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= 0.1 + 1e-12);
        }
    }

    #[test]
    fn duplicates_in_either_direction_are_dropped() {
        let a = vec![Point::new(0.0, 0.0), Point::new(5.0, 5.0)];
        let b = vec![Point::new(5.0, 5.0), Point::new(0.0, 0.0)];
        let c = vec![Point::new(0.0, 0.0), Point::new(5.0, 6.0)];
        let mut v = vec![a.clone(), b, c, a];
        assert_eq!(dedupe(&mut v, 0.01), 2);
        assert_eq!(v.len(), 2);
    }
}
