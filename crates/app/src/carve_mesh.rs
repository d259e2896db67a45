//! `oficina carve MODEL.stl`: the relief job on a triangle mesh. Roughing (and rest
//! machining) run the relief planner on the height field that drop-cutter gives; the finish
//! is an exact drop-cutter raster on the triangles. The program is then read back by the
//! interpreter, simulated on the stock and timed exactly as a picture's carving is.

use crate::Error;
use oficina_cam::memory::{self, Budget, Lever};
use oficina_cam::mesh::{
    finishing_moves, flat_pieces, grown, level_spacing, raster, rough, waterline_pieces,
    zlevel_bytes, ContactGrid, DropCutter, Raster, Strategy, ZLevel, OVERLAP,
};
use oficina_cam::relief::{plan_after, Direction, Progress, ReliefError};
use oficina_cam::{apply_moves, CutterShape, Move, Operation, Tool, Toolpath};
use oficina_canon::Canon;
use oficina_io::{Heightmap, Mesh};
use oficina_motion::Profile;
use oficina_post::{program_text, PostOptions};
use oficina_sim::carve::{bytes_per_move, interpret, to_machine, Settings};
use oficina_sim::{compare, feed_only_estimate, ideal_surface, replay, Report};
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};

/// Where the model comes from and how it is placed (mm, degrees).
#[derive(Clone, Debug)]
pub struct MeshSource {
    /// STL (binary or ASCII) or OBJ file.
    pub path: PathBuf,
    /// Uniform scale applied first (e.g. 25.4 for a model in inches).
    pub scale: f64,
    /// Turn about Z, degrees, after scaling.
    pub rotate: f64,
    /// Scale (again) so the largest dimension is this many mm.
    pub size: Option<f64>,
}

impl MeshSource {
    /// Reads and places the model within `budget` bytes; it keeps its own coordinates
    /// unless scaled or turned (both about the origin).
    pub fn load(&self, budget: u64) -> Result<Mesh, Error> {
        let mut mesh = oficina_io::load_mesh(&self.path, budget).map_err(|e| Error::chain(&e))?;
        let name = self.path.display();
        if !(self.scale.is_finite() && self.scale > 0.0 && self.scale <= 1e4) {
            return Err(Error(format!(
                "--scale {}: must be above 0 and at most 10000",
                self.scale
            )));
        }
        if !self.rotate.is_finite() {
            return Err(Error(format!("--rotate {}: not a number", self.rotate)));
        }
        let (s, c) = self.rotate.to_radians().sin_cos();
        let k = self.scale;
        mesh.map(|p| {
            let (x, y) = (p[0] * k, p[1] * k);
            [c * x - s * y, s * x + c * y, p[2] * k]
        });
        if let Some(size) = self.size {
            if !(size.is_finite() && size > 0.0 && size <= 1e4) {
                return Err(Error(format!(
                    "--size {size}: must be above 0 and at most 10000 mm"
                )));
            }
            let [lo, hi] = mesh.bounds();
            let big = (0..3).map(|i| hi[i] - lo[i]).fold(0.0, f64::max);
            if big <= 0.0 {
                return Err(Error(format!("{name}: the model has no extent to scale")));
            }
            mesh.map(|p| p.map(|v| v * size / big));
        }
        let [lo, hi] = mesh.bounds();
        if hi[0] - lo[0] <= 0.0 || hi[1] - lo[1] <= 0.0 {
            return Err(Error(format!(
                "{name}: the model is flat in X or Y: nothing to carve"
            )));
        }
        if (0..3).any(|i| hi[i] - lo[i] > oficina_cam::relief::MAX_EXTENT_MM) {
            return Err(Error(format!(
                "{name}: the model spans {:.0} x {:.0} x {:.0} mm, larger than any machine (--scale, --size)",
                hi[0] - lo[0],
                hi[1] - lo[1],
                hi[2] - lo[2]
            )));
        }
        Ok(mesh)
    }
}

/// The mesh job's own options beside the relief [`Settings`] (mm, degrees).
#[derive(Clone, Debug)]
pub struct MeshOptions {
    /// Finishing raster angle from +X; `None`: the settings' direction (X, Y or both).
    pub angle: Option<f64>,
    /// Grid of the roughing height field and the stock simulation; `None`: about 600
    /// samples across the model.
    pub pixel: Option<f64>,
    /// Stock top; `None`: the model's top.
    pub stock_top: Option<f64>,
    /// Stock bottom, the lowest the tool goes; `None`: the model's bottom.
    pub stock_bottom: Option<f64>,
    /// Largest gap between a straight finishing feed and the exact cutter location.
    pub tolerance: f64,
    /// How the roughing tool clears the stock.
    pub roughing: Roughing,
}

