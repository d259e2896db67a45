//! Drop-cutter on a height field: the tool-tip surface.
//!
//! For a tool centred over `p`, the lowest tip height that does not cut below the design is
//! `T(p) = max over offsets d of design(p + d) − profile(|d|)`: the grayscale dilation of the
//! design by the tool (seed 004 took the min here and gouged). The kernel splits the tool
//! into *flat pieces* (the flat bottom and the shank, constant lift over a disk) that cost a
//! running max per chord (van Herk / Gil-Werman: three compares per pixel whatever the
//! width) and *curved offsets* (ball, cone, corner radius), each one a contiguous
//! `max(out, row − lift)` pass that the compiler vectorises. Rows run in parallel.
//!
//! A kernel can be *widened*: along X by `along` mm (Minkowski sum with a segment) and
//! radially by `radial` mm. Linear moves interpolate Z between samples one pixel apart; a
//! surface widened by one pixel along the move bounds the true one at every point between
//! the two samples, so straight feeds between widened samples never gouge.

use crate::tool::Tool;
use oficina_io::Heightmap;
use rayon::prelude::*;

/// A disk (per-row half widths, −1 = empty row) lifted by a constant.
#[derive(Clone, Debug)]
struct FlatPiece {
    lift: f32,
    half_width: Vec<i32>,
}

#[derive(Clone, Debug)]
pub struct Kernel {
    /// Offsets span −reach..=reach pixels in X and Y.
    pub reach: usize,
    flats: Vec<FlatPiece>,
    /// Per row offset dy (index dy + reach): (dx, lift) of the curved part.
    curved: Vec<Vec<(i32, f32)>>,
    /// Every offset with its lift, for single-point queries.
    all: Vec<(i32, i32, f32)>,
}

impl Kernel {
    /// Kernel of `tool` on a grid of `pixel` mm, widened by `along` mm in X and `radial` mm
    /// in every direction.
    pub fn new(tool: &Tool, pixel: f64, along: f64, radial: f64) -> Kernel {
        let reach = ((tool.reach_radius() + along + radial) / pixel).ceil() as usize;
        let r = reach as i32;
        let effective = |dx: i32, dy: i32| {
            let ex = ((dx.abs() as f64) * pixel - along).max(0.0);
            let ey = dy.abs() as f64 * pixel;
            ((ex * ex + ey * ey).sqrt() - radial).max(0.0)
        };
        let flat_r = tool.flat_radius();
        let cut_r = tool.cutting_radius();
        let shank_r = tool.shank_diameter / 2.0;
        let mut pieces = Vec::new();
        if flat_r > 0.0 {
            pieces.push((0.0f64, flat_r));
        }
        if shank_r > cut_r {
            pieces.push((tool.profile(shank_r).unwrap_or(tool.flute_length), shank_r));
        }
        let flats = pieces
            .iter()
            .map(|&(lift, limit)| FlatPiece {
                lift: lift as f32,
                half_width: (-r..=r)
                    .map(|dy| {
                        (0..=r)
                            .take_while(|&dx| effective(dx, dy) <= limit)
                            .last()
                            .unwrap_or(-1)
                    })
                    .collect(),
            })
            .collect();
        let mut curved = vec![Vec::new(); 2 * reach + 1];
        let mut all = Vec::new();
        for dy in -r..=r {
            for dx in -r..=r {
                let rho = effective(dx, dy);
                if let Some(lift) = tool.profile(rho) {
                    all.push((dx, dy, lift as f32));
                    // Offsets on the flat bottom are served by its flat piece.
                    if !(flat_r > 0.0 && rho <= flat_r) && rho <= cut_r {
                        curved[(dy + r) as usize].push((dx, lift as f32));
                    }
                }
            }
        }
        Kernel {
            reach,
            flats,
            curved,
            all,
        }
    }

    /// Number of offsets in the footprint.
    pub fn footprint(&self) -> usize {
        self.all.len()
    }
}

/// The design padded with −∞ columns so every offset reads inside the buffer.
pub struct Padded<'a> {
    map: &'a Heightmap,
    pad: usize,
    data: Vec<f32>,
}

