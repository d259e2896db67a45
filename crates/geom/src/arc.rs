//! The one arc module: circular arcs in a plane (centre, radius, start angle, signed sweep),
//! how G-code gives them (centre offsets or radius, direction, turns), their length, box,
//! flattening to a chord tolerance, and helices in the XY / YZ / XZ planes.
//!
//! Angles are radians; `sweep > 0` is counter-clockwise. A sweep may exceed 2π (several turns).

use kurbo::{Point, Rect, Vec2};
use std::f64::consts::{FRAC_PI_2, PI, TAU};

/// Most chords one arc is ever cut into: bounds memory whatever the tolerance.
pub const MAX_CHORDS: usize = 1 << 20;

/// The plane of circular motion (G17 / G18 / G19).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Plane {
    /// G17.
    #[default]
    XY,
    /// G19.
    YZ,
    /// G18.
    XZ,
}

impl Plane {
    /// Indices into `[x, y, z]` of (first in-plane axis, second in-plane axis, normal axis),
    /// in LinuxCNC's order: XY → (X, Y, Z), YZ → (Y, Z, X), XZ → (Z, X, Y).
    pub fn axes(self) -> (usize, usize, usize) {
        match self {
            Plane::XY => (0, 1, 2),
            Plane::YZ => (1, 2, 0),
            Plane::XZ => (2, 0, 1),
        }
    }

    /// The in-plane coordinates of a 3-D point.
    pub fn project(self, p: [f64; 3]) -> Point {
        let (a, b, _) = self.axes();
        Point::new(p[a], p[b])
    }
}

/// When an arc given by a centre has end radii that differ, how much is allowed.
/// It is an error only when the difference exceeds `min_abs` and either exceeds `max_abs` or
/// is more than `rel` of the reference radius (the larger one, or the start one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArcTolerance {
    /// A start or end radius below this is a zero-radius arc; also the slack for R arcs.
    pub radius: f64,
    /// Radius difference always allowed, mm.
    pub min_abs: f64,
    /// Radius difference never allowed, mm.
    pub max_abs: f64,
    /// Radius difference allowed as a fraction of the reference radius.
    pub rel: f64,
    /// `rel` is measured against the start radius (grbl) instead of the larger one (LinuxCNC).
    pub rel_to_start: bool,
}

impl ArcTolerance {
    /// LinuxCNC (interp_arc.cc) in mm: 0.00005 in radius, 0.02·√2 mm and 0.1 % spiral.
    pub const LINUXCNC_MM: ArcTolerance = ArcTolerance {
        radius: 0.00127,
        min_abs: 0.02 * std::f64::consts::SQRT_2,
        max_abs: f64::INFINITY,
        rel: 0.001,
        rel_to_start: false,
    };
    /// LinuxCNC for inch programs, converted to mm: 0.002·√2 in spiral.
    pub const LINUXCNC_INCH: ArcTolerance = ArcTolerance {
        radius: 0.00005 * 25.4,
        min_abs: 0.002 * std::f64::consts::SQRT_2 * 25.4,
        max_abs: f64::INFINITY,
        rel: 0.001,
        rel_to_start: false,
    };
    /// grbl 1.1 (gc_execute_line): 0.005 mm always fine, 0.5 mm or 0.1 % of r0 an error.
    pub const GRBL: ArcTolerance = ArcTolerance {
        radius: 1e-9,
        min_abs: 0.005,
        max_abs: 0.5,
        rel: 0.001,
        rel_to_start: true,
    };
}

