//! `oficina carve`'s relief job from an image file: the design loaded by its scale, the
//! program's header, the evaluation (toolpaths, program, stock simulation, times) with memory
//! refusals that name the options to change, and seed 004's hemisphere comparison.

use crate::Error;
use oficina_cam::memory::Lever;
use oficina_cam::relief::{Progress, ReliefError, ReliefJob};
use oficina_cam::seed004;
use oficina_io::{DepthMapping, Heightmap, Scale};
use oficina_motion::Profile;
use oficina_post::{PostDialect, PostOptions};
use oficina_sim::carve::{evaluate, CarveError, Evaluation, Settings};
use std::path::{Path, PathBuf};

/// Where the design comes from and how its grey levels become depths (lengths in mm).
#[derive(Clone, Debug)]
pub struct DesignSource {
    /// The elevation image (PNG, JPEG, TIFF) or raw f32 height field (.f32).
    pub image: PathBuf,
    /// mm per pixel on the workpiece.
    pub pixel_size: Option<f64>,
    /// Width of the carving (instead of the pixel size).
    pub width: Option<f64>,
    /// Depth of black.
    pub depth: f64,
    /// White is deepest instead of black.
    pub invert: bool,
    /// Stretch the image's own darkest..brightest to the full depth.
    pub normalize: bool,
    /// Samples per row of a raw .f32 height field.
    pub raw_width: Option<usize>,
}

impl DesignSource {
    /// Load the design within `budget` bytes.
    pub fn load(&self, budget: u64) -> Result<Heightmap, Error> {
        let image = &self.image;
        let is_raw = image
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("f32"));
        if is_raw {
            let width = self
                .raw_width
                .ok_or_else(|| Error("a raw .f32 height field needs --raw-width".into()))?;
            let pixel = self
                .pixel_size
                .ok_or_else(|| Error("a raw .f32 height field needs --pixel-size".into()))?;
            return oficina_io::load_raw_f32(image, width, pixel, budget)
                .map_err(|e| Error::chain(&e));
        }
        let scale = match (self.pixel_size, self.width) {
            (Some(p), None) => Scale::PixelSize(p),
            (None, Some(w)) => Scale::Width(w),
            (None, None) => return Err(Error("give --pixel-size MM or --width MM".into())),
            (Some(_), Some(_)) => {
                return Err(Error("give --pixel-size or --width, not both".into()))
            }
        };
        let mapping = DepthMapping {
            max_depth: self.depth,
            invert: self.invert,
            normalize: self.normalize,
        };
        oficina_io::load_image(image, scale, mapping, budget).map_err(|e| Error::chain(&e))
    }

    /// The program's header: how it was made, readable (`name = value`).
    pub fn header(
        &self,
        command: String,
        design: &Heightmap,
        settings: &Settings,
        profile: &str,
    ) -> Vec<(String, String)> {
        let mut h = vec![
            ("command".to_string(), command),
            ("image".into(), self.image.display().to_string()),
            (
                "grid".into(),
                format!(
                    "{} x {} samples, {} mm per pixel",
                    design.width, design.height, design.pixel
                ),
            ),
        ];
        if self.raw_width.is_none() {
            let mut depth = format!("{} mm at black", self.depth);
            if self.invert {
                depth = format!("{} mm at white", self.depth);
            }
            if self.normalize {
                depth.push_str(", normalized");
            }
            h.push(("depth".into(), depth));
        }
        h.extend(settings.describe());
        h.push(("machine profile".into(), profile.to_string()));
        h
    }
}

/// The post's options for a relief program: `post` is grbl or linuxcnc.
pub fn relief_post(
    post: &str,
    allow_m6: bool,
    settings: Vec<(String, String)>,
) -> Result<PostOptions, Error> {
    let dialect: PostDialect = post.parse().map_err(Error::from_display)?;
    Ok(PostOptions {
        dialect,
        allow_m6,
        title: "Oficina relief carving".into(),
        settings,
    })
}

/// Evaluate a relief job: toolpaths, program, stock simulation and times, within `budget`
/// bytes; a memory refusal names the options that change it.
pub fn evaluate_relief(
    design: &Heightmap,
    job: &ReliefJob,
    profile: &Profile,
    post: &PostOptions,
    budget: u64,
    progress: Progress,
) -> Result<Evaluation, Error> {
    evaluate(design, job, Some(profile), post, budget, progress).map_err(explain)
}

/// A memory refusal names the options that change it.
fn explain(e: CarveError) -> Error {
    if let CarveError::Plan(ReliefError::TooLarge { .. }) = e {
        return Error(format!("{e} (options: --pixel-size or --width, --depth)"));
    }
    let Some(over) = e.over_budget() else {
        return Error::chain(&e);
    };
    let options = match over.lever {
        Lever::PixelSize => "--memory-mb, a picture of fewer pixels, --pixel-size or --width",
        Lever::Levels => "--stepdown, --depth, --memory-mb",
        Lever::Moves => "--stepover (or --scallop), --stepdown, --memory-mb",
    };
    Error(format!("{e} (options: {options})"))
}

/// Refuse outputs that would replace the design image (however the paths are spelled).
pub fn refuse_overwriting(image: &Path, outputs: &[&Path]) -> Result<(), Error> {
    for target in outputs {
        if crate::output::same_file(target, image) {
            return Err(Error(format!(
                "{} is the input image: choose another output name (-o / --preview)",
                target.display()
            )));
        }
    }
    Ok(())
}

/// One row of seed 004's comparison.
pub struct SeedRow {
    /// The strategy.
    pub name: &'static str,
    /// Its evaluation.
    pub evaluation: Evaluation,
    /// Machine time saved against the seed's 3 mm tool alone, percent.
    pub saving: f64,
}

/// Seed 004's 150 x 150 x 25 mm hemisphere at `pixel` mm: the seed's two strategies and ours,
/// each evaluated on `profile` (savings from the planner's times, else the feed-only ones).
pub fn seed_comparison(
    pixel: f64,
    profile: &Profile,
    budget: u64,
    progress: Progress,
) -> Result<Vec<SeedRow>, Error> {
    if !(pixel.is_finite() && (0.1..=5.0).contains(&pixel)) {
        return Err(Error(format!(
            "--seed-pixels: {pixel} mm is outside 0.1 ..= 5"
        )));
    }
    let design = seed004::hemisphere(150.0, 25.0, pixel);
    let post = PostOptions {
        dialect: PostDialect::Grbl,
        allow_m6: false,
        title: "seed 004 comparison".into(),
        settings: vec![],
    };
    let run = |job: &ReliefJob| evaluate_relief(&design, job, profile, &post, budget, progress);
    let one = run(&seed004::seed_one_tool())?;
    let two = run(&seed004::seed_two_tools())?;
    // Ours must be at least as good: finish scallop chosen to match the seed's mean leftover.
    let ours = run(&seed004::improved())?;
    let base = |e: &Evaluation| *e.planner.as_ref().unwrap_or(&e.feed_only_s);
    let reference = base(&one);
    Ok([
        ("seed: 3 mm flat alone", one),
        ("seed: 12 mm + 3 mm flat", two),
        ("ours: 12 mm flat + 3 mm ball", ours),
    ]
    .into_iter()
    .map(|(name, evaluation)| SeedRow {
        name,
        saving: 100.0 * (1.0 - base(&evaluation) / reference),
        evaluation,
    })
    .collect())
}
