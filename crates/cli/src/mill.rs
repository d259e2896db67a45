//! `oficina mill`: one 2.5D operation on an SVG/DXF drawing → program, preview, check, time.

use crate::progress::with_bar;
use anyhow::{Context, Result};
use clap::Args as ClapArgs;
use oficina_app::{check_output, Judged, PostParams, PROGRAM_EXTENSIONS};
use oficina_app::{mill, EntryKind, MillOpKind, MillParams, PocketStrategy};
use oficina_sim::render_png;
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub(crate) struct Args {
    /// Drawing: SVG or DXF (closed paths are contours; circles are holes for --op drill).
    #[arg(required_unless_present_any = ["text", "job"])]
    pub input: Option<PathBuf>,
    /// A job file (TOML): the drawing, stock, tool library and operations in order →
    /// one program with its tool changes (docs/cam-jobs.md). Replaces INPUT, --op, --tool…
    #[arg(long, conflicts_with_all = ["input", "text", "op"])]
    pub job: Option<PathBuf>,
    /// With --job: one program per tool (OUTPUT.T1.nc, …) instead of one with tool changes.
    #[arg(long, requires = "job")]
    pub per_tool: bool,
    /// With --job: stop after the first N operations of the cutting order (what the
    /// workbench's "stock after an operation" simulates; `oficina simulate` shows it).
    #[arg(long, requires = "job", value_name = "N")]
    pub upto: Option<usize>,
    /// Rest machining after a pocket or profile-in: this smaller tool (number
    /// --tool-number + 1) cuts what the first could not reach (flat:1, …).
    #[arg(long)]
    pub rest_tool: Option<String>,
    /// Carve this text in Hershey Roman Simplex single strokes instead of a drawing.
    #[arg(long, conflicts_with = "input")]
    pub text: Option<String>,
    /// Capital height of --text, mm.
    #[arg(long, default_value_t = 10.0)]
    pub text_height: f64,
    /// V-carving: largest height of material left at the medial axis and on capped
    /// floors, mm (sets the spacing of the passes).
    #[arg(long, default_value_t = 0.05)]
    pub leftover: f64,
    #[arg(long, value_enum, required_unless_present = "job")]
    pub op: Option<MillOpKind>,
    /// Tool: flat:D, ball:D, v:D:ANGLE … [,flute=L,shank=D], or with --library its number.
    #[arg(long, default_value = "flat:6")]
    pub tool: String,
    /// Tool library (TOML [[tool]] tables): --tool N is its tool N, whose number, rpm and
    /// feeds (chip load × flutes × rpm for --material) the program takes unless given.
    #[arg(long)]
    pub library: Option<PathBuf>,
    /// Material for the library's chip loads (aluminium, wood, … as the library names them).
    #[arg(long, requires = "library")]
    pub material: Option<String>,
    #[arg(long, default_value_t = 1)]
    pub tool_number: u32,
    /// Depth below the stock top, mm.
    #[arg(long, required_unless_present = "job")]
    pub depth: Option<f64>,
    /// Largest depth per pass, mm (default: half the tool diameter).
    #[arg(long)]
    pub stepdown: Option<f64>,
    /// Pocket step-over, mm (default 0.6 × tool diameter; 0.5–0.75 × D is usual).
    #[arg(long)]
    pub stepover: Option<f64>,
    /// Adaptive clearing: largest engagement angle of the tool in material, degrees.
    #[arg(long, default_value_t = 90.0)]
    pub max_engagement: f64,
    /// Adaptive clearing: stock left on the walls, mm.
    #[arg(long, default_value_t = 0.0)]
    pub stock_to_leave: f64,
    /// Pocket strategy.
    #[arg(long, default_value = "offset", value_parser = ["offset", "zigzag"])]
    pub strategy: String,
    /// Stock left by the depth passes for one finishing pass at full depth, mm.
    #[arg(long, default_value_t = 0.2)]
    pub allowance: f64,
    /// Cutting feed, mm/min (default: the library's, else 800).
    #[arg(long)]
    pub feed: Option<f64>,
    /// Ramp, helix and plunge feed, mm/min (default: a third of --feed).
    #[arg(long)]
    pub plunge_feed: Option<f64>,
    /// Spindle speed, rev/min (default: the library's, else 12000).
    #[arg(long)]
    pub rpm: Option<f64>,
    /// How cuts go down into material. `plunge` only for tools that cut under their centre.
    #[arg(long, value_enum, default_value = "ramp")]
    pub entry: EntryKind,
    /// Ramp and helix angle, degrees.
    #[arg(long, default_value_t = 3.0)]
    pub ramp_angle: f64,
    /// Helix radius, mm (default: a third of the tool diameter).
    #[arg(long)]
    pub helix_radius: Option<f64>,
    /// Tabs per contour for profiles (0 = none).
    #[arg(long, default_value_t = 0)]
    pub tabs: usize,
    #[arg(long, default_value_t = 5.0)]
    pub tab_width: f64,
    #[arg(long, default_value_t = 1.0)]
    pub tab_height: f64,
    /// Tangent lead-out arc radius after a profile, mm.
    #[arg(long, default_value_t = 0.0)]
    pub lead_out: f64,
    /// Tangent lead-in arc radius onto a profile, mm (default: the tool radius; 0: none).
    #[arg(long)]
    pub lead_in: Option<f64>,
    /// Profiles: post the part outline with G41 + D (LinuxCNC, Sinumerik) and let the
    /// control offset by the tool radius from its tool table.
    #[arg(long)]
    pub comp: bool,
    /// Drill peck depth, mm (G83).
    #[arg(long)]
    pub peck: Option<f64>,
    /// Drill dwell at the bottom, s (G82).
    #[arg(long, default_value_t = 0.0)]
    pub dwell: f64,
    /// Retraction plane above the stock top, mm.
    #[arg(long, default_value_t = 5.0)]
    pub clear_z: f64,
    /// Safe Z for tool changes and the end, mm.
    #[arg(long, default_value_t = 20.0)]
    pub safe_z: f64,
    #[command(flatten)]
    pub out: PostArgs,
    /// Output program.
    #[arg(short, long)]
    pub output: PathBuf,
    /// SVG preview of the toolpath over the drawing (default: OUTPUT with .svg).
    #[arg(long)]
    pub preview: Option<PathBuf>,
    /// Grid of the stock simulation, mm.
    #[arg(long, default_value_t = 0.2)]
    pub check_pixel: f64,
    /// Machine profile for the planner's time estimate: a bundled name or a TOML file.
    #[arg(long, default_value = crate::machine_profile::DEFAULT)]
    pub profile: String,
    /// Join ends of the drawing's paths that meet within this distance, mm: a path ending
    /// on its start is closed, open pieces (lines, arcs, curves of a layer) are chained.
    #[arg(long, default_value_t = oficina_io::JOIN_TOL)]
    pub join_tol: f64,
}

