//! The seed's "Circunferências Tangentes" (seed 001 §2.2, App. C): a closed G1 poly-arc.
//!
//! 1. Circle k passes through p(2k−1), p(2k), p(2k+1) (1-based); its centre is where the
//!    perpendicular bisectors of p1p2 and p2p3 meet, in slope–intercept form (eq. c.1–c.5):
//!      a1 = (y2² − y1² + x2² − x1²) / (2(y2 − y1)),  b1 = −(x2 − x1)/(y2 − y1), same for a2, b2,
//!      xc = −(a2 − a1)/(b2 − b1),  yc = a1 + b1·xc;
//!    a horizontal chord makes its bisector vertical: xc is the chord's mid x (c.3, c.4).
//! 2. In groups (C1, C, C2) = (1,2,3), (3,4,5), …, (m−1, m, 1) the odd circles stay, and the
//!    middle circle keeps its radius r while its centre moves until it touches both: in the
//!    frame with C1's centre at the origin and C2's at (d, 0),
//!      D = (G3² − G4² + d²) / 2d,   E = √(G3² − D²)·Sinal                       (eq. 3.1)
//!    with G3 = |r − r1| for internal contact (the arcs turn the same way) or r + r1 for
//!    external contact (an S-bend), G4 likewise with C2, and Sinal the side C was on.
//!    No real root (G3 + G4 < d or |G3 − G4| > d) is the seed's tangency failure.
//! 3. The junctions are the contact points, on the lines of centres.

// The numbered steps carry the seed's equations indented under them.
#![allow(clippy::doc_overindented_list_items)]

use crate::arc::{sweep_between, Arc};
use crate::drawing::{Path, Segment};
use kurbo::{Point, Vec2};

/// Why the tangent-circle fit failed, with the points to change.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum TangentError {
    /// The point count is not 4·(1+n).
    #[error("tangent circles need 4·(1+n) distinct points (n ≥ 1), got {0}")]
    PointCount(usize),
    /// Three points on one line: no circle.
    #[error("points {indices:?} are collinear: no circle passes through {points:?}; choose other points")]
    Collinear {
        /// Their indices.
        indices: [usize; 3],
        /// The points.
        points: [Point; 3],
    },
    #[error(
        "circle {circle} runs the wrong way round ({sweep:.2} rad) after the tangency moves: \
         a loop in the contour; choose other points near {points:?}"
    )]
    /// A circle turns the wrong way after the tangency moves.
    Loop {
        /// The circle's index.
        circle: usize,
        /// Its sweep, radians.
        sweep: f64,
        /// The points to change.
        points: Vec<Point>,
    },
    #[error(
        "circle {moved} cannot touch circles {fixed:?} (d = {d:.3}, G3 = {g3:.3}, G4 = {g4:.3}); \
         re-enter points near {points:?} so the neighbours reach each other"
    )]
    /// A circle cannot touch both neighbours.
    NoTangent {
        /// The circle moved.
        moved: usize,
        /// Its neighbours.
        fixed: [usize; 2],
        /// Distance between the neighbours' centres, mm.
        d: f64,
        /// The seed's G3 term.
        g3: f64,
        /// The seed's G4 term.
        g4: f64,
        /// The points to change.
        points: Vec<Point>,
    },
}

/// A circle of the method: centre, radius and turning sign (+1 counter-clockwise).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentCircle {
    /// Centre.
    pub center: Point,
    /// Radius, mm.
    pub radius: f64,
    /// +1 counter-clockwise, −1 clockwise.
    pub sign: f64,
}

const EPS: f64 = 1e-12;

fn rotate(v: Vec2, a: f64) -> Vec2 {
    let (s, c) = a.sin_cos();
    Vec2::new(c * v.x - s * v.y, s * v.x + c * v.y)
}

/// Centre and radius of the circle through three points by the seed's bisector formulas.
pub fn circle_through(p1: Point, p2: Point, p3: Point) -> Option<(Point, f64)> {
    let bisector = |p: Point, q: Point| {
        let dy = q.y - p.y;
        let a = (q.y * q.y - p.y * p.y + q.x * q.x - p.x * p.x) / (2.0 * dy);
        let b = -(q.x - p.x) / dy;
        (a, b)
    };
    let scale = p1.distance(p2).max(p2.distance(p3)).max(1e-300);
    let flat1 = (p2.y - p1.y).abs() <= EPS * scale;
    let flat2 = (p3.y - p2.y).abs() <= EPS * scale;
    let (xc, yc) = match (flat1, flat2) {
        (true, true) => return None,
        (true, false) => {
            // c.3: bisector 1 is vertical.
            let xc = (p1.x + p2.x) / 2.0;
            let (a2, b2) = bisector(p2, p3);
            (xc, a2 + b2 * xc)
        }
        (false, true) => {
            // c.4: bisector 2 is vertical.
            let xc = (p2.x + p3.x) / 2.0;
            let (a1, b1) = bisector(p1, p2);
            (xc, a1 + b1 * xc)
        }
        (false, false) => {
            let (a1, b1) = bisector(p1, p2);
            let (a2, b2) = bisector(p2, p3);
            // b2 − b1 = 0: parallel bisectors, the points are collinear.
            if (b2 - b1).abs() <= 1e-9 * (1.0 + b1.abs().max(b2.abs())) {
                return None;
            }
            let xc = -(a2 - a1) / (b2 - b1);
            (xc, a1 + b1 * xc)
        }
    };
    let c = Point::new(xc, yc);
    let r = p1.distance(c);
    (c.is_finite() && r.is_finite()).then_some((c, r))
}

