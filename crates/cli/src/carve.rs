//! `oficina carve`: relief carving from a grayscale elevation image. Parsing and printing
//! only: the job is `oficina_app::carve` (design, header, evaluation, seed 004 comparison).

use crate::machine_profile;
use crate::progress::progress_bar;
use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use oficina_app::carve::{evaluate_relief, refuse_overwriting, relief_post, DesignSource};
use oficina_motion::format_hms;
use oficina_sim::carve::{Evaluation, Settings};
use oficina_sim::render_png;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

#[derive(ClapArgs, Debug)]
pub(crate) struct Args {
    /// Elevation image (PNG, JPEG, TIFF; white = stock top, black = deepest), raw f32 (.f32),
    /// or a 3D model (STL binary or ASCII, OBJ; in mm, carved in its own coordinates).
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
    /// Model: uniform scale applied first (25.4 for a model in inches).
    #[arg(long, default_value_t = 1.0)]
    pub scale: f64,
    /// Model: turn about Z, degrees (after --scale).
    #[arg(long, default_value_t = 0.0)]
    pub rotate: f64,
    /// Model: scale so its largest dimension is this many mm.
    #[arg(long)]
    pub size: Option<f64>,
    /// Model: stock top, mm (default: the model's top).
    #[arg(long, allow_hyphen_values = true)]
    pub stock_top: Option<f64>,
    /// Model: stock bottom, the lowest the tool goes, mm (default: the model's bottom).
    #[arg(long, allow_hyphen_values = true)]
    pub stock_bottom: Option<f64>,
    /// Model: finishing raster angle from +X, degrees (instead of --direction).
    #[arg(long, allow_hyphen_values = true)]
    pub angle: Option<f64>,
    /// Model: finishing strategy: raster, waterline (loops at levels), or mix (raster on the
    /// flats, waterline on slopes steeper than --steep).
    #[arg(long, default_value = "raster")]
    pub strategy: String,
    /// Model: the slope, degrees, above which mix uses waterline; waterline levels are
    /// stepover x sin(steep) apart.
    #[arg(long, default_value_t = 45.0)]
    pub steep: f64,
    /// Model: how --rough-tool clears: zlevel (contours at each level on the mesh, the
    /// allowance kept from the model) or heightfield (the relief's levels on the model's
    /// height field).
    #[arg(long, default_value = "zlevel")]
    pub roughing: String,
    /// Model: largest gap between a finishing feed and the exact cutter location, mm.
    #[arg(long, default_value_t = 0.002)]
    pub tolerance: f64,
    /// Reproduce seed 004's hemisphere experiment and print the comparison table.
    #[arg(long)]
    pub seed_comparison: bool,
    /// Pixel sizes for --seed-comparison, mm.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1.0, 0.5])]
    pub seed_pixels: Vec<f64>,
}

pub(crate) fn run(args: Args) -> Result<std::process::ExitCode> {
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
    oficina_app::check_output("carve", "-o", output, oficina_app::PROGRAM_EXTENSIONS)?;
    let profile = machine_profile::resolve(&args.profile)?;
    let is_model = image
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("stl") || e.eq_ignore_ascii_case("obj"));
    if is_model {
        return carve_model(&args, image, output, &profile);
    }
    let source = DesignSource {
        image: image.clone(),
        pixel_size: args.pixel_size,
        width: args.width,
        depth: args.depth,
        invert: args.invert,
        normalize: args.normalize,
        raw_width: args.raw_width,
    };
    let design = source.load(budget(&args))?;
    let settings = settings(&args)?;
    let job = settings.job()?;
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let header = source.header(command, &design, &settings, &args.profile);
    let bar = progress_bar();
    let eval = evaluate_relief(
        &design,
        &job,
        &profile,
        &relief_post(&args.post, args.allow_m6, header)?,
        budget(&args),
        &|stage, f| bar.set_message(format!("{stage}: {:.0} %", f * 100.0)),
    );
    bar.finish_and_clear();
    let eval = eval?;
    // The preview sits beside the program; neither may ever replace the design image.
    let preview = args
        .preview
        .clone()
        .unwrap_or_else(|| output.with_extension("preview.png"));
    refuse_overwriting(image, &[output, &preview])?;
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
    print_quality(r, "design", &e.planner, e.feed_only_s);
}

