//! Geometry: `Drawing` (layers of lines, arcs and cubic Béziers), the one arc module, offsets
//! and booleans, curve fitting of digitised contours, grading of sizes and mirroring.

mod arc;
mod drawing;
pub mod fit;
mod grade;
mod mirror;
mod offset;
mod polygon;

pub use arc::{
    center_from_offsets, center_from_radius, chord_count, circumcenter, sweep_between, Arc,
    ArcError, ArcTolerance, Helix, Plane, MAX_CHORDS,
};
pub use drawing::{to_ring, Color, Drawing, Layer, Path, Segment, SourceRef, Style};
pub use grade::{GradeError, Grading, Reference, SizeSystem};
pub use kurbo;
pub use kurbo::{Point, Rect, Vec2};
pub use mirror::{mirror_drawing, mirror_path, MirrorAxis};
pub use offset::{offset_areas, oriented, Area};
pub use polygon::{
    boolean, boolean_fixed, offset_regions, offset_rings, offset_steps, ring_area, simplify,
    total_area, BoolOp, Fill, Join, PolygonError, Region, Ring,
};