/// Why an arc cannot be made, with the numbers a message needs.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ArcError {
    /// The start or end radius is (nearly) zero.
    #[error("zero-radius arc: r1={r1:.4} r2={r2:.4} about ({:.4}, {:.4})", center[0], center[1])]
    ZeroRadius {
        /// Start radius, mm.
        r1: f64,
        /// End radius, mm.
        r2: f64,
        /// The centre.
        center: [f64; 2],
    },
    /// The end radius differs from the start radius beyond the tolerance.
    #[error("end radius differs from start radius: r1={r1:.4} r2={r2:.4} about ({:.4}, {:.4})", center[0], center[1])]
    RadiiDiffer {
        /// Start radius, mm.
        r1: f64,
        /// End radius, mm.
        r2: f64,
        /// The centre.
        center: [f64; 2],
    },
    /// An arc by radius whose start and end are the same point.
    #[error("an arc given by its radius needs distinct start and end points")]
    SameEndPoint,
    #[error(
        "radius {radius:.4} too small to reach the end point: half the chord is {half_chord:.4}"
    )]
    /// The radius given is shorter than half the chord.
    RadiusTooSmall {
        /// The radius, mm.
        radius: f64,
        /// Half the chord, mm.
        half_chord: f64,
    },
    /// A number is NaN or infinite.
    #[error("arc numbers are not finite")]
    NotFinite,
}

/// Centre from the start point and a centre given absolutely (in-plane coordinates); checks
/// the end radius against the start radius with `tol`.
pub fn center_from_offsets(
    start: Point,
    end: Point,
    center: Point,
    tol: &ArcTolerance,
) -> Result<Point, ArcError> {
    let r1 = start.distance(center);
    let r2 = end.distance(center);
    if !(r1.is_finite() && r2.is_finite()) {
        return Err(ArcError::NotFinite);
    }
    let c = [center.x, center.y];
    if r1 < tol.radius || r2 < tol.radius {
        return Err(ArcError::ZeroRadius { r1, r2, center: c });
    }
    let abs = (r1 - r2).abs();
    let reference = if tol.rel_to_start { r1 } else { r1.max(r2) };
    if abs > tol.min_abs && (abs > tol.max_abs || abs > tol.rel * reference) {
        return Err(ArcError::RadiiDiffer { r1, r2, center: c });
    }
    Ok(center)
}

/// Centre from a radius: positive `radius` gives the arc of at most a half circle, negative
/// the longer one (NCMS p. 21). The centre lies on the chord's perpendicular bisector at
/// `√(r² − h²)` from the chord midpoint, h = half chord, on the side that makes the arc turn
/// the asked way.
pub fn center_from_radius(
    start: Point,
    end: Point,
    radius: f64,
    clockwise: bool,
    tol: &ArcTolerance,
) -> Result<Point, ArcError> {
    if !(start.is_finite() && end.is_finite() && radius.is_finite()) {
        return Err(ArcError::NotFinite);
    }
    if start == end {
        return Err(ArcError::SameEndPoint);
    }
    let r = radius.abs();
    let mid = start.midpoint(end);
    let mut half = mid.distance(end);
    if half - r > tol.radius {
        return Err(ArcError::RadiusTooSmall {
            radius: r,
            half_chord: half,
        });
    }
    // A chord a hair longer than the diameter is taken as a half circle.
    if half / r > 1.0 - 1e-12 {
        half = r;
    }
    let chord_angle = (end - start).atan2();
    let theta = if clockwise == (radius > 0.0) {
        chord_angle - FRAC_PI_2
    } else {
        chord_angle + FRAC_PI_2
    };
    let offset = r * (half / r).asin().cos();
    Ok(mid + Vec2::from_angle(theta) * offset)
}

/// Signed sweep from angle `a0` to `a1`: `turns > 0` counter-clockwise, `< 0` clockwise; its
/// magnitude counts the partial turn plus full turns (1 = less than one full turn). A zero
/// partial sweep (same start and end angle) is one full turn, as G2/G3 read it.
pub fn sweep_between(a0: f64, a1: f64, turns: i32) -> f64 {
    let extra = turns.unsigned_abs().saturating_sub(1) as f64 * TAU;
    let mut d = if turns >= 0 { a1 - a0 } else { a0 - a1 }.rem_euclid(TAU);
    if d <= 1e-12 {
        d += TAU;
    }
    if turns >= 0 {
        d + extra
    } else {
        -(d + extra)
    }
}

