//! How the simulated stock compares with the design.

use oficina_cam::Tool;
use oficina_cam::{surface_grid, Kernel};
use oficina_io::Heightmap;

/// How a simulated stock compares with its design (gouges, leftover, scallops).
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Deepest cut below the design, mm (0 = no gouge).
    pub max_gouge: f64,
    /// Where it is (mm).
    pub gouge_at: [f64; 2],
    /// Material left above the design, mm: includes what no tool of this shape can reach.
    pub leftover_max: f64,
    /// Mean material left above the design, mm.
    pub leftover_mean: f64,
    /// Material left above the best surface the finishing tool can make (the design opened
    /// by the tool): the scallops and anything the toolpath missed.
    pub scallop_max: f64,
    /// Mean of the scallop heights, mm.
    pub scallop_mean: f64,
}

/// The lowest surface any placement of `tool` above the design can leave: the design
/// dilated by the tool (tip heights) and eroded back (the tool's lower envelope).
pub fn ideal_surface(design: &Heightmap, tool: &Tool) -> Heightmap {
    let kernel = Kernel::new(tool, design.pixel, 0.0, 0.0);
    let tips = surface_grid(design, &kernel);
    // Erosion = −dilation of the negated field, since the tool is symmetric.
    let negated = Heightmap {
        z: tips.z.iter().map(|v| -v).collect(),
        ..tips
    };
    let eroded = surface_grid(&negated, &kernel);
    Heightmap {
        z: eroded.z.iter().map(|v| -v).collect(),
        ..eroded
    }
}

/// Compares `stock` with `design` (same grid) and, for scallops, with `ideal`.
pub fn compare(stock: &Heightmap, design: &Heightmap, ideal: &Heightmap) -> Report {
    let mut r = Report {
        max_gouge: 0.0,
        gouge_at: [0.0; 2],
        leftover_max: 0.0,
        leftover_mean: 0.0,
        scallop_max: 0.0,
        scallop_mean: 0.0,
    };
    let (mut left_sum, mut scallop_sum) = (0.0f64, 0.0f64);
    for (i, ((&s, &d), &best)) in stock.z.iter().zip(&design.z).zip(&ideal.z).enumerate() {
        let over = s as f64 - d as f64;
        if -over > r.max_gouge {
            r.max_gouge = -over;
            r.gouge_at = [design.x(i % design.width), design.y(i / design.width)];
        }
        let over = over.max(0.0);
        left_sum += over;
        r.leftover_max = r.leftover_max.max(over);
        let scallop = (s as f64 - best.max(d) as f64).max(0.0);
        scallop_sum += scallop;
        r.scallop_max = r.scallop_max.max(scallop);
    }
    let n = stock.z.len().max(1) as f64;
    r.leftover_mean = left_sum / n;
    r.scallop_mean = scallop_sum / n;
    r
}
