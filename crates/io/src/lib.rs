//! Importers: pictures and raw height fields become a [`Heightmap`], the one representation
//! of relief that the CAM consumes.
//!
//! ```
//! use oficina_io::svg_from_bytes;
//!
//! // A 20 × 10 mm rectangle and a text element, drawn with the single-stroke font.
//! let svg = br#"<svg xmlns="http://www.w3.org/2000/svg" width="100mm" height="50mm"
//!     viewBox="0 0 100 50">
//!   <rect x="10" y="10" width="20" height="10"/>
//!   <text x="5" y="40">hi</text>
//! </svg>"#;
//! let imported = svg_from_bytes(svg, "box.svg").unwrap();
//! let rect = imported.drawing.paths().next().unwrap();
//! assert!(rect.closed);
//! assert!((rect.area().abs() - 200.0).abs() < 1e-3, "{}", rect.area()); // usvg works in f32
//! assert!(imported.unsupported.is_empty());
//! // "hi" in single strokes (h: 2, i: the stem and its dot), on the baseline y = 50 − 40 mm.
//! let hi: Vec<_> = imported.drawing.paths().skip(1).collect();
//! assert_eq!(hi.len(), 4);
//! let low = hi.iter().filter_map(|p| p.bounding_box()).map(|b| b.y0).fold(f64::MAX, f64::min);
//! assert!((low - 10.0).abs() < 1e-3, "{low}");
//! ```

mod closure;
mod design;
mod dxf;
mod heightmap;
mod hpgl;
mod image_in;
mod import;
mod mesh;
mod points;
mod pubfile;
mod raw;
mod seed001;
mod svg;
mod svg_text;

pub use closure::{close_and_chain, Closure, OpenLayer, JOIN_TOL, MAX_JOIN_TOL};
pub use design::{
    design_from_bytes, design_from_paths, design_from_seed001, design_to_dxf, design_to_seed001,
    design_to_string, design_to_svg, entity_paths, parse_design, path_to_polyline, Design,
    DesignLayer, Entity, Shape, DESIGN_FORMAT, DESIGN_VERSION,
};
pub use dxf::{dxf_from_bytes, read_dxf, DxfOptions, DxfRead, DxfText};
pub use heightmap::Heightmap;
pub use hpgl::{hpgl_from_bytes, is_hpgl_file, load_hpgl, looks_like_hpgl, Hpgl, HPGL_EXTENSIONS};
pub use image_in::{
    load_image, load_image_bytes, luminance_to_heights, DepthMapping, ImageError, Scale,
};
pub use import::{
    load_drawing, load_drawing_with, ImportError, Imported, Unsupported, MAX_DRAWING_BYTES,
};
pub use mesh::{load_mesh, mesh_from_bytes, Mesh, MeshError, BYTES_PER_TRIANGLE};
/// The geometry crate the drawings are made of, for callers that only depend on `io`.
pub use oficina_geom as geom;
pub use points::{load_points, parse_points, write_points_csv};
pub use pubfile::{pub_from_str, PUB_COLOURS, PUB_MAX_LEVEL, PUB_SATIN_WIDTH};
pub use raw::{load_raw_f32, raw_f32_from_bytes, RawError};
pub use seed001::{parse_seed001, path_entities, SeedEntity, SeedFile};
pub use svg::{read_svg, svg_from_bytes, SvgOptions};
