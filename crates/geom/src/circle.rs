//! Is a closed path a circle? CAD programs draw holes as a CIRCLE, as two or four arcs, as a
//! 24-gon polyline, as a spline, or (SVG) as four Béziers: drilling and hole detection must
//! see the same hole in each. The test: a least-squares circle through the path's points
//! (segment ends; curves sampled) that every point lies on within a tolerance, with the points
//! going once around the centre in steps of at most 40° (a square's corners lie on a circle
//! too, but 90° apart: a square is not a hole).

use crate::drawing::{Path, Segment};
use kurbo::Point;
use std::f64::consts::TAU;

/// Largest angle between successive points for a polygon to count as a circle (a regular
/// polygon of 9 or more sides).
const MAX_STEP: f64 = 40.0 * std::f64::consts::PI / 180.0;

/// A circle fitted to a closed path.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CircleFit {
    /// The centre.
    pub center: Point,
    /// The radius, mm.
    pub radius: f64,
    /// The largest distance of a point of the path from the circle, mm.
    pub deviation: f64,
}

impl Path {
    /// The circle this closed path is, when every point (segment ends, arcs and curves
    /// sampled) lies within `tol` mm of one circle and they go once around it in steps of at
    /// most 40°; `None` otherwise (open paths, too few points, other shapes).
    pub fn as_circle(&self, tol: f64) -> Option<CircleFit> {
        self.fit_circle().filter(|c| c.deviation <= tol)
    }

    /// The least-squares circle through the closed path's points, with their largest
    /// deviation from it, when they go once around its centre in steps of at most 40°.
    pub fn fit_circle(&self) -> Option<CircleFit> {
        if !self.closed || self.segments.is_empty() {
            return None;
        }
        // One circle of arcs about one centre is exact (DXF CIRCLE, two or four ARCs).
        if let Some(c) = same_centre_arcs(self) {
            return Some(c);
        }
        let pts = self.flatten(1e-3);
        if pts.len() < 9 || pts.len() > 1_000_000 {
            return None;
        }
        let (center, radius) = kasa(&pts)?;
        let deviation = pts
            .iter()
            .map(|p| (p.distance(center) - radius).abs())
            .fold(0.0, f64::max);
        once_around(&pts, center).then_some(CircleFit {
            center,
            radius,
            deviation,
        })
    }
}

/// Every segment an arc about one centre, of one radius, sweeping a full turn in all.
fn same_centre_arcs(p: &Path) -> Option<CircleFit> {
    let arcs: Vec<_> = p
        .segments
        .iter()
        .map(|s| match s {
            Segment::Arc(a) => Some(*a),
            _ => None,
        })
        .collect::<Option<_>>()?;
    let first = arcs.first()?;
    let same = arcs
        .iter()
        .all(|a| a.center.distance(first.center) < 1e-6 && (a.radius - first.radius).abs() < 1e-6);
    let sweep: f64 = arcs.iter().map(|a| a.sweep).sum();
    (same && (sweep.abs() - TAU).abs() < 1e-6).then_some(CircleFit {
        center: first.center,
        radius: first.radius,
        deviation: 0.0,
    })
}

/// Kåsa's algebraic circle fit: x² + y² + D x + E y + F = 0 by least squares, in coordinates
/// about the points' mean (for conditioning far from the origin).
fn kasa(pts: &[Point]) -> Option<(Point, f64)> {
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |a, p| (a.0 + p.x / n, a.1 + p.y / n));
    let (mut suu, mut svv, mut suv, mut suuu, mut svvv, mut suvv, mut svuu) =
        (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    for p in pts {
        let (u, v) = (p.x - mx, p.y - my);
        suu += u * u;
        svv += v * v;
        suv += u * v;
        suuu += u * u * u;
        svvv += v * v * v;
        suvv += u * v * v;
        svuu += v * u * u;
    }
    // Centre (uc, vc) solves [suu suv; suv svv] (uc, vc) = ½ (suuu + suvv, svvv + svuu).
    let det = suu * svv - suv * suv;
    if !(det.abs() > 1e-18 * (suu * svv).max(1e-300)) {
        return None;
    }
    let (b0, b1) = (0.5 * (suuu + suvv), 0.5 * (svvv + svuu));
    let uc = (b0 * svv - b1 * suv) / det;
    let vc = (suu * b1 - suv * b0) / det;
    let r2 = uc * uc + vc * vc + (suu + svv) / n;
    let c = Point::new(uc + mx, vc + my);
    (r2 > 0.0 && c.is_finite()).then(|| (c, r2.sqrt()))
}

