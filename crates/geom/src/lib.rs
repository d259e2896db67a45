//! Geometry: `Drawing` (layers of lines, arcs and cubic Béziers), the one arc module, offsets
//! and booleans, curve fitting of digitised contours, grading of sizes and mirroring, and the
//! single-stroke font ([`text`]).
//!
//! ```
//! use oficina_geom::{offset_regions, Arc, Join, Point, Region};
//! use std::f64::consts::FRAC_PI_2;
//!
//! // A quarter circle of radius 10 mm: 5π mm long, ending on the Y axis.
//! let arc = Arc::new(Point::ZERO, 10.0, 0.0, FRAC_PI_2);
//! assert!((arc.length() - 5.0 * std::f64::consts::PI).abs() < 1e-12);
//! assert!(arc.end().distance(Point::new(0.0, 10.0)) < 1e-12);
//!
//! // A 10 mm square grown by 1 mm with sharp corners is the 12 mm square.
//! let square = vec![[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]];
//! let region = Region { outer: square, holes: vec![] };
//! let grown = offset_regions(&[region], 1.0, Join::Miter { min_angle: 0.1 }).unwrap();
//! assert_eq!(grown.len(), 1);
//! assert!((grown[0].area() - 144.0).abs() < 1e-6, "{}", grown[0].area());
//! ```

mod arc;
mod circle;
mod drawing;
pub mod fit;
mod grade;
mod mirror;
mod offset;
mod polygon;
pub mod text;

pub use arc::{
    center_from_offsets, center_from_radius, chord_count, circumcenter, sweep_between, Arc,
    ArcError, ArcTolerance, Helix, Plane, MAX_CHORDS,
};
pub use circle::CircleFit;
pub use drawing::{to_ring, Color, Drawing, Layer, Path, Segment, SourceRef, Style};
pub use grade::{GradeError, Grading, Reference, SizeSystem};
pub use kurbo;
pub use kurbo::{Point, Rect, Vec2};
pub use mirror::{mirror_drawing, mirror_path, MirrorAxis};
pub use offset::{offset_areas, oriented, Area};
pub use polygon::{
    boolean, boolean_fixed, bounds, offset_regions, offset_rings, offset_steps, ring_area,
    simplify, total_area, BoolOp, Fill, Join, PolygonError, Region, Ring,
};
pub use text::text_strokes;