/// How the roughing tool (`--rough-tool`) clears the stock.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Roughing {
    /// Contours at each level on the mesh itself (`oficina_cam::mesh::rough`).
    #[default]
    ZLevel,
    /// The relief planner's levels on the model's conservative height field.
    HeightField,
}

impl std::str::FromStr for Roughing {
    type Err = String;
    fn from_str(s: &str) -> Result<Roughing, String> {
        match s {
            "zlevel" => Ok(Roughing::ZLevel),
            "heightfield" => Ok(Roughing::HeightField),
            _ => Err(format!("unknown roughing '{s}' (zlevel, heightfield)")),
        }
    }
}

/// How the mesh job's finishing pass covers the model.
#[derive(Clone, Copy, Debug)]
pub struct MeshFinish {
    /// Raster, waterline, or raster on the flats and waterline on the steeps.
    pub strategy: Strategy,
    /// The slope, degrees from horizontal, above which `Mix` uses waterline; also sets the
    /// waterline's level spacing (stepover · sin(limit)).
    pub limit: f64,
}

impl Default for MeshFinish {
    fn default() -> MeshFinish {
        MeshFinish {
            strategy: Strategy::Raster,
            limit: 45.0,
        }
    }
}

/// What a mesh job gives: the program, its simulated stock and figures.
pub struct MeshEvaluation {
    /// The toolpath, in the model's coordinates.
    pub toolpath: Toolpath,
    /// The G-code program.
    pub program: String,
    /// The simulated stock (grid frame: origin at `origin`, z 0 at `top`).
    pub stock: Heightmap,
    /// The model's top surface on the same grid.
    pub design: Heightmap,
    /// Grid origin (X, Y) in model coordinates, mm.
    pub origin: [f64; 2],
    /// Stock top in model coordinates, mm.
    pub top: f64,
    /// Stock vs model.
    pub report: Report,
    /// Feed-only time, s.
    pub feed_only_s: f64,
    /// Planner's time, s, or why there is none.
    pub planner: Result<f64, String>,
    /// Triangles in the model.
    pub triangles: usize,
}

/// Grids held at once after planning: stock, design, rough design, ideal surface
/// (dilation, erosion and their copies) and the preview.
const GRIDS: u64 = 14;