/// Chords needed so that none strays more than `tol` from an arc of `radius` and `sweep`:
/// a chord of angle φ has sagitta r·(1 − cos φ/2) ≤ tol, so φ ≤ 2·acos(1 − tol/r). No chord
/// spans more than a quarter turn, however coarse the tolerance (a chord past a quadrant
/// point would cut the corner of the arc's box).
pub fn chord_count(radius: f64, sweep: f64, tol: f64) -> usize {
    let r = radius.abs();
    let tol = tol.max(1e-9);
    let quarter = FRAC_PI_2;
    if !(r.is_finite() && sweep.is_finite()) || r <= tol {
        return (sweep.abs() / quarter).ceil().clamp(1.0, MAX_CHORDS as f64) as usize;
    }
    let step = (2.0 * (1.0 - tol / r).clamp(-1.0, 1.0).acos()).min(quarter);
    (sweep.abs() / step).ceil().clamp(1.0, MAX_CHORDS as f64) as usize
}

/// A circular arc in a plane.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arc {
    /// Centre.
    pub center: Point,
    /// Radius, mm.
    pub radius: f64,
    /// Angle of the start point about the centre.
    pub start_angle: f64,
    /// Signed sweep, > 0 counter-clockwise.
    pub sweep: f64,
}

impl Arc {
    /// An arc about `center` from `start_angle` sweeping `sweep` (radians, > 0
    /// counter-clockwise).
    pub fn new(center: Point, radius: f64, start_angle: f64, sweep: f64) -> Arc {
        Arc {
            center,
            radius,
            start_angle,
            sweep,
        }
    }

    /// The arc from `start` about `center` to (the angle of) `end`, with G-code turns
    /// (> 0 counter-clockwise). The radius is the start radius.
    pub fn from_center(start: Point, end: Point, center: Point, turns: i32) -> Arc {
        let a0 = (start - center).atan2();
        let a1 = (end - center).atan2();
        Arc::new(
            center,
            start.distance(center),
            a0,
            sweep_between(a0, a1, turns),
        )
    }

    /// Arc from `start` to `end` that turns `ccw` or not, centre chosen as G2/G3 with R do.
    pub fn from_radius(
        start: Point,
        end: Point,
        radius: f64,
        ccw: bool,
        tol: &ArcTolerance,
    ) -> Result<Arc, ArcError> {
        let c = center_from_radius(start, end, radius, !ccw, tol)?;
        Ok(Arc::from_center(start, end, c, if ccw { 1 } else { -1 }))
    }

    /// DXF bulge: tan(sweep/4), positive counter-clockwise. None for a zero bulge (a line)
    /// or a zero-length chord.
    pub fn from_bulge(start: Point, end: Point, bulge: f64) -> Option<Arc> {
        let chord = end - start;
        let len = chord.hypot();
        if bulge.abs() < 1e-12 || len < 1e-12 || !bulge.is_finite() {
            return None;
        }
        let sweep = 4.0 * bulge.atan();
        // Radius from the chord: c/2 = r·sin(θ/2); the centre is on the left of the chord
        // for a counter-clockwise arc, at distance (c/2)/tan(θ/2) from its midpoint.
        let half = len / 2.0;
        let d = half / (sweep / 2.0).tan();
        let left = Vec2::new(-chord.y, chord.x) / len;
        let center = start.midpoint(end) + left * d;
        Some(Arc::new(
            center,
            (half / (sweep / 2.0).sin()).abs(),
            (start - center).atan2(),
            sweep,
        ))
    }

