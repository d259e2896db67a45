//! `oficina carve`: relief carving from a grayscale elevation image. Wiring only: the
//! import, CAM, post, simulator and estimators live in their crates.

use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use indicatif::{ProgressBar, ProgressStyle};
use oficina_cam::raster::Feeds;
use oficina_cam::relief::{plan, Cutter, Direction, Job, Pass, Planned};
use oficina_cam::{seed004, Tool};
use oficina_io::{DepthMapping, Heightmap, Scale};
use oficina_post::{program_text, Dialect, PostOptions};
use oficina_sim::{compare, feed_only_estimate, ideal_surface, render_png, replay, Report};
use std::collections::HashMap;
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
    /// Machine profile for the planner's time estimate.
    #[arg(long, default_value = "profiles/grbl-router.toml")]
    pub profile: PathBuf,
    /// Output program.
    #[arg(short, long)]
    pub output: Option<PathBuf>,
    /// Preview PNG of the simulated result (default: next to the program).
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Memory budget for the import, MB.
    #[arg(long, default_value_t = 2048)]
    pub memory_mb: u64,
    /// Reproduce seed 004's hemisphere experiment and print the comparison table.
    #[arg(long)]
    pub seed_comparison: bool,
    /// Pixel sizes for --seed-comparison, mm.
    #[arg(long, value_delimiter = ',', default_values_t = vec![1.0, 0.5])]
    pub seed_pixels: Vec<f64>,
}

