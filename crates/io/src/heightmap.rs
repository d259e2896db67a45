//! A height field on a regular grid.

/// Heights in mm on a square grid of `pixel` mm. `z = 0` is the stock top and depths are
/// negative. Storage is row-major with **row 0 at the smallest Y**: the importers flip image
/// rows so that the picture's top row lands at the largest Y and the carving is not mirrored.
#[derive(Clone, Debug, PartialEq)]
pub struct Heightmap {
    /// Columns (along X).
    pub width: usize,
    /// Rows (along Y).
    pub height: usize,
    /// Grid spacing in mm (X and Y alike).
    pub pixel: f64,
    /// Heights, mm, row-major: `width × height` values, row 0 at the smallest Y.
    pub z: Vec<f32>,
}

impl Heightmap {
    /// A flat map at height `z0`.
    pub fn flat(width: usize, height: usize, pixel: f64, z0: f32) -> Heightmap {
        Heightmap {
            width,
            height,
            pixel,
            z: vec![z0; width * height],
        }
    }

    /// Samples `f(x, y)` (mm) at every grid point.
    pub fn from_fn(
        width: usize,
        height: usize,
        pixel: f64,
        f: impl Fn(f64, f64) -> f64,
    ) -> Heightmap {
        let mut z = Vec::with_capacity(width * height);
        for iy in 0..height {
            for ix in 0..width {
                z.push(f(ix as f64 * pixel, iy as f64 * pixel) as f32);
            }
        }
        Heightmap {
            width,
            height,
            pixel,
            z,
        }
    }

    /// The height at column `ix`, row `iy`, mm.
    #[inline]
    pub fn at(&self, ix: usize, iy: usize) -> f32 {
        self.z[iy * self.width + ix]
    }

    /// The heights of row `iy`, mm.
    pub fn row(&self, iy: usize) -> &[f32] {
        &self.z[iy * self.width..(iy + 1) * self.width]
    }

    /// X of column `ix` in mm.
    pub fn x(&self, ix: usize) -> f64 {
        ix as f64 * self.pixel
    }

    /// Y of row `iy` in mm.
    pub fn y(&self, iy: usize) -> f64 {
        iy as f64 * self.pixel
    }

    /// Size in mm covered by the grid points (first to last).
    pub fn extent(&self) -> (f64, f64) {
        (
            (self.width.saturating_sub(1)) as f64 * self.pixel,
            (self.height.saturating_sub(1)) as f64 * self.pixel,
        )
    }

    /// Lowest and highest height.
    pub fn range(&self) -> (f32, f32) {
        self.z
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &v| {
                (lo.min(v), hi.max(v))
            })
    }
}
