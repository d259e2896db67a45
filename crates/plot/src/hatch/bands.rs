//! Images hatched as shapes are filled: each darkness band (darkness between k/(n+1) and
//! (k+1)/(n+1), the darkest band open above) becomes regions, outlined by marching squares
//! with the darker bands as holes, and is filled by `fill_regions` (parallel, cross or
//! concentric) at spacing/k. Band k then holds k/spacing of line per unit of area, as k
//! overlaid layers of the layered hatching do; bands do not overlap, so lines of two bands
//! never coincide.

use oficina_geom::{ring_area, simplify, Fill, Region};

use super::contour::{Field, MAX_CELLS};
use super::{Gray, HatchError};
use crate::fill::{fill_regions, FillStyle, MAX_FILL_LINES};
use crate::strokes::Stroke;

/// At most this many bands.
pub const MAX_BANDS: usize = 8;

/// The regions of each darkness band of `img` (`pixel` mm a pixel, lower-left corner at the
/// origin), lightest band first. `finest` is the smallest spacing they will be filled at:
/// pixels are averaged over blocks up to half of it (detail finer than that is not drawn).
pub fn band_regions(
    img: &Gray,
    pixel: f64,
    bands: usize,
    finest: f64,
) -> Result<Vec<Vec<Region>>, HatchError> {
    super::check_picture(img, pixel)?;
    if !(1..=MAX_BANDS).contains(&bands) {
        return Err(HatchError::Settings(format!(
            "hatch layers (darkness bands) must be 1…{MAX_BANDS}, got {bands}"
        )));
    }
    let by_spacing = if finest.is_finite() && finest > 0.0 {
        (finest * 0.5 / pixel).floor() as usize
    } else {
        1
    };
    // Smallest f with ⌈w/f⌉·⌈h/f⌉ within the cap: f ≥ √(w·h / cap), then step up if the
    // rounding up of partial blocks still overshoots.
    let mut f = by_spacing
        .max(
            ((img.width * img.height) as f64 / MAX_CELLS as f64)
                .sqrt()
                .ceil() as usize,
        )
        .max(1);
    while (img.width.div_ceil(f) + 2) * (img.height.div_ceil(f) + 2) > MAX_CELLS {
        f += 1;
    }
    let field = Field::new(img, pixel, f);
    let level = |k: usize| k as f64 / (bands + 1) as f64;
    let mut out = Vec::with_capacity(bands);
    let mut above = field.outlines(level(1));
    for k in 1..=bands {
        let darker = if k < bands {
            field.outlines(level(k + 1))
        } else {
            Vec::new()
        };
        // Outlines of two levels do not cross (a saddle cell's chords could touch): read
        // even-odd, the darker outlines are holes.
        let mut rings = std::mem::take(&mut above);
        rings.extend(darker.iter().cloned());
        let regions =
            simplify(&rings, Fill::EvenOdd).map_err(|e| HatchError::Settings(e.to_string()))?;
        out.push(regions);
        above = darker;
    }
    Ok(out)
}

/// Strokes of each band, lightest first: band k (from 1) filled by `style` at
/// `style.spacing / k`. `tol` is the chord tolerance of concentric rings' round corners.
pub fn fill_bands(
    bands: &[Vec<Region>],
    style: &FillStyle,
    tol: f64,
) -> Result<Vec<Vec<Stroke>>, HatchError> {
    let mut budget = MAX_FILL_LINES;
    let mut out = Vec::with_capacity(bands.len());
    for (i, regions) in bands.iter().enumerate() {
        let spacing = style.spacing / (i + 1) as f64;
        // Detail under a spacing square cannot be drawn at that spacing: such regions and
        // holes are dropped (a noisy picture's specks, which would cost rings and budget).
        // Concentric: a ring inset by s needs a disc of radius s inside, area π·s².
        let least = if style.concentric {
            std::f64::consts::PI * spacing * spacing
        } else {
            spacing * spacing
        };
        let kept: Vec<Region> = regions
            .iter()
            .filter(|r| r.area() >= least)
            .map(|r| Region {
                outer: r.outer.clone(),
                holes: r
                    .holes
                    .iter()
                    .filter(|h| ring_area(h).abs() >= spacing * spacing)
                    .cloned()
                    .collect(),
            })
            .collect();
        let s = FillStyle { spacing, ..*style };
        out.push(fill_regions(&kept, &s, tol, &mut budget).map_err(HatchError::Settings)?);
    }
    Ok(out)
}
