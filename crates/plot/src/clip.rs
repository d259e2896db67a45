//! Cutting polylines by areas (rings read even-odd, as `geom::simplify` returns them: outers
//! and holes that do not overlap): the pieces inside or outside. Occlusion keeps the outside,
//! hatching and cropping the inside.

use oficina_geom::{Point, Ring};

use crate::strokes::Stroke;

/// An area to cut by: rings read even-odd, with their bounding box.
#[derive(Clone, Debug)]
pub(crate) struct Area {
    pub(crate) rings: Vec<Ring>,
    pub(crate) bbox: [f64; 4],
}

impl Area {
    /// `None` when no ring has three points.
    pub(crate) fn new(rings: Vec<Ring>) -> Option<Area> {
        let rings: Vec<Ring> = rings.into_iter().filter(|r| r.len() >= 3).collect();
        let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
        for p in rings.iter().flatten() {
            b = [
                b[0].min(p[0]),
                b[1].min(p[1]),
                b[2].max(p[0]),
                b[3].max(p[1]),
            ];
        }
        (!rings.is_empty()).then_some(Area { rings, bbox: b })
    }

    fn edges(&self) -> impl Iterator<Item = (Point, Point)> + '_ {
        self.rings.iter().flat_map(|r| {
            (0..r.len()).map(move |i| {
                let (a, b) = (r[i], r[(i + 1) % r.len()]);
                (Point::new(a[0], a[1]), Point::new(b[0], b[1]))
            })
        })
    }

    /// Even-odd crossing test.
    pub(crate) fn contains(&self, p: Point) -> bool {
        if p.x < self.bbox[0] || p.x > self.bbox[2] || p.y < self.bbox[1] || p.y > self.bbox[3] {
            return false;
        }
        let mut inside = false;
        for (a, b) in self.edges() {
            if (a.y > p.y) != (b.y > p.y) {
                let x = a.x + (p.y - a.y) / (b.y - a.y) * (b.x - a.x);
                if x > p.x {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// Distance from `p` to the nearest edge.
    fn boundary_distance(&self, p: Point) -> f64 {
        self.edges()
            .map(|(a, b)| {
                let ab = b - a;
                let l2 = ab.hypot2();
                let t = if l2 > 0.0 {
                    ((p - a).dot(ab) / l2).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                p.distance(a + ab * t)
            })
            .fold(f64::INFINITY, f64::min)
    }

    fn overlaps(&self, b: &[f64; 4]) -> bool {
        !(b[2] < self.bbox[0] || b[0] > self.bbox[2] || b[3] < self.bbox[1] || b[1] > self.bbox[3])
    }
}

fn stroke_bbox(s: &[Point]) -> [f64; 4] {
    let mut b = [f64::MAX, f64::MAX, f64::MIN, f64::MIN];
    for p in s {
        b = [b[0].min(p.x), b[1].min(p.y), b[2].max(p.x), b[3].max(p.y)];
    }
    b
}

/// Parameters in (0, 1) where segment a–b crosses the area's edges.
fn crossings(area: &Area, a: Point, b: Point, out: &mut Vec<f64>) {
    let d = b - a;
    for (p, q) in area.edges() {
        let e = q - p;
        let den = d.cross(e);
        if den.abs() < 1e-15 {
            continue; // parallel: collinear runs are split at the edge ends below
        }
        let w = p - a;
        let t = w.cross(e) / den;
        let u = w.cross(d) / den;
        if t > 0.0 && t < 1.0 && (0.0..=1.0).contains(&u) {
            out.push(t);
        }
    }
    // Ring vertices lying on the segment start or end collinear overlaps.
    let l2 = d.hypot2();
    if l2 > 0.0 {
        for r in &area.rings {
            for v in r {
                let v = Point::new(v[0], v[1]);
                let t = (v - a).dot(d) / l2;
                if t > 0.0 && t < 1.0 && (a + d * t).distance(v) < 1e-9 {
                    out.push(t);
                }
            }
        }
    }
}

/// The pieces of `s` inside `area` (`keep_inside`) or outside it. Pieces along the boundary
/// count as inside when `boundary_inside` (an occluding shape hides its own outline's place,
/// as shapely's difference does) and as outside otherwise.
pub(crate) fn cut(
    s: &[Point],
    area: &Area,
    keep_inside: bool,
    boundary_inside: bool,
) -> Vec<Stroke> {
    if s.len() < 2 {
        return Vec::new();
    }
    if !area.overlaps(&stroke_bbox(s)) {
        return if keep_inside {
            Vec::new()
        } else {
            vec![s.to_vec()]
        };
    }
    let eps = 1e-9 * (1.0 + area.bbox[2] - area.bbox[0] + area.bbox[3] - area.bbox[1]);
    let keep = |m: Point| {
        let inside = if area.boundary_distance(m) < eps {
            boundary_inside
        } else {
            area.contains(m)
        };
        inside == keep_inside
    };
    let mut out: Vec<Stroke> = Vec::new();
    let mut cur: Stroke = Vec::new();
    let mut ts = Vec::new();
    for w in s.windows(2) {
        let (a, b) = (w[0], w[1]);
        if a == b {
            continue;
        }
        ts.clear();
        crossings(area, a, b, &mut ts);
        ts.push(0.0);
        ts.push(1.0);
        ts.sort_by(f64::total_cmp);
        ts.dedup_by(|x, y| (*x - *y).abs() < 1e-12);
        for t in ts.windows(2) {
            let (p, q) = (a.lerp(b, t[0]), a.lerp(b, t[1]));
            if keep(p.midpoint(q)) {
                if cur.last() != Some(&p) {
                    if cur.len() >= 2 {
                        out.push(std::mem::take(&mut cur));
                    }
                    cur.clear();
                    cur.push(p);
                }
                cur.push(q);
            } else if cur.len() >= 2 {
                out.push(std::mem::take(&mut cur));
            } else {
                cur.clear();
            }
        }
    }
    if cur.len() >= 2 {
        out.push(cur);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x0: f64, y0: f64, x1: f64, y1: f64) -> Ring {
        vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]]
    }

    #[test]
    fn a_line_through_a_square_with_a_hole() {
        let a = Area::new(vec![
            square(0.0, 0.0, 10.0, 10.0),
            square(4.0, 4.0, 6.0, 6.0),
        ])
        .unwrap();
        let line = [Point::new(-5.0, 5.0), Point::new(15.0, 5.0)];
        let len = |v: &[Stroke]| v.iter().map(|s| crate::polyline_length(s)).sum::<f64>();
        let inside = cut(&line, &a, true, false);
        assert_eq!(inside.len(), 2);
        assert!((len(&inside) - 8.0).abs() < 1e-9);
        let outside = cut(&line, &a, false, false);
        assert!((len(&outside) - 12.0).abs() < 1e-9, "{outside:?}");
        // Along the boundary: hidden by an occluder, kept by a crop.
        let edge = [Point::new(0.0, 0.0), Point::new(10.0, 0.0)];
        assert!(cut(&edge, &a, false, true).is_empty());
        assert_eq!(cut(&edge, &a, true, false).len(), 0);
        assert_eq!(cut(&edge, &a, false, false).len(), 1);
    }
}
