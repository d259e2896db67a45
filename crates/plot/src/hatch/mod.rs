//! Images → hatching: darker pixels get more layers of parallel lines (0°, 90°, 45°, 135°),
//! each layer drawn where the darkness passes its threshold; or (`bands`) darkness bands
//! filled as shapes are.

mod bands;
mod contour;

pub use bands::{band_regions, fill_bands, MAX_BANDS};

use oficina_geom::{Point, Vec2};

use crate::strokes::Stroke;

/// Images larger than this many pixels are refused (bounded memory).
pub(crate) const MAX_PIXELS: u64 = 64_000_000;
/// At most this many hatch lines per layer.
const MAX_LINES: f64 = 200_000.0;

/// How a picture becomes hatch lines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hatching {
    /// Width of one pixel on paper, mm.
    pub pixel: f64,
    /// Distance between hatch lines, mm.
    pub pitch: f64,
    /// Layers of hatching (1…4): darkness above k/(layers+1) gets layer k.
    pub layers: usize,
    /// Direction of the first layer, degrees from +X; the others at +90°, +45°, +135°.
    pub angle: f64,
}

/// Why a picture could not be hatched.
#[derive(Debug, thiserror::Error)]
pub enum HatchError {
    /// The picture could not be read.
    #[error("{file}: {msg}")]
    Image {
        /// The picture's file.
        file: String,
        /// What went wrong.
        msg: String,
    },
    /// A setting out of range; says which.
    #[error("{0}")]
    Settings(String),
}

/// A grayscale picture, row 0 at the top, 0 = black.
pub struct Gray<'a> {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width × height` gray levels, row by row.
    pub pixels: &'a [u8],
}

/// Loads an image file as 8-bit grayscale, refusing empty and huge pictures.
pub fn load_gray(path: &std::path::Path) -> Result<(usize, usize, Vec<u8>), HatchError> {
    let file = path.display().to_string();
    let bad = |msg: String| HatchError::Image {
        file: file.clone(),
        msg,
    };
    let reader = image::ImageReader::open(path)
        .map_err(|e| bad(e.to_string()))?
        .with_guessed_format()
        .map_err(|e| bad(e.to_string()))?;
    let (w, h) = reader
        .into_dimensions()
        .map_err(|e| bad(format!("not a readable image: {e}")))?;
    if w as u64 * h as u64 > MAX_PIXELS {
        return Err(bad(format!(
            "{w} × {h} pixels is over the {MAX_PIXELS}-pixel limit"
        )));
    }
    let img = image::open(path).map_err(|e| bad(format!("not a readable image: {e}")))?;
    let g = img.to_luma8();
    Ok((g.width() as usize, g.height() as usize, g.into_raw()))
}

/// Refuses a pixel size that is not a length and a picture without its pixels.
fn check_picture(img: &Gray, pixel: f64) -> Result<(), HatchError> {
    if !(pixel.is_finite() && pixel > 0.0) {
        return Err(HatchError::Settings(format!(
            "pixel size {pixel} mm must be > 0"
        )));
    }
    if img.width == 0 || img.height == 0 || img.pixels.len() < img.width * img.height {
        return Err(HatchError::Settings("the image has no pixels".into()));
    }
    Ok(())
}

