//! Left ↔ right mirroring as the seed does it (eq. 6.1, 6.2): about a vertical line x = xr,
//! x' = 2·xr − x; about a horizontal line y = yr, y' = 2·yr − y. A reflection reverses the
//! turning of every arc (G02 ↔ G03) and the winding of closed paths; the cutter-compensation
//! side (G41 ↔ G42) is the post-processor's to swap.

use crate::drawing::{Drawing, Path, Segment};
use kurbo::Point;

/// The mirror line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MirrorAxis {
    /// The vertical line x = value.
    X(f64),
    /// The horizontal line y = value.
    Y(f64),
}

impl MirrorAxis {
    /// `p` mirrored across the line.
    pub fn point(&self, p: Point) -> Point {
        match *self {
            MirrorAxis::X(xr) => Point::new(2.0 * xr - p.x, p.y),
            MirrorAxis::Y(yr) => Point::new(p.x, 2.0 * yr - p.y),
        }
    }
}

/// The mirror image of a path: arcs turn the other way, a counter-clockwise contour becomes
/// clockwise.
pub fn mirror_path(p: &Path, axis: MirrorAxis) -> Path {
    p.map(
        |q| axis.point(q),
        |a| {
            Segment::Arc(match axis {
                MirrorAxis::X(xr) => a.mirrored_x(xr),
                MirrorAxis::Y(yr) => a.mirrored_y(yr),
            })
        },
    )
}

/// The mirror image of every path of a drawing.
pub fn mirror_drawing(d: &Drawing, axis: MirrorAxis) -> Drawing {
    d.map_paths(|p| mirror_path(p, axis))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::arc::Arc;

    #[test]
    fn mirroring_swaps_arc_direction_and_winding_and_is_an_involution() {
        let p = Path::new(
            vec![
                Segment::line(Point::new(0.0, 0.0), Point::new(10.0, 0.0)),
                Segment::Arc(Arc::from_center(
                    Point::new(10.0, 0.0),
                    Point::new(10.0, 10.0),
                    Point::new(10.0, 5.0),
                    1,
                )),
                Segment::line(Point::new(10.0, 10.0), Point::new(0.0, 0.0)),
            ],
            true,
        );
        let m = mirror_path(&p, MirrorAxis::X(20.0));
        assert!(
            (p.area() + m.area()).abs() < 1e-6,
            "winding reversed, same size"
        );
        let Segment::Arc(a) = m.segments[1] else {
            panic!()
        };
        assert!(!a.is_ccw(), "G03 became G02");
        assert!(a.start().distance(Point::new(30.0, 0.0)) < 1e-9);
        assert_eq!(m.segments[0].start(), Point::new(40.0, 0.0));
        let back = mirror_path(&m, MirrorAxis::X(20.0));
        for (s, t) in p.segments.iter().zip(&back.segments) {
            assert!(s.start().distance(t.start()) < 1e-9 && s.end().distance(t.end()) < 1e-9);
        }
        let y = mirror_path(&p, MirrorAxis::Y(0.0));
        assert!(y.segments[2].start().distance(Point::new(10.0, -10.0)) < 1e-9);
    }
}
