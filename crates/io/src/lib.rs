//! Importers: pictures and raw height fields become a [`Heightmap`], the one representation
//! of relief that the CAM consumes.

pub mod heightmap;
pub mod image_in;
pub mod raw;

pub use heightmap::Heightmap;
pub use image_in::{load_image, load_image_bytes, DepthMapping, ImageError, Scale};
pub use raw::{load_raw_f32, raw_f32_from_bytes, RawError};