/// Plans, posts, reads back, simulates and times the job on `mesh` within `budget` bytes,
/// finishing with `finish_with`. It gives up with [`Error::cancelled`] soon after `cancel`
/// is set: every drop-cutter query answers at once from then on (rows, grids and loops run
/// out on every thread) and the flag is read after each stage and z-level.
#[allow(clippy::too_many_arguments)]
pub fn evaluate_mesh(
    mesh: &Mesh,
    settings: &Settings,
    opts: &MeshOptions,
    finish_with: &MeshFinish,
    profile: &Profile,
    post: &PostOptions,
    budget: u64,
    progress: Progress,
    cancel: &AtomicBool,
) -> Result<MeshEvaluation, Error> {
    let stopped = || {
        if cancel.load(Ordering::Relaxed) {
            Err(Error::cancelled())
        } else {
            Ok(())
        }
    };
    if !(finish_with.limit.is_finite() && (10.0..=80.0).contains(&finish_with.limit)) {
        return Err(Error(format!(
            "--steep {}: between 10 and 80 degrees",
            finish_with.limit
        )));
    }
    let job = settings.job().map_err(|e| Error::chain(&e))?;
    let finish = job
        .passes
        .last()
        .cloned()
        .ok_or_else(|| Error("no finishing pass".into()))?;
    let tool = finish.cutter.tool.clone();
    let [lo, hi] = mesh.bounds();
    let top = opts.stock_top.unwrap_or(hi[2]);
    let bottom = opts.stock_bottom.unwrap_or(lo[2]);
    if !(top.is_finite() && bottom.is_finite() && bottom < top) {
        return Err(Error(format!(
            "stock bottom {bottom} must be below the stock top {top}"
        )));
    }
    if !(opts.tolerance.is_finite() && opts.tolerance > 0.0 && opts.tolerance <= 1.0) {
        return Err(Error(format!(
            "--tolerance {}: between 0 and 1 mm",
            opts.tolerance
        )));
    }
    // The grid covers the model and the ring the tool's centre sweeps around it.
    let reach = tool.cutting_radius();
    let span = (hi[0] - lo[0]).max(hi[1] - lo[1]) + 2.0 * reach;
    let pixel = opts.pixel.unwrap_or((span / 600.0).max(0.02));
    if !(pixel.is_finite() && pixel > 0.0) {
        return Err(Error(format!("--pixel-size {pixel}: must be above 0")));
    }
    let origin = [lo[0] - reach, lo[1] - reach];
    let width = ((hi[0] - lo[0] + 2.0 * reach) / pixel).ceil() as usize + 1;
    let height = ((hi[1] - lo[1] + 2.0 * reach) / pixel).ceil() as usize + 1;
    let region = [lo[0] - reach, lo[1] - reach, hi[0] + reach, hi[1] + reach];
    // The waterline's contact grid: finer than the rows, so loops are found between them.
    let contact_step = (finish.stepover / 2.0).min(pixel).min(0.25);
    let contact_bytes = match finish_with.strategy {
        Strategy::Raster => 0,
        _ => ContactGrid::bytes_estimate(region, contact_step),
    };
    let fixed = memory::grid_bytes(width, height)
        .saturating_mul(GRIDS)
        .saturating_add(DropCutter::bytes_estimate(mesh.triangles.len()).saturating_mul(3))
        .saturating_add(contact_bytes);
    memory::check(
        || format!("the {width} x {height} grid of the model and its stock"),
        fixed,
        budget,
        Lever::PixelSize,
    )
    .map_err(|e| Error(format!("{e} (options: --pixel-size, --memory-mb)")))?;

    progress("model height field", 0.0);
    // The model's top (a 1 µm flat tool) for the report, and a conservative one for the
    // relief planner: the highest point within the pixel's circumscribed circle.
    let point = DropCutter::new(
        mesh,
        &Tool::new(CutterShape::Flat, 0.002).map_err(Error::from_display)?,
    )
    .cancelled_by(cancel);
    let design = point.height_field(origin, pixel, width, height, bottom, top);
    stopped()?;
    let mut operations = Vec::new();
    let rough_passes: Vec<_> = job.passes[..job.passes.len() - 1].to_vec();
    let safe = top + job.safe_z;
    if !rough_passes.is_empty() {
        let cover = Tool::new(CutterShape::Flat, pixel * std::f64::consts::SQRT_2)
            .map_err(Error::from_display)?;
        let rough_design = DropCutter::new(mesh, &cover)
            .cancelled_by(cancel)
            .height_field(origin, pixel, width, height, bottom, top);
        stopped()?;
        let mut earlier = None;
        let mut relief_passes = rough_passes.clone();
        if opts.roughing == Roughing::ZLevel {
            progress("z-level roughing", 0.0);
            let p = relief_passes.remove(0);
            let rtool = &p.cutter.tool;
            let wide = grown(rtool, p.allowance).map_err(Error)?;
            let z = ZLevel {
                stepover: p.stepover,
                stepdown: p.stepdown,
                allowance: p.allowance,
                tolerance: opts.tolerance,
                top,
                floor: bottom,
                stock: region,
                safe,
                clearance: job.clearance,
                feed: p.cutter.feeds.cut,
                plunge: p.cutter.feeds.plunge,
                radius: rtool.diameter / 2.0,
            };
            memory::check(
                || "the z-level roughing's contact grid".to_string(),
                fixed.saturating_add(zlevel_bytes(&z, wide.cutting_radius())),
                budget,
                Lever::PixelSize,
            )
            .map_err(|e| Error(format!("{e} (options: --memory-mb)")))?;
            let dc = DropCutter::new(mesh, &wide).cancelled_by(cancel);
            let moves = rough(&dc, rtool, &z, &|| cancel.load(Ordering::Relaxed));
            stopped()?;
            let moves = moves.map_err(|e| Error(format!("--rough-tool {}: {e}", rtool.spec())))?;
            // What it leaves, on the planner's grid, for the rest pass to start from.
            let mut stock = Heightmap::flat(width, height, pixel, 0.0);
            let mut at = [0.0, 0.0, job.safe_z];
            for chunk in moves.chunks(4096) {
                stopped()?;
                let local: Vec<Move> = chunk
                    .iter()
                    .map(|m| {
                        let mut m = m.clone();
                        shift_move(&mut m, [-origin[0], -origin[1], -top]);
                        m
                    })
                    .collect();
                at = apply_moves(&mut stock, rtool, at, &local);
            }
            earlier = Some(stock);
            operations.push(Operation {
                name: format!("{} (mesh z-level)", p.name),
                tool_number: p.cutter.number,
                tool: rtool.clone(),
                spindle_rpm: p.cutter.spindle_rpm,
                moves,
            });
        }
        if !relief_passes.is_empty() {
            let rough_job = oficina_cam::relief::ReliefJob {
                passes: relief_passes,
                ..job.clone()
            };
            let b = Budget {
                bytes: budget,
                reserved: fixed,
                per_move: bytes_per_move(),
            };
            let planned = plan_after(&rough_design, &rough_job, b, progress, cancel, earlier)
                .map_err(|e| match e {
                    ReliefError::Cancelled => Error::cancelled(),
                    e => Error(format!(
                        "{e} (options: --pixel-size, --stepdown, --memory-mb)"
                    )),
                })?;
            for mut op in planned.toolpath.operations {
                for m in &mut op.moves {
                    shift_move(m, [origin[0], origin[1], top]);
                }
                operations.push(op);
            }
        }
    }

    progress("finishing drop-cutter", 0.0);
    let dc = DropCutter::new(mesh, &tool).cancelled_by(cancel);
    let angles: Vec<f64> = match (opts.angle, finish.direction) {
        (Some(a), _) => vec![a],
        (None, Direction::X) => vec![0.0],
        (None, Direction::Y) => vec![90.0],
        (None, Direction::Both) => vec![0.0, 90.0],
    };
    let grid = (finish_with.strategy != Strategy::Raster).then(|| {
        progress("waterline contact grid", 0.0);
        ContactGrid::new(&dc, region, contact_step)
    });
    stopped()?;
    let mut moves = Vec::new();
    for (k, angle) in angles.iter().enumerate() {
        let r = Raster {
            angle: *angle,
            stepover: finish.stepover,
            step: (pixel / 2.0).min(finish.stepover).min(0.25),
            tolerance: opts.tolerance,
            floor: bottom,
            region,
        };
        let rows = match (&grid, finish_with.strategy) {
            (_, Strategy::Raster) => raster(&dc, &r),
            (Some(g), Strategy::Mix) => {
                flat_pieces(&raster(&dc, &r), g, bottom, finish_with.limit + OVERLAP)
            }
            _ => Vec::new(),
        };
        // The waterline once, after the first direction's rows.
        let mut paths = rows;
        if let (Some(g), 0) = (&grid, k) {
            progress("waterline loops", 0.0);
            let dz = level_spacing(finish.stepover, finish_with.limit);
            let steep =
                (finish_with.strategy == Strategy::Mix).then_some(finish_with.limit - OVERLAP);
            paths.extend(waterline_pieces(&dc, g, bottom, dz, opts.tolerance, steep));
        }
        stopped()?;
        moves.extend(finishing_moves(
            &dc,
            &r,
            &paths,
            safe,
            finish.cutter.feeds.cut,
            finish.cutter.feeds.plunge,
        ));
    }
    stopped()?;
    let count: usize = operations
        .iter()
        .map(|o: &Operation| o.moves.len())
        .sum::<usize>()
        + moves.len();
    memory::check(
        || format!("{count} moves"),
        fixed.saturating_add((count as u64).saturating_mul(bytes_per_move())),
        budget,
        Lever::Moves,
    )
    .map_err(|e| {
        Error(format!(
            "{e} (options: --stepover or --scallop, --tolerance, --memory-mb)"
        ))
    })?;
    operations.push(Operation {
        name: match finish_with.strategy {
            Strategy::Raster => "finishing (mesh drop-cutter raster)",
            Strategy::Waterline => "finishing (mesh waterline)",
            Strategy::Mix => "finishing (mesh raster on flats, waterline on steeps)",
        }
        .into(),
        tool_number: finish.cutter.number,
        tool: tool.clone(),
        spindle_rpm: finish.cutter.spindle_rpm,
        moves,
    });
    let toolpath = Toolpath {
        safe_z: safe,
        operations,
    };

    stopped()?;
    progress("writing G-code", 0.0);
    let program = program_text(&toolpath, post).map_err(Error::from_display)?;
    progress("interpreting the program", 0.0);
    let canon = interpret(&program, post).map_err(|e| Error::chain(&e))?;
    let local: Vec<Canon> = canon
        .iter()
        .map(|c| c.translated([-origin[0], -origin[1], -top]))
        .collect();
    stopped()?;
    progress("simulating the stock", 0.0);
    let mut stock = Heightmap::flat(width, height, pixel, 0.0);
    let start = [0.0, 0.0, job.safe_z];
    replay(&local, &toolpath.tools(), &mut stock, start).map_err(|e| Error::chain(&e))?;
    // A vertical wall of the model falls between two grid points: the one on the wall takes
    // the wall's top, and a tool running down the wall's face (tangent to it) is counted as
    // cutting that top away. The model is known to a grid step, so a cut is a gouge only
    // where it is below the model at every point within one step (a real gouge is wider).
    let known = lowest_within_a_step(&design);
    let report = compare(&stock, &known, &ideal_surface(&design, &tool));
    progress("estimating time", 0.0);
    let feed_only_s = feed_only_estimate(&local, start, 6000.0);
    let planner = oficina_motion::estimate(to_machine(&local, job.safe_z + 1.0), profile)
        .map(|e| e.seconds)
        .map_err(|e| e.to_string());
    Ok(MeshEvaluation {
        toolpath,
        program,
        stock,
        design,
        origin,
        top,
        report,
        feed_only_s,
        planner,
        triangles: mesh.triangles.len(),
    })
}