/// Post-processor choice and format options, shared by `mill` and `sole`.
#[derive(ClapArgs, Debug)]
pub(crate) struct PostArgs {
    /// linuxcnc, grbl, sinumerik or legacy-2006.
    #[arg(long, default_value = "linuxcnc")]
    pub post: String,
    /// The machine handles M6 (grbl forks with a changer).
    #[arg(long)]
    pub allow_m6: bool,
    /// Decimals in numbers (the dialect's default when not given).
    #[arg(long)]
    pub precision: Option<u8>,
    /// Write the program in inches.
    #[arg(long)]
    pub inch: bool,
    /// Number blocks N10, N20, … (START:STEP, e.g. 10:10).
    #[arg(long)]
    pub line_numbers: Option<String>,
    /// Write every word on every block instead of leaving out repeated modal words.
    #[arg(long)]
    pub no_modal: bool,
}

impl PostArgs {
    pub(crate) fn params(&self) -> PostParams {
        PostParams {
            post: self.post.clone(),
            allow_m6: self.allow_m6,
            precision: self.precision,
            inch: self.inch,
            line_numbers: self.line_numbers.clone(),
            no_modal: self.no_modal,
        }
    }
}

/// The machine profile for a time estimate (a bundled name or a file): loaded, or why not
/// (not fatal).
pub(crate) fn estimate_profile(spec: &str) -> Result<oficina_motion::Profile, String> {
    crate::machine_profile::resolve(spec).map_err(|e| e.to_string())
}

pub(crate) fn print_judged(j: &Judged) {
    for l in j.summary_lines() {
        println!("  {l}");
    }
}

