//! Relief carving from a height map: roughing by depth levels, rest machining where a
//! bigger tool could not reach, and raster finishing, all on exact drop-cutter surfaces.
//!
//! Every pass is the same loop: a target tip surface `T` (the design dilated by the tool,
//! sampled at several points per pixel along the raster and bounded so that straight feeds
//! between samples stay above it, see [`segment_bound`]),
//! a known-free surface `C` (the simulated stock dilated by the tool), and depth levels.
//! Level k cuts `max(T, z_k)` wherever that is below what is already free; what it cut
//! becomes free for level k+1. Nothing ever goes below `T`, so nothing gouges.

use crate::memory::{check, Budget, Lever, OverBudget, PassShape};
use crate::raster::{cut_rows, raster_rows, Clear, Emitter, Feeds, Frame, Row};
use crate::regions::{grow, label, Region};
use crate::stock::apply_moves;
use crate::surface::{
    segment_bound, sub_len, surface_grid_until, surface_rows_sub_until, transpose, Kernel,
    SubKernels,
};
use crate::tool::Tool;
use crate::toolpath::{Operation, Toolpath};
use oficina_io::Heightmap;
use std::sync::atomic::{AtomicBool, Ordering};

/// A tool with its cutting data.
#[derive(Clone, Debug, PartialEq)]
pub struct Cutter {
    /// Tool number in the program.
    pub number: u32,
    /// The cutter.
    pub tool: Tool,
    /// Cutting and plunge feeds.
    pub feeds: Feeds,
    /// Spindle speed, rpm.
    pub spindle_rpm: f64,
}

/// Which way raster rows run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Rows along X.
    X,
    /// Rows along Y.
    Y,
    /// Along X, then along Y.
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
    /// The pass's name for comments and reports.
    pub name: String,
    /// The tool and its cutting data.
    pub cutter: Cutter,
    /// mm between raster rows.
    pub stepover: f64,
    /// Largest depth of cut per level, mm.
    pub stepdown: f64,
    /// Material left above the design, mm (roughing).
    pub allowance: f64,
    /// Which way the rows run.
    pub direction: Direction,
    /// Cut both ways along alternate rows (else one way, rapid back).
    pub zigzag: bool,
    /// Only where the stock left by earlier passes stands more than `min_cut` above this
    /// tool's target, region by region (rest machining).
    pub rest_only: bool,
    /// Thinnest layer worth a visit, mm.
    pub min_cut: f64,
}

/// A relief (heightmap) job: passes of raster machining.
#[derive(Clone, Debug, PartialEq)]
pub struct ReliefJob {
    /// Height for rapids, mm.
    pub safe_z: f64,
    /// Height above free stock for short travels, mm.
    pub clearance: f64,
    /// How far straight feeds may stay above the surface when merging samples, mm.
    pub tolerance: f64,
    /// Tip heights evaluated per pixel along the raster (1 or more): more points leave less
    /// material on slopes (the bound between samples tightens) at proportional cost.
    pub samples_per_pixel: usize,
    /// The passes, in cutting order.
    pub passes: Vec<Pass>,
    /// Simulate the stock after the last pass too (for reports); earlier passes are
    /// always simulated since the next pass starts from their stock.
    pub simulate_last: bool,
}