/// The points go once around `c`, each step turning the same way by at most [`MAX_STEP`].
fn once_around(pts: &[Point], c: Point) -> bool {
    let ang: Vec<f64> = pts.iter().map(|p| (p.y - c.y).atan2(p.x - c.x)).collect();
    let mut total = 0.0;
    let mut sign = 0.0;
    for i in 0..ang.len() {
        let mut d = ang[(i + 1) % ang.len()] - ang[i];
        if d > std::f64::consts::PI {
            d -= TAU;
        } else if d < -std::f64::consts::PI {
            d += TAU;
        }
        if d.abs() > MAX_STEP + 1e-9 || (sign != 0.0 && d * sign < 0.0 && d.abs() > 1e-9) {
            return false;
        }
        if sign == 0.0 && d.abs() > 1e-9 {
            sign = d.signum();
        }
        total += d;
    }
    (total.abs() - TAU).abs() < 1e-6
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Arc;
    use kurbo::{Affine, CubicBez};

    fn polygon(n: usize, c: Point, r: f64) -> Path {
        let pts: Vec<Point> = (0..n)
            .map(|i| {
                let a = TAU * i as f64 / n as f64;
                Point::new(c.x + r * a.cos(), c.y + r * a.sin())
            })
            .collect();
        Path::polyline(&pts, true)
    }

    #[test]
    fn a_24_gon_four_arcs_and_four_beziers_are_circles() {
        let c = Point::new(120.0, -35.0);
        let gon = polygon(24, c, 4.0).as_circle(0.01).expect("24-gon");
        assert!(
            gon.center.distance(c) < 1e-9 && (gon.radius - 4.0).abs() < 1e-9,
            "{gon:?}"
        );
        let quarters: Vec<Segment> = (0..4)
            .map(|i| Segment::Arc(Arc::new(c, 4.0, i as f64 * TAU / 4.0, TAU / 4.0)))
            .collect();
        let arcs = Path::new(quarters, true).as_circle(0.0).expect("four arcs");
        assert_eq!(arcs.center, c);
        // SVG's circle: four cubics (kurbo's, as usvg makes them), 0.03 % off the circle.
        let mut segs = Vec::new();
        let mut from = Point::new(c.x + 4.0, c.y);
        kurbo::Arc::new(c, (4.0, 4.0), 0.0, TAU, 0.0).to_cubic_beziers(0.1, |p1, p2, p3| {
            segs.push(Segment::Cubic(CubicBez::new(from, p1, p2, p3)));
            from = p3;
        });
        let bez = Path::new(segs, true).as_circle(0.01).expect("Béziers");
        assert!(
            bez.center.distance(c) < 1e-3 && bez.deviation < 0.01,
            "{bez:?}"
        );
    }

    #[test]
    fn squares_octagons_ellipses_slots_and_open_arcs_are_not() {
        let c = Point::new(0.0, 0.0);
        assert!(
            polygon(4, c, 4.0).fit_circle().is_none(),
            "a square's corners are 90° apart"
        );
        assert!(polygon(8, c, 4.0).fit_circle().is_none(), "45° steps");
        assert!(polygon(9, c, 4.0).fit_circle().is_some());
        let ellipse = polygon(48, c, 4.0).transform(Affine::scale_non_uniform(1.0, 0.9));
        let e = ellipse.fit_circle().expect("goes around");
        assert!(
            e.deviation > 0.1 && ellipse.as_circle(0.01).is_none(),
            "{e:?}"
        );
        let mut open = polygon(24, c, 4.0);
        open.closed = false;
        assert!(open.as_circle(1.0).is_none());
        // A half circle closed by its diameter: the chord jumps 180°.
        let half = Path::new(vec![Segment::Arc(Arc::new(c, 4.0, 0.0, TAU / 2.0))], true);
        let mut half = half;
        half.close_gap();
        assert!(half.as_circle(0.01).is_none());
    }
}