fn shift_move(m: &mut Move, d: [f64; 3]) {
    let add = |p: &mut [f64; 3]| {
        for k in 0..3 {
            p[k] += d[k];
        }
    };
    match m {
        Move::Rapid { to } | Move::Line { to, .. } => add(to),
        Move::Arc { to, center, .. } => {
            add(to);
            center[0] += d[0];
            center[1] += d[1];
        }
        _ => {}
    }
}

/// Each grid point's height lowered to the lowest of it and its eight neighbours.
fn lowest_within_a_step(map: &Heightmap) -> Heightmap {
    let (w, h) = (map.width, map.height);
    Heightmap::from_fn(w, h, map.pixel, |x, y| {
        let (ix, iy) = (
            (x / map.pixel).round() as usize,
            (y / map.pixel).round() as usize,
        );
        let mut low = f32::INFINITY;
        for jy in iy.saturating_sub(1)..=(iy + 1).min(h - 1) {
            for jx in ix.saturating_sub(1)..=(ix + 1).min(w - 1) {
                low = low.min(map.at(jx, jy));
            }
        }
        f64::from(low)
    })
}

/// The program header of a mesh carving after its first line (`command`): the model, its
/// placed box and triangles, the settings and the machine profile (the CLI's and the page's).
pub fn model_header(
    model: &str,
    mesh: &Mesh,
    settings: &Settings,
    profile: &str,
) -> Vec<(String, String)> {
    let [lo, hi] = mesh.bounds();
    let mut header = vec![
        ("model".to_string(), model.to_string()),
        (
            "model box".into(),
            format!(
                "X {:.3}..{:.3} Y {:.3}..{:.3} Z {:.3}..{:.3} mm, {} triangles",
                lo[0],
                hi[0],
                lo[1],
                hi[1],
                lo[2],
                hi[2],
                mesh.triangles.len()
            ),
        ),
    ];
    header.extend(settings.describe());
    header.push(("machine profile".into(), profile.to_string()));
    header
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A wall between grid points is not a gouge; a groove three points wide still is.
    #[test]
    fn the_gouge_check_forgives_a_wall_point_not_a_groove() {
        let px = 0.1;
        // The model: 10 mm high for x < 1.0, 0 beyond (the wall's top sits on x = 1.0).
        let design =
            Heightmap::from_fn(41, 5, px, |x, _| if x <= 1.0 + 1e-9 { 0.0 } else { -10.0 });
        // A tool running down the wall's face took the wall's top point down to −8.
        let wall = Heightmap::from_fn(41, 5, px, |x, _| {
            if (x - 1.0).abs() < 1e-9 {
                -8.0
            } else if x <= 1.0 {
                0.0
            } else {
                -10.0
            }
        });
        let known = lowest_within_a_step(&design);
        assert_eq!(compare(&wall, &known, &design).max_gouge, 0.0);
        assert!(compare(&wall, &design, &design).max_gouge > 7.9);
        // A groove 0.3 mm wide and 2 mm deep into the top.
        let groove = Heightmap::from_fn(41, 5, px, |x, _| {
            if (0.3..0.55).contains(&x) {
                -2.0
            } else if x <= 1.0 + 1e-9 {
                0.0
            } else {
                -10.0
            }
        });
        let g = compare(&groove, &known, &design).max_gouge;
        assert!((g - 2.0).abs() < 1e-6, "{g}");
    }
}