/// Why a relief job could not be planned.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ReliefError {
    /// A pass setting is not a finite number above 0.
    #[error("pass '{pass}': {what} must be a finite number above 0, got {value}")]
    Parameter {
        /// The pass's name.
        pass: String,
        /// The setting.
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// The tool spans more pixels than the footprint table holds.
    #[error("pass '{pass}': the tool spans {reach} pixels each side at {pixel} mm per pixel (at most {max}); use a coarser pixel size")]
    ToolTooLarge {
        /// The pass's name.
        pass: String,
        /// Pixels each side the tool spans.
        reach: usize,
        /// Pixel size, mm.
        pixel: f64,
        /// Largest reach allowed, pixels.
        max: usize,
    },
    /// The step-down is too small.
    #[error("pass '{pass}': step-down {value} mm is below {MIN_STEPDOWN_MM} mm")]
    StepDown {
        /// The pass's name.
        pass: String,
        /// The step-down given, mm.
        value: f64,
    },
    /// The height map has no samples.
    #[error("the height map is empty")]
    EmptyDesign,
    /// The pixel size is not a finite number above 0.
    #[error("the pixel size must be a finite number above 0, got {0}")]
    Pixel(f64),
    /// The part would be larger than any machine.
    #[error("the part would be {size:.0} mm {what}, more than any machine's {MAX_EXTENT_MM} mm; use a smaller pixel size or depth")]
    TooLarge {
        /// "wide", "long" or "deep".
        what: &'static str,
        /// The size, mm.
        size: f64,
    },
    /// The height map's size does not match its samples.
    #[error("the height map claims {width} x {height} samples but holds {len}")]
    CutterShape {
        /// Columns claimed.
        width: usize,
        /// Rows claimed.
        height: usize,
        /// Samples held.
        len: usize,
    },
    /// A job setting is negative or not finite; names it.
    #[error("{0} must be finite and at least 0")]
    ReliefJob(&'static str),
    /// Samples per pixel out of range.
    #[error("samples per pixel must be between 1 and {max}, got {got}")]
    Samples {
        /// The value given.
        got: usize,
        /// Largest allowed.
        max: usize,
    },
    /// The plan would need more memory than allowed.
    #[error(transparent)]
    Memory(#[from] OverBudget),
    /// The caller cancelled the planning.
    #[error("cancelled")]
    Cancelled,
}

/// Largest size of a part in X, Y or Z, mm (100 m: beyond any router's travel, and far
/// inside what f64 coordinates and G-code numbers carry exactly enough).
pub const MAX_EXTENT_MM: f64 = 100_000.0;

/// How far a program may place the tool from the planned XY, mm: posts write 4 decimals, so
/// each axis rounds by up to 0.05 µm, 0.07 µm both together. The targets are the tool-tip
/// surface dilated over a disk this wide, so a rounded move still touches nothing below the
/// design: on a 1° tapered ball's flank 0.07 µm across is 4 µm down.
pub const XY_ROUNDING_MM: f64 = 1.0e-4;

/// Smallest step-down, mm (1 µm).
pub const MIN_STEPDOWN_MM: f64 = 1.0e-3;

/// Default tip heights per pixel along the raster.
pub const SAMPLES_PER_PIXEL: usize = 4;
/// Most tip heights per pixel accepted.
pub const MAX_SAMPLES_PER_PIXEL: usize = 16;

/// Largest kernel half-width, in pixels, that keeps the footprint table small.
pub const MAX_REACH_PX: usize = 1000;

/// Progress: stage name and fraction done.
pub type Progress<'a> = &'a (dyn Fn(&str, f64) + Sync);

/// A planned relief job.
pub struct Planned {
    /// The toolpath of every pass.
    pub toolpath: Toolpath,
    /// Stock after the simulated passes (`None` if nothing was simulated).
    pub stock: Option<Heightmap>,
}

/// Plans `job` on `design` with no memory limit; see [`plan_within`].
pub fn plan(
    design: &Heightmap,
    job: &ReliefJob,
    progress: Progress,
) -> Result<Planned, ReliefError> {
    plan_within(design, job, Budget::UNLIMITED, progress)
}

/// Plans `job` on `design`. Every pass's grids are estimated before any is allocated and the
/// moves are counted as they grow: whatever would exceed `budget` is refused
/// ([`ReliefError::Memory`]) instead of allocated.
pub fn plan_within(
    design: &Heightmap,
    job: &ReliefJob,
    budget: Budget,
    progress: Progress,
) -> Result<Planned, ReliefError> {
    plan_cancellable(design, job, budget, progress, &AtomicBool::new(false))
}

/// Simulated moves applied to the stock between two looks at the cancel flag.
const MOVES_PER_CANCEL_CHECK: usize = 4096;

/// [`plan_within`] that stops with [`ReliefError::Cancelled`] soon after `cancel` is set:
/// the flag is read per row of every tool-shape surface, per depth level (when progress
/// within the pass is reported too) and per few thousand simulated moves, so a cancel
/// waits for at most one of those, never for a whole pass.
pub fn plan_cancellable(
    design: &Heightmap,
    job: &ReliefJob,
    budget: Budget,
    progress: Progress,
    cancel: &AtomicBool,
) -> Result<Planned, ReliefError> {
    plan_after(design, job, budget, progress, cancel, None)
}

/// [`plan_cancellable`] on the stock `earlier` passes left (same grid as `design`, 0 at
/// the stock top), e.g. a mesh's z-level roughing: a rest pass starts from it.
pub fn plan_after(
    design: &Heightmap,
    job: &ReliefJob,
    budget: Budget,
    progress: Progress,
    cancel: &AtomicBool,
    earlier: Option<Heightmap>,
) -> Result<Planned, ReliefError> {
    let cancelled = || {
        if cancel.load(Ordering::Relaxed) {
            Err(ReliefError::Cancelled)
        } else {
            Ok(())
        }
    };
    if design.width == 0 || design.height == 0 {
        return Err(ReliefError::EmptyDesign);
    }
    if !(design.pixel.is_finite() && design.pixel > 0.0) {
        return Err(ReliefError::Pixel(design.pixel));
    }
    let (ex, ey) = design.extent();
    let side = ex.max(ey);
    if !(side <= MAX_EXTENT_MM) {
        return Err(ReliefError::TooLarge {
            what: "wide",
            size: side,
        });
    }
    if !(job.safe_z.is_finite() && job.safe_z >= 0.0) {
        return Err(ReliefError::ReliefJob("safe Z"));
    }
    if !(job.clearance.is_finite() && job.clearance >= 0.0) {
        return Err(ReliefError::ReliefJob("clearance"));
    }
    if !(job.tolerance.is_finite() && job.tolerance >= 0.0) {
        return Err(ReliefError::ReliefJob("tolerance"));
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
    for (i, pass) in job.passes.iter().enumerate() {
        for (d, &along_y) in directions(pass.direction).iter().enumerate() {
            let shape = pass_shape(design, pass, along_y, job.samples_per_pixel, i + d > 0);
            check(
                || {
                    format!(
                        "pass '{}' ({} rows of {} x {} grid points)",
                        pass.name, shape.rows, shape.width, shape.height
                    )
                },
                shape.bytes().saturating_add(budget.reserved),
                budget.bytes,
                Lever::PixelSize,
            )?;
        }
    }
    if design.width.checked_mul(design.height) != Some(design.z.len()) {
        return Err(ReliefError::CutterShape {
            width: design.width,
            height: design.height,
            len: design.z.len(),
        });
    }
    let (lo, hi) = design.range();
    let deep = (hi as f64 - lo as f64)
        .max(hi.abs() as f64)
        .max(lo.abs() as f64);
    if !(deep <= MAX_EXTENT_MM) {
        return Err(ReliefError::TooLarge {
            what: "deep",
            size: deep,
        });
    }
    let mut stock: Option<Heightmap> = earlier;
    let mut operations = Vec::new();
    let mut pos: Option<[f64; 3]> = None;
    for (i, pass) in job.passes.iter().enumerate() {
        let mut em = Emitter::new(pass.cutter.feeds, job.safe_z, job.clearance);
        em.pos = pos;
        let directions = directions(pass.direction);
        for (d, &along_y) in directions.iter().enumerate() {
            let stage = format!(
                "{} ({})",
                pass.name,
                if along_y { "along Y" } else { "along X" }
            );
            progress(&stage, 0.0);
            let before = em.moves.len();
            let shape = pass_shape(
                design,
                pass,
                along_y,
                job.samples_per_pixel,
                stock.is_some(),
            );
            let moves = Moves {
                earlier: operations.iter().map(|o: &Operation| o.moves.len()).sum(),
                budget,
                fixed: shape.bytes().saturating_add(budget.reserved),
                pass: &pass.name,
            };
            cancelled()?;
            let within = Within {
                progress: &|f| progress(&stage, f),
                cancel,
            };
            cut_pass(
                &mut em,
                design,
                stock.as_ref(),
                pass,
                along_y,
                job.tolerance,
                job.samples_per_pixel,
                &moves,
                &within,
            )?;
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
                let mut at = start;
                for chunk in em.moves[before..].chunks(MOVES_PER_CANCEL_CHECK) {
                    cancelled()?;
                    at = apply_moves(s, &pass.cutter.tool, at, chunk);
                }
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

/// Raster directions of a pass: `false` = rows along X, `true` = along Y.
fn directions(d: Direction) -> &'static [bool] {
    match d {
        Direction::X => &[false],
        Direction::Y => &[true],
        Direction::Both => &[false, true],
    }
}

/// How one pass in one direction lays out its grids, for the memory estimate.
fn pass_shape(
    design: &Heightmap,
    pass: &Pass,
    along_y: bool,
    sub: usize,
    has_stock: bool,
) -> PassShape {
    let (width, height) = if along_y {
        (design.height, design.width)
    } else {
        (design.width, design.height)
    };
    // As `SubKernels`: the widest shifted kernel reaches one pixel further at most.
    let reach = ((pass.cutter.tool.reach_radius() + pass.allowance + XY_ROUNDING_MM) / design.pixel
        + 1.0)
        .ceil() as usize;
    PassShape {
        width,
        height,
        reach,
        rows: raster_rows(height, design.pixel, pass.stepover).len(),
        sub,
        has_stock,
        rest_only: pass.rest_only,
    }
}

/// The move count of a plan against its budget: moves of earlier passes, and the bytes the
/// current pass holds besides its moves.
struct Moves<'a> {
    earlier: usize,
    budget: Budget,
    fixed: u64,
    pass: &'a str,
}

impl Moves<'_> {
    fn bytes(&self, count: u64) -> u64 {
        count
            .saturating_add(self.earlier as u64)
            .saturating_mul(self.budget.per_move)
            .saturating_add(self.fixed)
    }

    /// Before cutting: `Err` when `at_least` more moves cannot fit.
    fn check_bound(&self, at_least: u64) -> Result<(), OverBudget> {
        check(
            || {
                format!(
                    "the toolpath of pass '{}' (at least {at_least} moves)",
                    self.pass
                )
            },
            self.bytes(at_least),
            self.budget.bytes,
            Lever::Levels,
        )
    }

    /// While cutting: `Err` once `count` moves, `done` of `levels` levels into the pass, no
    /// longer fit; the figure given is the whole pass's at the rate so far.
    fn check_count(&self, count: u64, done: usize, levels: usize) -> Result<(), OverBudget> {
        if self.bytes(count) <= self.budget.bytes {
            return Ok(());
        }
        let whole = (count as f64 * levels as f64 / done.max(1) as f64) as u64;
        Err(OverBudget {
            what: format!(
                "the toolpath of pass '{}' ({count} moves after {done} of {levels} levels)",
                self.pass
            ),
            needed: self.bytes(whole.max(count)),
            budget: self.budget.bytes,
            lever: Lever::Moves,
        })
    }
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
    // Finer depth steps than this mean nothing to a router, and f64 levels over a part
    // of MAX_EXTENT_MM stay distinct.
    if p.stepdown < MIN_STEPDOWN_MM {
        return Err(ReliefError::StepDown {
            pass: p.name.clone(),
            value: p.stepdown,
        });
    }
    if !(p.allowance.is_finite() && p.allowance >= 0.0) {
        return Err(bad("allowance", p.allowance));
    }
    if !(p.min_cut.is_finite() && p.min_cut > 0.0) {
        return Err(bad("minimum cut", p.min_cut));
    }
    // The widest kernel of the pass: shifted by up to a pixel, widened by the allowance and
    // the programs' rounding.
    let reach =
        ((p.cutter.tool.reach_radius() + pixel + p.allowance + XY_ROUNDING_MM) / pixel).ceil();
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
/// Floor of depth level `k` (1, 2, …): `stepdown` apart below `top`; the last level, the
/// first that would reach `deepest`, has no floor (−∞).
fn level_floor(k: u64, deepest: f32, top: f32, stepdown: f64) -> f32 {
    let z = top as f64 - k as f64 * stepdown;
    if z <= deepest as f64 {
        f32::NEG_INFINITY
    } else {
        z as f32
    }
}

/// Number of depth levels from `top` down to `deepest`.
fn level_count(deepest: f32, top: f32, stepdown: f64) -> u64 {
    ((top as f64 - deepest as f64) / stepdown).floor().max(0.0) as u64 + 1
}

/// The highest floor that still cuts something in `rows`: a level cuts a sample (allowed,
/// target `t`, free height `c`) only when its floor and `t` both lie below `c − min_cut`.
/// −∞ when no sample is left to cut.
fn cut_ceiling(rows: &[Row], targets: &[&[f32]], min_cut: f32) -> f32 {
    let mut ceiling = f32::NEG_INFINITY;
    for (r, t) in rows.iter().zip(targets) {
        for (j, (&t, &c)) in t.iter().zip(&r.clear).enumerate() {
            if t < c - min_cut && r.allowed.as_ref().is_none_or(|a| a[j]) {
                ceiling = ceiling.max(c - min_cut);
            }
        }
    }
    ceiling
}

#[allow(clippy::too_many_arguments)]
/// A pass's view of the job's feedback: its progress (fraction of the pass) and the cancel
/// flag.
struct Within<'a> {
    progress: &'a dyn Fn(f64),
    cancel: &'a AtomicBool,
}

impl Within<'_> {
    /// Reports `fraction` of the pass done, or stops a cancelled job.
    fn tick(&self, fraction: f64) -> Result<(), ReliefError> {
        if self.cancel.load(Ordering::Relaxed) {
            return Err(ReliefError::Cancelled);
        }
        (self.progress)(fraction.clamp(0.0, 1.0));
        Ok(())
    }
}

#[allow(clippy::too_many_arguments)]
fn cut_pass(
    em: &mut Emitter,
    design: &Heightmap,
    stock: Option<&Heightmap>,
    pass: &Pass,
    along_y: bool,
    tol: f64,
    sub: usize,
    moves: &Moves,
    within: &Within,
) -> Result<(), ReliefError> {
    let cancelled = || ReliefError::Cancelled;
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
    let clear_grid = match stock {
        Some(s) => {
            let s = if along_y { transpose(s) } else { s.clone() };
            let k = Kernel::new(tool, s.pixel, 0.0, 0.0);
            Some(surface_grid_until(&s, &k, within.cancel).ok_or_else(cancelled)?)
        }
        None => None,
    };
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
        let k = Kernel::new(tool, grid.pixel, 0.0, pass.allowance);
        let full = surface_grid_until(&grid, &k, within.cancel).ok_or_else(cancelled)?;
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
    // Widened by the programs' rounding: a move written to the nearest 0.1 µm still clears.
    let kernels = SubKernels::new(tool, grid.pixel, pass.allowance + XY_ROUNDING_MM, sub);
    // Between grid points a pointed tool reaches below the samples beside it (a needle-thin
    // V bit by metres, a tool narrower than a pixel to −∞ with no sample under it): no
    // target goes beneath the design's lowest point, which touches no sample either.
    let lowest = grid.range().0;
    let targets: Vec<Vec<f32>> = surface_rows_sub_until(&grid, &kernels, &rows, within.cancel)
        .ok_or_else(cancelled)?
        .into_iter()
        .map(|mut r| {
            r.iter_mut().for_each(|t| *t = t.max(lowest) + allowance);
            segment_bound(&mut r);
            r
        })
        .collect();
    let samples = sub_len(grid.width, sub);
    // Grid column(s) either side of sample j.
    let columns = |j: usize| (j / sub, j.div_ceil(sub));

    let mut todo: Vec<&Region> = blocks.iter().collect();
    let block_count = blocks.len().max(1) as f64;
    let mut blocks_begun = 0usize;
    while !todo.is_empty() {
        within.tick(blocks_begun as f64 / block_count)?;
        blocks_begun += 1;
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
        // Each row visited at a level costs a travel and a feed at least: refuse a number of
        // levels that cannot fit before cutting any.
        // A sample whose target lies `d` below its free height is cut at every level whose
        // floor falls in between: at least ⌊(d − min cut) / stepdown⌋ of them.
        let step = if pass.stepdown >= pass.min_cut {
            pass.stepdown
        } else {
            // Cut again only once the floor is `min_cut` below the last cut.
            pass.min_cut + pass.stepdown
        };
        let visits: u64 = block_rows
            .iter()
            .zip(&members)
            .map(|(r, &i)| {
                let deepest_cut = targets[i]
                    .iter()
                    .zip(&r.clear)
                    .map(|(&t, &c)| (c - t) as f64)
                    .fold(0.0, f64::max);
                ((deepest_cut - pass.min_cut) / step).floor().max(0.0) as u64
            })
            .fold(0u64, u64::saturating_add);
        moves.check_bound((em.moves.len() as u64).saturating_add(visits.saturating_mul(2)))?;
        let levels = level_count(deepest, top, pass.stepdown);
        let block_targets: Vec<&[f32]> = members.iter().map(|&i| &targets[i][..]).collect();
        let min_cut = pass.min_cut as f32;
        let floor_at = |k: u64| level_floor(k, deepest, top, pass.stepdown);
        let mut k = 1u64;
        loop {
            // Levels that cut nothing are skipped (else a tiny step-down over a deep block
            // would loop without end): their only effect, lowering free heights to
            // max(target, floor), is that of the last one skipped, since floors descend.
            let ceiling = cut_ceiling(&block_rows, &block_targets, min_cut);
            if ceiling == f32::NEG_INFINITY {
                break;
            }
            if floor_at(k) >= ceiling {
                let mut next = (((top - ceiling) as f64 / pass.stepdown).floor().max(0.0) as u64)
                    .saturating_add(1)
                    .max(k + 1);
                while next > k + 1 && floor_at(next - 1) < ceiling {
                    next -= 1;
                }
                while floor_at(next) >= ceiling {
                    next += 1;
                }
                let skipped = floor_at(next - 1);
                for (r, t) in block_rows.iter_mut().zip(&block_targets) {
                    for (c, &t) in r.clear.iter_mut().zip(t.iter()) {
                        *c = c.min(t.max(skipped));
                    }
                }
                k = next;
                continue;
            }
            // This block's share of the pass, by levels begun.
            let in_block = (k - 1) as f64 / levels.max(1) as f64;
            within.tick(((blocks_begun - 1) as f64 + in_block.min(1.0)) / block_count)?;
            let floor = floor_at(k);
            let done = k as usize;
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
            moves.check_count(em.moves.len() as u64, done, levels as usize)?;
            // What this level reached is free for the next one.
            for (r, l) in block_rows.iter_mut().zip(&level_rows) {
                for (c, &t) in r.clear.iter_mut().zip(&l.target) {
                    *c = c.min(t);
                }
            }
            if floor == f32::NEG_INFINITY {
                break;
            }
            k += 1;
        }
    }
    Ok(())
}
