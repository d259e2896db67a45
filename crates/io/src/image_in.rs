//! Grayscale elevation images → [`Heightmap`].
//!
//! Brightness encodes height: white is the stock top, black the deepest point (seed 004's
//! `depth = (255 − I)/255 · Dmax`, generalised to any bit depth and to a chosen white/black).
//! Colour images are reduced to luminance. The header is read first and the size checked
//! against a memory budget, so a hostile 100k × 100k picture is refused before decoding.

use crate::Heightmap;
use image::{ImageReader, Limits};
use std::io::Cursor;
use std::path::Path;

/// How big a pixel is on the workpiece.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Scale {
    /// mm per pixel.
    PixelSize(f64),
    /// Width of the whole picture in mm; the pixel size follows from the pixel count.
    Width(f64),
}

/// How brightness maps to depth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthMapping {
    /// Depth in mm of the black level (positive number).
    pub max_depth: f64,
    /// Swap the sense: white deepest, black at the top.
    pub invert: bool,
    /// Stretch the picture's own darkest..brightest to 0..max_depth instead of black..white.
    pub normalize: bool,
}

impl DepthMapping {
    pub fn new(max_depth: f64) -> DepthMapping {
        DepthMapping {
            max_depth,
            invert: false,
            normalize: false,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    #[error("{path}: cannot read the file: {source}")]
    Read {
        path: String,
        source: std::io::Error,
    },
    #[error("{path}: the file is empty (0 bytes); give a PNG, JPEG or TIFF elevation image")]
    Empty { path: String },
    #[error("{path}: the file is {size} bytes, over the memory budget of {budget} bytes")]
    FileTooLarge {
        path: String,
        size: u64,
        budget: u64,
    },
    #[error("{path}: not a readable PNG, JPEG or TIFF image: {detail}")]
    Format { path: String, detail: String },
    #[error(
        "{path}: the image is {width} × {height} pixels and would need about {needed} MB to \
         process, over the budget of {budget} MB; scale it down first"
    )]
    TooBig {
        path: String,
        width: u32,
        height: u32,
        needed: u64,
        budget: u64,
    },
    #[error("{path}: the image has no pixels ({width} × {height})")]
    NoPixels {
        path: String,
        width: u32,
        height: u32,
    },
    #[error("{path}: cannot decode the image (truncated or corrupt?): {detail}")]
    Decode { path: String, detail: String },
    #[error("{what} must be a finite number above 0, got {value}")]
    BadParameter { what: &'static str, value: f64 },
}

/// Default memory budget for one import: 2 GiB.
pub const DEFAULT_BUDGET: u64 = 2 << 30;

/// Bytes needed per pixel: the decoder's buffer (up to 4 × 16-bit channels, or 32-bit float
/// RGBA), the luminance copy and the f32 height grid.
const BYTES_PER_PIXEL: u64 = 16 + 4 + 4;

/// Reads an image file; see [`load_image_bytes`].
pub fn load_image(
    path: &Path,
    scale: Scale,
    mapping: DepthMapping,
    budget: u64,
) -> Result<Heightmap, ImageError> {
    let name = path.display().to_string();
    let meta = std::fs::metadata(path).map_err(|source| ImageError::Read {
        path: name.clone(),
        source,
    })?;
    if meta.len() > budget {
        return Err(ImageError::FileTooLarge {
            path: name,
            size: meta.len(),
            budget,
        });
    }
    let bytes = std::fs::read(path).map_err(|source| ImageError::Read {
        path: name.clone(),
        source,
    })?;
    load_image_bytes(&name, &bytes, scale, mapping, budget)
}

/// Decodes `bytes` (named `name` in messages) into a height map.
pub fn load_image_bytes(
    name: &str,
    bytes: &[u8],
    scale: Scale,
    mapping: DepthMapping,
    budget: u64,
) -> Result<Heightmap, ImageError> {
    check_positive("max depth", mapping.max_depth)?;
    match scale {
        Scale::PixelSize(p) => check_positive("pixel size", p)?,
        Scale::Width(w) => check_positive("width", w)?,
    }
    if bytes.is_empty() {
        return Err(ImageError::Empty { path: name.into() });
    }
    let (width, height) = header_dimensions(name, bytes)?;
    if width == 0 || height == 0 {
        return Err(ImageError::NoPixels {
            path: name.into(),
            width,
            height,
        });
    }
    let needed = width as u64 * height as u64 * BYTES_PER_PIXEL;
    if needed > budget {
        return Err(ImageError::TooBig {
            path: name.into(),
            width,
            height,
            needed: needed >> 20,
            budget: budget >> 20,
        });
    }

    let mut reader = guessed_reader(name, bytes)?;
    let mut limits = Limits::default();
    limits.max_image_width = Some(width);
    limits.max_image_height = Some(height);
    limits.max_alloc = Some(budget);
    reader.limits(limits);
    let picture = reader.decode().map_err(|e| ImageError::Decode {
        path: name.into(),
        detail: e.to_string(),
    })?;
    let luma = picture.to_luma32f();
    let pixel = match scale {
        Scale::PixelSize(p) => p,
        Scale::Width(w) => w / width as f64,
    };
    Ok(luminance_to_heights(
        width as usize,
        height as usize,
        luma.as_raw(),
        pixel,
        mapping,
    ))
}

fn check_positive(what: &'static str, value: f64) -> Result<(), ImageError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ImageError::BadParameter { what, value })
    }
}

fn guessed_reader<'a>(
    name: &str,
    bytes: &'a [u8],
) -> Result<ImageReader<Cursor<&'a [u8]>>, ImageError> {
    let reader = ImageReader::new(Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| ImageError::Format {
            path: name.into(),
            detail: e.to_string(),
        })?;
    if reader.format().is_none() {
        return Err(ImageError::Format {
            path: name.into(),
            detail: "unrecognised file signature".into(),
        });
    }
    Ok(reader)
}

/// Width and height from the header alone, without decoding pixels.
fn header_dimensions(name: &str, bytes: &[u8]) -> Result<(u32, u32), ImageError> {
    guessed_reader(name, bytes)?
        .into_dimensions()
        .map_err(|e| ImageError::Decode {
            path: name.into(),
            detail: e.to_string(),
        })
}

/// Luminance (0 = black … 1 = white, image row 0 on top) → heights, flipping rows so the
/// picture's top is the largest Y.
pub fn luminance_to_heights(
    width: usize,
    height: usize,
    luma: &[f32],
    pixel: f64,
    mapping: DepthMapping,
) -> Heightmap {
    let (mut black, mut white) = (0.0f32, 1.0f32);
    if mapping.normalize {
        let (lo, hi) = luma
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), &v| {
                (l.min(v), h.max(v))
            });
        if hi > lo {
            (black, white) = (lo, hi);
        }
    }
    let range = white - black;
    let scale = (mapping.max_depth / range as f64) as f32;
    let mut z = Vec::with_capacity(width * height);
    for image_row in (0..height).rev() {
        for &l in &luma[image_row * width..(image_row + 1) * width] {
            let l = l.clamp(black, white);
            let depth = if mapping.invert {
                (l - black) * scale
            } else {
                (white - l) * scale
            };
            z.push(-depth);
        }
    }
    Heightmap {
        width,
        height,
        pixel,
        z,
    }
}
