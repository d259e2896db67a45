//! `oficina mill`: one 2.5D operation on an SVG/DXF drawing → program, preview, check, time.

use anyhow::{bail, Context, Result};
use clap::{Args as ClapArgs, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use oficina_cam::ops::{
    allowed_region, preview_svg, toolpath, Cut, DrillParams, Entry, MillOp, PocketParams,
    ProfileParams, Side, Strategy, Tabs,
};
use oficina_cam::{Tool, Toolpath};
use oficina_post::{
    post_for, read_back, write_program_with, Dialect, Format, LineNumbers, Numbers, PostOptions,
    Units,
};
use oficina_sim::{check_mill, feed_only_estimate, render_png, Design};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum Op {
    Pocket,
    ProfileIn,
    ProfileOut,
    ProfileOn,
    Drill,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum EntryKind {
    Ramp,
    Helix,
    Plunge,
}

#[derive(ClapArgs, Debug)]
pub struct Args {
    /// Drawing: SVG or DXF (closed paths are contours; circles are holes for --op drill).
    pub input: PathBuf,
    #[arg(long, value_enum)]
    pub op: Op,
    /// Tool: flat:D, ball:D, v:D:ANGLE … [,flute=L,shank=D].
    #[arg(long, default_value = "flat:6")]
    pub tool: String,
    #[arg(long, default_value_t = 1)]
    pub tool_number: u32,
    /// Depth below the stock top, mm.
    #[arg(long)]
    pub depth: f64,
    /// Largest depth per pass, mm (default: half the tool diameter).
    #[arg(long)]
    pub stepdown: Option<f64>,
    /// Pocket step-over, mm (default 0.6 × tool diameter; 0.5–0.75 × D is usual).
    #[arg(long)]
    pub stepover: Option<f64>,
    /// Pocket strategy.
    #[arg(long, default_value = "offset", value_parser = ["offset", "zigzag"])]
    pub strategy: String,
    /// Stock left by the depth passes for one finishing pass at full depth, mm.
    #[arg(long, default_value_t = 0.2)]
    pub allowance: f64,
    /// Cutting feed, mm/min.
    #[arg(long, default_value_t = 800.0)]
    pub feed: f64,
    /// Ramp, helix and plunge feed, mm/min (default: a third of --feed).
    #[arg(long)]
    pub plunge_feed: Option<f64>,
    #[arg(long, default_value_t = 12000.0)]
    pub rpm: f64,
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
    /// Machine profile for the planner's time estimate.
    #[arg(long, default_value = "profiles/grbl-router.toml")]
    pub profile: PathBuf,
}

/// Post-processor choice and format options, shared by `mill` and `sole`.
#[derive(ClapArgs, Debug)]
pub struct PostArgs {
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
    pub fn options(
        &self,
        title: &str,
        settings: Vec<(String, String)>,
    ) -> Result<(PostOptions, Format)> {
        let dialect: Dialect = self.post.parse().map_err(anyhow::Error::msg)?;
        let mut f = post_for(dialect).default_format();
        if let Some(p) = self.precision {
            if matches!(f.numbers, Numbers::Integer { .. }) {
                bail!("--precision: the {} post writes integer words", self.post);
            }
            f.numbers = Numbers::Decimal { places: p };
        }
        if self.inch {
            f.units = Units::Inch;
        }
        if let Some(s) = &self.line_numbers {
            let (a, b) = s.split_once(':').unwrap_or((s, "10"));
            let parse = |v: &str| {
                v.trim()
                    .parse::<u32>()
                    .with_context(|| format!("--line-numbers {s}: write START:STEP, e.g. 10:10"))
            };
            f.line_numbers = Some(LineNumbers {
                start: parse(a)?,
                step: parse(b)?,
            });
        }
        if self.no_modal {
            f.modal = false;
        }
        post_for(dialect)
            .check_format(&f)
            .map_err(anyhow::Error::msg)?;
        Ok((
            PostOptions {
                dialect,
                allow_m6: self.allow_m6,
                title: title.into(),
                settings,
            },
            f,
        ))
    }
}

pub fn progress_bar() -> ProgressBar {
    let bar = ProgressBar::new(100);
    bar.set_style(
        ProgressStyle::with_template("{spinner} {elapsed_precise} {wide_msg}")
            .expect("static template"),
    );
    bar.enable_steady_tick(std::time::Duration::from_millis(200));
    bar
}

/// What a milling program was judged to be.
pub struct Judged {
    pub program: String,
    pub gouge: Option<(f64, [f64; 2])>,
    pub leftover_mean: Option<f64>,
    pub feed_only_s: f64,
    pub planner_s: Option<f64>,
    pub planner_error: Option<String>,
    pub stock_png: Option<oficina_io::Heightmap>,
}

/// Posts, reads back as the interpreter does, simulates against `design`, times.
pub fn judge(
    tp: &Toolpath,
    post: &PostOptions,
    format: &Format,
    design: Option<Design>,
    check_pixel: f64,
    profile: &Path,
    bar: &ProgressBar,
) -> Result<Judged> {
    bar.set_message("writing the program");
    let mut buf = Vec::new();
    write_program_with(tp, post, format, post_for(post.dialect).as_ref(), &mut buf)?;
    let program = String::from_utf8(buf)?;
    bar.set_message("reading it back as the control will");
    let canon = read_back(&program, post)
        .map_err(|e| anyhow::anyhow!("internal error, please report: {e}"))?;
    let tools: HashMap<u32, Tool> = tp
        .operations
        .iter()
        .map(|o| (o.tool_number, o.tool.clone()))
        .collect();
    let (mut gouge, mut leftover_mean, mut stock_png) = (None, None, None);
    if let Some(design) = design {
        bar.set_message("simulating the stock");
        // The tool in the spindle when the program starts: the legacy control has no tool
        // words, and the Sinumerik program moves to its change position before T01 M06.
        // Nothing after the last motion cuts (the Sinumerik end loads the empty T99).
        let end = canon
            .iter()
            .rposition(|c| c.op.is_motion())
            .map_or(0, |k| k + 1);
        let mut ops = canon[..end].to_vec();
        if let Some(first) = tp.operations.first() {
            ops.insert(
                0,
                oficina_canon::Canon {
                    line: 0,
                    op: oficina_canon::CanonOp::SelectTool(first.tool_number),
                },
            );
            let check = check_mill(
                &ops,
                &tools,
                &design,
                check_pixel,
                2.0 * first.tool.diameter + 2.0,
                tp.safe_z,
                &tp.operations.last().expect("one").tool,
            )?;
            gouge = Some((check.report.max_gouge, check.report.gouge_at));
            leftover_mean = Some(check.report.scallop_mean);
            stock_png = Some(check.stock);
        }
    }
    bar.set_message("estimating time");
    let feed_only_s = feed_only_estimate(&canon, [0.0, 0.0, tp.safe_z], 6000.0);
    let (planner_s, planner_error) = match oficina_motion::Profile::load(profile) {
        Ok(p) => {
            match oficina_motion::estimate(oficina_sim::to_machine(&canon, tp.safe_z + 1.0), &p) {
                Ok(e) => (Some(e.seconds), None),
                Err(e) => (None, Some(e.to_string())),
            }
        }
        Err(e) => (None, Some(e.to_string())),
    };
    Ok(Judged {
        program,
        gouge,
        leftover_mean,
        feed_only_s,
        planner_s,
        planner_error,
        stock_png,
    })
}

pub fn hms(s: f64) -> String {
    oficina_motion::format_hms(s, 0)
}

pub fn print_judged(j: &Judged) {
    match j.gouge {
        Some((g, at)) if g > 1e-3 => println!(
            "  gouge:    {g:.3} mm at ({:.2}, {:.2})  ← cut outside the drawing",
            at[0], at[1]
        ),
        Some(_) => println!("  gouge:    none (within 0.001 mm)"),
        None => println!("  gouge:    not checked (a cut on the line is its own design)"),
    }
    if let Some(l) = j.leftover_mean {
        println!(
            "  leftover: {l:.4} mm mean over the checked area, above what the last tool can reach"
        );
    }
    match (j.planner_s, &j.planner_error) {
        (Some(s), _) => println!(
            "  time:     {} (planner), {} at programmed feeds",
            hms(s),
            hms(j.feed_only_s)
        ),
        (None, Some(e)) => println!(
            "  time:     {} at programmed feeds (planner: {e})",
            hms(j.feed_only_s)
        ),
        _ => println!("  time:     {} at programmed feeds", hms(j.feed_only_s)),
    }
}

pub fn run(args: Args) -> Result<std::process::ExitCode> {
    let imported = oficina_io::load_drawing(&args.input)?;
    if !imported.unsupported.is_empty() {
        eprintln!(
            "oficina: warning: {}: {}",
            args.input.display(),
            imported.unsupported
        );
    }
    let paths: Vec<oficina_geom::Path> = imported.drawing.paths().cloned().collect();
    if paths.is_empty() {
        bail!("{}: the drawing has no paths", args.input.display());
    }
    let tool: Tool = args.tool.parse()?;
    let d = tool.diameter;
    let entry = match args.entry {
        EntryKind::Plunge => Entry::Plunge,
        EntryKind::Ramp => Entry::Ramp {
            angle: args.ramp_angle,
        },
        EntryKind::Helix => Entry::Helix {
            radius: args.helix_radius.unwrap_or(d / 3.0),
            angle: args.ramp_angle,
        },
    };
    let cut = Cut {
        tool_number: args.tool_number,
        tool,
        spindle_rpm: args.rpm,
        feed: args.feed / 60.0,
        plunge_feed: args.plunge_feed.unwrap_or(args.feed / 3.0) / 60.0,
        top: 0.0,
        depth: args.depth,
        stepdown: args.stepdown.unwrap_or((d / 2.0).min(args.depth)),
        clear_z: args.clear_z,
        entry,
    };
    let profile = |side| {
        MillOp::Profile(ProfileParams {
            side,
            allowance: if matches!(side, Side::On) {
                0.0
            } else {
                args.allowance
            },
            tabs: (args.tabs > 0).then_some(Tabs {
                count: args.tabs,
                width: args.tab_width,
                height: args.tab_height,
            }),
            lead_out: args.lead_out,
        })
    };
    let op = match args.op {
        Op::Pocket => MillOp::Pocket(PocketParams {
            strategy: if args.strategy == "zigzag" {
                Strategy::ZigZag
            } else {
                Strategy::Offset
            },
            stepover: args.stepover.unwrap_or(0.6 * d),
            allowance: args.allowance,
        }),
        Op::ProfileIn => profile(Side::Inside),
        Op::ProfileOut => profile(Side::Outside),
        Op::ProfileOn => profile(Side::On),
        Op::Drill => MillOp::Drill(DrillParams {
            peck: args.peck,
            dwell: args.dwell,
        }),
    };
    if args.safe_z < args.clear_z {
        bail!(
            "--safe-z {} must be at or above --clear-z {}",
            args.safe_z,
            args.clear_z
        );
    }
    let bar = progress_bar();
    bar.set_message(format!("{} with {}", op.name(), cut.tool.spec()));
    let tp = toolpath(&paths, &cut, &op, args.safe_z)?;
    let settings = vec![
        ("input".into(), args.input.display().to_string()),
        ("operation".into(), op.name().into()),
        (
            "tool".into(),
            format!("T{} {}", cut.tool_number, cut.tool.spec()),
        ),
        (
            "depth".into(),
            format!("{} mm in passes of at most {} mm", cut.depth, cut.stepdown),
        ),
    ];
    let (post, format) = args.out.options("Oficina 2.5D milling", settings)?;
    let design = allowed_region(&paths, &op)?.map(|(rings, cut_inside)| Design {
        rings,
        cut_inside,
        top: cut.top,
        floor: cut.bottom(),
    });
    let judged = judge(
        &tp,
        &post,
        &format,
        design,
        args.check_pixel,
        &args.profile,
        &bar,
    )?;
    std::fs::write(&args.output, &judged.program)
        .with_context(|| format!("{}: cannot write the program", args.output.display()))?;
    let preview = args
        .preview
        .clone()
        .unwrap_or_else(|| args.output.with_extension("svg"));
    std::fs::write(&preview, preview_svg(&paths, &tp))
        .with_context(|| format!("{}: cannot write the preview", preview.display()))?;
    let stock_png = args.output.with_extension("stock.png");
    if let Some(stock) = &judged.stock_png {
        render_png(stock, &stock_png).map_err(anyhow::Error::msg)?;
    }
    bar.finish_and_clear();
    println!(
        "{}: {} ({} moves)",
        args.output.display(),
        op.name(),
        tp.move_count()
    );
    println!("  preview:  {}", preview.display());
    if judged.stock_png.is_some() {
        println!("  stock:    {}", stock_png.display());
    }
    print_judged(&judged);
    let gouged = judged.gouge.is_some_and(|(g, _)| g > 1e-3);
    Ok(if gouged {
        std::process::ExitCode::from(2)
    } else {
        std::process::ExitCode::SUCCESS
    })
}
