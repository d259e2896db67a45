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
    /// Black is `max_depth` mm deep, white the stock top; no inversion or stretching.
    pub fn new(max_depth: f64) -> DepthMapping {
        DepthMapping {
            max_depth,
            invert: false,
            normalize: false,
        }
    }
}

/// Why an elevation image could not be read.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The file cannot be read.
    #[error("{path}: cannot read the file: {source}")]
    Read {
        /// The file.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The file is empty.
    #[error("{path}: the file is empty (0 bytes); give a PNG, JPEG or TIFF elevation image")]
    Empty {
        /// The file.
        path: String,
    },
    /// The file is larger than the memory budget.
    #[error("{path}: the file is {size} bytes, over the memory budget of {budget} bytes")]
    FileTooLarge {
        /// The file.
        path: String,
        /// Its size, bytes.
        size: u64,
        /// The budget, bytes.
        budget: u64,
    },
    /// Not a PNG, JPEG or TIFF.
    #[error("{path}: not a readable PNG, JPEG or TIFF image: {detail}")]
    Format {
        /// The file.
        path: String,
        /// What the decoder said.
        detail: String,
    },
    /// Decoding would take more memory than the budget.
    #[error(
        "{path}: the image is {width} × {height} pixels and would need about {needed} MB to \
         process, over the budget of {budget} MB; scale it down first"
    )]
    TooBig {
        /// The file.
        path: String,
        /// Width, pixels.
        width: u32,
        /// Height, pixels.
        height: u32,
        /// Memory needed, MB.
        needed: u64,
        /// The budget, MB.
        budget: u64,
    },
    /// The image has no pixels.
    #[error("{path}: the image has no pixels ({width} × {height})")]
    NoPixels {
        /// The file.
        path: String,
        /// Width, pixels.
        width: u32,
        /// Height, pixels.
        height: u32,
    },
    /// The image is truncated or corrupt.
    #[error("{path}: cannot decode the image (truncated or corrupt?): {detail}")]
    Decode {
        /// The file.
        path: String,
        /// What the decoder said.
        detail: String,
    },
    /// A parameter is not a finite number above 0.
    #[error("{what} must be a finite number above 0, got {value}")]
    BadParameter {
        /// The parameter.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A depth (mm) beyond any part.
    #[error("a depth of {0} mm is beyond any part (at most {MAX_DEPTH_MM} mm)")]
    TooDeep(f64),
}

/// Deepest black level accepted, mm: a kilometre, far beyond any machine and well inside
/// what f32 heights hold.
pub(crate) const MAX_DEPTH_MM: f64 = 1.0e6;

/// Default memory budget for one import: 2 GiB.
#[cfg(test)]
pub(crate) const DEFAULT_BUDGET: u64 = 2 << 30;

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
    if mapping.max_depth > MAX_DEPTH_MM {
        return Err(ImageError::TooDeep(mapping.max_depth));
    }
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
    // 2^32 × 2^32 × 24 does not fit in u64: saturate, or a hostile header would wrap to a
    // small figure and pass.
    let needed = (width as u64 * height as u64).saturating_mul(BYTES_PER_PIXEL);
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
    use image::ImageFormat::{Jpeg, Png, Tiff};
    match reader.format() {
        Some(Png | Jpeg | Tiff) => Ok(reader),
        Some(other) => Err(ImageError::Format {
            path: name.into(),
            detail: format!("it looks like {other:?}, which is not supported"),
        }),
        None => Err(ImageError::Format {
            path: name.into(),
            detail: "unrecognised file signature".into(),
        }),
    }
}