/// The circles through the point triples (step 1), before any is moved.
pub fn initial_circles(pts: &[Point]) -> Result<Vec<TangentCircle>, TangentError> {
    let n = pts.len();
    if n < 8 || !n.is_multiple_of(4) {
        return Err(TangentError::PointCount(n));
    }
    (0..n / 2)
        .map(|k| {
            let idx = [2 * k, 2 * k + 1, (2 * k + 2) % n];
            let [p1, p2, p3] = idx.map(|i| pts[i]);
            let (center, radius) = circle_through(p1, p2, p3).ok_or(TangentError::Collinear {
                indices: idx,
                points: [p1, p2, p3],
            })?;
            let sign = if (p2 - p1).cross(p3 - p2) > 0.0 {
                1.0
            } else {
                -1.0
            };
            Ok(TangentCircle {
                center,
                radius,
                sign,
            })
        })
        .collect()
}

/// Moves every even (1-based) circle to touch its two fixed neighbours (step 2).
pub fn make_tangent(circles: &mut [TangentCircle], pts: &[Point]) -> Result<(), TangentError> {
    let m = circles.len();
    for j in 0..m / 2 {
        let (i1, i, i2) = (2 * j, 2 * j + 1, (2 * j + 2) % m);
        let (c1, c, c2) = (circles[i1], circles[i], circles[i2]);
        let v = c2.center - c1.center;
        let d = v.hypot();
        let theta = v.atan2();
        // Position of C in the rotated frame: which side of the line of centres it is on.
        let rel = rotate(c.center - c1.center, -theta);
        let sinal = if rel.y < 0.0 { -1.0 } else { 1.0 };
        let contact = |other: &TangentCircle| {
            if other.sign == c.sign {
                (c.radius - other.radius).abs()
            } else {
                c.radius + other.radius
            }
        };
        let (g3, g4) = (contact(&c1), contact(&c2));
        let fail = d < EPS || g3 + g4 < d || (g3 - g4).abs() > d;
        if fail {
            let n = pts.len();
            let points = (2 * i1..=2 * i1 + 4).map(|k| pts[k % n]).collect();
            return Err(TangentError::NoTangent {
                moved: i + 1,
                fixed: [i1 + 1, i2 + 1],
                d,
                g3,
                g4,
                points,
            });
        }
        let dd = (g3 * g3 - g4 * g4 + d * d) / (2.0 * d);
        let e = (g3 * g3 - dd * dd).max(0.0).sqrt() * sinal;
        circles[i].center = c1.center + rotate(Vec2::new(dd, e), theta);
    }
    Ok(())
}

/// Contact point of consecutive circles a → b (on their line of centres); `near` settles
/// concentric circles.
fn contact_point(a: &TangentCircle, b: &TangentCircle, near: Point) -> Point {
    let v = b.center - a.center;
    let d = v.hypot();
    if d < EPS {
        return a.center + (near - a.center).normalize() * a.radius;
    }
    if a.sign == b.sign {
        // Internal: on the ray from the larger centre through the smaller, at the larger radius.
        let (big, small) = if a.radius >= b.radius { (a, b) } else { (b, a) };
        big.center + (small.center - big.center).normalize() * big.radius
    } else {
        a.center + v / d * a.radius
    }
}

