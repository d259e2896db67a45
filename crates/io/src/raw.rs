//! Raw height fields: little-endian f32, row-major, image row 0 on top, values in mm
//! (0 = stock top, negative = below). For z-buffers exported from 3D programs.

use crate::Heightmap;

/// Why a raw height field could not be read.
#[derive(Debug, thiserror::Error)]
pub enum RawError {
    /// The file cannot be read.
    #[error("{path}: cannot read the file: {source}")]
    Read {
        /// The file.
        path: String,
        /// The I/O error.
        source: std::io::Error,
    },
    /// The size is not a whole number of rows.
    #[error(
        "{path}: {bytes} bytes is not a whole number of {width}-sample f32 rows ({row} bytes each)"
    )]
    Shape {
        /// The file.
        path: String,
        /// Its size, bytes.
        bytes: u64,
        /// Samples per row.
        width: usize,
        /// Bytes per row.
        row: u64,
    },
    /// The file is empty.
    #[error("{path}: the height field is empty")]
    Empty {
        /// The file.
        path: String,
    },
    /// The file is larger than the memory budget.
    #[error("{path}: {bytes} bytes is over the memory budget of {budget} bytes")]
    TooBig {
        /// The file.
        path: String,
        /// Its size, bytes.
        bytes: u64,
        /// The budget, bytes.
        budget: u64,
    },
    /// A sample is NaN or infinite.
    #[error("{path}: sample at row {row}, column {col} is {value}; heights must be finite")]
    NotFinite {
        /// The file.
        path: String,
        /// Row.
        row: usize,
        /// Column.
        col: usize,
        /// The value given.
        value: f32,
    },
    /// A parameter is not above 0.
    #[error("{what} must be above 0")]
    BadParameter {
        /// The parameter.
        what: &'static str,
    },
}

/// Loads `width`-wide rows of f32 heights from `path`, with `pixel` mm spacing.
pub fn load_raw_f32(
    path: &std::path::Path,
    width: usize,
    pixel: f64,
    budget: u64,
) -> Result<Heightmap, RawError> {
    let name = path.display().to_string();
    check_parameters(width, pixel)?;
    let bytes = std::fs::metadata(path)
        .map_err(|source| RawError::Read {
            path: name.clone(),
            source,
        })?
        .len();
    if bytes > budget / 2 {
        return Err(RawError::TooBig {
            path: name,
            bytes,
            budget,
        });
    }
    let data = std::fs::read(path).map_err(|source| RawError::Read {
        path: name.clone(),
        source,
    })?;
    raw_f32_from_bytes(&name, &data, width, pixel)
}

fn check_parameters(width: usize, pixel: f64) -> Result<(), RawError> {
    if width == 0 {
        return Err(RawError::BadParameter { what: "raw width" });
    }
    if !(pixel.is_finite() && pixel > 0.0) {
        return Err(RawError::BadParameter { what: "pixel size" });
    }
    Ok(())
}

/// Decodes `data` (named `name` in messages): rows of `width` f32 samples, `pixel` mm apart.
pub fn raw_f32_from_bytes(
    name: &str,
    data: &[u8],
    width: usize,
    pixel: f64,
) -> Result<Heightmap, RawError> {
    check_parameters(width, pixel)?;
    // A width whose row does not even fit in u64 is simply not a whole number of rows.
    let row = (width as u64).saturating_mul(4);
    if data.is_empty() {
        return Err(RawError::Empty { path: name.into() });
    }
    if !(data.len() as u64).is_multiple_of(row) {
        return Err(RawError::Shape {
            path: name.into(),
            bytes: data.len() as u64,
            width,
            row,
        });
    }
    let height = (data.len() as u64 / row) as usize;
    let mut z = Vec::with_capacity(width * height);
    for image_row in (0..height).rev() {
        for col in 0..width {
            let at = (image_row * width + col) * 4;
            let value = f32::from_le_bytes([data[at], data[at + 1], data[at + 2], data[at + 3]]);
            if !value.is_finite() {
                return Err(RawError::NotFinite {
                    path: name.into(),
                    row: image_row,
                    col,
                    value,
                });
            }
            z.push(value);
        }
    }
    Ok(Heightmap {
        width,
        height,
        pixel,
        z,
    })
}
