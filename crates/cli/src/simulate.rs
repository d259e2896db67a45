//! `oficina simulate PROGRAM --stock WxHxT`: any program replayed on a box of stock with its
//! tools' real shapes; the stock rendered to a PNG and what to look at printed.

use crate::gcode_input::{loaded, machine_for, ProgramArgs};
use crate::machine_profile;
use oficina_app::simulate::{
    simulate, DesignImage, SimulateRequest, SimulationReport, StockSize, ToolChoice,
    DEFAULT_SIM_MEMORY_MB,
};
use oficina_cam::{Library, Tool};
use oficina_motion::format_hms;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    #[command(flatten)]
    pub program: ProgramArgs,
    /// Stock size `WxHxT` in mm (width X, height Y, thickness Z), or `auto` (the cuts'
    /// extents plus --margin and the tool radius).
    #[arg(long, value_parser = parse_stock)]
    pub stock: StockSize,
    /// Lower-left X, Y and top Z of the stock, mm (default: the cuts' lower-left, top Z 0).
    #[arg(long, value_parser = machine_profile::parse_xyz)]
    pub stock_origin: Option<[f64; 3]>,
    /// Margin around the cuts for `--stock auto`, mm.
    #[arg(long, default_value_t = 2.0)]
    pub margin: f64,
    /// Tool shape: `flat:3`, `ball:6`, `v:6:60` for every tool not known otherwise, or
    /// `N=SPEC` for tool N; repeat.
    #[arg(long)]
    pub tool: Vec<String>,
    /// A tool library (TOML, as `mill` reads) giving each tool number's shape.
    #[arg(long)]
    pub tool_library: Option<PathBuf>,
    /// Grid cell, mm (default: the finest that fits --memory-mb and seconds of stamping).
    #[arg(long)]
    pub resolution: Option<f64>,
    /// Memory budget for the stock grids, MB.
    #[arg(long, default_value_t = DEFAULT_SIM_MEMORY_MB)]
    pub memory_mb: u64,
    /// Shaded render of the stock (PNG).
    #[arg(short, long, default_value = "stock.png")]
    pub output: PathBuf,
    /// The design as a grayscale image (white = stock top) to compare with: gouge, leftover.
    #[arg(long)]
    pub design: Option<PathBuf>,
    /// Depth of black in --design, mm.
    #[arg(long, default_value_t = 3.0)]
    pub design_depth: f64,
    /// Print the report as JSON instead of text.
    #[arg(long)]
    pub json: bool,
    /// Machine profile whose planner times the program (default: the program's
    /// `(machine: NAME)` comment, else grbl-router).
    #[arg(long)]
    pub machine: Option<String>,
}

fn parse_stock(text: &str) -> Result<StockSize, String> {
    if text.eq_ignore_ascii_case("auto") {
        return Ok(StockSize::Auto { margin: 0.0 });
    }
    let parts: Vec<&str> = text.split(['x', 'X']).map(str::trim).collect();
    let nums: Vec<f64> = parts.iter().filter_map(|p| p.parse().ok()).collect();
    if parts.len() != 3 || nums.len() != 3 {
        return Err(format!(
            "expected WxHxT in mm (e.g. 100x80x10) or auto, got '{text}'"
        ));
    }
    Ok(StockSize::Given([nums[0], nums[1], nums[2]]))
}

