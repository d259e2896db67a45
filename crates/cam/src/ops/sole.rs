//! The shoe-sole mold job of seed 001 (§3, §4, §6.4, §7): a digitised pattern contour is
//! graded to the target size with shrinkage, re-fitted (tangent circles, biarcs if the
//! points admit no tangent solution), mirrored for the other foot, and machined as an
//! insert (postiço: the sole outline standing proud, cut outside) and a cavity (the same
//! outline as a pocket) for each foot, with the seed's tools and feeds.

use super::pocket::{pocket, PocketParams, Strategy};
use super::profile::{profile, Comp, ProfileParams, Side, OFFSET_TOL};
use super::rest::rest_machining;
use super::{Cut, Entry, OpError};
use crate::{Tool, Toolpath};
use oficina_geom::fit::{fit_method, Fit, Method};
use oficina_geom::{
    mirror_path, offset_areas, oriented, Arc, Area, Grading, MirrorAxis, Path, Point, Reference,
    Segment, SizeSystem, Vec2,
};

/// What to make.
#[derive(Clone, Debug, PartialEq)]
pub struct SoleJob {
    /// The size the digitised contour is.
    pub from_size: f64,
    /// The size to make.
    pub to_size: f64,
    /// The size system (mm per size).
    pub system: SizeSystem,
    /// Material shrinkage as a fraction (seed: 2 % = 0.02).
    pub shrink: f64,
    /// Largest distance of the fitted contour from the graded points, mm.
    pub fit_tolerance: f64,
    /// The insert is made this much smaller all round so it fits the cavity (seed: ~0.05).
    pub insert_clearance: f64,
    /// Insert plate thickness = its cut depth (seed: 22 mm in 3 passes).
    pub insert_depth: f64,
    /// Cavity depth (seed: 26 mm in 3 passes).
    pub cavity_depth: f64,
    /// Block margin round the contour, mm (the part zero is the block's lower-left corner).
    pub margin: f64,
    /// The insert's tread details (seed §7: slots and letters), closed shapes in the
    /// pattern's own frame (the digitised points'): graded, mirrored and placed with the
    /// contour, pocketed [`TREAD_DEPTH`] deep by the 6 mm mill and the 1 mm bit after it.
    pub tread: Vec<Path>,
}

/// Depth of the tread details in the insert (seed §7: 2 mm, one pass of each tool).
pub const TREAD_DEPTH: f64 = 2.0;

impl SoleJob {
    /// The seed's prototype: size 34 → 40, Brazilian sizes, 2 % shrinkage.
    pub fn seed(from_size: f64, to_size: f64) -> SoleJob {
        SoleJob {
            from_size,
            to_size,
            system: SizeSystem::BRAZILIAN,
            shrink: 0.02,
            fit_tolerance: 0.3,
            insert_clearance: 0.05,
            insert_depth: 22.0,
            cavity_depth: 26.0,
            margin: 30.0,
            tread: vec![],
        }
    }
}

/// Which foot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Foot {
    /// Left foot.
    Left,
    /// Right foot (the left mirrored).
    Right,
}

/// Which half of the mould.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// The insert plate, cut out with the tread.
    Insert,
    /// The cavity the insert fits in.
    Cavity,
}

/// One program of the job.
#[derive(Clone, Debug)]
pub struct SoleProgram {
    /// Which foot.
    pub foot: Foot,
    /// Insert or cavity.
    pub part: Part,
    /// The contour as machined (placed on the block, insert clearance applied).
    pub contour: Path,
    /// Block size X, Y, Z (mm).
    pub block: [f64; 3],
    /// Depth cut below the block top, mm.
    pub depth: f64,
    /// The tread details as placed (insert only), cut [`TREAD_DEPTH`] deep.
    pub tread: Vec<Path>,
    /// The program's toolpath.
    pub toolpath: Toolpath,
}

