//! Seed 001's mold job: a digitised size-N contour → graded, fitted, mirrored insert and
//! cavity programs for both feet, each checked against its design and timed.

use crate::judge::{judge, Judged};
use crate::{Error, Feedback, PostParams};
use oficina_cam::ops::TREAD_DEPTH;
use oficina_cam::ops::{preview_svg, sole_job, Part, SoleJob, GOUGE_TOL};
use oficina_geom::{offset_areas, to_ring, Area, SizeSystem};
use oficina_sim::Design;
use serde::Deserialize;
use std::path::Path;

/// The form of a sole-mold job.
#[derive(Clone, Debug, Deserialize)]
#[serde(default)]
pub struct SoleParams {
    /// The size the contour was digitised at.
    pub from_size: f64,
    /// The size to make.
    pub to_size: f64,
    /// br (Brazilian/French, Paris point) or us (English/American).
    pub system: String,
    /// Material shrinkage, percent.
    pub shrink: f64,
    /// Fitting tolerance, mm.
    pub fit_tolerance: f64,
    /// Grid of the stock simulation, mm.
    pub check_pixel: f64,
    /// A drawing (SVG/DXF) of the insert's tread details, closed shapes in the points' frame.
    /// Never read from a form: a path from the page could name any file on the server.
    #[serde(skip)]
    pub tread: Option<std::path::PathBuf>,
    /// Ends of the tread drawing's paths that meet within this distance are joined, mm.
    pub join_tol: f64,
    #[serde(flatten)]
    /// The post-processor and format.
    pub post: PostParams,
}

impl Default for SoleParams {
    fn default() -> Self {
        SoleParams {
            from_size: 37.0,
            to_size: 40.0,
            system: "br".into(),
            shrink: 2.0,
            fit_tolerance: 0.3,
            check_pixel: 0.5,
            join_tol: oficina_io::JOIN_TOL,
            tread: None,
            post: PostParams::default(),
        }
    }
}

/// One program of the job: a part for one foot.
pub struct SoleOutput {
    /// `left-insert`, `right-cavity`, …
    pub name: String,
    /// Operations in the program.
    pub operations: usize,
    /// Moves in the program.
    pub moves: usize,
    /// The SVG preview.
    pub preview_svg: String,
    /// The program and what it was judged to be.
    pub judged: Judged,
}

/// A sole-mold job's output.
pub struct SoleResult {
    /// Grading and fitting, a line each.
    pub summary: Vec<String>,
    /// One program a part and foot.
    pub programs: Vec<SoleOutput>,
    /// The graded, fitted contour of the left and right foot in the points' frame.
    pub feet: [oficina_geom::Path; 2],
}

impl SoleResult {
    /// The deepest gouge of all programs, mm.
    pub fn worst_gouge(&self) -> f64 {
        self.programs
            .iter()
            .map(|p| p.judged.gouge.map_or(0.0, |g| g.0))
            .fold(0.0, f64::max)
    }
}