pub(crate) fn run(args: Args) -> Result<std::process::ExitCode> {
    check_output("mill", "-o", &args.output, PROGRAM_EXTENSIONS)?;
    if let Some(job) = &args.job {
        return crate::mill_job::run(job, &args);
    }
    let (Some(op), Some(depth)) = (args.op, args.depth) else {
        anyhow::bail!("mill: --op and --depth are needed without --job");
    };
    // The preview beside the program (part.svg for part.nc), or part.preview.svg when that
    // name is the drawing being milled: the usual `mill part.svg -o part.nc` just works.
    let preview = args.preview.clone().unwrap_or_else(|| {
        let beside = args.output.with_extension("svg");
        match &args.input {
            Some(input) if oficina_app::same_file(&beside, input) => {
                args.output.with_extension("preview.svg")
            }
            _ => beside,
        }
    });
    let stock_png = args.output.with_extension("stock.png");
    if let Some(input) = &args.input {
        oficina_app::refuse_overwriting_drawing(input, &[&args.output, &preview, &stock_png])?;
    }
    // A library tool: its spec, number and feeds, each unless given on the line.
    let (tool, tool_number, feeds) = match &args.library {
        Some(lib) => {
            let n: u32 = args.tool.parse().map_err(|_| {
                anyhow::anyhow!(
                    "--tool {}: with --library give the tool's number",
                    args.tool
                )
            })?;
            let c = oficina_app::library_tool(lib, n, args.material.as_deref())
                .map_err(|e| anyhow::anyhow!(e.0))?;
            (c.spec, n, c.feeds)
        }
        None => (args.tool.clone(), args.tool_number, None),
    };
    let params = MillParams {
        op,
        tool,
        tool_number,
        depth,
        stepdown: args.stepdown,
        stepover: args.stepover,
        strategy: if args.strategy == "zigzag" {
            PocketStrategy::Zigzag
        } else {
            PocketStrategy::Offset
        },
        allowance: args.allowance,
        max_engagement: args.max_engagement,
        stock_to_leave: args.stock_to_leave,
        feed: args
            .feed
            .or(feeds.as_ref().map(|f| f.feed))
            .unwrap_or(800.0),
        plunge_feed: args.plunge_feed.or(feeds.as_ref().map(|f| f.plunge_feed)),
        rpm: args
            .rpm
            .or(feeds.as_ref().map(|f| f.rpm))
            .unwrap_or(12000.0),
        entry: args.entry,
        ramp_angle: args.ramp_angle,
        helix_radius: args.helix_radius,
        tabs: args.tabs,
        tab_width: args.tab_width,
        tab_height: args.tab_height,
        lead_out: args.lead_out,
        lead_in: args.lead_in,
        comp: args.comp,
        peck: args.peck,
        dwell: args.dwell,
        clear_z: args.clear_z,
        safe_z: args.safe_z,
        check_pixel: args.check_pixel,
        leftover: args.leftover,
        rest_tool: args.rest_tool.clone(),
        text: args.text.clone(),
        text_height: args.text_height,
        join_tol: args.join_tol,
        post: args.out.params(),
    };
    let profile = estimate_profile(&args.profile);
    let input = args
        .input
        .clone()
        .unwrap_or_else(|| PathBuf::from("--text"));
    let (result, bar) = with_bar(|fb| mill(&input, &params, &profile, fb));
    let r = result?;
    if let Some(w) = &r.warning {
        bar.suspend(|| eprintln!("oficina: warning: {w}"));
    }
    bar.suspend(|| {
        for l in &r.imported {
            println!("imported: {l}");
        }
        for l in &r.shapes {
            println!("shape:    {l}");
        }
    });
    std::fs::write(&args.output, &r.judged.program)
        .with_context(|| format!("{}: cannot write the program", args.output.display()))?;
    std::fs::write(&preview, &r.preview_svg)
        .with_context(|| format!("{}: cannot write the preview", preview.display()))?;
    if let Some(stock) = &r.judged.stock {
        render_png(stock, &stock_png).map_err(anyhow::Error::msg)?;
    }
    bar.finish_and_clear();
    println!(
        "{}: {} ({} moves)",
        args.output.display(),
        r.op_name,
        r.moves
    );
    println!("  preview:  {}", preview.display());
    if r.judged.stock.is_some() {
        println!("  stock:    {}", stock_png.display());
    }
    print_judged(&r.judged);
    Ok(if r.judged.gouged() {
        std::process::ExitCode::from(2)
    } else {
        std::process::ExitCode::SUCCESS
    })
}
