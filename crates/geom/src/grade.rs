//! Grading of sizes (seed 001 §3.3, eq. 3.2–3.5): non-uniform, multiplicative scaling about a
//! chosen reference point, x the width and y the length of the sole:
//!
//!   α(ND) = 1 + (ND − NP)·VL/LP + CTM      x' = xr + (x − xr)·α
//!   β(ND) = 1 + (ND − NP)·VC/CP + CTM      y' = yr + (y − yr)·β
//!
//! so each size adds VL to the width LP and VC to the length CP, and shrinkage CTM (a
//! fraction) enlarges both. The seed scaled about the drawing origin; here the centre is
//! explicit (the seed's gap).

use crate::drawing::{Path, Segment};
use kurbo::{Point, Rect};

/// Millimetres per size in width (VL) and length (VC).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SizeSystem {
    /// The system's name.
    pub name: &'static str,
    /// Width added per size, mm.
    pub width_per_size: f64,
    /// Length added per size, mm.
    pub length_per_size: f64,
}

impl SizeSystem {
    /// Brazilian and French (Paris point, 2/3 cm): VL 1.66, VC 6.66.
    pub const BRAZILIAN: SizeSystem = SizeSystem {
        name: "Brazilian/French",
        width_per_size: 1.66,
        length_per_size: 6.66,
    };
    /// English and American (1/3 inch): VL 2.10, VC 8.46.
    pub const ENGLISH: SizeSystem = SizeSystem {
        name: "English/US",
        width_per_size: 2.10,
        length_per_size: 8.46,
    };

    /// `br`, `fr` → Brazilian/French; `us`, `uk`, `en` → English/US.
    pub fn parse(s: &str) -> Option<SizeSystem> {
        match s.to_ascii_lowercase().as_str() {
            "br" | "fr" | "brazilian" | "french" | "paris" => Some(SizeSystem::BRAZILIAN),
            "us" | "uk" | "en" | "english" | "american" => Some(SizeSystem::ENGLISH),
            _ => None,
        }
    }
}

/// Where the scaling is centred.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Reference {
    /// The drawing origin, as the seed did.
    Origin,
    /// The lower-left corner of the contour's box (heel side when the sole runs along +y).
    BoxMin,
    /// The centre of the contour's box.
    BoxCenter,
    /// The lowest point of the contour (the heel's back on a sole along +y).
    Heel,
    /// A given point.
    At(Point),
}

/// A grading of one base contour.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Grading {
    /// The size system.
    pub system: SizeSystem,
    /// NP, the pattern size.
    pub base_size: f64,
    /// LP, the base width (x extent), mm.
    pub base_width: f64,
    /// CP, the base length (y extent), mm.
    pub base_length: f64,
    /// CTM, shrinkage as a fraction (2 % = 0.02).
    pub shrink: f64,
    /// The fixed point of the scaling.
    pub reference: Point,
}

/// Why a grading cannot be set up.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum GradeError {
    /// The contour has no width or no length.
    #[error("the contour has no width or no length (box {0:?}): nothing to grade")]
    Degenerate(Rect),
    /// Shrinkage outside −0.5..0.5.
    #[error("shrinkage {0} is not a fraction between -0.5 and 0.5")]
    Shrink(f64),
    /// A size whose scale factor is not positive.
    #[error("size {0} gives a non-positive scale factor")]
    Size(f64),
}

impl Grading {
    /// Grading of the contour through `points`, its width and length taken from their box.
    pub fn for_points(
        points: &[Point],
        system: SizeSystem,
        base_size: f64,
        shrink: f64,
        reference: Reference,
    ) -> Result<Grading, GradeError> {
        let bbox = points
            .iter()
            .fold(None, |r: Option<Rect>, p| {
                Some(r.map_or(Rect::from_points(*p, *p), |r| r.union_pt(*p)))
            })
            .unwrap_or(Rect::ZERO);
        if !(bbox.width() > 0.0 && bbox.height() > 0.0 && bbox.is_finite()) {
            return Err(GradeError::Degenerate(bbox));
        }
        if !(-0.5..=0.5).contains(&shrink) {
            return Err(GradeError::Shrink(shrink));
        }
        let reference = match reference {
            Reference::Origin => Point::ORIGIN,
            Reference::BoxMin => Point::new(bbox.x0, bbox.y0),
            Reference::BoxCenter => bbox.center(),
            Reference::Heel => *points
                .iter()
                .min_by(|a, b| a.y.total_cmp(&b.y))
                .expect("non-empty: the box has a size"),
            Reference::At(p) => p,
        };
        Ok(Grading {
            system,
            base_size,
            base_width: bbox.width(),
            base_length: bbox.height(),
            shrink,
            reference,
        })
    }

    /// (α, β) for size `size`.
    pub fn factors(&self, size: f64) -> (f64, f64) {
        let n = size - self.base_size;
        (
            1.0 + n * self.system.width_per_size / self.base_width + self.shrink,
            1.0 + n * self.system.length_per_size / self.base_length + self.shrink,
        )
    }