    /// The arc from `p1` through `p2` to `p3`; None if the points are (nearly) collinear.
    pub fn through(p1: Point, p2: Point, p3: Point) -> Option<Arc> {
        let c = circumcenter(p1, p2, p3)?;
        let a1 = (p1 - c).atan2();
        let a2 = (p2 - c).atan2();
        let a3 = (p3 - c).atan2();
        let ccw = (p2 - p1).cross(p3 - p2) > 0.0;
        let turns = if ccw { 1 } else { -1 };
        // p2 lies between p1 and p3 in the direction of travel.
        let s13 = sweep_between(a1, a3, turns);
        let s12 = sweep_between(a1, a2, turns);
        debug_assert!(s12.abs() <= s13.abs() + 1e-9);
        Some(Arc::new(c, p1.distance(c), a1, s13))
    }

    /// A whole circle starting at angle 0, counter-clockwise.
    pub fn circle(center: Point, radius: f64) -> Arc {
        Arc::new(center, radius, 0.0, TAU)
    }

    /// Turns counter-clockwise.
    pub fn is_ccw(&self) -> bool {
        self.sweep > 0.0
    }

    /// Angle of the end point, radians.
    pub fn end_angle(&self) -> f64 {
        self.start_angle + self.sweep
    }

    /// The point at fraction `t` ∈ [0, 1] of the sweep.
    pub fn point_at(&self, t: f64) -> Point {
        self.center + Vec2::from_angle(self.start_angle + self.sweep * t) * self.radius
    }

    /// Start point.
    pub fn start(&self) -> Point {
        self.point_at(0.0)
    }

    /// End point.
    pub fn end(&self) -> Point {
        self.point_at(1.0)
    }

    /// Point half-way along the sweep.
    pub fn mid(&self) -> Point {
        self.point_at(0.5)
    }

    /// G-code turns: the sign of the sweep, magnitude = full turns + 1.
    pub fn turns(&self) -> i32 {
        let full = ((self.sweep.abs() - 1e-9) / TAU).floor().max(0.0) as i32;
        if self.sweep >= 0.0 {
            full + 1
        } else {
            -(full + 1)
        }
    }

    /// Length along the arc, mm.
    pub fn length(&self) -> f64 {
        self.radius * self.sweep.abs()
    }

    /// Unit tangent in the direction of travel at fraction `t`.
    pub fn tangent_at(&self, t: f64) -> Vec2 {
        let a = self.start_angle + self.sweep * t;
        let radial = Vec2::from_angle(a);
        let left = Vec2::new(-radial.y, radial.x);
        if self.sweep >= 0.0 {
            left
        } else {
            -left
        }
    }

    /// The same arc run the other way.
    pub fn reversed(&self) -> Arc {
        Arc::new(self.center, self.radius, self.end_angle(), -self.sweep)
    }

    /// Whether angle `a` lies within the sweep (with `slack` radians on each end).
    pub fn contains_angle(&self, a: f64, slack: f64) -> bool {
        if self.sweep.abs() >= TAU - slack {
            return true;
        }
        let off = if self.sweep >= 0.0 {
            (a - self.start_angle).rem_euclid(TAU)
        } else {
            (self.start_angle - a).rem_euclid(TAU)
        };
        off <= self.sweep.abs() + slack || off >= TAU - slack
    }

    /// Distance from `p` to the arc.
    pub fn distance(&self, p: Point) -> f64 {
        let v = p - self.center;
        if v.hypot() > 0.0 && self.contains_angle(v.atan2(), 0.0) {
            (v.hypot() - self.radius).abs()
        } else {
            p.distance(self.start()).min(p.distance(self.end()))
        }
    }

    /// Points along the arc, both ends included, no chord further than `tol` from it.
    pub fn flatten(&self, tol: f64) -> Vec<Point> {
        let n = chord_count(self.radius, self.sweep, tol);
        (0..=n)
            .map(|k| self.point_at(k as f64 / n as f64))
            .collect()
    }

