//! `oficina carve`: relief carving from a grayscale elevation image. Wiring only: the
//! import, CAM, post, simulator and estimators live in their crates.

use crate::machine_profile;
use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};
use oficina_cam::memory::Lever;
use oficina_cam::relief::{ReliefError, ReliefJob};
use oficina_cam::seed004;
use oficina_io::{DepthMapping, Heightmap, Scale};
use oficina_motion::format_hms;
use oficina_post::{PostDialect, PostOptions};
use oficina_sim::carve::{evaluate, CarveError, Evaluation, Settings};
use oficina_sim::render_png;
use std::path::{Path, PathBuf};

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Elevation image (PNG, JPEG, TIFF; white = stock top, black = deepest) or raw f32 (.f32).
    pub image: Option<PathBuf>,
    /// mm per pixel on the workpiece.
    #[arg(long)]
    pub pixel_size: Option<f64>,
    /// Width of the carving in mm (instead of --pixel-size).
    #[arg(long)]
    pub width: Option<f64>,
    /// Depth of black, mm.
    #[arg(long, default_value_t = 10.0)]
    pub depth: f64,
    /// White is deepest instead of black.
    #[arg(long)]
    pub invert: bool,
    /// Stretch the image's own darkest..brightest to the full depth.
    #[arg(long)]
    pub normalize: bool,
    /// Samples per row of a raw .f32 height field (values in mm, 0 = top).
    #[arg(long)]
    pub raw_width: Option<usize>,
    /// Finishing tool: flat:D, ball:D, v:D:ANGLE, bull:D:CORNER, taper:TIP:ANGLE[,flute=L,shank=D].
    #[arg(long, default_value = "ball:6")]
    pub tool: String,
    /// Roughing tool (same syntax); enables roughing by levels and rest machining.
    #[arg(long)]
    pub rough_tool: Option<String>,
    /// Target scallop height of the finish, mm (sets the step-over).
    #[arg(long, default_value_t = 0.02)]
    pub scallop: f64,
    /// Finishing step-over, mm (overrides --scallop).
    #[arg(long)]
    pub stepover: Option<f64>,
    /// Roughing step-over as a fraction of the roughing tool's diameter.
    #[arg(long, default_value_t = 0.8)]
    pub rough_stepover: f64,
    /// Largest depth per level, mm (seed 004: 5 mm for the trim router).
    #[arg(long, default_value_t = 5.0)]
    pub stepdown: f64,
    /// Material the roughing leaves for the finishing tool, mm.
    #[arg(long, default_value_t = 0.5)]
    pub allowance: f64,
    /// Finishing raster direction: x, y or both.
    #[arg(long, default_value = "x")]
    pub direction: String,
    /// Cut every row in the same direction instead of zig-zag.
    #[arg(long)]
    pub one_way: bool,
    /// Skip the rest-machining pass of the finishing tool after roughing.
    #[arg(long)]
    pub no_rest: bool,
    /// Cutting feed, mm/min.
    #[arg(long, default_value_t = 2000.0)]
    pub feed: f64,
    /// Plunge feed, mm/min.
    #[arg(long, default_value_t = 500.0)]
    pub plunge_feed: f64,
    #[arg(long, default_value_t = 18000.0)]
    pub rpm: f64,
    /// Safe Z above the stock top, mm.
    #[arg(long, default_value_t = 5.0)]
    pub safe_z: f64,
    /// Post-processor: grbl or linuxcnc.
    #[arg(long, default_value = "grbl")]
    pub post: String,
    /// The machine accepts M6 (grbl otherwise pauses with M0 at tool changes).
    #[arg(long)]
    pub allow_m6: bool,
    /// Machine profile for the planner's time estimate: a TOML file or a bundled name
    /// (grbl-router, hotwire-xy, polar-plotter, polargraph-wall, embroidery-xy).
    #[arg(long, default_value = machine_profile::DEFAULT)]
    pub profile: String,
    /// Output program.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Preview PNG of the simulated result (default: next to the program).
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Memory budget for the whole job (image, toolpaths, program, simulation, preview), MB.
    #[arg(long, default_value_t = 2048)]
    pub memory_mb: u64,
    /// Reproduce seed 004's hemisphere experiment and print the comparison table.
    #[arg(long)]
    pub seed_comparison: bool,
    /// Pixel sizes for --seed-comparison, mm.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1.0, 0.5])]
    pub seed_pixels: Vec<f64>,
}

