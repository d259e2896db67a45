//! Importers: pictures and raw height fields become a [`Heightmap`], the one representation
//! of relief that the CAM consumes.
//!
//! ```
//! use oficina_io::svg_from_bytes;
//!
//! // A 20 × 10 mm rectangle and a text element, which must be converted to paths first.
//! let svg = br#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="50mm"
//!     viewBox="0 0 100 50">
//!   <rect x="10" y="10" width="20" height="10"/>
//!   <text x="5" y="40">hi</text>
//! </svg>"#;
//! let imported = svg_from_bytes(svg, "box.svg").unwrap();
//! let rect = imported.drawing.paths().next().unwrap();
//! assert!(rect.closed);
//! assert!((rect.area().abs() - 200.0).abs() < 1e-3, "{}", rect.area()); // usvg works in f32
//! assert_eq!(imported.unsupported.total(), 1); // the text
//! ```

mod closure;
mod dxf;
mod heightmap;
mod hpgl;
mod image_in;
mod import;
mod points;
mod raw;
mod seed001;
mod svg;

pub use closure::{close_and_chain, Closure, OpenLayer, JOIN_TOL, MAX_JOIN_TOL};
pub use dxf::{dxf_from_bytes, read_dxf, DxfOptions, DxfRead, DxfText};
pub use heightmap::Heightmap;
pub use hpgl::{hpgl_from_bytes, is_hpgl_file, load_hpgl, looks_like_hpgl, Hpgl, HPGL_EXTENSIONS};
pub use image_in::{
    load_image, load_image_bytes, luminance_to_heights, DepthMapping, ImageError, Scale,
};
pub use import::{
    load_drawing, load_drawing_with, ImportError, Imported, Unsupported, MAX_DRAWING_BYTES,
};
/// The geometry crate the drawings are made of, for callers that only depend on `io`.
pub use oficina_geom as geom;
pub use points::{load_points, parse_points, write_points_csv};
pub use raw::{load_raw_f32, raw_f32_from_bytes, RawError};
pub use seed001::{parse_seed001, SeedEntity, SeedFile};
pub use svg::svg_from_bytes;
