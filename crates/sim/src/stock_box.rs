//! Simulating any program on a box of stock: the grid chosen from a memory budget, the
//! material removed with [`replay_watched`], and the moves a machinist must see before
//! running it (a rapid into material, a cut below the stock's bottom, cuts off the stock).

use crate::replay::{replay_watched, Move, MoveKind, SimError};
use oficina_cam::Tool;
use oficina_canon::Canon;
use oficina_io::Heightmap;
use std::borrow::Borrow;
use std::collections::HashMap;

/// Smallest and largest stock side accepted, mm: below a tenth of a millimetre nothing is
/// cut; above 10 m no router holds it (and a typo such as 1e9 must not size a grid).
pub const SIDE_RANGE_MM: (f64, f64) = (0.1, 10_000.0);

/// Finest grid chosen automatically, mm: finer shows nothing a router leaves.
pub const FINEST_AUTO_MM: f64 = 0.02;

/// Tool-footprint cell updates the automatic resolution allows for the whole program: a few
/// seconds of stamping (the cost grows as 1 / pixel³).
const WORK_BUDGET: f64 = 6e8;

/// Bytes per grid cell while simulating: the f32 stock, the PNG's byte, and (with a design)
/// the design and its ideal surface.
pub fn bytes_per_cell(with_design: bool) -> u64 {
    if with_design {
        4 + 1 + 4 + 4 + 4
    } else {
        4 + 1
    }
}

/// A box of stock: lower-left corner `origin` (program XY, mm), top at `top` (program Z),
/// `size` = width (X), height (Y), thickness (Z), mm.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StockBox {
    /// Lower-left corner, program X and Y, mm.
    pub origin: [f64; 2],
    /// Stock top, program Z, mm.
    pub top: f64,
    /// Width, height, thickness, mm.
    pub size: [f64; 3],
}

impl StockBox {
    /// Refuses a box that is not one: a side of 0, not a number, or beyond [`SIDE_RANGE_MM`].
    pub fn validate(&self) -> Result<(), String> {
        let (lo, hi) = SIDE_RANGE_MM;
        for (name, v) in ["width", "height", "thickness"].iter().zip(self.size) {
            if !(v.is_finite() && (lo..=hi).contains(&v)) {
                return Err(format!(
                    "stock {name} {v} mm: it must be between {lo} and {hi} mm"
                ));
            }
        }
        if !(self.origin.iter().all(|v| v.is_finite()) && self.top.is_finite()) {
            return Err("the stock origin must be finite numbers".into());
        }
        Ok(())
    }

    /// Stock bottom, program Z.
    pub fn bottom(&self) -> f64 {
        self.top - self.size[2]
    }

    /// Whether program point (x, y) lies over the stock.
    pub fn covers(&self, x: f64, y: f64) -> bool {
        let [x0, y0] = self.origin;
        (x0..=x0 + self.size[0]).contains(&x) && (y0..=y0 + self.size[1]).contains(&y)
    }
}

/// The grid the stock is sampled on: cells of `pixel` mm, `width` × `height` of them, and
/// why this pixel (for the report).
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Cell size, mm.
    pub pixel: f64,
    /// Cells along X.
    pub width: usize,
    /// Cells along Y.
    pub height: usize,
    /// How the pixel was chosen, in words.
    pub why: String,
}

/// What the grid choice needs to know of the program: feed length (mm) and the largest
/// tool radius, to bound the stamping work.
#[derive(Clone, Copy, Debug)]
pub struct Workload {
    /// Length of every move, mm.
    pub path_mm: f64,
    /// Largest tool radius, mm.
    pub tool_radius: f64,
}

