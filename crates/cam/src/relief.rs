//! Relief carving from a height map: roughing by depth levels, rest machining where a
//! bigger tool could not reach, and raster finishing, all on exact drop-cutter surfaces.
//!
//! Every pass is the same loop: a target tip surface `T` (the design dilated by the tool,
//! sampled at several points per pixel along the raster and bounded so that straight feeds
//! between samples stay above it, see [`segment_bound`]),
//! a known-free surface `C` (the simulated stock dilated by the tool), and depth levels.
//! Level k cuts `max(T, z_k)` wherever that is below what is already free; what it cut
//! becomes free for level k+1. Nothing ever goes below `T`, so nothing gouges.

use crate::raster::{cut_rows, raster_rows, Clear, Emitter, Feeds, Frame, Row};
use crate::regions::{grow, label, Region};
use crate::stock::apply_moves;
use crate::surface::{
    segment_bound, sub_len, surface_grid, surface_rows_sub, transpose, Kernel, SubKernels,
};
use crate::tool::Tool;
use crate::toolpath::{Operation, Toolpath};
use oficina_io::Heightmap;

/// A tool with its cutting data.
#[derive(Clone, Debug, PartialEq)]
pub struct Cutter {
    pub number: u32,
    pub tool: Tool,
    pub feeds: Feeds,
    pub spindle_rpm: f64,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    X,
    Y,
    Both,
}

impl std::str::FromStr for Direction {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.to_ascii_lowercase().as_str() {
            "x" => Ok(Direction::X),
            "y" => Ok(Direction::Y),
            "both" | "xy" => Ok(Direction::Both),
            other => Err(format!(
                "unknown raster direction '{other}': use x, y or both"
            )),
        }
    }
}

/// One pass of one tool.
#[derive(Clone, Debug, PartialEq)]
pub struct Pass {
    pub name: String,
    pub cutter: Cutter,
    /// mm between raster rows.
    pub stepover: f64,
    /// Largest depth of cut per level, mm.
    pub stepdown: f64,
    /// Material left above the design, mm (roughing).
    pub allowance: f64,
    pub direction: Direction,
    pub zigzag: bool,
    /// Only where the stock left by earlier passes stands more than `min_cut` above this
    /// tool's target, region by region (rest machining).
    pub rest_only: bool,
    /// Thinnest layer worth a visit, mm.
    pub min_cut: f64,
}