impl SoleProgram {
    /// `insert-left`, `cavity-right`, …
    pub fn name(&self) -> String {
        let part = match self.part {
            Part::Insert => "insert",
            Part::Cavity => "cavity",
        };
        let foot = match self.foot {
            Foot::Left => "left",
            Foot::Right => "right",
        };
        format!("{part}-{foot}")
    }
}

/// A sole job's result: the grading, the fitted contour and the programs.
pub struct SoleResult {
    /// The grading used.
    pub grading: Grading,
    /// (α, β) applied.
    pub factors: (f64, f64),
    /// The fitted contour.
    pub fit: Fit,
    /// Why tangent circles were not used, if they were not.
    pub fallback: Option<String>,
    /// One program per foot and part.
    pub programs: Vec<SoleProgram>,
    /// The graded contour of each foot in the points' frame (before placing on a block).
    pub feet: [Path; 2],
}

/// Seed 001 §7 tools: (number, spec, rpm, feed mm/min).
pub(super) const ROUGH_16: (u32, &str, f64, f64) = (1, "flat:16,flute=30", 1600.0, 190.0);
pub(super) const FINISH_16: (u32, &str, f64, f64) = (1, "flat:16,flute=30", 1800.0, 100.0);
pub(super) const DETAIL_6: (u32, &str, f64, f64) = (2, "flat:6,flute=30", 2000.0, 170.0);
/// The seed's 1 mm carbide bit (a truncated cone with a 1 mm tip, cutting 2 mm per pass),
/// modelled as a 1 mm end mill whose flutes reach the mold's depth.
pub(super) const DETAIL_1: (u32, &str, f64, f64) = (3, "flat:1,flute=30", 2500.0, 140.0);
/// Depth of one pass of the 1 mm bit (seed §7: 2 mm in one pass).
pub(super) const DETAIL_1_STEP: f64 = 2.0;

/// Safety plane Z (seed Fig. 7.3) and retraction plane.
pub(super) const SAFE_Z: f64 = 40.0;
pub(super) const CLEAR_Z: f64 = 5.0;

fn cut(tool: (u32, &str, f64, f64), depth: f64, passes: usize) -> Result<Cut, OpError> {
    let t: Tool = tool
        .1
        .parse()
        .map_err(|e: crate::ToolError| OpError::Invalid(e.to_string()))?;
    Ok(Cut {
        tool_number: tool.0,
        tool: t,
        spindle_rpm: tool.2,
        feed: tool.3 / 60.0,
        plunge_feed: tool.3 / 2.0 / 60.0,
        top: 0.0,
        depth,
        stepdown: depth / passes as f64 + 1e-9,
        clear_z: CLEAR_Z,
        entry: Entry::Ramp { angle: 3.0 },
    })
}

/// The graded, fitted contour of both feet in the points' frame, before placing on a block.
#[derive(Clone, Debug)]
pub struct GradedFeet {
    /// The grading used.
    pub grading: Grading,
    /// (α, β) applied.
    pub factors: (f64, f64),
    /// The fit of the graded points.
    pub fit: Fit,
    /// Why tangent circles were not used, if they were not.
    pub fallback: Option<String>,
    /// The fitted contour, counter-clockwise.
    pub left: Path,
    /// `left` mirrored across the vertical line through its box's centre, counter-clockwise.
    pub right: Path,
    /// That line.
    pub axis: MirrorAxis,
}

