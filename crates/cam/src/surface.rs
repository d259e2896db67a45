//! Drop-cutter on a height field: the tool-tip surface.
//!
//! For a tool centred over `p`, the lowest tip height that does not cut below the design is
//! `T(p) = max over offsets d of design(p + d) − profile(|d|)`: the grayscale dilation of the
//! design by the tool (seed 004 took the min here and gouged). The kernel splits the tool
//! into *flat pieces* (the flat bottom and the shank, constant lift over a disk) that cost a
//! running max per chord (van Herk / Gil-Werman, [`crate::sliding_max`]) and *curved
//! offsets* (ball, cone, corner radius), folded [`LANES`] output samples at a time with the
//! accumulators in vector registers ([`crate::lane_max`]). A kernel row whose best possible
//! value (highest design sample in reach minus the row's smallest lift) cannot beat any
//! accumulator of the block is skipped; rows are visited from the centre out so that
//! happens early. Rows run in parallel.
//!
//! A kernel may be *shifted* by a fraction of a pixel along X: it then gives `T` at
//! `x + shift` for each grid point `x`. [`SubKernels`] evaluates a row at several points per
//! pixel; [`segment_bound`] turns those samples into heights that straight moves may join
//! without ever dipping below `T` (see there for why that is exact).
//!
//! A kernel can also be *widened*: along X by `along` mm (Minkowski sum with a segment) and
//! radially by `radial` mm (a roughing allowance).

use crate::lane_max::{fold_offsets, LANES};
use crate::sliding_max::window_max;
use crate::tool::Tool;
use oficina_io::Heightmap;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// A disk lifted by a constant: per kernel row the inclusive range of dx it covers.
#[derive(Clone, Debug)]
struct FlatPiece {
    lift: f32,
    span: Vec<Option<(i32, i32)>>,
}

/// A tool's footprint on the pixel grid: how high the tip sits above each pixel it
/// covers.
#[derive(Clone, Debug)]
pub struct Kernel {
    /// Offsets span −reach..=reach pixels in X and Y.
    pub reach: usize,
    flats: Vec<FlatPiece>,
    /// Per row offset dy (index dy + reach): (dx, lift) of the curved part.
    curved: Vec<Vec<(i32, f32)>>,
    /// Smallest lift in each row of `curved` (+∞ when empty), for skipping rows.
    least_lift: Vec<f32>,
    /// Row indices from the centre out.
    order: Vec<usize>,
    /// Every offset with its lift, for single-point queries.
    all: Vec<(i32, i32, f32)>,
}

impl Kernel {
    /// Kernel of `tool` on a grid of `pixel` mm, widened by `along` mm in X and `radial` mm
    /// in every direction.
    pub fn new(tool: &Tool, pixel: f64, along: f64, radial: f64) -> Kernel {
        Kernel::build(tool, pixel, along, radial, 0.0)
    }

    /// Kernel giving the tip height `shift` pixels (0 ≤ shift < 1) to the right of each
    /// grid point.
    pub fn shifted(tool: &Tool, pixel: f64, radial: f64, shift: f64) -> Kernel {
        Kernel::build(tool, pixel, 0.0, radial, shift)
    }

    fn build(tool: &Tool, pixel: f64, along: f64, radial: f64, shift: f64) -> Kernel {
        let reach = ((tool.reach_radius() + along + radial) / pixel + shift).ceil() as usize;
        Kernel::build_with_reach(tool, pixel, along, radial, shift, reach)
    }