pub fn run(args: Args) -> Result<std::process::ExitCode> {
    if args.seed_comparison {
        seed_comparison(&args)?;
        return Ok(std::process::ExitCode::SUCCESS);
    }
    let Some(image) = &args.image else {
        bail!("give an IMAGE to carve (or --seed-comparison)")
    };
    let Some(output) = &args.output else {
        bail!("give the output program with -o OUT.nc")
    };
    let profile = machine_profile::resolve(&args.profile)?;
    let design = load_design(&args, image)?;
    let settings = settings(&args)?;
    let job = settings.job()?;
    let header = header(&args, image, &design, &settings);
    let bar = progress_bar();
    let eval = evaluate(
        &design,
        &job,
        Some(&profile),
        &post_options(&args, header)?,
        budget(&args),
        &|stage, f| bar.set_message(format!("{stage}: {:.0} %", f * 100.0)),
    )
    .map_err(explain);
    bar.finish_and_clear();
    let eval = eval?;
    // The preview sits beside the program; neither may ever replace the design image.
    let preview = args
        .preview
        .clone()
        .unwrap_or_else(|| output.with_extension("preview.png"));
    for target in [output, &preview] {
        if same_file(target, image) {
            bail!(
                "{} is the input image: choose another output name (-o / --preview)",
                target.display()
            );
        }
    }
    std::fs::write(output, &eval.program)
        .with_context(|| format!("{}: cannot write the program", output.display()))?;
    render_png(&eval.stock, &preview).map_err(anyhow::Error::msg)?;
    println!(
        "program: {} ({} lines)",
        output.display(),
        eval.program.lines().count()
    );
    println!("preview: {}", preview.display());
    print_evaluation(&eval);
    Ok(std::process::ExitCode::SUCCESS)
}

fn budget(args: &Args) -> u64 {
    args.memory_mb.saturating_mul(1 << 20)
}

/// A memory refusal names the options that change it.
fn explain(e: CarveError) -> anyhow::Error {
    if let CarveError::Plan(ReliefError::TooLarge { .. }) = e {
        return anyhow::anyhow!("{e} (options: --pixel-size or --width, --depth)");
    }
    let Some(over) = e.over_budget() else {
        return e.into();
    };
    let options = match over.lever {
        Lever::PixelSize => "--memory-mb, a picture of fewer pixels, --pixel-size or --width",
        Lever::Levels => "--stepdown, --depth, --memory-mb",
        Lever::Moves => "--stepover (or --scallop), --stepdown, --memory-mb",
    };
    anyhow::anyhow!("{e} (options: {options})")
}

fn load_design(args: &Args, image: &Path) -> Result<Heightmap> {
    let budget = budget(args);
    let is_raw = image
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("f32"));
    if is_raw {
        let width = args
            .raw_width
            .context("a raw .f32 height field needs --raw-width")?;
        let pixel = args
            .pixel_size
            .context("a raw .f32 height field needs --pixel-size")?;
        return Ok(oficina_io::load_raw_f32(image, width, pixel, budget)?);
    }
    let scale = match (args.pixel_size, args.width) {
        (Some(p), None) => Scale::PixelSize(p),
        (None, Some(w)) => Scale::Width(w),
        (None, None) => bail!("give --pixel-size MM or --width MM"),
        (Some(_), Some(_)) => bail!("give --pixel-size or --width, not both"),
    };
    let mapping = DepthMapping {
        max_depth: args.depth,
        invert: args.invert,
        normalize: args.normalize,
    };
    Ok(oficina_io::load_image(image, scale, mapping, budget)?)
}

fn settings(args: &Args) -> Result<Settings> {
    Ok(Settings {
        tool: args.tool.clone(),
        rough_tool: args.rough_tool.clone(),
        scallop: args.scallop,
        stepover: args.stepover,
        rough_stepover: args.rough_stepover,
        stepdown: args.stepdown,
        allowance: args.allowance,
        direction: args.direction.parse().map_err(anyhow::Error::msg)?,
        one_way: args.one_way,
        no_rest: args.no_rest,
        feed: args.feed,
        plunge_feed: args.plunge_feed,
        rpm: args.rpm,
        safe_z: args.safe_z,
    })
}

/// The program's header: how it was made, readable (`name = value`).
fn header(
    args: &Args,
    image: &Path,
    design: &Heightmap,
    settings: &Settings,
) -> Vec<(String, String)> {
    let mut h = vec![
        (
            "command".to_string(),
            std::env::args().collect::<Vec<_>>().join(" "),
        ),
        ("image".into(), image.display().to_string()),
        (
            "grid".into(),
            format!(
                "{} x {} samples, {} mm per pixel",
                design.width, design.height, design.pixel
            ),
        ),
    ];
    if args.raw_width.is_none() {
        let mut depth = format!("{} mm at black", args.depth);
        if args.invert {
            depth = format!("{} mm at white", args.depth);
        }
        if args.normalize {
            depth.push_str(", normalized");
        }
        h.push(("depth".into(), depth));
    }
    h.extend(settings.describe());
    h.push(("machine profile".into(), args.profile.clone()));
    h
}