/// Grades the pattern's digitised points from `job.from_size` to `job.to_size` about the
/// heel, fits them (tangent circles, biarcs when those deviate more than the tolerance)
/// and mirrors the fit for the other foot: the contours both the mold job and the design
/// editor's grading use.
pub fn graded_feet(points: &[Point], job: &SoleJob) -> Result<GradedFeet, OpError> {
    let grading = Grading::for_points(
        points,
        job.system,
        job.from_size,
        job.shrink,
        Reference::Heel,
    )
    .map_err(|e| OpError::Invalid(e.to_string()))?;
    let graded = grading
        .points(points, job.to_size)
        .map_err(|e| OpError::Invalid(e.to_string()))?;
    let factors = grading.factors(job.to_size);
    let (fit, fallback) = match fit_method(Method::TangentCircles, &graded, job.fit_tolerance) {
        Ok(f) if f.max_deviation <= job.fit_tolerance => (f, None),
        first => {
            let why = match first {
                Ok(f) => format!(
                    "tangent circles deviate {:.3} mm (> {} mm)",
                    f.max_deviation, job.fit_tolerance
                ),
                Err(e) => e.to_string(),
            };
            let f = fit_method(Method::Biarc, &graded, job.fit_tolerance)
                .map_err(|e| OpError::Geometry(e.to_string()))?;
            (f, Some(why))
        }
    };
    let left = oriented(&fit.path, true);
    let bbox = left
        .bounding_box()
        .ok_or_else(|| OpError::Geometry("the fitted contour is empty".into()))?;
    let axis = MirrorAxis::X(bbox.center().x);
    let right = oriented(&mirror_path(&left, axis), true);
    Ok(GradedFeet {
        grading,
        factors,
        fit,
        fallback,
        left,
        right,
        axis,
    })
}

/// Runs the whole job on the pattern's digitised points (closed contour, any direction).
pub fn sole_job(points: &[Point], job: &SoleJob) -> Result<SoleResult, OpError> {
    let bad = |what: &str, v: f64| OpError::Invalid(format!("{what} {v} is out of range"));
    if !(job.insert_depth > 0.0 && job.insert_depth <= 29.0) {
        return Err(bad(
            "insert depth (0–29 mm for the 30 mm flutes)",
            job.insert_depth,
        ));
    }
    if !(job.cavity_depth > 0.0 && job.cavity_depth <= 29.0) {
        return Err(bad(
            "cavity depth (0–29 mm for the 30 mm flutes)",
            job.cavity_depth,
        ));
    }
    if !(job.margin >= 20.0 && job.margin <= 500.0) {
        return Err(bad("margin (20–500 mm)", job.margin));
    }
    if !(job.insert_clearance >= 0.0 && job.insert_clearance < 1.0) {
        return Err(bad("insert clearance (0–1 mm)", job.insert_clearance));
    }
    let feet = graded_feet(points, job)?;
    let tread_left = graded_tread(&job.tread, &feet.grading, job.to_size)?;
    let tread_right: Vec<Path> = tread_left
        .iter()
        .map(|p| mirror_path(p, feet.axis))
        .collect();
    let mut programs = Vec::new();
    for (foot, contour, tread) in [
        (Foot::Left, &feet.left, &tread_left),
        (Foot::Right, &feet.right, &tread_right),
    ] {
        let b = contour.bounding_box().expect("not empty");
        let shift = Vec2::new(job.margin - b.x0, job.margin - b.y0);
        let placed = translate(contour, shift);
        let tread: Vec<Path> = tread.iter().map(|p| translate(p, shift)).collect();
        let block_xy = [b.width() + 2.0 * job.margin, b.height() + 2.0 * job.margin];
        let insert = shrunk(&placed, job.insert_clearance)?;
        check_tread_inside(&tread, &insert)?;
        programs.push(SoleProgram {
            foot,
            part: Part::Insert,
            toolpath: insert_toolpath(&insert, &tread, job.insert_depth)?,
            contour: insert,
            block: [block_xy[0], block_xy[1], job.insert_depth],
            depth: job.insert_depth,
            tread,
        });
        programs.push(SoleProgram {
            foot,
            part: Part::Cavity,
            toolpath: cavity_toolpath(&placed, job.cavity_depth)?,
            contour: placed,
            block: [block_xy[0], block_xy[1], job.cavity_depth + 10.0],
            depth: job.cavity_depth,
            tread: vec![],
        });
    }
    Ok(SoleResult {
        grading: feet.grading,
        factors: feet.factors,
        fit: feet.fit,
        fallback: feet.fallback,
        programs,
        feet: [feet.left, feet.right],
    })
}