impl<'a> Padded<'a> {
    pub fn new(map: &'a Heightmap, pad: usize) -> Padded<'a> {
        let stride = map.width + 2 * pad;
        let mut data = vec![f32::NEG_INFINITY; stride * map.height];
        for iy in 0..map.height {
            data[iy * stride + pad..iy * stride + pad + map.width].copy_from_slice(map.row(iy));
        }
        Padded { map, pad, data }
    }

    fn row(&self, iy: usize) -> &[f32] {
        let stride = self.map.width + 2 * self.pad;
        &self.data[iy * stride..(iy + 1) * stride]
    }
}

/// Tool-tip heights along row `iy` of `padded` (padded by at least `kernel.reach`).
pub fn surface_row(
    padded: &Padded,
    kernel: &Kernel,
    iy: usize,
    out: &mut [f32],
    scratch: &mut Vec<f32>,
) {
    let map = padded.map;
    let (w, pad, r) = (map.width, padded.pad, kernel.reach as i64);
    out.fill(f32::NEG_INFINITY);
    for dy in -r..=r {
        let sy = iy as i64 + dy;
        if sy < 0 || sy >= map.height as i64 {
            continue;
        }
        let src = padded.row(sy as usize);
        let k = (dy + r) as usize;
        for piece in &kernel.flats {
            let hw = piece.half_width[k];
            if hw < 0 {
                continue;
            }
            window_max(src, hw as usize, scratch);
            let lift = piece.lift;
            for (o, &m) in out.iter_mut().zip(&scratch[pad..pad + w]) {
                *o = o.max(m - lift);
            }
        }
        for &(dx, lift) in &kernel.curved[k] {
            let start = (pad as i64 + dx as i64) as usize;
            for (o, &s) in out.iter_mut().zip(&src[start..start + w]) {
                *o = o.max(s - lift);
            }
        }
    }
}

/// `out[i] = max(src[i − w ..= i + w])` for every i with the window inside `src`
/// (van Herk / Gil-Werman: block prefix and suffix maxima).
fn window_max(src: &[f32], w: usize, out: &mut Vec<f32>) {
    let n = src.len();
    let k = 2 * w + 1;
    out.clear();
    out.resize(n, f32::NEG_INFINITY);
    if w == 0 {
        out.copy_from_slice(src);
        return;
    }
    let mut prefix = vec![f32::NEG_INFINITY; n];
    let mut suffix = vec![f32::NEG_INFINITY; n];
    for start in (0..n).step_by(k) {
        let end = (start + k).min(n);
        let mut m = f32::NEG_INFINITY;
        for i in start..end {
            m = m.max(src[i]);
            prefix[i] = m;
        }
        m = f32::NEG_INFINITY;
        for i in (start..end).rev() {
            m = m.max(src[i]);
            suffix[i] = m;
        }
    }
    for i in w..n.saturating_sub(w) {
        out[i] = suffix[i - w].max(prefix[i + w]);
    }
}

/// The tool-tip surface at every grid point.
pub fn surface_grid(design: &Heightmap, kernel: &Kernel) -> Heightmap {
    let rows: Vec<usize> = (0..design.height).collect();
    let z = surface_rows(design, kernel, &rows).concat();
    Heightmap {
        z,
        ..design.clone()
    }
}

/// The tool-tip surface along the listed rows only (in that order).
pub fn surface_rows(design: &Heightmap, kernel: &Kernel, rows: &[usize]) -> Vec<Vec<f32>> {
    let padded = Padded::new(design, kernel.reach);
    rows.par_iter()
        .map_init(Vec::new, |scratch, &iy| {
            let mut out = vec![0.0f32; design.width];
            surface_row(&padded, kernel, iy, &mut out, scratch);
            out
        })
        .collect()
}

/// The tool-tip height over one grid point (brute force over the footprint).
pub fn surface_at(design: &Heightmap, kernel: &Kernel, ix: usize, iy: usize) -> f32 {
    let mut best = f32::NEG_INFINITY;
    for &(dx, dy, lift) in &kernel.all {
        let (x, y) = (ix as i64 + dx as i64, iy as i64 + dy as i64);
        if x >= 0 && y >= 0 && (x as usize) < design.width && (y as usize) < design.height {
            best = best.max(design.at(x as usize, y as usize) - lift);
        }
    }
    best
}

/// Swaps X and Y, so raster-along-Y reuses the along-X code.
pub fn transpose(map: &Heightmap) -> Heightmap {
    let mut z = Vec::with_capacity(map.z.len());
    for ix in 0..map.width {
        for iy in 0..map.height {
            z.push(map.at(ix, iy));
        }
    }
    Heightmap {
        width: map.height,
        height: map.width,
        pixel: map.pixel,
        z,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The definition, evaluated literally with the tool profile.
    fn brute(design: &Heightmap, tool: &Tool, ix: usize, iy: usize) -> f32 {
        let mut best = f64::NEG_INFINITY;
        for qy in 0..design.height {
            for qx in 0..design.width {
                let d = ((qx as f64 - ix as f64).powi(2) + (qy as f64 - iy as f64).powi(2)).sqrt()
                    * design.pixel;
                if let Some(p) = tool.profile(d) {
                    best = best.max(design.at(qx, qy) as f64 - p);
                }
            }
        }
        best as f32
    }

    fn bumpy() -> Heightmap {
        Heightmap::from_fn(41, 37, 0.5, |x, y| {
            -5.0 + 3.0 * (x * 0.7).sin() * (y * 0.4).cos() - ((x * 13.0 + y * 7.0) % 3.0)
        })
    }

    #[test]
    fn every_shape_matches_the_definition() {
        let design = bumpy();
        for spec in [
            "flat:4",
            "ball:6",
            "v:6:60",
            "bull:6:1",
            "taper:1:10,flute=4",
            "flat:2,flute=2,shank=6",
            "ball:3,flute=1,shank=5",
        ] {
            let tool: Tool = spec.parse().unwrap();
            let kernel = Kernel::new(&tool, design.pixel, 0.0, 0.0);
            let grid = surface_grid(&design, &kernel);
            for iy in 0..design.height {
                for ix in 0..design.width {
                    let want = brute(&design, &tool, ix, iy);
                    assert!(
                        (grid.at(ix, iy) - want).abs() < 1e-5,
                        "{spec} at {ix},{iy}: {} vs {want}",
                        grid.at(ix, iy)
                    );
                    if (ix + iy) % 7 == 0 {
                        assert!((surface_at(&design, &kernel, ix, iy) - want).abs() < 1e-5);
                    }
                }
            }
        }
    }

    #[test]
    fn widened_kernel_bounds_positions_between_samples() {
        let design = bumpy();
        let tool: Tool = "ball:4".parse().unwrap();
        let widened = surface_grid(
            &design,
            &Kernel::new(&tool, design.pixel, design.pixel, 0.0),
        );
        // Tool centred halfway between two samples of a row.
        for iy in 0..design.height {
            for ix in 0..design.width - 1 {
                let (cx, cy) = ((ix as f64 + 0.5) * design.pixel, iy as f64 * design.pixel);
                let mut need = f64::NEG_INFINITY;
                for qy in 0..design.height {
                    for qx in 0..design.width {
                        let d = ((design.x(qx) - cx).powi(2) + (design.y(qy) - cy).powi(2)).sqrt();
                        if let Some(p) = tool.profile(d) {
                            need = need.max(design.at(qx, qy) as f64 - p);
                        }
                    }
                }
                let chord = 0.5 * (widened.at(ix, iy) + widened.at(ix + 1, iy)) as f64;
                assert!(
                    chord >= need - 1e-5,
                    "at {ix}.5,{iy}: chord {chord} below {need}"
                );
            }
        }
    }

    #[test]
    fn window_max_is_a_sliding_maximum() {
        let src: Vec<f32> = (0..50).map(|i| ((i * 37) % 11) as f32).collect();
        let mut out = Vec::new();
        for w in 0..6 {
            window_max(&src, w, &mut out);
            for i in w..src.len() - w {
                let want = src[i - w..=i + w].iter().cloned().fold(f32::MIN, f32::max);
                assert_eq!(out[i], want);
            }
        }
    }
}