/// What one planned job gives: times and the simulated quality.
pub struct Evaluation {
    pub planned: Planned,
    pub program: String,
    pub stock: Heightmap,
    pub report: Report,
    pub feed_only_s: f64,
    pub planner_s: Option<f64>,
    pub planner_error: Option<String>,
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
    let design = load_design(&args, image)?;
    let job = build_job(&args, &design)?;
    let settings = settings(&args, &design);
    let bar = progress_bar();
    let eval = evaluate(
        &design,
        &job,
        &args.profile,
        &post_options(&args, settings)?,
        &bar,
    )?;
    bar.finish_and_clear();
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

fn load_design(args: &Args, image: &Path) -> Result<Heightmap> {
    let budget = args.memory_mb.saturating_mul(1 << 20);
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

fn cutter(args: &Args, number: u32, spec: &str) -> Result<Cutter> {
    let tool: Tool = spec.parse()?;
    Ok(Cutter {
        number,
        tool,
        feeds: Feeds {
            cut: args.feed / 60.0,
            plunge: args.plunge_feed / 60.0,
            rapid: 5000.0 / 60.0,
        },
        spindle_rpm: args.rpm,
    })
}

fn build_job(args: &Args, design: &Heightmap) -> Result<Job> {
    let direction: Direction = args.direction.parse().map_err(anyhow::Error::msg)?;
    let finish = cutter(args, 2, &args.tool)?;
    let stepover = args
        .stepover
        .unwrap_or_else(|| finish.tool.stepover_for_scallop(args.scallop));
    let base = |name: &str, c: Cutter, stepover: f64| Pass {
        name: name.into(),
        cutter: c,
        stepover,
        stepdown: args.stepdown,
        allowance: 0.0,
        direction: Direction::X,
        zigzag: !args.one_way,
        rest_only: false,
        min_cut: 0.01,
    };
    let mut passes = Vec::new();
    if let Some(spec) = &args.rough_tool {
        let rough = cutter(args, 1, spec)?;
        let so = rough.tool.diameter * args.rough_stepover;
        passes.push(Pass {
            allowance: args.allowance,
            ..base("roughing", rough, so)
        });
        if !args.no_rest {
            // The finishing tool clears, level by level, what the big tool could not reach.
            let so = finish.tool.diameter * 0.5;
            passes.push(Pass {
                allowance: args.allowance.min(0.2),
                rest_only: true,
                min_cut: args.allowance + 0.3,
                ..base("rest machining", finish.clone(), so)
            });
        }
    }
    passes.push(Pass {
        direction,
        ..base("finishing", finish, stepover)
    });
    let _ = design;
    Ok(Job {
        safe_z: args.safe_z,
        clearance: 1.0,
        tolerance: 0.005,
        samples_per_pixel: oficina_cam::relief::SAMPLES_PER_PIXEL,
        passes,
        simulate_last: false,
    })
}

fn settings(args: &Args, design: &Heightmap) -> Vec<(String, String)> {
    let mut s = vec![
        (
            "command".to_string(),
            std::env::args().collect::<Vec<_>>().join(" "),
        ),
        (
            "grid".into(),
            format!(
                "{} x {} samples, {} mm per pixel",
                design.width, design.height, design.pixel
            ),
        ),
    ];
    s.push(("settings".into(), format!("{args:?}")));
    s
}

fn post_options(args: &Args, settings: Vec<(String, String)>) -> Result<PostOptions> {
    let dialect: Dialect = args.post.parse().map_err(anyhow::Error::msg)?;
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

/// Plans, posts, simulates and times one job.
pub fn evaluate(
    design: &Heightmap,
    job: &Job,
    profile: &Path,
    post: &PostOptions,
    bar: &ProgressBar,
) -> Result<Evaluation> {
    let report_stage =
        |stage: &str, f: f64| bar.set_message(format!("{stage}: {:.0} %", f * 100.0));
    let planned = plan(design, job, &report_stage)?;
    bar.set_message("writing G-code");
    let program = program_text(&planned.toolpath, post);
    // Everything downstream judges the program as a machine would read it: the written
    // text through the interpreter, never the CAM's own idea of the moves.
    bar.set_message("interpreting the program");
    let canon = interpret(&program, post)?;
    bar.set_message("simulating the stock");
    let tools: HashMap<u32, Tool> = planned
        .toolpath
        .operations
        .iter()
        .map(|o| (o.tool_number, o.tool.clone()))
        .collect();
    let mut stock = Heightmap::flat(design.width, design.height, design.pixel, 0.0);
    let start = [0.0, 0.0, job.safe_z];
    replay(&canon, &tools, &mut stock, start)?;
    let last_tool = &planned
        .toolpath
        .operations
        .last()
        .context("the job has no passes")?
        .tool;
    let report = compare(&stock, design, &ideal_surface(design, last_tool));
    bar.set_message("estimating time");
    let feed_only_s = feed_only_estimate(&canon, start, 6000.0);
    let (planner_s, planner_error) = match oficina_motion::Profile::load(profile) {
        Ok(p) => {
            match oficina_motion::estimate(to_machine(&canon, job.safe_z + 1.0).into_iter(), &p) {
                Ok(e) => (Some(e.seconds), None),
                Err(e) => (None, Some(e.to_string())),
            }
        }
        Err(e) => (None, Some(e.to_string())),
    };
    Ok(Evaluation {
        planned,
        program,
        stock,
        report,
        feed_only_s,
        planner_s,
        planner_error,
    })
}

/// The canonical operations of our own program. Any diagnostic means the post wrote
/// something the control would reject or misread: a bug, reported with its line.
pub fn interpret(program: &str, post: &PostOptions) -> Result<Vec<oficina_canon::Canon>> {
    oficina_post::read_back(program, post)
        .map_err(|e| anyhow::anyhow!("internal error: {e}; please report it"))
}

/// The program placed in machine coordinates with the work zero `drop` mm below the
/// top of Z travel (the usual Z-zero-at-top router), so the planner's travel check passes;
/// times do not depend on where the work zero is.
fn to_machine(canon: &[oficina_canon::Canon], drop: f64) -> Vec<oficina_canon::Canon> {
    use oficina_canon::CanonOp;
    let shift = |mut p: oficina_canon::Pos| {
        p.z -= drop;
        p
    };
    canon
        .iter()
        // The interpreter resets the feed to 0 on G94 before any F word; the planner takes
        // every feed rate as one to move at. A feed move without F is an interpreter error,
        // so dropping the reset loses nothing.
        .filter(|c| !matches!(c.op, CanonOp::SetFeedRate(f) if f <= 0.0))
        .map(|c| {
            let op = match &c.op {
                CanonOp::StraightTraverse { to } => CanonOp::StraightTraverse { to: shift(*to) },
                CanonOp::StraightFeed { to } => CanonOp::StraightFeed { to: shift(*to) },
                CanonOp::ArcFeed {
                    plane,
                    end,
                    center,
                    turns,
                } => CanonOp::ArcFeed {
                    plane: *plane,
                    end: shift(*end),
                    center: *center,
                    turns: *turns,
                },
                other => other.clone(),
            };
            oficina_canon::Canon { line: c.line, op }
        })
        .collect()
}

fn hms(s: f64) -> String {
    let s = s.round() as u64;
    format!("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60)
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
    match (e.planner_s, &e.planner_error) {
        (Some(p), _) => println!(
            "time: planner {}   feed-only {}",
            hms(p),
            hms(e.feed_only_s)
        ),
        (None, Some(err)) => println!(
            "time: feed-only {} (planner unavailable: {err})",
            hms(e.feed_only_s)
        ),
        _ => println!("time: feed-only {}", hms(e.feed_only_s)),
    }
}

fn seed_comparison(args: &Args) -> Result<()> {
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
        if !(pixel.is_finite() && pixel >= 0.1 && pixel <= 5.0) {
            bail!("--seed-pixels: {pixel} mm is outside 0.1 ..= 5");
        }
        let design = seed004::hemisphere(150.0, 25.0, pixel);
        let post = PostOptions {
            dialect: Dialect::Grbl,
            allow_m6: false,
            title: "seed 004 comparison".into(),
            settings: vec![],
        };
        let bar = progress_bar();
        let one = evaluate(
            &design,
            &seed004::seed_one_tool(),
            &args.profile,
            &post,
            &bar,
        )?;
        let two = evaluate(
            &design,
            &seed004::seed_two_tools(),
            &args.profile,
            &post,
            &bar,
        )?;
        // Ours must be at least as good: finish scallop chosen to match the seed's mean leftover.
        let ours = evaluate(&design, &seed004::improved(), &args.profile, &post, &bar)?;
        bar.finish_and_clear();
        if let Some(err) = [&one, &two, &ours]
            .iter()
            .find_map(|e| e.planner_error.as_ref())
        {
            println!("        (planner unavailable, savings from feed-only times: {err})");
        }
        let base = |e: &Evaluation| e.planner_s.unwrap_or(e.feed_only_s);
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
                e.planner_s.map(hms).unwrap_or_else(|| "-".into()),
                hms(e.feed_only_s),
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