/// The tread graded to `size` with the contour's own factors, each shape flattened to
/// 0.01 mm first (grading scales X and Y apart: an arc would not stay an arc).
fn graded_tread(tread: &[Path], grading: &Grading, size: f64) -> Result<Vec<Path>, OpError> {
    tread
        .iter()
        .map(|p| {
            if !p.closed {
                return Err(OpError::Invalid(format!(
                    "tread {}: open strokes are not machined yet; draw slots and letters as closed outlines",
                    p.source
                )));
            }
            let pts = grading
                .points(&p.flatten(0.01), size)
                .map_err(|e| OpError::Invalid(e.to_string()))?;
            Ok(Path::polyline(&pts, true).with_source(p.source.clone()))
        })
        .collect()
}

/// Every tread shape lies inside the insert outline (a shape across it would cut the wall).
fn check_tread_inside(tread: &[Path], insert: &Path) -> Result<(), OpError> {
    let ring = super::chain::Chain::from_path(insert).polygon(0.01);
    for p in tread {
        if let Some(q) = p
            .flatten(0.01)
            .into_iter()
            .find(|q| !super::chain::inside(std::slice::from_ref(&ring), [q.x, q.y]))
        {
            return Err(OpError::Invalid(format!(
                "tread {}: the point ({:.2}, {:.2}) of the graded tread lies outside the insert",
                p.source, q.x, q.y
            )));
        }
    }
    Ok(())
}

fn translate(p: &Path, v: Vec2) -> Path {
    p.map(
        |q| q + v,
        |a| {
            Segment::Arc(Arc {
                center: a.center + v,
                ..*a
            })
        },
    )
}

/// The outer contour of `p` offset by `d` (> 0 grows).
fn offset_outer(p: &Path, d: f64) -> Result<Path, OpError> {
    let areas = offset_areas(&Area::from_paths(std::slice::from_ref(p)), d, OFFSET_TOL)
        .map_err(|e| OpError::Geometry(e.to_string()))?;
    areas
        .into_iter()
        .next()
        .map(|a| a.outer)
        .ok_or_else(|| OpError::Geometry(format!("the contour vanishes offset by {d} mm")))
}

fn shrunk(p: &Path, d: f64) -> Result<Path, OpError> {
    if d > 0.0 {
        offset_outer(p, -d)
    } else {
        Ok(p.clone())
    }
}

/// Stock the roughing passes leave on the wall for the finishing pass, mm.
pub(super) const ALLOWANCE: f64 = 0.5;

/// Seed §7's detail tools as rest machining of `region` (what the 16 mm tool was to cut):
/// the 6 mm mill pockets what the 16 mm one could not reach, then the 1 mm bit what the
/// 6 mm one could not, each only where something is left ([`rest_machining`]).
fn detail_passes(
    part: &str,
    region: &[Area],
    depth: f64,
    ops: &mut Vec<crate::Operation>,
) -> Result<(), OpError> {
    let six = cut(DETAIL_6, depth, 2)?;
    if let Some(op) = rest_machining(
        &format!("{part} rest (6 mm after 16 mm)"),
        region,
        8.0,
        &six,
    )? {
        ops.push(op);
    }
    let passes = (depth / DETAIL_1_STEP).ceil().max(1.0) as usize;
    let one = cut(DETAIL_1, depth, passes)?;
    if let Some(op) = rest_machining(
        &format!("{part} rest (1 mm after 6 mm)"),
        region,
        six.radius(),
        &one,
    )? {
        ops.push(op);
    }
    Ok(())
}

