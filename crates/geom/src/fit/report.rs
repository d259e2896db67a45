//! One call fits a digitised contour by every method and reports, for each, the NC blocks
//! it makes (lines and arcs) and its largest distance from the digitised points.

use super::biarc::fit_biarcs;
use super::prepare::{denoise, resample_closed};
use super::spline::{bezier_seed, bspline_clamped, interpolate_local, merge_collinear};
use super::tangent::{tangent_circles, TangentError};
use crate::drawing::Path;
use kurbo::Point;
use std::fmt;

/// A fitting method.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Method {
    /// Seed 001's tangent circles.
    TangentCircles,
    /// Biarcs.
    Biarc,
    /// Clamped cubic B-spline.
    BSpline,
    /// The seed's Bézier.
    Bezier,
    /// Local cubic interpolation.
    Interpolation,
}

impl Method {
    /// Every method.
    pub const ALL: [Method; 5] = [
        Method::TangentCircles,
        Method::Biarc,
        Method::BSpline,
        Method::Bezier,
        Method::Interpolation,
    ];

    /// The method's name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::TangentCircles => "tangent circles",
            Method::Biarc => "biarc",
            Method::BSpline => "B-spline (clamped cubic)",
            Method::Bezier => "Bezier (seed)",
            Method::Interpolation => "interpolation (local cubic)",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A fitted contour.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// The method used.
    pub method: Method,
    /// Lines and arcs (the polyline methods are flattened to the tolerance).
    pub path: Path,
    /// Segments of `path`: one NC block each.
    pub blocks: usize,
    /// Largest distance from a digitised point to the path, mm.
    pub max_deviation: f64,
    /// Control points the method was given.
    pub control_points: usize,
}

/// Why a contour could not be fitted.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum FitError {
    /// Fewer than 8 distinct points.
    #[error("a contour needs at least 8 distinct points, got {0}")]
    TooFewPoints(usize),
    /// The tangent-circle method failed.
    #[error("tangent circles: {0}")]
    Tangent(#[from] TangentError),
}

/// Largest distance from `points` to `path`.
pub fn max_deviation(points: &[Point], path: &Path) -> f64 {
    points.iter().map(|p| path.distance(*p)).fold(0.0, f64::max)
}

/// Samples per knot span before flattening: enough for any chord tolerance used here.
const PER_SPAN: usize = 32;

/// The dense curve of a polyline method as a path of lines: flattened to `tol`/2 (Douglas–
/// Peucker on the dense samples), then the seed's 0.004 rad collinear merge.
fn polyline_path(dense: &[Point], tol: f64) -> Path {
    let flat = super::prepare::simplify_open(dense, tol / 2.0);
    Path::polyline(&merge_collinear(&flat, 0.004), true)
}

/// Fits `points` (a closed digitised contour, any orientation) by `method` within `tol`.
pub fn fit_method(method: Method, points: &[Point], tol: f64) -> Result<Fit, FitError> {
    let pts = denoise(points, 1e-6, tol / 4.0);
    if pts.len() < 8 {
        return Err(FitError::TooFewPoints(pts.len()));
    }
    let (path, control) = match method {
        Method::TangentCircles => fit_tangent_circles(&pts, points, tol)?,
        // Denoising moved points by up to tol/4: the biarcs get the rest.
        Method::Biarc => (fit_biarcs(&pts, tol * 0.75), pts.len()),
        Method::BSpline => (
            polyline_path(&bspline_clamped(&pts, PER_SPAN), tol),
            pts.len(),
        ),
        Method::Interpolation => (
            polyline_path(&interpolate_local(&pts, PER_SPAN), tol),
            pts.len(),
        ),
        Method::Bezier => {
            let b = bezier_seed(&pts);
            (polyline_path(&b.flatten(tol / 8.0), tol), pts.len())
        }
    };
    Ok(Fit {
        method,
        blocks: path.segments.len(),
        max_deviation: max_deviation(points, &path),
        path,
        control_points: control,
    })
}

