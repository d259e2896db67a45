//! CAM on triangle meshes: exact drop-cutter for every tool shape ([`DropCutter`]), the
//! height field it gives for roughing ([`DropCutter::height_field`]), raster finishing
//! that follows the cutter-location surface between samples ([`raster`]), waterline loops
//! ([`loops_at`]), the two mixed by slope ([`Strategy`]) and z-level roughing ([`rough`]).

mod drop;
mod finish;
mod grid;
mod mix;
mod waterline;
mod zlevel;

pub use finish::{finishing_moves, raster, Raster};
pub use mix::{flat_pieces, level_spacing, split, waterline_pieces, Strategy, OVERLAP};
pub use waterline::{loops_at, ContactGrid};
pub use zlevel::{bytes_estimate as zlevel_bytes, grown, rough, ZLevel};

use crate::Tool;
use drop::Shape;
use grid::Buckets;
use oficina_io::{Heightmap, Mesh};
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};

/// A mesh made ready for dropping one tool onto it (triangles bucketed by XY).
pub struct DropCutter<'c> {
    shape: Shape,
    buckets: Buckets,
    /// Once set, every drop answers `None` at once: the loops over drops (rows, grids,
    /// bisections, on any number of threads) run out fast and their caller, which reads the
    /// flag after them, gives up.
    cancel: Option<&'c AtomicBool>,
}

impl<'c> DropCutter<'c> {
    /// Buckets `mesh`'s triangles for `tool` (its cutting part; shank and holder are not
    /// checked, as in OpenCAMLib).
    pub fn new(mesh: &Mesh, tool: &Tool) -> DropCutter<'c> {
        let shape = Shape::of(tool);
        DropCutter {
            buckets: Buckets::new(&mesh.triangles, shape.radius()),
            shape,
            cancel: None,
        }
    }

    /// The same cutter, stopped by `cancel` (see the field).
    pub fn cancelled_by(self, cancel: &'c AtomicBool) -> DropCutter<'c> {
        DropCutter {
            cancel: Some(cancel),
            ..self
        }
    }

    /// Whether the cancel flag is set.
    pub fn is_cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// Bytes [`DropCutter::new`] allocates for `triangles` triangles, at most.
    pub fn bytes_estimate(triangles: usize) -> u64 {
        Buckets::bytes_estimate(triangles)
    }

    /// The cutting radius, mm.
    pub fn radius(&self) -> f64 {
        self.shape.radius()
    }

    /// The tip height (mm) of the tool dropped along the vertical through `(x, y)` until it
    /// touches the mesh; `None` when no triangle is within the tool's radius.
    pub fn drop(&self, x: f64, y: f64) -> Option<f64> {
        if self.is_cancelled() {
            return None;
        }
        self.buckets.drop(&self.shape, [x, y])
    }

    /// [`DropCutter::drop`] at every point, on all cores.
    pub fn drop_all(&self, points: &[[f64; 2]]) -> Vec<Option<f64>> {
        points.par_iter().map(|p| self.drop(p[0], p[1])).collect()
    }

    /// The tip heights on a grid of `pixel` mm from `origin` (X, Y), `width × height`
    /// samples, `floor` where the mesh is out of reach or lower, as a heightmap (heights
    /// relative to `top`: the relief's stock top is 0).
    pub fn height_field(
        &self,
        origin: [f64; 2],
        pixel: f64,
        width: usize,
        height: usize,
        floor: f64,
        top: f64,
    ) -> Heightmap {
        let z: Vec<f32> = (0..height)
            .into_par_iter()
            .flat_map_iter(|iy| {
                let y = origin[1] + iy as f64 * pixel;
                (0..width).map(move |ix| {
                    let x = origin[0] + ix as f64 * pixel;
                    let z = self.drop(x, y).unwrap_or(floor).max(floor).min(top);
                    (z - top) as f32
                })
            })
            .collect();
        Heightmap {
            width,
            height,
            pixel,
            z,
        }
    }
}

/// A test model always at hand: a sphere of `radius` mm centred on the top of a square
/// plate `side` mm wide and `thickness` thick (top at z = 0, corner at the origin), the
/// sphere cut by the plate; `n` segments around (a multiple of 4).
pub fn sphere_on_plate(side: f64, thickness: f64, radius: f64, n: usize) -> Mesh {
    let n = n.max(8);
    let c = [side / 2.0, side / 2.0];
    let mut triangles = Vec::new();
    // Upper half of the sphere: rings at polar angles 0..90°, the last one on the plate.
    let ring = |k: usize| -> Vec<[f64; 3]> {
        let th = std::f64::consts::FRAC_PI_2 * k as f64 / (n / 4) as f64;
        (0..n)
            .map(|j| {
                let ph = std::f64::consts::TAU * j as f64 / n as f64;
                let rr = radius * th.sin();
                [
                    c[0] + rr * ph.cos(),
                    c[1] + rr * ph.sin(),
                    radius * th.cos(),
                ]
            })
            .collect()
    };
    let rings: Vec<Vec<[f64; 3]>> = (0..=n / 4).map(ring).collect();
    for k in 0..n / 4 {
        for j in 0..n {
            let (a, b) = (rings[k][j], rings[k][(j + 1) % n]);
            let (p, q) = (rings[k + 1][j], rings[k + 1][(j + 1) % n]);
            if k > 0 {
                triangles.push([a, p, b]);
            }
            triangles.push([b, p, q]);
        }
    }
    // The plate's top: two triangles under the sphere too (drop-cutter and distances only
    // see the union of the surfaces, so the overlap is harmless).
    let corners = [[0.0, 0.0], [side, 0.0], [side, side], [0.0, side]];
    triangles.push([[0.0, 0.0, 0.0], [side, 0.0, 0.0], [side, side, 0.0]]);
    triangles.push([[0.0, 0.0, 0.0], [side, side, 0.0], [0.0, side, 0.0]]);
    // Plate sides and bottom.
    let (lo, hi) = (-thickness, 0.0);
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        triangles.push([[a[0], a[1], lo], [b[0], b[1], lo], [b[0], b[1], hi]]);
        triangles.push([[a[0], a[1], lo], [b[0], b[1], hi], [a[0], a[1], hi]]);
    }
    triangles.push([[0.0, 0.0, lo], [side, side, lo], [side, 0.0, lo]]);
    triangles.push([[0.0, 0.0, lo], [0.0, side, lo], [side, side, lo]]);
    Mesh { triangles }
}
