//! Fitting digitised contours: the seed's tangent circles, biarcs, clamped cubic B-splines,
//! the seed's Bézier and local interpolation, with a report of blocks and deviation.

mod biarc;
mod prepare;
mod report;
mod spline;
mod tangent;

pub use biarc::{biarc, fit_biarcs};
pub use prepare::{denoise, resample_closed, signed_area, simplify_closed, simplify_open};
pub use report::{fit_all, fit_method, max_deviation, Fit, FitError, Method};
pub use spline::{bezier_seed, bspline_clamped, interpolate_local, merge_collinear};
pub use tangent::{
    circle_through, initial_circles, make_tangent, tangent_circles, TangentCircle, TangentError,
};