/// Chooses the grid: `resolution` if given (refused when it would pass `budget` bytes),
/// else the finest pixel that fits the budget and keeps the stamping work bounded.
pub fn choose_grid(
    stock: &StockBox,
    resolution: Option<f64>,
    budget: u64,
    per_cell: u64,
    work: Workload,
) -> Result<Grid, String> {
    let [w, h, _] = stock.size;
    let cells_for = |p: f64| (w / p).round().max(1.0) * (h / p).round().max(1.0);
    let max_cells = budget as f64 / per_cell as f64;
    let mb = |b: f64| b / 1e6;
    let (pixel, why) = match resolution {
        Some(p) => {
            if !(p.is_finite() && p > 0.0) {
                return Err(format!("--resolution {p}: give a cell size in mm above 0"));
            }
            let need = cells_for(p) * per_cell as f64;
            if need > budget as f64 {
                return Err(format!(
                    "--resolution {p} mm on a {w} x {h} mm stock needs {:.0} MB, over the \
                     {:.0} MB budget (--memory-mb raises it; a coarser --resolution lowers the need)",
                    mb(need),
                    mb(budget as f64)
                ));
            }
            (p, format!("{p} mm as given (--resolution)"))
        }
        None => {
            let by_memory = (w * h / max_cells).sqrt();
            // Stamps per mm (4 per pixel) × cells per stamp (π r² / p²) × path: ∝ 1 / p³.
            let r = work.tool_radius.max(0.5);
            let by_work = (4.0 * work.path_mm * std::f64::consts::PI * r * r / WORK_BUDGET).cbrt();
            let p = FINEST_AUTO_MM.max(by_memory).max(by_work);
            let p = (p * 1000.0).ceil() / 1000.0;
            let reason = if p <= FINEST_AUTO_MM + 1e-9 {
                "the finest automatic cell".to_string()
            } else if by_memory >= by_work {
                format!(
                    "the finest that fits the {:.0} MB memory budget (--memory-mb, --resolution)",
                    mb(budget as f64)
                )
            } else {
                format!(
                    "the finest that keeps {:.0} mm of feed moves with a {:.1} mm tool to \
                     seconds of stamping (--resolution overrides)",
                    work.path_mm,
                    2.0 * work.tool_radius
                )
            };
            (p, format!("{p} mm, {reason}"))
        }
    };
    let (width, height) = (
        (w / pixel).round().max(1.0) as usize,
        (h / pixel).round().max(1.0) as usize,
    );
    Ok(Grid {
        pixel,
        width,
        height,
        why,
    })
}

/// A move to look at before running the program.
#[derive(Clone, Debug, PartialEq)]
pub enum Finding {
    /// A rapid that goes through material, `depth` mm into it at its worst.
    RapidIntoMaterial {
        /// Source line.
        line: u32,
        /// Deepest engagement, mm.
        depth: f64,
    },
    /// A move whose tip goes below the stock's bottom (into the table), to `z`.
    BelowBottom {
        /// Source line.
        line: u32,
        /// Lowest tip Z, program mm.
        z: f64,
    },
    /// A move that ends below the stock top and off the stock.
    OffStock {
        /// Source line.
        line: u32,
        /// The end point, program X and Y.
        at: [f64; 2],
    },
}

/// Findings of each kind kept with their line; past this only counted (bounded memory).
pub const FINDINGS_KEPT: usize = 50;

/// The simulated stock and what the replay found.
pub struct Simulated {
    /// The stock's top surface, program Z, on the grid (cell centres; clamped at the bottom).
    pub stock: Heightmap,
    /// Program XY of grid cell (0, 0)'s centre.
    pub cell_origin: [f64; 2],
    /// Material removed, mm³.
    pub removed_mm3: f64,
    /// Lowest and highest stock surface after the program, program Z.
    pub depth_range: (f64, f64),
    /// Area cut through to the bottom, mm².
    pub through_mm2: f64,
    /// The first [`FINDINGS_KEPT`] findings of each kind, in program order.
    pub findings: Vec<Finding>,
    /// How many of each kind there were: rapids into material, below bottom, off the stock.
    pub counts: [usize; 3],
}