    /// `p` of the base contour at `size`.
    pub fn point(&self, p: Point, size: f64) -> Point {
        let (a, b) = self.factors(size);
        let r = self.reference;
        Point::new(r.x + (p.x - r.x) * a, r.y + (p.y - r.y) * b)
    }

    /// The control points for `size` (to be re-fitted, as the seed does).
    pub fn points(&self, pts: &[Point], size: f64) -> Result<Vec<Point>, GradeError> {
        let (a, b) = self.factors(size);
        if !(a > 0.0 && b > 0.0) {
            return Err(GradeError::Size(size));
        }
        Ok(pts.iter().map(|&p| self.point(p, size)).collect())
    }

    /// Every size of `sizes` in one call.
    pub fn run(&self, pts: &[Point], sizes: &[f64]) -> Result<Vec<(f64, Vec<Point>)>, GradeError> {
        sizes
            .iter()
            .map(|&s| Ok((s, self.points(pts, s)?)))
            .collect()
    }

    /// A fitted path scaled directly: lines and Béziers map exactly; an arc stays an arc
    /// only when α = β, otherwise it becomes cubic Béziers (an ellipse is no circle).
    pub fn path(&self, p: &Path, size: f64) -> Path {
        let (a, b) = self.factors(size);
        let uniform = (a - b).abs() < 1e-12;
        let mut segments = Vec::new();
        for s in &p.segments {
            match s {
                Segment::Arc(arc) if !uniform => {
                    let k = kurbo::Arc::new(
                        arc.center,
                        (arc.radius, arc.radius),
                        arc.start_angle,
                        arc.sweep,
                        0.0,
                    );
                    let mut from = arc.start();
                    k.to_cubic_beziers(1e-4, |p1, p2, p3| {
                        segments.push(Segment::Cubic(kurbo::CubicBez::new(
                            self.point(from, size),
                            self.point(p1, size),
                            self.point(p2, size),
                            self.point(p3, size),
                        )));
                        from = p3;
                    });
                }
                Segment::Arc(arc) => {
                    let mut g = *arc;
                    g.center = self.point(arc.center, size);
                    g.radius *= a;
                    segments.push(Segment::Arc(g));
                }
                other => segments.push(
                    Path::new(vec![*other], false)
                        .map(|q| self.point(q, size), |_| unreachable!())
                        .segments[0],
                ),
            }
        }
        Path {
            segments,
            ..p.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sole_box() -> Vec<Point> {
        // A rough size-34 outline: 82 mm wide, 228 mm long (the seed's example file).
        vec![
            Point::new(20.0, 0.0),
            Point::new(62.0, 10.0),
            Point::new(82.0, 150.0),
            Point::new(50.0, 228.0),
            Point::new(0.0, 160.0),
        ]
    }

    #[test]
    fn each_size_adds_vl_to_width_and_vc_to_length_plus_shrinkage() {
        let pts = sole_box();
        let g = Grading::for_points(&pts, SizeSystem::BRAZILIAN, 34.0, 0.02, Reference::BoxMin)
            .unwrap();
        let run = g
            .run(&pts, &(33..=44).map(f64::from).collect::<Vec<_>>())
            .unwrap();
        assert_eq!(run.len(), 12);
        for (size, q) in &run {
            let (lo_x, hi_x) = q
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.x), b.max(p.x)));
            let (lo_y, hi_y) = q
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.y), b.max(p.y)));
            let n = size - 34.0;
            assert!(((hi_x - lo_x) - (82.0 + n * 1.66 + 0.02 * 82.0)).abs() < 1e-9);
            assert!(((hi_y - lo_y) - (228.0 + n * 6.66 + 0.02 * 228.0)).abs() < 1e-9);
            assert!(
                lo_x.abs() < 1e-12 && lo_y.abs() < 1e-12,
                "box corner stays put"
            );
        }
        // Size 40, US: α = 1 + 6·2.10/82 + 0.02.
        let us = Grading {
            system: SizeSystem::parse("us").unwrap(),
            ..g
        };
        let (a, b) = us.factors(40.0);
        assert!((a - (1.0 + 6.0 * 2.10 / 82.0 + 0.02)).abs() < 1e-15);
        assert!((b - (1.0 + 6.0 * 8.46 / 228.0 + 0.02)).abs() < 1e-15);
    }

    #[test]
    fn degenerate_contours_and_absurd_sizes_are_errors() {
        let line = [Point::new(0.0, 0.0), Point::new(0.0, 10.0)];
        assert!(
            Grading::for_points(&line, SizeSystem::BRAZILIAN, 34.0, 0.0, Reference::Origin)
                .is_err()
        );
        let g = Grading::for_points(
            &sole_box(),
            SizeSystem::BRAZILIAN,
            34.0,
            0.0,
            Reference::Heel,
        )
        .unwrap();
        assert_eq!(g.reference, Point::new(20.0, 0.0));
        assert!(g.points(&sole_box(), -1000.0).is_err());
    }
}