/// The seed's method on control points `pts` (counter-clockwise, closed: a repeated first
/// point at the end is dropped). Returns one arc per circle.
pub fn tangent_circles(pts: &[Point]) -> Result<Path, TangentError> {
    let mut pts = pts.to_vec();
    if pts.len() > 1 && pts[0].distance(*pts.last().unwrap()) < 1e-9 {
        pts.pop();
    }
    let mut circles = initial_circles(&pts)?;
    make_tangent(&mut circles, &pts)?;
    let m = circles.len();
    let n = pts.len();
    // Junction k joins circle k and k+1 near the shared point p(2k+2).
    let junction: Vec<Point> = (0..m)
        .map(|k| contact_point(&circles[k], &circles[(k + 1) % m], pts[(2 * k + 2) % n]))
        .collect();
    let mut segments = Vec::with_capacity(m);
    for k in 0..m {
        let c = circles[k];
        let (s, e) = (junction[(k + m - 1) % m], junction[k]);
        let a0 = (s - c.center).atan2();
        let sweep = sweep_between(a0, (e - c.center).atan2(), c.sign as i32);
        // Three neighbouring points of a closed contour span well under half a turn; an arc
        // of more than that met its neighbours' contacts in the reverse order (a loop).
        if sweep.abs() > std::f64::consts::PI {
            return Err(TangentError::Loop {
                circle: k + 1,
                sweep,
                points: (2 * k..=2 * k + 2).map(|i| pts[i % n]).collect(),
            });
        }
        segments.push(Segment::Arc(Arc::new(c.center, c.radius, a0, sweep)));
    }
    Ok(Path::new(segments, true))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn bisector_formulas_with_their_special_cases() {
        let (c, r) = circle_through(
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
            Point::new(-1.0, 0.0),
        )
        .unwrap();
        assert!(c.distance(Point::ORIGIN) < 1e-12 && (r - 1.0).abs() < 1e-12);
        // y2 − y1 = 0 (c.3) and y3 − y2 = 0 (c.4).
        let (c, _) = circle_through(
            Point::new(-1.0, 0.0),
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
        )
        .unwrap();
        assert!(c.distance(Point::ORIGIN) < 1e-12);
        let (c, _) = circle_through(
            Point::new(0.0, -1.0),
            Point::new(-1.0, 0.0),
            Point::new(1.0, 0.0),
        )
        .unwrap();
        assert!(c.distance(Point::ORIGIN) < 1e-12);
        assert!(circle_through(
            Point::new(0.0, 0.0),
            Point::new(1.0, 1.0),
            Point::new(2.0, 2.0)
        )
        .is_none());
    }

    /// Points on an ellipse, counter-clockwise.
    fn ellipse(n: usize, a: f64, b: f64) -> Vec<Point> {
        (0..n)
            .map(|k| {
                // Started off the axis: circles in mirror-image pairs have equal radii and
                // cannot touch internally (one of the seed's tangency failures).
                let t = TAU * k as f64 / n as f64 + 0.1;
                Point::new(a * t.cos(), b * t.sin())
            })
            .collect()
    }

    #[test]
    fn an_ellipse_gives_a_closed_g1_poly_arc_near_the_points() {
        let pts = ellipse(20, 40.0, 110.0);
        let path = tangent_circles(&pts).unwrap();
        assert_eq!(
            path.segments.len(),
            10,
            "10 circles for 20 points, as the seed's example"
        );
        let segs = &path.segments;
        for k in 0..segs.len() {
            let (Segment::Arc(a), Segment::Arc(b)) = (segs[k], segs[(k + 1) % segs.len()]) else {
                panic!()
            };
            assert!(a.end().distance(b.start()) < 1e-9, "C0 at junction {k}");
            assert!(
                a.tangent_at(1.0).dot(b.tangent_at(0.0)) > 1.0 - 1e-9,
                "G1 at junction {k}"
            );
            assert!(a.sweep > 0.0 && a.sweep < std::f64::consts::PI);
        }
        let dev = pts.iter().map(|p| path.distance(*p)).fold(0.0, f64::max);
        assert!(dev < 3.0, "deviation {dev}");
        assert!((path.area() - std::f64::consts::PI * 40.0 * 110.0).abs() < 0.02 * 13823.0);
    }

    #[test]
    fn odd_counts_and_unreachable_neighbours_are_reported_with_points() {
        assert_eq!(
            tangent_circles(&ellipse(10, 1.0, 2.0)),
            Err(TangentError::PointCount(10))
        );
        // Small circles far apart at the ends, joined by flat stretches: a moved circle
        // cannot reach both neighbours (eq. 3.1 has no real root).
        let pts = [
            Point::new(0.0, 0.0),
            Point::new(1.0, -1.0),
            Point::new(2.0, 0.0),
            Point::new(25.0, -1.0),
            Point::new(50.0, 0.0),
            Point::new(51.0, 1.0),
            Point::new(50.0, 2.0),
            Point::new(25.0, 30.0),
        ];
        match tangent_circles(&pts) {
            Err(TangentError::NoTangent {
                moved,
                fixed,
                points,
                g3,
                g4,
                d,
            }) => {
                // Circle 2 could be placed; circle 4, between 3 and 1, cannot.
                assert_eq!((moved, fixed), (4, [3, 1]));
                assert!(g3 + g4 < d || (g3 - g4).abs() > d);
                assert_eq!(points, vec![pts[4], pts[5], pts[6], pts[7], pts[0]]);
            }
            other => panic!("expected no tangent solution, got {other:?}"),
        }
    }
}