/// Hatch strokes of the picture, its lower-left corner at the origin, Y up: one list per
/// layer, lightest (first drawn everywhere darkness passes 1/(layers+1)) first.
pub fn hatch(img: &Gray, h: &Hatching) -> Result<Vec<Vec<Stroke>>, HatchError> {
    check_picture(img, h.pixel)?;
    if !(h.pitch.is_finite() && h.pitch > 0.0) {
        return Err(HatchError::Settings(format!(
            "pitch {} mm must be > 0",
            h.pitch
        )));
    }
    if !h.angle.is_finite() {
        return Err(HatchError::Settings(format!(
            "angle {}: must be a number of degrees",
            h.angle
        )));
    }
    if !(1..=4).contains(&h.layers) {
        return Err(HatchError::Settings(format!(
            "layers must be 1…4, got {}",
            h.layers
        )));
    }
    let (wmm, hmm) = (img.width as f64 * h.pixel, img.height as f64 * h.pixel);
    if wmm.hypot(hmm) / h.pitch > MAX_LINES {
        return Err(HatchError::Settings(format!(
            "pitch {} mm gives more than {MAX_LINES} lines over {wmm:.0} × {hmm:.0} mm",
            h.pitch
        )));
    }
    let dark = |p: Point| -> f64 {
        let c = (p.x / h.pixel).floor();
        let r = ((hmm - p.y) / h.pixel).floor();
        if c < 0.0 || r < 0.0 || c >= img.width as f64 || r >= img.height as f64 {
            return 0.0;
        }
        1.0 - img.pixels[r as usize * img.width + c as usize] as f64 / 255.0
    };
    let angles = [0.0f64, 90.0, 45.0, 135.0];
    let corners = [
        Point::ORIGIN,
        Point::new(wmm, 0.0),
        Point::new(0.0, hmm),
        Point::new(wmm, hmm),
    ];
    // Sample along a line at half a pixel so no pixel is skipped.
    let step = h.pixel * 0.5;
    let mut layers = Vec::with_capacity(h.layers);
    for (k, a) in angles
        .iter()
        .map(|a| a + h.angle)
        .take(h.layers)
        .enumerate()
    {
        let threshold = (k + 1) as f64 / (h.layers + 1) as f64;
        let mut out = Vec::new();
        let u = Vec2::from_angle(a.to_radians());
        let nrm = Vec2::new(-u.y, u.x);
        let proj = |v: Vec2| corners.iter().map(move |c| c.to_vec2().dot(v));
        let (t0, t1) = (
            proj(nrm).fold(f64::MAX, f64::min),
            proj(nrm).fold(f64::MIN, f64::max),
        );
        let (s0, s1) = (
            proj(u).fold(f64::MAX, f64::min),
            proj(u).fold(f64::MIN, f64::max),
        );
        let mut t = t0 + h.pitch * 0.5;
        while t < t1 {
            let mut run: Option<Point> = None;
            let mut s = s0;
            let mut last = Point::ORIGIN;
            while s <= s1 + step {
                let p = (nrm * t + u * s).to_point();
                let inside = dark(p) > threshold;
                match (inside, run) {
                    (true, None) => run = Some(p),
                    (false, Some(a)) => {
                        if a != last {
                            out.push(vec![a, last]);
                        }
                        run = None;
                    }
                    _ => {}
                }
                last = p;
                s += step;
            }
            if let Some(a) = run {
                if a != last {
                    out.push(vec![a, last]);
                }
            }
            t += h.pitch;
        }
        layers.push(out);
    }
    Ok(layers)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn black_gets_every_layer_white_none_and_grey_some() {
        // 20 × 10: left half black, right half white.
        let mut px = vec![255u8; 200];
        for r in 0..10 {
            for c in 0..10 {
                px[r * 20 + c] = 0;
            }
        }
        let g = Gray {
            width: 20,
            height: 10,
            pixels: &px,
        };
        let s = hatch(
            &g,
            &Hatching {
                pixel: 1.0,
                pitch: 1.0,
                layers: 2,
                angle: 0.0,
            },
        )
        .unwrap()
        .concat();
        assert!(!s.is_empty());
        for p in s.iter().flatten() {
            assert!(p.x <= 10.0 + 1e-9, "hatch in the white half at {p:?}");
        }
        // Horizontal layer: 10 lines 10 mm long in the black half.
        let horiz: f64 = s
            .iter()
            .filter(|s| (s[0].y - s[1].y).abs() < 1e-9)
            .map(|s| s[0].distance(s[1]))
            .sum();
        assert!((horiz - 100.0).abs() < 10.0, "{horiz}");
        let one = Gray {
            width: 1,
            height: 1,
            pixels: &[0],
        };
        assert!(hatch(
            &one,
            &Hatching {
                pixel: 1.0,
                pitch: 0.5,
                layers: 1,
                angle: 0.0,
            }
        )
        .is_ok());
        assert!(hatch(
            &g,
            &Hatching {
                pixel: 1.0,
                pitch: 0.0,
                layers: 1,
                angle: 0.0,
            }
        )
        .is_err());
    }
}