/// Replays `ops` on `stock_box` sampled on `grid`, from `start` (program coordinates).
pub fn simulate<B: Borrow<Canon>>(
    ops: impl IntoIterator<Item = B>,
    tools: &HashMap<u32, Tool>,
    stock_box: &StockBox,
    grid: &Grid,
    start: [f64; 3],
) -> Result<Simulated, SimError> {
    let p = grid.pixel;
    let mut stock = Heightmap::flat(grid.width, grid.height, p, stock_box.top as f32);
    let cell_origin = [stock_box.origin[0] + p / 2.0, stock_box.origin[1] + p / 2.0];
    let mut findings = Vec::new();
    let mut counts = [0usize; 3];
    let mut keep = |f: Finding, kind: usize| {
        counts[kind] += 1;
        if counts[kind] <= FINDINGS_KEPT {
            findings.push(f);
        }
    };
    let (top, bottom) = (stock_box.top, stock_box.bottom());
    // A rapid grazing less than this is the stamping's own ripple, not a crash.
    let graze = (0.25 * p).max(0.05);
    replay_watched(ops, tools, &mut stock, start, cell_origin, |m, s| {
        let low = m.from[2].min(m.to[2]);
        if low < bottom - 1e-6 {
            keep(
                Finding::BelowBottom {
                    line: m.line,
                    z: low,
                },
                1,
            );
        }
        let end = [m.to[0] + cell_origin[0], m.to[1] + cell_origin[1]];
        // Only where the move ends below the top: a retract from there is not another cut.
        if m.to[2] < top - 1e-6 && !stock_box.covers(end[0], end[1]) {
            keep(
                Finding::OffStock {
                    line: m.line,
                    at: end,
                },
                2,
            );
        }
        if m.kind == MoveKind::Rapid && low < top {
            let depth = engagement(m, s);
            if depth > graze {
                keep(
                    Finding::RapidIntoMaterial {
                        line: m.line,
                        depth,
                    },
                    0,
                );
            }
        }
    })?;
    // Nothing is left below the bottom: a cut through leaves the bottom's height.
    let mut through = 0usize;
    let mut removed = 0.0f64;
    for v in stock.z.iter_mut() {
        if (*v as f64) <= bottom {
            *v = bottom as f32;
            through += 1;
        }
        removed += top - *v as f64;
    }
    let (lo, hi) = stock.range();
    Ok(Simulated {
        removed_mm3: removed * p * p,
        depth_range: (lo as f64, hi as f64),
        through_mm2: through as f64 * p * p,
        stock,
        cell_origin,
        findings,
        counts,
    })
}

/// How deep (mm) the tool moving along `m` (grid coordinates) would go into `stock` as it
/// stands: the most any cell stands above the tool's lower surface.
fn engagement(m: &Move, stock: &Heightmap) -> f64 {
    let p = stock.pixel;
    let (a, b) = (m.from, m.to);
    let len = (b[0] - a[0]).hypot(b[1] - a[1]);
    // Half a pixel apart: no cell is skipped; bounded by the move's length on the grid.
    let steps = ((len / (0.5 * p)).ceil() as usize).clamp(1, 4 * (stock.width + stock.height));
    let reach = m.tool.reach_radius();
    let mut worst = 0.0f64;
    for s in 0..=steps {
        let t = s as f64 / steps as f64;
        let (x, y, z) = (
            a[0] + (b[0] - a[0]) * t,
            a[1] + (b[1] - a[1]) * t,
            a[2] + (b[2] - a[2]) * t,
        );
        let ix0 = ((x - reach) / p).ceil().max(0.0) as usize;
        let iy0 = ((y - reach) / p).ceil().max(0.0) as usize;
        let ix1 = ((x + reach) / p).floor().min(stock.width as f64 - 1.0);
        let iy1 = ((y + reach) / p).floor().min(stock.height as f64 - 1.0);
        if ix1 < 0.0 || iy1 < 0.0 {
            continue;
        }
        for iy in iy0..=iy1 as usize {
            for ix in ix0..=ix1 as usize {
                let rho = (ix as f64 * p - x).hypot(iy as f64 * p - y);
                if let Some(lift) = m.tool.profile(rho) {
                    worst = worst.max(stock.at(ix, iy) as f64 - (z + lift));
                }
            }
        }
    }
    worst
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stock(w: f64, h: f64) -> StockBox {
        StockBox {
            origin: [0.0, 0.0],
            top: 0.0,
            size: [w, h, 10.0],
        }
    }

    #[test]
    fn the_automatic_grid_fits_the_budget_whatever_the_stock() {
        let work = Workload {
            path_mm: 1e5,
            tool_radius: 3.0,
        };
        let budget = 256_000_000;
        for (w, h) in [
            (10.0, 10.0),
            (600.0, 400.0),
            (10_000.0, 10_000.0),
            (0.1, 9000.0),
        ] {
            let g = choose_grid(&stock(w, h), None, budget, bytes_per_cell(true), work).unwrap();
            let bytes = (g.width * g.height) as u64 * bytes_per_cell(true);
            assert!(bytes <= budget, "{w} x {h}: {bytes} bytes ({g:?})");
            assert!(g.pixel >= FINEST_AUTO_MM, "{g:?}");
        }
    }

    #[test]
    fn stocks_that_are_not_ones_are_refused_by_their_side() {
        assert!(stock(0.0, 10.0).validate().unwrap_err().contains("width 0"));
        assert!(stock(10.0, 1e9).validate().unwrap_err().contains("height"));
        assert!(stock(f64::NAN, 10.0).validate().is_err());
        assert!(stock(100.0, 100.0).validate().is_ok());
    }
}
