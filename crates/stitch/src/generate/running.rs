//! Running stitch along a polyline (seed §7, POLIL / ARCOL): the line between two corners is
//! cut into n = ⌈L / PASSO⌉ equal stitches measured along the path, so a curve (flattened
//! finely first) gets stitches of PASSO of arc, as the seed subdivides arcs. The seed leaves
//! the remainder open; equal division avoids a short last stitch. Corners (a turn above
//! `CORNER`) are always needle points so the stitch line keeps the drawing's shape.

use oficina_geom::Point;

/// A turn sharper than this (radians) is a corner kept as a needle point.
const CORNER: f64 = 0.35;

/// Needle points along `points` (first included), stitches at most `len` long.
pub fn running(points: &[Point], len: f64) -> Vec<Point> {
    let pts: Vec<Point> = dedup(points);
    let mut out = Vec::new();
    if pts.is_empty() {
        return out;
    }
    out.push(pts[0]);
    let mut start = 0;
    for i in 1..pts.len() {
        let last = i == pts.len() - 1;
        if last || turn(pts[i - 1], pts[i], pts[i + 1]) > CORNER {
            subdivide(&pts[start..=i], len, &mut out);
            start = i;
        }
    }
    out
}

fn dedup(points: &[Point]) -> Vec<Point> {
    let mut v: Vec<Point> = Vec::with_capacity(points.len());
    for p in points {
        if v.last().is_none_or(|q| q.distance(*p) > 1e-6) {
            v.push(*p);
        }
    }
    v
}

/// Angle between the directions a→b and b→c.
fn turn(a: Point, b: Point, c: Point) -> f64 {
    let (u, v) = (b - a, c - b);
    v.cross(u).atan2(u.dot(v)).abs()
}

/// Appends the points after the first of `piece`, equally spaced along it.
fn subdivide(piece: &[Point], len: f64, out: &mut Vec<Point>) {
    let total: f64 = piece.windows(2).map(|w| w[0].distance(w[1])).sum();
    let n = (total / len - 1e-9).ceil().max(1.0) as usize;
    let step = total / n as f64;
    let (mut seg, mut seg_start) = (0usize, 0.0);
    for k in 1..n {
        let s = k as f64 * step;
        while seg + 1 < piece.len() - 1 && seg_start + piece[seg].distance(piece[seg + 1]) < s {
            seg_start += piece[seg].distance(piece[seg + 1]);
            seg += 1;
        }
        let l = piece[seg].distance(piece[seg + 1]);
        let t = if l > 0.0 { (s - seg_start) / l } else { 0.0 };
        out.push(piece[seg].lerp(piece[seg + 1], t.clamp(0.0, 1.0)));
    }
    out.push(*piece.last().unwrap());
}

/// Points from `a` to `b` (a excluded), stitches at most `len`.
pub(super) fn straight(a: Point, b: Point, len: f64) -> Vec<Point> {
    let n = (a.distance(b) / len - 1e-9).ceil().max(1.0) as usize;
    (1..=n).map(|k| a.lerp(b, k as f64 / n as f64)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_line_is_cut_equally_and_corners_kept() {
        let p = running(
            &[
                Point::new(0.0, 0.0),
                Point::new(10.0, 0.0),
                Point::new(10.0, 4.0),
            ],
            3.0,
        );
        // 10 mm → 4 stitches of 2.5; the corner at (10, 0) kept; 4 mm → 2 of 2.
        assert_eq!(p.len(), 1 + 4 + 2);
        assert!(p[4].distance(Point::new(10.0, 0.0)) < 1e-12);
        assert!((p[1].x - 2.5).abs() < 1e-12);
    }

    #[test]
    fn an_arc_gets_stitches_of_passo_along_it() {
        let arc: Vec<Point> = (0..=400)
            .map(|i| {
                let t = i as f64 / 400.0 * std::f64::consts::PI;
                Point::new(20.0 * t.cos(), 20.0 * t.sin())
            })
            .collect();
        let p = running(&arc, 2.0);
        // π·20 = 62.83 mm → 32 stitches of 1.963 mm of arc.
        assert_eq!(p.len(), 33);
        let chord = p[0].distance(p[1]);
        assert!(
            (chord - 2.0 * 20.0 * (62.83185f64 / 32.0 / 40.0).sin()).abs() < 1e-3,
            "{chord}"
        );
    }
}