    /// Box of the arc: its ends plus every quadrant point the sweep passes.
    pub fn bounding_box(&self) -> Rect {
        let mut r = Rect::from_points(self.start(), self.end());
        for q in 0..4 {
            let a = q as f64 * FRAC_PI_2;
            if self.contains_angle(a, 0.0) {
                r = r.union_pt(self.center + Vec2::from_angle(a) * self.radius);
            }
        }
        r
    }

    /// Mirror image about the vertical line x = `xr` (x' = 2·xr − x): the direction flips.
    pub fn mirrored_x(&self, xr: f64) -> Arc {
        Arc::new(
            Point::new(2.0 * xr - self.center.x, self.center.y),
            self.radius,
            PI - self.start_angle,
            -self.sweep,
        )
    }

    /// Mirror image about the horizontal line y = `yr` (y' = 2·yr − y).
    pub fn mirrored_y(&self, yr: f64) -> Arc {
        Arc::new(
            Point::new(self.center.x, 2.0 * yr - self.center.y),
            self.radius,
            -self.start_angle,
            -self.sweep,
        )
    }
}

/// Centre of the circle through three points; None if they are (nearly) collinear.
pub fn circumcenter(p1: Point, p2: Point, p3: Point) -> Option<Point> {
    let b = p2 - p1;
    let c = p3 - p1;
    let d = 2.0 * b.cross(c);
    let scale = b.hypot2().max(c.hypot2());
    if d.abs() <= 1e-12 * scale || !d.is_finite() {
        return None;
    }
    let ux = (c.y * b.hypot2() - b.y * c.hypot2()) / d;
    let uy = (b.x * c.hypot2() - c.x * b.hypot2()) / d;
    Some(p1 + Vec2::new(ux, uy))
}

/// An arc or helix of a G-code program: an arc in `plane` with the normal axis moving
/// linearly from `axial.0` to `axial.1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Helix {
    /// Plane of the arc.
    pub plane: Plane,
    /// The arc in the plane's own coordinates.
    pub arc: Arc,
    /// The normal axis at the start and at the end, mm.
    pub axial: (f64, f64),
}

impl Helix {
    /// From the canonical arc feed: start and end positions (x, y, z), the centre as
    /// in-plane coordinates, and G-code turns (> 0 counter-clockwise).
    pub fn new(plane: Plane, from: [f64; 3], to: [f64; 3], center: [f64; 2], turns: i32) -> Helix {
        let (_, _, n) = plane.axes();
        let arc = Arc::from_center(
            plane.project(from),
            plane.project(to),
            Point::new(center[0], center[1]),
            turns,
        );
        Helix {
            plane,
            arc,
            axial: (from[n], to[n]),
        }
    }

    /// The 3-D point at fraction `t`. The radius runs linearly from the start radius to the
    /// end radius is not modelled: the start radius is kept (G-code's spiral slack is small).
    pub fn point_at(&self, t: f64) -> [f64; 3] {
        let (a, b, n) = self.plane.axes();
        let p = self.arc.point_at(t);
        let mut out = [0.0; 3];
        out[a] = p.x;
        out[b] = p.y;
        out[n] = self.axial.0 + (self.axial.1 - self.axial.0) * t;
        out
    }

    /// The 3-D point at fraction `t` of the spiral that starts like this helix and whose
    /// radius runs linearly to `end_radius`: a G-code arc whose end radius differs from its
    /// start one within the interpreter's tolerance still ends exactly at its end point.
    pub fn spiral_point_at(&self, t: f64, end_radius: f64) -> [f64; 3] {
        let (a, b, n) = self.plane.axes();
        let r = self.arc.radius + (end_radius - self.arc.radius) * t;
        let p = self.arc.center + Vec2::from_angle(self.arc.start_angle + self.arc.sweep * t) * r;
        let mut out = [0.0; 3];
        out[a] = p.x;
        out[b] = p.y;
        out[n] = self.axial.0 + (self.axial.1 - self.axial.0) * t;
        out
    }