/// The tread pockets, [`TREAD_DEPTH`] deep in one pass each: the 6 mm mill where it fits
/// ("all offsets except the last", seed §7), the 1 mm bit for the rest.
fn tread_passes(tread: &[Path], ops: &mut Vec<crate::Operation>) -> Result<(), OpError> {
    let six = cut(DETAIL_6, TREAD_DEPTH, 1)?;
    match pocket(
        "tread pockets (6 mm)",
        tread,
        &six,
        &PocketParams {
            strategy: Strategy::Offset,
            stepover: 0.6 * 6.0,
            allowance: 0.0,
        },
    ) {
        Ok(op) => ops.push(op),
        Err(OpError::Empty(_)) => {}
        Err(e) => return Err(e),
    }
    let one = cut(DETAIL_1, TREAD_DEPTH, 1)?;
    if let Some(op) = rest_machining(
        "tread rest (1 mm after 6 mm)",
        &Area::from_paths(tread),
        six.radius(),
        &one,
    )? {
        ops.push(op);
    }
    Ok(())
}

/// Insert: two roughing offsets (the second 0.75·D further out clears the block edge) in 3
/// passes, the finishing offset in one pass at full depth, then the detail tools where the
/// 16 mm one could not reach.
fn insert_toolpath(contour: &Path, tread: &[Path], depth: f64) -> Result<Toolpath, OpError> {
    let rough = cut(ROUGH_16, depth, 3)?;
    let outer = [
        offset_outer(contour, ALLOWANCE)?,
        offset_outer(contour, ALLOWANCE + 0.75 * 16.0)?,
    ];
    let side = |side| ProfileParams {
        side,
        allowance: 0.0,
        tabs: None,
        lead_out: 0.0,
        lead_in: 0.0,
        comp: Comp::Computer,
    };
    let mut ops = Vec::new();
    for (k, ring) in outer.iter().enumerate().rev() {
        ops.push(profile(
            &format!("insert roughing offset {}", k + 1),
            std::slice::from_ref(ring),
            &rough,
            &side(Side::Outside),
        )?);
    }
    let finish = cut(FINISH_16, depth, 1)?;
    ops.push(profile(
        "insert finishing offset",
        std::slice::from_ref(contour),
        &finish,
        &ProfileParams {
            lead_out: 4.0,
            lead_in: 0.0,
            comp: Comp::Computer,
            ..side(Side::Outside)
        },
    )?);
    // What the 16 mm tool swept: the band from the outline out past the second roughing
    // offset (whose own outer edge is convex, so it leaves no rest there).
    let band = Area::from_paths(&[
        offset_outer(contour, ALLOWANCE + 0.75 * 16.0 + 8.0)?,
        contour.clone(),
    ]);
    detail_passes("insert", &band, depth, &mut ops)?;
    if !tread.is_empty() {
        tread_passes(tread, &mut ops)?;
    }
    Ok(Toolpath {
        safe_z: SAFE_Z,
        operations: ops,
    })
}

/// Cavity: contour-parallel pocket from the centre out in 3 passes, the finishing offset at
/// full depth in one pass, the detail tools in what the 16 mm one could not reach.
fn cavity_toolpath(contour: &Path, depth: f64) -> Result<Toolpath, OpError> {
    let mut rough = cut(ROUGH_16, depth, 3)?;
    rough.entry = Entry::Helix {
        radius: 4.0,
        angle: 3.0,
    };
    let inner = offset_outer(contour, -ALLOWANCE)?;
    let mut ops = vec![pocket(
        "cavity roughing (centre out)",
        std::slice::from_ref(&inner),
        &rough,
        &PocketParams {
            strategy: Strategy::Offset,
            stepover: 0.6 * 16.0,
            allowance: 0.0,
        },
    )?];
    let side = ProfileParams {
        side: Side::Inside,
        allowance: 0.0,
        tabs: None,
        lead_out: 0.0,
        lead_in: 0.0,
        comp: Comp::Computer,
    };
    ops.push(profile(
        "cavity finishing offset",
        std::slice::from_ref(contour),
        &cut(FINISH_16, depth, 1)?,
        &side,
    )?);
    detail_passes(
        "cavity",
        &Area::from_paths(std::slice::from_ref(contour)),
        depth,
        &mut ops,
    )?;
    Ok(Toolpath {
        safe_z: SAFE_Z,
        operations: ops,
    })
}