    /// As `build`, with offsets up to `reach` pixels (at least what the tool needs).
    fn build_with_reach(
        tool: &Tool,
        pixel: f64,
        along: f64,
        radial: f64,
        shift: f64,
        reach: usize,
    ) -> Kernel {
        let r = reach as i32;
        let effective = |dx: i32, dy: i32| {
            let ex = (((dx as f64) - shift).abs() * pixel - along).max(0.0);
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
                span: (-r..=r)
                    .map(|dy| {
                        let inside: Vec<i32> =
                            (-r..=r).filter(|&dx| effective(dx, dy) <= limit).collect();
                        Some((*inside.first()?, *inside.last()?))
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
        let least_lift = curved
            .iter()
            .map(|row| row.iter().map(|o| o.1).fold(f32::INFINITY, f32::min))
            .collect();
        let mut order: Vec<usize> = (0..curved.len()).collect();
        order.sort_by_key(|&k| (k as i64 - r as i64).abs());
        Kernel {
            reach,
            flats,
            curved,
            least_lift,
            order,
            all,
        }
    }

    /// Number of offsets in the footprint.
    pub fn footprint(&self) -> usize {
        self.all.len()
    }
}

/// The design padded with −∞ columns so every offset (and a block of [`LANES`] past the
/// right edge) reads inside the buffer.
pub(crate) struct Padded<'a> {
    map: &'a Heightmap,
    pad: usize,
    stride: usize,
    data: Vec<f32>,
}

impl<'a> Padded<'a> {
    pub(crate) fn new(map: &'a Heightmap, pad: usize) -> Padded<'a> {
        let stride = map.width + 2 * pad + LANES;
        let mut data = vec![f32::NEG_INFINITY; stride * map.height];
        for iy in 0..map.height {
            data[iy * stride + pad..iy * stride + pad + map.width].copy_from_slice(map.row(iy));
        }
        Padded {
            map,
            pad,
            stride,
            data,
        }
    }

    fn row(&self, iy: usize) -> &[f32] {
        &self.data[iy * self.stride..(iy + 1) * self.stride]
    }
}

/// Reusable buffers of one worker.
#[derive(Default)]
pub(crate) struct Scratch {
    acc: Vec<f32>,
    window: Vec<f32>,
}

/// Tool-tip heights along row `iy` of `padded` (padded by at least `kernel.reach`).
pub(crate) fn surface_row(
    padded: &Padded,
    kernel: &Kernel,
    iy: usize,
    out: &mut [f32],
    scratch: &mut Scratch,
) {
    surface_row_multi(
        padded,
        std::slice::from_ref(kernel),
        iy,
        &mut [out],
        scratch,
    );
}

/// One row for several kernels of equal reach at once (the shifts of [`SubKernels`]): they
/// read the same design rows, so the test that skips a kernel row is paid once for all.
fn surface_row_multi(
    padded: &Padded,
    kernels: &[Kernel],
    iy: usize,
    outs: &mut [&mut [f32]],
    scratch: &mut Scratch,
) {
    let map = padded.map;
    let reach = kernels[0].reach;
    let (w, pad, r) = (map.width, padded.pad, reach as i64);
    assert!(pad >= reach, "padding narrower than the kernel");
    assert!(
        kernels.iter().all(|k| k.reach == reach),
        "kernels of unequal reach"
    );
    let blocks = w.div_ceil(LANES);
    let n = kernels.len();
    let acc = &mut scratch.acc;
    acc.clear();
    acc.resize(n * blocks * LANES, f32::NEG_INFINITY);
    let source = |k: usize| {
        let sy = iy as i64 + k as i64 - r;
        (sy >= 0 && sy < map.height as i64).then(|| padded.row(sy as usize))
    };
    for (s, kernel) in kernels.iter().enumerate() {
        let acc = &mut acc[s * blocks * LANES..][..w];
        for piece in &kernel.flats {
            for (k, span) in piece.span.iter().enumerate() {
                let (Some((lo, hi)), Some(src)) = (span, source(k)) else {
                    continue;
                };
                window_max(src, (hi - lo + 1) as usize, &mut scratch.window);
                let first = (pad as i64 + *lo as i64) as usize;
                for (o, &m) in acc.iter_mut().zip(&scratch.window[first..first + w]) {
                    *o = o.max(m - piece.lift);
                }
            }
        }
    }
    let mut lanes = vec![[f32::NEG_INFINITY; LANES]; n];
    let mut worst = vec![f32::NEG_INFINITY; n];
    for b in 0..blocks {
        let x0 = b * LANES;
        for (s, l) in lanes.iter_mut().enumerate() {
            *l = acc[(s * blocks + b) * LANES..][..LANES]
                .try_into()
                .expect("LANES long");
        }
        // Skipping needs every lane to be a real sample.
        let whole = x0 + LANES <= w;
        let mut stale = true;
        for &k in &kernels[0].order {
            let Some(src) = source(k) else { continue };
            let best = if whole {
                src[pad + x0 - reach..pad + x0 + LANES + reach]
                    .iter()
                    .fold(f32::NEG_INFINITY, |m, &v| m.max(v))
            } else {
                f32::INFINITY
            };
            if stale {
                for (w, l) in worst.iter_mut().zip(&lanes) {
                    *w = l.iter().fold(f32::INFINITY, |m, &v| m.min(v));
                }
                stale = false;
            }
            for (s, kernel) in kernels.iter().enumerate() {
                let offsets = &kernel.curved[k];
                // The row's best case (highest sample in reach, least lift) beats nothing.
                if offsets.is_empty() || best - kernel.least_lift[k] <= worst[s] {
                    continue;
                }
                fold_offsets(&mut lanes[s], src, pad + x0, offsets);
                stale = true;
            }
        }
        for (s, l) in lanes.iter().enumerate() {
            acc[(s * blocks + b) * LANES..][..LANES].copy_from_slice(l);
        }
    }
    for (s, out) in outs.iter_mut().enumerate() {
        out.copy_from_slice(&acc[s * blocks * LANES..][..w]);
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

/// [`surface_grid`] that gives up (`None`) once `cancel` is set, at the next row.
pub(crate) fn surface_grid_until(
    design: &Heightmap,
    kernel: &Kernel,
    cancel: &AtomicBool,
) -> Option<Heightmap> {
    let rows: Vec<usize> = (0..design.height).collect();
    let z = surface_rows_until(design, kernel, &rows, cancel)?.concat();
    Some(Heightmap {
        z,
        ..design.clone()
    })
}

/// The tool-tip surface along the listed rows only (in that order).
pub fn surface_rows(design: &Heightmap, kernel: &Kernel, rows: &[usize]) -> Vec<Vec<f32>> {
    surface_rows_until(design, kernel, rows, &AtomicBool::new(false)).expect("never cancelled")
}

/// [`surface_rows`] that gives up (`None`) once `cancel` is set: rows not yet begun are
/// skipped, so a cancel costs at most one row per thread.
pub(crate) fn surface_rows_until(
    design: &Heightmap,
    kernel: &Kernel,
    rows: &[usize],
    cancel: &AtomicBool,
) -> Option<Vec<Vec<f32>>> {
    let padded = Padded::new(design, kernel.reach);
    let out: Vec<Vec<f32>> = rows
        .par_iter()
        .map_init(Scratch::default, |scratch, &iy| {
            if cancel.load(Ordering::Relaxed) {
                return Vec::new();
            }
            let mut out = vec![0.0f32; design.width];
            surface_row(&padded, kernel, iy, &mut out, scratch);
            out
        })
        .collect();
    (!cancel.load(Ordering::Relaxed)).then_some(out)
}

/// Kernels for `count` evenly spaced points per pixel along X.
pub(crate) struct SubKernels {
    pub count: usize,
    kernels: Vec<Kernel>,
}

impl SubKernels {
    pub(crate) fn new(tool: &Tool, pixel: f64, radial: f64, count: usize) -> SubKernels {
        let count = count.max(1);
        let shift = |k: usize| k as f64 / count as f64;
        // One reach for all, so they can share the rows they read.
        let reach = (0..count)
            .map(|k| Kernel::shifted(tool, pixel, radial, shift(k)).reach)
            .max()
            .unwrap_or(0);
        SubKernels {
            count,
            kernels: (0..count)
                .map(|k| Kernel::build_with_reach(tool, pixel, 0.0, radial, shift(k), reach))
                .collect(),
        }
    }

    pub(crate) fn reach(&self) -> usize {
        self.kernels[0].reach
    }
}

/// Number of sub-samples along a row of `width` grid points at `count` per pixel.
pub(crate) fn sub_len(width: usize, count: usize) -> usize {
    width.saturating_sub(1) * count + 1
}

/// Tool-tip heights along the listed rows at `kernels.count` points per pixel: entry
/// `j` is the height at X = j / count pixels.
#[cfg(test)]
pub(crate) fn surface_rows_sub(
    design: &Heightmap,
    kernels: &SubKernels,
    rows: &[usize],
) -> Vec<Vec<f32>> {
    surface_rows_sub_until(design, kernels, rows, &AtomicBool::new(false)).expect("never cancelled")
}

/// [`surface_rows_sub`] that gives up (`None`) once `cancel` is set, at the next row.
pub(crate) fn surface_rows_sub_until(
    design: &Heightmap,
    kernels: &SubKernels,
    rows: &[usize],
    cancel: &AtomicBool,
) -> Option<Vec<Vec<f32>>> {
    let padded = Padded::new(design, kernels.reach());
    let (w, n) = (design.width, kernels.count);
    let out: Vec<Vec<f32>> = rows
        .par_iter()
        .map_init(
            || (Scratch::default(), vec![vec![0.0f32; w]; n]),
            |(scratch, shifts), &iy| {
                if cancel.load(Ordering::Relaxed) {
                    return Vec::new();
                }
                let mut views: Vec<&mut [f32]> = shifts.iter_mut().map(|v| &mut v[..]).collect();
                surface_row_multi(&padded, &kernels.kernels, iy, &mut views, scratch);
                let mut out = vec![0.0f32; sub_len(w, n)];
                for (k, one) in shifts.iter().enumerate() {
                    for (o, &t) in out.iter_mut().skip(k).step_by(n).zip(one.iter()) {
                        *o = t;
                    }
                }
                out
            },
        )
        .collect();
    (!cancel.load(Ordering::Relaxed)).then_some(out)
}

/// Turns tip heights sampled along a row (X = j·h) into heights that straight moves may
/// join: after it, any line whose ends and every sample between stand on or above these
/// values keeps the tool above the design at every X in between, not only at the samples.
///
/// Why this is exact and enough: `T(x)` is the max over design points `q` of
/// `design(q) − profile(|x − q|)`. Each such term is monotone in X between two grid
/// columns (the profile grows with distance and the term peaks at `q`'s own column), so on
/// a sub-interval `[j·h, (j+1)·h]` that holds no grid column inside it, `T ≤ max(T_j, T_j+1)`.
/// A line above that bound at both ends of the sub-interval is above it throughout; raising
/// each sample to the max of itself and its two neighbours states that for every
/// sub-interval a move may cross. Requires sample positions that include every grid column
/// (an integer number of samples per pixel).
pub(crate) fn segment_bound(tips: &mut [f32]) {
    let n = tips.len();
    if n < 2 {
        return;
    }
    let mut prev = tips[0];
    tips[0] = tips[0].max(tips[1]);
    for j in 1..n {
        let here = tips[j];
        let next = if j + 1 < n { tips[j + 1] } else { here };
        tips[j] = here.max(prev).max(next);
        prev = here;
    }
}

/// The tool-tip height over one grid point (brute force over the footprint): the unit
/// tests' oracle for the fast sweeps.
#[cfg(test)]
pub(crate) fn surface_at(design: &Heightmap, kernel: &Kernel, ix: usize, iy: usize) -> f32 {
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
pub(crate) fn transpose(map: &Heightmap) -> Heightmap {
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

    /// The definition at a fractional X (pixels), evaluated literally.
    fn brute_at(design: &Heightmap, tool: &Tool, x: f64, iy: usize) -> f64 {
        let mut best = f64::NEG_INFINITY;
        for qy in 0..design.height {
            for qx in 0..design.width {
                let d = ((qx as f64 - x).powi(2) + (qy as f64 - iy as f64).powi(2)).sqrt()
                    * design.pixel;
                if let Some(p) = tool.profile(d) {
                    best = best.max(design.at(qx, qy) as f64 - p);
                }
            }
        }
        best
    }

    #[test]
    fn sub_samples_match_the_definition_and_bound_every_point_between() {
        let design = bumpy();
        for spec in ["ball:4", "flat:2", "v:6:60", "bull:4:1"] {
            let tool: Tool = spec.parse().unwrap();
            let sub = 4;
            let kernels = SubKernels::new(&tool, design.pixel, 0.0, sub);
            let rows = [0, 17, design.height - 1];
            for (iy, tips) in rows.iter().zip(surface_rows_sub(&design, &kernels, &rows)) {
                assert_eq!(tips.len(), sub_len(design.width, sub));
                for (j, &t) in tips.iter().enumerate() {
                    let want = brute_at(&design, &tool, j as f64 / sub as f64, *iy);
                    assert!(
                        (t as f64 - want).abs() < 1e-4,
                        "{spec} {iy} {j}: {t} vs {want}"
                    );
                }
                // Lines between bounded samples stay above the surface at 16 points per
                // sub-interval, even through the pointed and flat tools' kinks.
                let mut bound = tips.clone();
                segment_bound(&mut bound);
                for j in 0..bound.len() - 1 {
                    for s in 0..=16 {
                        let f = s as f64 / 16.0;
                        let x = (j as f64 + f) / sub as f64;
                        let line = bound[j] as f64 * (1.0 - f) + bound[j + 1] as f64 * f;
                        let need = brute_at(&design, &tool, x, *iy);
                        assert!(line >= need - 1e-4, "{spec} {iy} at x {x}: {line} < {need}");
                    }
                }
            }
        }
    }
}