/// Runs the job on the points of `points` (CSV or whitespace x y per line).
pub fn sole(
    points: &Path,
    p: &SoleParams,
    profile: &Result<oficina_motion::Profile, String>,
    fb: Feedback,
) -> Result<SoleResult, Error> {
    fb.stage("reading the points")?;
    let pts = oficina_io::load_points(points).map_err(|e| Error::chain(&e))?;
    let Some(system) = SizeSystem::parse(&p.system) else {
        return Err(Error(format!(
            "--system {}: use br (Brazilian/French) or us (English/American)",
            p.system
        )));
    };
    if !(0.0..=20.0).contains(&p.shrink) {
        return Err(Error(format!("--shrink {} %: use 0 to 20", p.shrink)));
    }
    if !(p.check_pixel.is_finite() && (0.01..=10.0).contains(&p.check_pixel)) {
        return Err(Error(format!(
            "--check-pixel {}: use 0.01 to 10 mm",
            p.check_pixel
        )));
    }
    if !(p.join_tol.is_finite() && (0.0..=oficina_io::MAX_JOIN_TOL).contains(&p.join_tol)) {
        return Err(Error(format!(
            "--join-tol {}: use 0 to {} mm",
            p.join_tol,
            oficina_io::MAX_JOIN_TOL
        )));
    }
    let mut tread_summary = vec![];
    let tread = match &p.tread {
        Some(file) => {
            let imported =
                oficina_io::load_drawing_with(file, p.join_tol).map_err(|e| Error::chain(&e))?;
            let paths: Vec<oficina_geom::Path> = imported.drawing.paths().cloned().collect();
            if paths.is_empty() {
                return Err(Error(format!("{}: the tread has no paths", file.display())));
            }
            tread_summary = imported
                .summary()
                .into_iter()
                .map(|l| format!("tread: {l}"))
                .collect();
            paths
        }
        None => vec![],
    };
    let job = SoleJob {
        system,
        tread,
        shrink: p.shrink / 100.0,
        fit_tolerance: p.fit_tolerance,
        ..SoleJob::seed(p.from_size, p.to_size)
    };
    fb.stage("grading, fitting, mirroring, toolpaths")?;
    let result = sole_job(&pts, &job).map_err(|e| Error::chain(&e))?;
    let (a, b) = result.factors;
    let mut summary = vec![format!(
        "size {} → {} ({}), shrinkage {} %: α = {a:.4} (width), β = {b:.4} (length), about the heel point ({:.2}, {:.2})",
        p.from_size, p.to_size, system.name, p.shrink, result.grading.reference.x, result.grading.reference.y
    )];
    summary.push(format!(
        "contour: {} with {} blocks, max deviation {:.3} mm from the graded points{}",
        result.fit.method,
        result.fit.blocks,
        result.fit.max_deviation,
        result
            .fallback
            .as_ref()
            .map(|w| format!(" (tangent circles: {w})"))
            .unwrap_or_default()
    ));
    let mut programs = Vec::new();
    for prog in &result.programs {
        fb.stage(&format!("{}: post, read back, simulate, time", prog.name()))?;
        let settings = vec![
            ("points".into(), points.display().to_string()),
            (
                "job".into(),
                format!(
                    "{} size {} from {} ({}), shrink {} %",
                    prog.name(),
                    p.to_size,
                    p.from_size,
                    system.name,
                    p.shrink
                ),
            ),
            (
                "block".into(),
                format!(
                    "{:.1} x {:.1} x {:.1} mm, part zero at its lower-left top corner",
                    prog.block[0], prog.block[1], prog.block[2]
                ),
            ),
        ];
        let (post, format) = p
            .post
            .options(&format!("Oficina sole mold: {}", prog.name()), settings)?;
        // Insert: everything outside the (clearance-reduced) outline may go; cavity: inside.
        let area = Area::from_paths(std::slice::from_ref(&prog.contour));
        let (dist, cut_inside) = match prog.part {
            Part::Insert => (-GOUGE_TOL, false),
            Part::Cavity => (GOUGE_TOL, true),
        };
        let rings: Vec<Vec<[f64; 2]>> = offset_areas(&area, dist, 0.001)
            .map_err(|e| Error::chain(&e))?
            .iter()
            .flat_map(|a| {
                a.paths()
                    .map(|p| to_ring(&p.flatten(1e-4)))
                    .collect::<Vec<_>>()
            })
            .collect();
        let mut designs = vec![Design {
            rings,
            cut_inside,
            top: 0.0,
            floor: -prog.depth,
            slope: 0.0,
        }];
        if !prog.tread.is_empty() {
            // The tread pockets, TREAD_DEPTH deep inside the insert's top.
            let grown = offset_areas(&Area::from_paths(&prog.tread), GOUGE_TOL, 0.001)
                .map_err(|e| Error::chain(&e))?;
            designs.push(Design {
                rings: grown
                    .iter()
                    .flat_map(|a| {
                        a.paths()
                            .map(|p| to_ring(&p.flatten(1e-4)))
                            .collect::<Vec<_>>()
                    })
                    .collect(),
                cut_inside: true,
                top: 0.0,
                floor: -TREAD_DEPTH,
                slope: 0.0,
            });
        }
        let judged = judge(
            &prog.toolpath,
            &post,
            &format,
            Some(designs),
            p.check_pixel,
            profile,
            fb,
        )?;
        programs.push(SoleOutput {
            name: prog.name(),
            operations: prog.toolpath.operations.len(),
            moves: prog.toolpath.move_count(),
            preview_svg: preview_svg(
                &[std::slice::from_ref(&prog.contour), &prog.tread[..]].concat(),
                &prog.toolpath,
            ),
            judged,
        });
    }
    summary.extend(tread_summary);
    Ok(SoleResult {
        summary,
        programs,
        feet: result.feet,
    })
}