/// Tangent circles on 4·k control points taken evenly round the contour (k = 2, 3, …), the
/// first start of the four tried that fits: the fewest circles within `tol`, else the
/// closest fit found. The seed's user picked the points by hand; this picks them by length.
fn fit_tangent_circles(pts: &[Point], raw: &[Point], tol: f64) -> Result<(Path, usize), FitError> {
    let mut best: Option<(f64, Path, usize)> = None;
    let mut last_err = None;
    let max_k = (pts.len() / 4).clamp(2, 200);
    for k in 2..=max_k {
        for shift in 0..4 {
            let mut ctrl = resample_closed(pts, 4 * k * 4);
            ctrl.rotate_left(shift);
            let ctrl: Vec<Point> = ctrl.into_iter().step_by(4).collect();
            match tangent_circles(&ctrl) {
                // A simple closed contour turns once; anything else has a loop somewhere.
                Ok(path) if (turning(&path) - std::f64::consts::TAU).abs() > 0.1 => {}
                Ok(path) => {
                    let dev = max_deviation(raw, &path);
                    if dev <= tol {
                        return Ok((path, ctrl.len()));
                    }
                    if best.as_ref().is_none_or(|b| dev < b.0) {
                        best = Some((dev, path, ctrl.len()));
                    }
                }
                Err(e) => last_err = Some(e),
            }
        }
    }
    match (best, last_err) {
        (Some((_, p, n)), _) => Ok((p, n)),
        (None, Some(e)) => Err(e.into()),
        (None, None) => Err(FitError::TooFewPoints(pts.len())),
    }
}

/// Total turning of a path of arcs and lines joined smoothly: the sum of the arc sweeps.
fn turning(p: &Path) -> f64 {
    p.segments
        .iter()
        .map(|s| match s {
            crate::drawing::Segment::Arc(a) => a.sweep,
            _ => 0.0,
        })
        .sum()
}

/// Every method on the same contour.
pub fn fit_all(points: &[Point], tol: f64) -> Vec<(Method, Result<Fit, FitError>)> {
    Method::ALL
        .iter()
        .map(|&m| (m, fit_method(m, points, tol)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::TAU;

    #[test]
    fn every_method_fits_an_ellipse_and_arcs_need_fewest_blocks() {
        let pts: Vec<Point> = (0..120)
            .map(|k| {
                let t = TAU * k as f64 / 120.0;
                Point::new(40.0 * t.cos(), 110.0 * t.sin())
            })
            .collect();
        let all = fit_all(&pts, 0.1);
        let get = |m| {
            all.iter()
                .find(|(x, _)| *x == m)
                .unwrap()
                .1
                .as_ref()
                .unwrap()
        };
        let biarc = get(Method::Biarc);
        assert!(biarc.max_deviation <= 0.1 + 1e-9);
        let interp = get(Method::Interpolation);
        assert!(
            interp.max_deviation <= 0.1,
            "passes through the points: {}",
            interp.max_deviation
        );
        assert!(
            biarc.blocks * 2 < interp.blocks,
            "{} vs {}",
            biarc.blocks,
            interp.blocks
        );
        let tc = get(Method::TangentCircles);
        assert!(
            tc.blocks < interp.blocks,
            "{} vs {}",
            tc.blocks,
            interp.blocks
        );
        // Each reported deviation is re-measured independently by sampling the path.
        for (_, f) in &all {
            let f = f.as_ref().unwrap();
            let dense = f.path.flatten(1e-4);
            let worst = pts
                .iter()
                .map(|p| {
                    dense
                        .iter()
                        .map(|q| q.distance(*p))
                        .fold(f64::MAX, f64::min)
                })
                .fold(0.0, f64::max);
            // Distance to vertices only overestimates, by at most half the spacing.
            assert!(
                worst + 1e-9 >= f.max_deviation - 1e-6,
                "{}: {worst} < {}",
                f.method,
                f.max_deviation
            );
        }
    }
}