fn tool_choice(args: &Args) -> anyhow::Result<ToolChoice> {
    let mut choice = ToolChoice::default();
    for t in &args.tool {
        match t.split_once('=') {
            Some((n, spec)) => {
                let n: u32 = n
                    .trim()
                    .trim_start_matches(['T', 't'])
                    .parse()
                    .map_err(|_| anyhow::anyhow!("--tool {t}: '{n}' is not a tool number"))?;
                choice.by_number.push((n, spec.parse::<Tool>()?));
            }
            None => choice.default = Some(t.parse::<Tool>()?),
        }
    }
    if let Some(path) = &args.tool_library {
        choice.library = Some(Library::load(path)?);
    }
    Ok(choice)
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    let machine = machine_for(args.machine.as_deref(), &args.program.file);
    let profile = machine_profile::resolve(&machine)?;
    let run = args.program.run_options_on(&profile, &machine, true)?;
    let text = loaded(oficina_app::read_program(
        &args.program.file,
        oficina_app::DEFAULT_MAX_PROGRAM_MB,
    ))?;
    oficina_app::check_output("simulate", "-o", &args.output, &["png"])?;
    if oficina_app::same_file(&args.output, &args.program.file) {
        anyhow::bail!("-o {} is the program itself", args.output.display());
    }
    let stock = match args.stock {
        StockSize::Auto { .. } => StockSize::Auto {
            margin: args.margin,
        },
        s => s,
    };
    let req = SimulateRequest {
        text: Arc::new(text),
        run,
        profile,
        tools: tool_choice(&args)?,
        stock,
        stock_origin: args.stock_origin,
        resolution: args.resolution,
        memory_mb: args.memory_mb,
        design: args.design.clone().map(|path| DesignImage {
            path,
            depth: args.design_depth,
        }),
    };
    let sim = simulate(&req)?;
    oficina_sim::render_png(&sim.stock, &args.output).map_err(anyhow::Error::msg)?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&sim.report)?);
    } else {
        print_report(&args.program.file, &sim.report, &machine);
        println!("  render                  {}", args.output.display());
    }
    Ok(ExitCode::SUCCESS)
}

fn print_report(file: &std::path::Path, r: &SimulationReport, machine: &str) {
    println!("{}: simulated on stock", file.display());
    for e in &r.errors {
        eprintln!(
            "{}:{}:{}: error: {}",
            file.display(),
            e.line,
            e.col,
            e.message
        );
    }
    let [w, h, t] = r.stock_size;
    println!(
        "  stock                   {w:.3} x {h:.3} x {t:.3} mm, lower-left X{:.3} Y{:.3}, top Z{:.3}",
        r.stock_origin[0], r.stock_origin[1], r.stock_top
    );
    println!(
        "  grid                    {} x {} cells of {}",
        r.grid_width, r.grid_height, r.resolution_note
    );
    for t in &r.tools {
        println!("  tool T{:<20} {} ({})", t.number, t.spec, t.from);
    }
    println!("  material removed        {:.1} mm³", r.removed_mm3);
    println!(
        "  stock surface           Z {:.3} … {:.3} (program's lowest tip Z {})",
        r.lowest_z,
        r.highest_z,
        r.program_lowest_z
            .map_or("none".into(), |z| format!("{z:.3}"))
    );
    if r.through_mm2 > 0.0 {
        println!(
            "  cut through             {:.1} mm² down to the bottom",
            r.through_mm2
        );
    }
    match &r.machine_seconds {
        Ok(s) => println!(
            "  machine time            {} on {machine} (planner; {:.1} mm of feed moves)",
            format_hms(*s, 1),
            r.feed_length
        ),
        Err(e) => println!("  machine time            not available on {machine}: {e}"),
    }
    let list = |name: &str, count: usize, items: Vec<String>| {
        if count > 0 {
            println!(
                "  {name:<23} {count}: {}{}",
                items.join(", "),
                if count > items.len() { ", …" } else { "" }
            );
        }
    };
    list(
        "RAPID INTO MATERIAL",
        r.counts[0],
        r.rapids_into_material
            .iter()
            .map(|(l, d)| format!("line {l} ({d:.3} mm deep)"))
            .collect(),
    );
    list(
        "BELOW STOCK BOTTOM",
        r.counts[1],
        r.below_bottom
            .iter()
            .map(|(l, z)| format!("line {l} (Z{z:.3})"))
            .collect(),
    );
    list(
        "cuts off the stock",
        r.counts[2],
        r.off_stock
            .iter()
            .take(10)
            .map(|(l, a)| format!("line {l} (X{:.2} Y{:.2})", a[0], a[1]))
            .collect(),
    );
    if let Some(d) = &r.design {
        println!(
            "  against the design      gouge {:.3} mm at X{:.2} Y{:.2}, leftover max {:.3} mm, mean {:.3} mm",
            d.max_gouge, d.gouge_at[0], d.gouge_at[1], d.leftover_max, d.leftover_mean
        );
    }
    for n in &r.notes {
        println!("  note: {n}");
    }
}