/// Width and height from the header alone, without decoding pixels. PNG is read by hand
/// from its fixed-place IHDR: the decoder would first look for image data, and a hostile
/// header without any must still get the size error, not a decoding one.
fn header_dimensions(name: &str, bytes: &[u8]) -> Result<(u32, u32), ImageError> {
    const PNG: &[u8] = b"\x89PNG\r\n\x1a\n";
    if bytes.starts_with(PNG) {
        return match bytes.get(8..24) {
            Some(h) if &h[4..8] == b"IHDR" => Ok((
                u32::from_be_bytes([h[8], h[9], h[10], h[11]]),
                u32::from_be_bytes([h[12], h[13], h[14], h[15]]),
            )),
            _ => Err(ImageError::Decode {
                path: name.into(),
                detail: "PNG without its IHDR header (truncated?)".into(),
            }),
        };
    }
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

#[cfg(test)]
mod tests {
    use super::*;
    use image::{ImageBuffer, Luma, Rgb};

    fn png<P: image::PixelWithColorType>(img: &ImageBuffer<P, Vec<P::Subpixel>>) -> Vec<u8>
    where
        P::Subpixel: image::Primitive,
        [P::Subpixel]: image::EncodableLayout,
    {
        let mut out = Cursor::new(Vec::new());
        img.write_to(&mut out, image::ImageFormat::Png).unwrap();
        out.into_inner()
    }

    fn load(bytes: &[u8], scale: Scale, mapping: DepthMapping) -> Result<Heightmap, ImageError> {
        load_image_bytes("t.png", bytes, scale, mapping, DEFAULT_BUDGET)
    }

    #[test]
    fn white_is_the_top_black_the_depth_and_row_zero_the_largest_y() {
        // 3 × 2: top row white, mid-gray, black; bottom row all black.
        let img = ImageBuffer::from_fn(3, 2, |x, y| {
            Luma([if y == 1 {
                0u8
            } else {
                [255, 51, 0][x as usize]
            }])
        });
        let m = load(&png(&img), Scale::PixelSize(0.5), DepthMapping::new(10.0)).unwrap();
        assert_eq!((m.width, m.height, m.pixel), (3, 2, 0.5));
        // Image row 0 (top) is grid row 1 (largest Y).
        assert_eq!(m.at(0, 1), 0.0);
        assert!((m.at(1, 1) + 8.0).abs() < 1e-5, "(255 − 51)/255 · 10 = 8");
        assert_eq!(m.at(2, 1), -10.0);
        assert!(m.row(0).iter().all(|&z| z == -10.0));
        let inverted = DepthMapping {
            invert: true,
            ..DepthMapping::new(10.0)
        };
        let m = load(&png(&img), Scale::PixelSize(0.5), inverted).unwrap();
        assert_eq!((m.at(0, 1), m.at(2, 1)), (-10.0, 0.0));
    }

    #[test]
    fn sixteen_bit_keeps_its_resolution() {
        let img = ImageBuffer::from_fn(2, 1, |x, _| Luma([[65535u16, 65534][x as usize]]));
        let m = load(
            &png(&img),
            Scale::PixelSize(1.0),
            DepthMapping::new(65535.0),
        )
        .unwrap();
        assert_eq!(m.at(0, 0), 0.0);
        assert!(
            (m.at(1, 0) + 1.0).abs() < 1e-2,
            "one 16-bit step = 1 mm here: {}",
            m.at(1, 0)
        );
    }

    #[test]
    fn colour_becomes_luminance() {
        let img = ImageBuffer::from_fn(3, 1, |x, _| {
            Rgb([[255u8, 0, 0], [0, 255, 0], [0, 0, 255]][x as usize])
        });
        let m = load(&png(&img), Scale::PixelSize(1.0), DepthMapping::new(1.0)).unwrap();
        // Rec. 709 weights, as the image crate uses: 0.2126, 0.7152, 0.0722.
        for (ix, w) in [0.2126f32, 0.7152, 0.0722].iter().enumerate() {
            assert!(
                (m.at(ix, 0) + (1.0 - w)).abs() < 0.01,
                "channel {ix}: {}",
                m.at(ix, 0)
            );
        }
    }

    #[test]
    fn width_sets_the_pixel_size_and_normalize_stretches() {
        let img = ImageBuffer::from_fn(4, 1, |x, _| Luma([100 + 50 * x as u8]));
        let m = load(
            &png(&img),
            Scale::Width(100.0),
            DepthMapping {
                normalize: true,
                ..DepthMapping::new(6.0)
            },
        )
        .unwrap();
        assert_eq!(m.pixel, 25.0);
        assert_eq!((m.at(0, 0), m.at(3, 0)), (-6.0, 0.0));
        assert!((m.at(1, 0) + 4.0).abs() < 1e-5);
    }

    #[test]
    fn bad_inputs_are_named_errors() {
        let good = png(&ImageBuffer::from_fn(8, 8, |_, _| Luma([7u8])));
        let mapping = DepthMapping::new(5.0);
        let px = Scale::PixelSize(1.0);
        assert!(matches!(
            load(&[], px, mapping),
            Err(ImageError::Empty { .. })
        ));
        assert!(matches!(
            load(b"hello, not an image", px, mapping),
            Err(ImageError::Format { .. })
        ));
        let e = load(&good[..good.len() / 2], px, mapping).unwrap_err();
        assert!(matches!(e, ImageError::Decode { .. }), "{e}");
        assert!(matches!(
            load(&good[..12], px, mapping),
            Err(ImageError::Decode { .. })
        ));
        assert!(matches!(
            load(&good, Scale::PixelSize(0.0), mapping),
            Err(ImageError::BadParameter { .. })
        ));
        assert!(matches!(
            load(&good, px, DepthMapping::new(f64::NAN)),
            Err(ImageError::BadParameter { .. })
        ));
        // A header claiming 100000 × 100000 and nothing else: the size error, before decoding.
        let mut huge = good[..33].to_vec();
        huge[16..20].copy_from_slice(&100_000u32.to_be_bytes());
        huge[20..24].copy_from_slice(&100_000u32.to_be_bytes());
        let e = load(&huge, px, mapping).unwrap_err();
        assert!(
            matches!(e, ImageError::TooBig { width: 100_000, .. }),
            "{e}"
        );
        assert!(e.to_string().contains("100000 × 100000"));
    }
}
