//! Importers: pictures and raw height fields become a [`Heightmap`], the one representation
//! of relief that the CAM consumes.

pub mod heightmap;
pub mod image_in;
pub mod raw;

pub use heightmap::Heightmap;
pub use image_in::{load_image, load_image_bytes, DepthMapping, ImageError, Scale};
pub use raw::{load_raw_f32, raw_f32_from_bytes, RawError};

pub mod dxf;
pub mod import;
pub mod points;
pub mod seed001;
pub mod svg;

pub use import::{load_drawing, ImportError, Imported, Unsupported, MAX_DRAWING_BYTES};
/// The geometry crate the drawings are made of, for callers that only depend on `io`.
pub use oficina_geom as geom;
pub use points::{load_points, parse_points, write_points_csv};
pub use seed001::{parse_seed001, SeedEntity, SeedFile};
pub mod hpgl;
