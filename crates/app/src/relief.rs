//! A relief job from an uploaded image: heightmap, finishing raster (with optional roughing
//! and rest machining) and the grbl program, reporting progress as it goes and stopping
//! within the pass when cancelled (the workbench's job; `oficina carve`'s evaluation with the
//! stock simulation is [`crate::carve`]).

use crate::{Error, Feedback};
use oficina_cam::memory::Budget;
use oficina_cam::relief::{
    plan_cancellable as plan_cancellable_within, Cutter, Direction, Pass, ReliefError, ReliefJob,
};
use oficina_cam::Feeds;
use oficina_cam::Tool;
use oficina_io::{DepthMapping, Scale};
use oficina_post::{program_text, PostDialect, PostOptions};
use serde::Deserialize;

/// The form of a relief job; lengths in mm, feeds in mm/min.
#[derive(Clone, Debug, Deserialize)]
pub struct ReliefParams {
    /// Width of the carving on the workpiece.
    pub width: f64,
    /// Depth of black.
    pub depth: f64,
    /// `ball:6`, `flat:3`, `v:6:60` …
    pub tool: String,
    /// Roughing tool, same syntax.
    pub rough_tool: Option<String>,
    /// Finishing step-over.
    pub stepover: f64,
    /// Largest depth per level.
    pub stepdown: f64,
    /// Cutting feed.
    pub feed: f64,
    /// Plunge feed.
    pub plunge_feed: f64,
    /// Safe Z above the stock top.
    pub safe_z: f64,
    #[serde(default)]
    /// White is deepest instead of black.
    pub invert: bool,
}

/// A relief job's output.
pub struct ReliefResult {
    /// The grbl program.
    pub program: String,
    /// The image's width and height, pixels.
    pub pixels: [usize; 2],
    /// mm per pixel.
    pub pixel_size: f64,
}

/// Images larger than this are refused before decoding (bytes of the decoded grid).
const MEMORY_BUDGET: u64 = 512 << 20;

fn positive(name: &str, v: f64, max: f64) -> Result<(), Error> {
    if v.is_finite() && v > 0.0 && v <= max {
        Ok(())
    } else {
        Err(Error(format!("{name} {v}: must be > 0 and at most {max}")))
    }
}

/// The relief planner with the job's progress and its cancel flag, which the planner reads
/// inside every pass (per surface row, per depth level), not only between passes.
fn plan_cancellable(
    design: &oficina_io::Heightmap,
    job: &ReliefJob,
    fb: Feedback,
) -> Result<oficina_cam::relief::Planned, Error> {
    match plan_cancellable_within(design, job, Budget::UNLIMITED, fb.progress, fb.cancel) {
        Ok(p) => Ok(p),
        Err(ReliefError::Cancelled) => Err(Error::cancelled()),
        Err(e) => Err(Error::from_display(e)),
    }
}

/// Carve `image` (PNG, JPEG or TIFF bytes named `name`).
pub fn carve_relief(
    name: &str,
    image: &[u8],
    p: &ReliefParams,
    fb: Feedback,
) -> Result<ReliefResult, Error> {
    positive("width", p.width, 10_000.0)?;
    positive("depth", p.depth, 1_000.0)?;
    positive("step-over", p.stepover, 100.0)?;
    positive("step-down", p.stepdown, 100.0)?;
    positive("feed", p.feed, 100_000.0)?;
    positive("plunge feed", p.plunge_feed, 100_000.0)?;
    if !(p.safe_z.is_finite() && (0.0..=1000.0).contains(&p.safe_z)) {
        return Err(Error(format!("safe Z {}: between 0 and 1000 mm", p.safe_z)));
    }
    fb.stage("reading the image")?;
    let design = oficina_io::load_image_bytes(
        name,
        image,
        Scale::Width(p.width),
        DepthMapping {
            max_depth: p.depth,
            invert: p.invert,
            normalize: false,
        },
        MEMORY_BUDGET,
    )
    .map_err(|e| Error(format!("{name}: {e}")))?;
    let cutter = |number: u32, spec: &str| -> Result<Cutter, Error> {
        let tool: Tool = spec
            .parse()
            .map_err(|e| Error(format!("tool '{spec}': {e}")))?;
        Ok(Cutter {
            number,
            tool,
            feeds: Feeds {
                cut: p.feed / 60.0,
                plunge: p.plunge_feed / 60.0,
                rapid: 5000.0 / 60.0,
            },
            spindle_rpm: 18000.0,
        })
    };
    let finish = cutter(2, &p.tool)?;
    let pass = |name: &str, c: Cutter, stepover: f64| Pass {
        name: name.into(),
        cutter: c,
        stepover,
        stepdown: p.stepdown,
        allowance: 0.0,
        direction: Direction::X,
        zigzag: true,
        rest_only: false,
        min_cut: 0.01,
    };
    let mut passes = Vec::new();
    if let Some(spec) = p.rough_tool.as_deref().filter(|s| !s.is_empty()) {
        let rough = cutter(1, spec)?;
        let so = rough.tool.diameter * 0.8;
        passes.push(Pass {
            allowance: 0.5,
            ..pass("roughing", rough, so)
        });
    }
    passes.push(pass("finishing", finish, p.stepover));
    let job = ReliefJob {
        safe_z: p.safe_z,
        clearance: 1.0,
        tolerance: 0.005,
        samples_per_pixel: oficina_cam::relief::SAMPLES_PER_PIXEL,
        passes,
        simulate_last: false,
    };
    let planned = plan_cancellable(&design, &job, fb)?;
    fb.stage("writing G-code")?;
    let program = program_text(
        &planned.toolpath,
        &PostOptions {
            dialect: PostDialect::Grbl,
            allow_m6: false,
            title: "Oficina relief carving (workbench)".into(),
            settings: vec![("settings".into(), format!("{p:?}"))],
        },
    )
    .map_err(Error::from_display)?;
    Ok(ReliefResult {
        program,
        pixels: [design.width, design.height],
        pixel_size: design.pixel,
    })
}