fn seed_comparison(args: &Args) -> Result<()> {
    let profile = &machine_profile::resolve(&args.profile)?;
    println!(
        "Seed 004 hemisphere: 150 x 150 mm, 25 mm deep, F{} mm/min (the seed's feed)",
        oficina_cam::seed004::SEED_FEED_MM_MIN
    );
    println!("seed's measurement: two tools 1:53:50 vs 3 mm alone 3:00:00 = 36.8 % saved");
    println!(
        "{:>6}  {:<34} {:>10} {:>10} {:>8} {:>9} {:>9} {:>9}",
        "pixel", "strategy", "planner", "feed-only", "gouge", "left max", "left mean", "saving"
    );
    for &pixel in &args.seed_pixels {
        let bar = progress_bar();
        let rows =
            oficina_app::carve::seed_comparison(pixel, profile, budget(args), &|stage, f| {
                bar.set_message(format!("{stage}: {:.0} %", f * 100.0))
            });
        bar.finish_and_clear();
        let rows = rows?;
        if let Some(err) = rows
            .iter()
            .find_map(|r| r.evaluation.planner.as_ref().err())
        {
            println!("        (planner unavailable, savings from feed-only times: {err})");
        }
        for row in &rows {
            let e = &row.evaluation;
            println!(
                "{:>6}  {:<34} {:>10} {:>10} {:>8.4} {:>9.3} {:>9.4} {:>8.1}%",
                pixel,
                row.name,
                e.planner
                    .as_ref()
                    .map(|p| format_hms(*p, 0))
                    .unwrap_or_else(|_| "-".into()),
                format_hms(e.feed_only_s, 0),
                e.report.max_gouge,
                e.report.leftover_max,
                e.report.leftover_mean,
                row.saving
            );
        }
    }
    Ok(())
}

/// `oficina carve MODEL.stl`: the same job and report on a triangle mesh.
fn carve_model(
    args: &Args,
    model: &std::path::Path,
    output: &std::path::Path,
    profile: &oficina_motion::Profile,
) -> Result<std::process::ExitCode> {
    use oficina_app::carve_mesh::{
        evaluate_mesh, model_header, MeshFinish, MeshOptions, MeshSource,
    };
    let finish = MeshFinish {
        strategy: args
            .strategy
            .parse()
            .map_err(|e: String| anyhow::anyhow!("--strategy: {e}"))?,
        limit: args.steep,
    };
    let source = MeshSource {
        path: model.to_path_buf(),
        scale: args.scale,
        rotate: args.rotate,
        size: args.size,
    };
    let mesh = source.load(budget(args))?;
    let [lo, hi] = mesh.bounds();
    let settings = settings(args)?;
    let opts = MeshOptions {
        angle: args.angle,
        pixel: args.pixel_size,
        stock_top: args.stock_top,
        stock_bottom: args.stock_bottom,
        tolerance: args.tolerance,
        roughing: args
            .roughing
            .parse()
            .map_err(|e: String| anyhow::anyhow!("--roughing: {e}"))?,
    };
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let mut header = vec![("command".to_string(), command)];
    header.extend(model_header(
        &model.display().to_string(),
        &mesh,
        &settings,
        &args.profile,
    ));
    let preview = args
        .preview
        .clone()
        .unwrap_or_else(|| output.with_extension("preview.png"));
    refuse_overwriting(model, &[output, &preview])?;
    let bar = progress_bar();
    let eval = evaluate_mesh(
        &mesh,
        &settings,
        &opts,
        &finish,
        profile,
        &relief_post(&args.post, args.allow_m6, header)?,
        budget(args),
        &|stage, f| bar.set_message(format!("{stage}: {:.0} %", f * 100.0)),
        // Ctrl-C ends the process; nothing else cancels a CLI carving.
        &AtomicBool::new(false),
    );
    bar.finish_and_clear();
    let e = eval?;
    std::fs::write(output, &e.program)
        .with_context(|| format!("{}: cannot write the program", output.display()))?;
    render_png(&e.stock, &preview).map_err(anyhow::Error::msg)?;
    println!(
        "model: {} ({} triangles, X {:.3}..{:.3} Y {:.3}..{:.3} Z {:.3}..{:.3} mm)",
        model.display(),
        e.triangles,
        lo[0],
        hi[0],
        lo[1],
        hi[1],
        lo[2],
        hi[2]
    );
    println!(
        "program: {} ({} lines)",
        output.display(),
        e.program.lines().count()
    );
    println!("preview: {}", preview.display());
    println!("moves: {}", e.toolpath.move_count());
    for op in &e.toolpath.operations {
        println!(
            "  {}: T{} {}, {} moves",
            op.name,
            op.tool_number,
            op.tool.spec(),
            op.moves.len()
        );
    }
    let r = &e.report;
    println!(
        "stock grid: {} x {} at {} mm",
        e.stock.width, e.stock.height, e.stock.pixel
    );
    print_quality(r, "model", &e.planner, e.feed_only_s);
    Ok(std::process::ExitCode::SUCCESS)
}

/// The carving's gouge, leftover against `against` (the design or the model), scallop, and
/// its times: the last lines of the picture's and the model's reports alike.
fn print_quality<E: std::fmt::Display>(
    r: &oficina_sim::Report,
    against: &str,
    planner: &Result<f64, E>,
    feed_only_s: f64,
) {
    println!("max gouge: {:.4} mm   leftover vs {against}: max {:.3} mean {:.4} mm   scallop vs ideal: max {:.3} mean {:.4} mm", r.max_gouge, r.leftover_max, r.leftover_mean, r.scallop_max, r.scallop_mean);
    match planner {
        Ok(p) => println!(
            "time: planner {}   feed-only {}",
            format_hms(*p, 0),
            format_hms(feed_only_s, 0)
        ),
        Err(err) => println!(
            "time: feed-only {} (planner unavailable: {err})",
            format_hms(feed_only_s, 0)
        ),
    }
}