#[derive(Clone, Debug, PartialEq)]
pub struct Job {
    pub safe_z: f64,
    /// Height above free stock for short travels, mm.
    pub clearance: f64,
    /// How far straight feeds may stay above the surface when merging samples, mm.
    pub tolerance: f64,
    /// Tip heights evaluated per pixel along the raster (1 or more): more points leave less
    /// material on slopes (the bound between samples tightens) at proportional cost.
    pub samples_per_pixel: usize,
    pub passes: Vec<Pass>,
    /// Simulate the stock after the last pass too (for reports); earlier passes are
    /// always simulated since the next pass starts from their stock.
    pub simulate_last: bool,
}

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ReliefError {
    #[error("pass '{pass}': {what} must be a finite number above 0, got {value}")]
    Parameter {
        pass: String,
        what: &'static str,
        value: f64,
    },
    #[error("pass '{pass}': the tool spans {reach} pixels each side at {pixel} mm per pixel (at most {max}); use a coarser pixel size")]
    ToolTooLarge {
        pass: String,
        reach: usize,
        pixel: f64,
        max: usize,
    },
    #[error("the height map is empty")]
    EmptyDesign,
    #[error("{0} must be finite and at least 0")]
    Job(&'static str),
    #[error("samples per pixel must be between 1 and {max}, got {got}")]
    Samples { got: usize, max: usize },
}

/// Default tip heights per pixel along the raster.
pub const SAMPLES_PER_PIXEL: usize = 4;
/// Most tip heights per pixel accepted.
pub const MAX_SAMPLES_PER_PIXEL: usize = 16;

/// Largest kernel half-width, in pixels, that keeps the footprint table small.
pub const MAX_REACH_PX: usize = 1000;

/// Progress: stage name and fraction done.
pub type Progress<'a> = &'a (dyn Fn(&str, f64) + Sync);

pub struct Planned {
    pub toolpath: Toolpath,
    /// Stock after the simulated passes (`None` if nothing was simulated).
    pub stock: Option<Heightmap>,
}

pub fn plan(design: &Heightmap, job: &Job, progress: Progress) -> Result<Planned, ReliefError> {
    if design.width == 0 || design.height == 0 {
        return Err(ReliefError::EmptyDesign);
    }
    if !(job.safe_z.is_finite() && job.safe_z >= 0.0) {
        return Err(ReliefError::Job("safe Z"));
    }
    if !(job.clearance.is_finite() && job.clearance >= 0.0) {
        return Err(ReliefError::Job("clearance"));
    }
    if !(job.tolerance.is_finite() && job.tolerance >= 0.0) {
        return Err(ReliefError::Job("tolerance"));
    }
    if !(1..=MAX_SAMPLES_PER_PIXEL).contains(&job.samples_per_pixel) {
        return Err(ReliefError::Samples {
            got: job.samples_per_pixel,
            max: MAX_SAMPLES_PER_PIXEL,
        });
    }
    for p in &job.passes {
        check_pass(p, design.pixel)?;
    }
    let mut stock: Option<Heightmap> = None;
    let mut operations = Vec::new();
    let mut pos: Option<[f64; 3]> = None;
    for (i, pass) in job.passes.iter().enumerate() {
        let mut em = Emitter::new(pass.cutter.feeds, job.safe_z, job.clearance);
        em.pos = pos;
        let directions: &[bool] = match pass.direction {
            Direction::X => &[false],
            Direction::Y => &[true],
            Direction::Both => &[false, true],
        };
        for (d, &along_y) in directions.iter().enumerate() {
            let stage = format!(
                "{} ({})",
                pass.name,
                if along_y { "along Y" } else { "along X" }
            );
            progress(&stage, 0.0);
            let before = em.moves.len();
            cut_pass(
                &mut em,
                design,
                stock.as_ref(),
                pass,
                along_y,
                job.tolerance,
                job.samples_per_pixel,
            );
            let last = i + 1 == job.passes.len() && d + 1 == directions.len();
            if !last || job.simulate_last {
                // The next direction or pass starts from what this one left.
                let s = stock.get_or_insert_with(|| {
                    Heightmap::flat(design.width, design.height, design.pixel, 0.0)
                });
                let start = if before == 0 {
                    pos.unwrap_or([0.0, 0.0, job.safe_z])
                } else {
                    em_pos_before(&em, before)
                };
                apply_moves(s, &pass.cutter.tool, start, &em.moves[before..]);
            }
            progress(&stage, 1.0);
        }
        em.retract();
        pos = em.pos;
        operations.push(Operation {
            name: pass.name.clone(),
            tool_number: pass.cutter.number,
            tool: pass.cutter.tool.clone(),
            spindle_rpm: pass.cutter.spindle_rpm,
            moves: em.moves,
        });
    }
    Ok(Planned {
        toolpath: Toolpath {
            safe_z: job.safe_z,
            operations,
        },
        stock,
    })
}

/// Where the tool was before move `index`.
fn em_pos_before(em: &Emitter, index: usize) -> [f64; 3] {
    em.moves[..index]
        .iter()
        .rev()
        .find_map(|m| m.end())
        .unwrap_or([0.0, 0.0, em.safe_z])
}

fn check_pass(p: &Pass, pixel: f64) -> Result<(), ReliefError> {
    let bad = |what, value: f64| ReliefError::Parameter {
        pass: p.name.clone(),
        what,
        value,
    };
    for (what, v) in [
        ("stepover", p.stepover),
        ("stepdown", p.stepdown),
        ("cutting feed", p.cutter.feeds.cut),
        ("plunge feed", p.cutter.feeds.plunge),
    ] {
        if !(v.is_finite() && v > 0.0) {
            return Err(bad(what, v));
        }
    }
    if !(p.allowance.is_finite() && p.allowance >= 0.0) {
        return Err(bad("allowance", p.allowance));
    }
    if !(p.min_cut.is_finite() && p.min_cut > 0.0) {
        return Err(bad("minimum cut", p.min_cut));
    }
    let reach = ((p.cutter.tool.reach_radius() + pixel + p.allowance) / pixel).ceil();
    if reach > MAX_REACH_PX as f64 {
        return Err(ReliefError::ToolTooLarge {
            pass: p.name.clone(),
            reach: reach as usize,
            pixel,
            max: MAX_REACH_PX,
        });
    }
    Ok(())
}

/// Depth levels: floors every `stepdown` down to the deepest target.
fn level_floors(deepest: f32, top: f32, stepdown: f64) -> Vec<f32> {
    let mut floors = Vec::new();
    let mut k = 1;
    loop {
        let z = top as f64 - k as f64 * stepdown;
        if z <= deepest as f64 {
            floors.push(f32::NEG_INFINITY);
            return floors;
        }
        floors.push(z as f32);
        k += 1;
    }
}

fn cut_pass(
    em: &mut Emitter,
    design: &Heightmap,
    stock: Option<&Heightmap>,
    pass: &Pass,
    along_y: bool,
    tol: f64,
    sub: usize,
) {
    let tool = &pass.cutter.tool;
    let grid = if along_y {
        transpose(design)
    } else {
        design.clone()
    };
    let frame = Frame {
        pixel: design.pixel,
        along_y,
        sub,
    };
    let clear_grid = stock.map(|s| {
        let s = if along_y { transpose(s) } else { s.clone() };
        surface_grid(&s, &Kernel::new(tool, s.pixel, 0.0, 0.0))
    });
    let clear = match &clear_grid {
        Some(c) => Clear::Grid {
            width: c.width,
            z: &c.z,
        },
        None => Clear::Top(0.0),
    };
    let rows = raster_rows(grid.height, grid.pixel, pass.stepover);
    let allowance = pass.allowance as f32;

    // The blocks to machine: the whole grid, or the regions with material left.
    let (blocks, labels): (Vec<Region>, Option<Vec<u32>>) = if pass.rest_only {
        let full = surface_grid(&grid, &Kernel::new(tool, grid.pixel, 0.0, pass.allowance));
        let mask: Vec<bool> = full
            .z
            .iter()
            .zip(0..)
            .map(|(&t, i)| {
                t + allowance < clear.at(i % grid.width, i / grid.width) - pass.min_cut as f32
            })
            .collect();
        let grown = grow(&mask, grid.width, tool.cutting_radius() / grid.pixel);
        let (labels, regions) = label(&grown, grid.width);
        (regions, Some(labels))
    } else {
        (
            vec![Region {
                label: 1,
                x0: 0,
                y0: 0,
                x1: grid.width - 1,
                y1: grid.height - 1,
                area: grid.width * grid.height,
            }],
            None,
        )
    };
    let kernels = SubKernels::new(tool, grid.pixel, pass.allowance, sub);
    let targets: Vec<Vec<f32>> = surface_rows_sub(&grid, &kernels, &rows)
        .into_iter()
        .map(|mut r| {
            r.iter_mut().for_each(|t| *t += allowance);
            segment_bound(&mut r);
            r
        })
        .collect();
    let samples = sub_len(grid.width, sub);
    // Grid column(s) either side of sample j.
    let columns = |j: usize| (j / sub, j.div_ceil(sub));

    let mut todo: Vec<&Region> = blocks.iter().collect();
    while !todo.is_empty() {
        // Nearest block next: less air time than scanning in label order.
        let here = em.pos.unwrap_or([0.0, 0.0, em.safe_z]);
        let (k, _) = todo
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let p = frame.point(r.y0, r.x0 * sub, 0.0);
                (k, (p[0] - here[0]).powi(2) + (p[1] - here[1]).powi(2))
            })
            .fold(
                (0, f64::INFINITY),
                |best, c| if c.1 < best.1 { c } else { best },
            );
        let region = todo.swap_remove(k);
        let members: Vec<usize> = (0..rows.len())
            .filter(|&i| rows[i] >= region.y0 && rows[i] <= region.y1)
            .collect();
        if members.is_empty() {
            continue;
        }
        let mut block_rows: Vec<Row> = members
            .iter()
            .map(|&i| {
                let iy = rows[i];
                Row {
                    index: iy,
                    target: targets[i].clone(),
                    // Free heights are a dilation too: between columns at most their max.
                    clear: (0..samples)
                        .map(|j| {
                            let (a, b) = columns(j);
                            clear.at(a, iy).max(clear.at(b, iy))
                        })
                        .collect(),
                    allowed: labels.as_ref().map(|l| {
                        let row = &l[iy * grid.width..(iy + 1) * grid.width];
                        (0..samples)
                            .map(|j| {
                                let (a, b) = columns(j);
                                row[a] == region.label && row[b] == region.label
                            })
                            .collect()
                    }),
                }
            })
            .collect();
        let deepest = members
            .iter()
            .flat_map(|&i| targets[i].iter().cloned())
            .fold(f32::INFINITY, f32::min);
        let top = block_rows
            .iter()
            .flat_map(|r| r.clear.iter().cloned())
            .fold(f32::NEG_INFINITY, f32::max);
        for floor in level_floors(deepest, top, pass.stepdown) {
            let level_rows: Vec<Row> = block_rows
                .iter()
                .zip(&members)
                .map(|(r, &i)| Row {
                    index: r.index,
                    target: targets[i].iter().map(|&t| t.max(floor)).collect(),
                    clear: r.clear.clone(),
                    allowed: r.allowed.clone(),
                })
                .collect();
            cut_rows(
                em,
                frame,
                &level_rows,
                &clear,
                pass.zigzag,
                pass.min_cut as f32,
                tol,
            );
            // What this level reached is free for the next one.
            for (r, l) in block_rows.iter_mut().zip(&level_rows) {
                for (c, &t) in r.clear.iter_mut().zip(&l.target) {
                    *c = c.min(t);
                }
            }
        }
    }
}