    /// Length of the helix: √(planar² + axial²).
    pub fn length(&self) -> f64 {
        self.arc.length().hypot(self.axial.1 - self.axial.0)
    }

    /// Chord end points (the start excluded, the end included), none further than `tol`
    /// from the arc.
    pub fn chords(&self, tol: f64) -> Vec<[f64; 3]> {
        let n = chord_count(self.arc.radius, self.arc.sweep, tol);
        (1..=n)
            .map(|k| self.point_at(k as f64 / n as f64))
            .collect()
    }

    /// Box swept in 3-D: (min, max).
    pub fn extents(&self) -> ([f64; 3], [f64; 3]) {
        let r = self.arc.bounding_box();
        let (a, b, n) = self.plane.axes();
        let mut lo = [0.0; 3];
        let mut hi = [0.0; 3];
        lo[a] = r.x0;
        hi[a] = r.x1;
        lo[b] = r.y0;
        hi[b] = r.y1;
        lo[n] = self.axial.0.min(self.axial.1);
        hi[n] = self.axial.0.max(self.axial.1);
        (lo, hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Point, b: Point) -> bool {
        a.distance(b) < 1e-9
    }

    #[test]
    fn quarter_arc_length_box_and_ends() {
        let a = Arc::from_center(
            Point::new(10.0, 0.0),
            Point::new(0.0, 10.0),
            Point::ORIGIN,
            1,
        );
        assert!((a.length() - 5.0 * PI).abs() < 1e-12);
        assert!(close(a.end(), Point::new(0.0, 10.0)));
        let b = a.bounding_box();
        assert!((b.x0 - 0.0).abs() < 1e-9 && (b.y1 - 10.0).abs() < 1e-9);
        // Clockwise the long way: three quarters, through the negative quadrants.
        let cw = Arc::from_center(
            Point::new(10.0, 0.0),
            Point::new(0.0, 10.0),
            Point::ORIGIN,
            -1,
        );
        assert!((cw.sweep + 1.5 * PI).abs() < 1e-12);
        assert!((cw.bounding_box().y0 + 10.0).abs() < 1e-9);
    }

    #[test]
    fn same_start_and_end_is_a_full_turn_and_turns_add() {
        let p = Point::new(5.0, 0.0);
        let a = Arc::from_center(p, p, Point::ORIGIN, 3);
        assert!((a.sweep - 3.0 * TAU).abs() < 1e-12);
        assert_eq!(a.turns(), 3);
        assert_eq!(a.reversed().turns(), -3);
    }

    #[test]
    fn radius_form_short_and_long_and_too_small() {
        let t = ArcTolerance::LINUXCNC_MM;
        let s = Point::new(0.0, 0.0);
        let e = Point::new(10.0, 0.0);
        let short = Arc::from_radius(s, e, 10.0, false, &t).unwrap();
        let long = Arc::from_radius(s, e, -10.0, false, &t).unwrap();
        assert!(short.sweep.abs() < PI && long.sweep.abs() > PI);
        assert!(short.sweep < 0.0 && long.sweep < 0.0);
        assert!(close(short.end(), e) && close(long.end(), e));
        assert!(matches!(
            Arc::from_radius(s, e, 4.0, true, &t),
            Err(ArcError::RadiusTooSmall { .. })
        ));
    }

    #[test]
    fn spiral_tolerances_of_linuxcnc_and_grbl_differ() {
        let s = Point::new(10.0, 0.0);
        // End radius 10.02: 0.02 mm off, 0.2 % of 10 — LinuxCNC allows it (< 0.028 mm).
        let e = Point::new(0.0, 10.02);
        assert!(center_from_offsets(s, e, Point::ORIGIN, &ArcTolerance::LINUXCNC_MM).is_ok());
        // grbl: 0.02 > 0.005 and 0.02 > 0.1 % of 10 → error.
        assert!(center_from_offsets(s, e, Point::ORIGIN, &ArcTolerance::GRBL).is_err());
    }

    #[test]
    fn flattening_keeps_every_chord_within_tolerance() {
        let a = Arc::new(Point::new(3.0, -2.0), 25.0, 0.3, -4.0);
        for tol in [0.1, 0.01, 0.001] {
            let pts = a.flatten(tol);
            for w in pts.windows(2) {
                let mid = w[0].midpoint(w[1]);
                let sag = a.radius - mid.distance(a.center);
                assert!(sag <= tol * 1.000001, "sagitta {sag} > {tol}");
            }
            assert!(close(pts[0], a.start()) && close(*pts.last().unwrap(), a.end()));
        }
        assert!(chord_count(1e9, 1.0, 1e-300) <= MAX_CHORDS);
    }

    #[test]
    fn bulge_half_circle_and_three_point_arc() {
        let a = Arc::from_bulge(Point::new(0.0, 0.0), Point::new(2.0, 0.0), 1.0).unwrap();
        assert!(close(a.center, Point::new(1.0, 0.0)));
        assert!((a.sweep - PI).abs() < 1e-12);
        // Counter-clockwise from (0,0) to (2,0) about (1,0) passes below: (1,-1).
        assert!(close(a.mid(), Point::new(1.0, -1.0)));
        let t = Arc::through(
            Point::new(1.0, 0.0),
            Point::new(0.0, 1.0),
            Point::new(-1.0, 0.0),
        )
        .unwrap();
        assert!(close(t.center, Point::ORIGIN) && (t.sweep - PI).abs() < 1e-12);
        assert!(Arc::through(Point::ORIGIN, Point::new(1.0, 1.0), Point::new(2.0, 2.0)).is_none());
    }

    #[test]
    fn mirror_swaps_direction_and_keeps_ends_mirrored() {
        let a = Arc::from_center(
            Point::new(10.0, 0.0),
            Point::new(0.0, 10.0),
            Point::ORIGIN,
            1,
        );
        let m = a.mirrored_x(5.0);
        assert!(!m.is_ccw());
        assert!(close(m.start(), Point::new(0.0, 0.0)));
        assert!(close(m.end(), Point::new(10.0, 10.0)));
        let my = a.mirrored_y(1.0);
        assert!(close(my.end(), Point::new(0.0, -8.0)) && !my.is_ccw());
    }

    #[test]
    fn helix_in_xz_plane_has_axial_y_and_length() {
        // XZ plane: first axis Z, second X, normal Y.
        let h = Helix::new(Plane::XZ, [10.0, 0.0, 0.0], [10.0, 4.0, 0.0], [0.0, 0.0], 2);
        assert!((h.arc.sweep - 2.0 * TAU).abs() < 1e-9);
        let l = (2.0 * TAU * 10.0f64).hypot(4.0);
        assert!((h.length() - l).abs() < 1e-9);
        let last = *h.chords(0.01).last().unwrap();
        assert!((last[1] - 4.0).abs() < 1e-12 && (last[0] - 10.0).abs() < 1e-9);
        let (lo, hi) = h.extents();
        assert!((lo[2] + 10.0).abs() < 1e-9 && (hi[0] - 10.0).abs() < 1e-9);
    }

    #[test]
    fn spiral_ends_on_its_end_radius_and_chords_stay_under_a_quarter_turn() {
        let h = Helix::new(Plane::XY, [10.0, 0.0, 0.0], [0.0, 10.5, 2.0], [0.0, 0.0], 1);
        let end = h.spiral_point_at(1.0, 10.5);
        assert!(end[0].abs() < 1e-9 && (end[1] - 10.5).abs() < 1e-9 && end[2] == 2.0);
        assert_eq!(h.spiral_point_at(0.5, 10.0), h.point_at(0.5));
        // A tolerance as coarse as the radius still gives a chord per quadrant.
        assert_eq!(chord_count(1.0, TAU, 0.99), 4);
    }
}