fn post_options(args: &Args, settings: Vec<(String, String)>) -> Result<PostOptions> {
    let dialect: PostDialect = args.post.parse().map_err(anyhow::Error::msg)?;
    Ok(PostOptions {
        dialect,
        allow_m6: args.allow_m6,
        title: "Oficina relief carving".into(),
        settings,
    })
}

fn progress_bar() -> ProgressBar {
    let bar = ProgressBar::new(100);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {elapsed_precise} {wide_msg}")
            .expect("static template"),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

fn print_evaluation(e: &Evaluation) {
    let r = &e.report;
    println!("moves: {}", e.planned.toolpath.move_count());
    for op in &e.planned.toolpath.operations {
        println!(
            "  {}: T{} {}, {} moves",
            op.name,
            op.tool_number,
            op.tool.spec(),
            op.moves.len()
        );
    }
    println!("max gouge: {:.4} mm   leftover vs design: max {:.3} mean {:.4} mm   scallop vs ideal: max {:.3} mean {:.4} mm", r.max_gouge, r.leftover_max, r.leftover_mean, r.scallop_max, r.scallop_mean);
    match &e.planner {
        Ok(p) => println!(
            "time: planner {}   feed-only {}",
            format_hms(*p, 0),
            format_hms(e.feed_only_s, 0)
        ),
        Err(err) => println!(
            "time: feed-only {} (planner unavailable: {err})",
            format_hms(e.feed_only_s, 0)
        ),
    }
}

fn seed_comparison(args: &Args) -> Result<()> {
    let profile = &machine_profile::resolve(&args.profile)?;
    println!(
        "Seed 004 hemisphere: 150 x 150 mm, 25 mm deep, F{} mm/min (the seed's feed)",
        seed004::SEED_FEED_MM_MIN
    );
    println!("seed's measurement: two tools 1:53:50 vs 3 mm alone 3:00:00 = 36.8 % saved");
    println!(
        "{:>6}  {:<34} {:>10} {:>10} {:>8} {:>9} {:>9} {:>9}",
        "pixel", "strategy", "planner", "feed-only", "gouge", "left max", "left mean", "saving"
    );
    for &pixel in &args.seed_pixels {
        if !(pixel.is_finite() && (0.1..=5.0).contains(&pixel)) {
            bail!("--seed-pixels: {pixel} mm is outside 0.1 ..= 5");
        }
        let design = seed004::hemisphere(150.0, 25.0, pixel);
        let post = PostOptions {
            dialect: PostDialect::Grbl,
            allow_m6: false,
            title: "seed 004 comparison".into(),
            settings: vec![],
        };
        let bar = progress_bar();
        let run = |job: &ReliefJob| {
            evaluate(
                &design,
                job,
                Some(profile),
                &post,
                budget(args),
                &|stage, f| bar.set_message(format!("{stage}: {:.0} %", f * 100.0)),
            )
            .map_err(explain)
        };
        let one = run(&seed004::seed_one_tool())?;
        let two = run(&seed004::seed_two_tools())?;
        // Ours must be at least as good: finish scallop chosen to match the seed's mean leftover.
        let ours = run(&seed004::improved())?;
        bar.finish_and_clear();
        if let Some(err) = [&one, &two, &ours]
            .iter()
            .find_map(|e| e.planner.as_ref().err())
        {
            println!("        (planner unavailable, savings from feed-only times: {err})");
        }
        let base = |e: &Evaluation| *e.planner.as_ref().unwrap_or(&e.feed_only_s);
        for (name, e) in [
            ("seed: 3 mm flat alone", &one),
            ("seed: 12 mm + 3 mm flat", &two),
            ("ours: 12 mm flat + 3 mm ball", &ours),
        ] {
            let saving = 100.0 * (1.0 - base(e) / base(&one));
            println!(
                "{:>6}  {:<34} {:>10} {:>10} {:>8.4} {:>9.3} {:>9.4} {:>8.1}%",
                pixel,
                name,
                e.planner
                    .as_ref()
                    .map(|p| format_hms(*p, 0))
                    .unwrap_or_else(|_| "-".into()),
                format_hms(e.feed_only_s, 0),
                e.report.max_gouge,
                e.report.leftover_max,
                e.report.leftover_mean,
                saving
            );
        }
    }
    Ok(())
}

/// True when both paths name one existing file (however they are spelled).
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::canonicalize(a), std::fs::canonicalize(b)) {
        (Ok(x), Ok(y)) => x == y,
        _ => false,
    }
}
