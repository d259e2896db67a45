//! `oficina bench carve`: tool surface + toolpath generation for a generated relief, beside
//! LinuxCNC's image-to-gcode on a crop of the same image with the same tool and step, and
//! both programs replayed through the interpreter and the stock simulator for gouge.

use anyhow::{bail, Result};
use clap::Args as ClapArgs;
use oficina_app::bench::carve::{
    check_size, compare_on_crop, design, job, peer_script, peer_window, peer_worked_pixels,
    plan_and_post, relief_image, Ours, BALL_DIAMETER, DEPTH, MAX_SIZE, PIXEL, STEP_PX,
};
use oficina_app::bench::{self, BenchError, Cost};
use oficina_io::Heightmap;
use std::path::PathBuf;

#[derive(ClapArgs, Debug)]
pub(crate) struct Args {
    /// Side of the generated square image, pixels.
    #[arg(long, default_value_t = 4000)]
    pub size: usize,
    /// Side of the crop (top-left corner) given to image-to-gcode, pixels.
    #[arg(long, default_value_t = 600)]
    pub peer_crop: usize,
    /// Skip image-to-gcode and the crop comparison.
    #[arg(long)]
    pub no_peer: bool,
    /// Python 3 with numpy, for image-to-gcode.
    #[arg(long, default_value = "/usr/bin/python3")]
    pub python: PathBuf,
    /// The driver script for image-to-gcode.
    #[arg(long)]
    pub peer_script: Option<PathBuf>,
    /// How far oficina's straight moves may stay above the surface when merging samples,
    /// mm (one-sided: never below). image-to-gcode's 0.001 is two-sided, a 0.002 band.
    #[arg(long, default_value_t = 0.002)]
    pub tolerance: f64,
    /// Tip heights oficina evaluates per pixel along a row.
    #[arg(long, default_value_t = oficina_cam::relief::SAMPLES_PER_PIXEL)]
    pub samples_per_pixel: usize,
    /// Memory budget for the generated relief, the toolpath and its G-code text, MB.
    #[arg(long, default_value_t = 4096)]
    pub memory_mb: u64,
    /// The mesh case instead: drop-cutter on this STL/OBJ beside OpenCAMLib's BatchDropCutter.
    #[arg(long)]
    pub mesh: Option<PathBuf>,
    /// Mesh case: the tool (flat:D, ball:D, bull:D:CORNER, v:D:ANGLE).
    #[arg(long, default_value = "ball:3")]
    pub mesh_tool: String,
    /// Mesh case: spacing of the grid of drop points, mm.
    #[arg(long, default_value_t = 0.1)]
    pub grid_step: f64,
    /// Mesh case: Python 3 with opencamlib.
    #[arg(long, default_value = "python3")]
    pub ocl_python: PathBuf,
    /// Mesh case: the OpenCAMLib driver script (default crates/cam/tests/peer/ocl_drop.py).
    #[arg(long)]
    pub ocl_script: Option<PathBuf>,
}

/// A memory refusal names the options that change it.
fn explain(e: BenchError) -> anyhow::Error {
    match e {
        BenchError::OverMemory(s) => anyhow::anyhow!("{s} (options: --size, --memory-mb)"),
        e => e.into(),
    }
}

fn budget(args: &Args) -> u64 {
    args.memory_mb.saturating_mul(1 << 20)
}

fn time_ours(map: &Heightmap, args: &Args) -> Result<Ours> {
    plan_and_post(
        map,
        &job(args.tolerance, args.samples_per_pixel),
        budget(args),
    )
    .map_err(explain)
}

pub(crate) fn run(args: Args) -> Result<()> {
    if let Some(mesh) = &args.mesh {
        return run_mesh(&args, mesh);
    }
    if !(64..=MAX_SIZE).contains(&args.size) {
        bail!(
            "--size must be between 64 and {MAX_SIZE} pixels, got {}",
            args.size
        );
    }
    let c = args.peer_crop;
    // The quality comparison leaves out a tool-diameter margin on each side of the crop.
    let least = 2 * (BALL_DIAMETER / PIXEL).ceil() as usize + 8;
    if !args.no_peer && !(least..=args.size).contains(&c) {
        bail!(
            "--peer-crop must be between {least} and --size ({}), got {c}",
            args.size
        );
    }
    let n = args.size;
    println!(
        "Relief toolpath benchmark: generated {n} x {n} relief, {PIXEL} mm/pixel, {DEPTH} mm deep, \
         ball {BALL_DIAMETER} mm, rows every {STEP_PX} pixels ({} mm), one finishing pass along X",
        STEP_PX as f64 * PIXEL
    );
    // The gray picture (1 byte a pixel), its luminance and the height grid (4 bytes each).
    check_size(n, budget(&args)).map_err(explain)?;
    let gray = relief_image(n);
    let full = design(&gray, n);
    let ours = time_ours(&full, &args)?;
    let ours_total = ours.plan.plus(ours.post);
    let px = (n * n) as f64;
    println!(
        "oficina, full {n} x {n}: {:.2} s wall, {:.2} s CPU ({:.1} ns/pixel wall), {} moves, {:.0} MB of G-code",
        ours_total.wall,
        ours_total.cpu,
        ours_total.wall / px * 1e9,
        ours.moves,
        ours.program.len() as f64 / 1e6
    );
    if args.no_peer {
        print_peak_memory();
        return Ok(());
    }
    let dir = tempfile::tempdir()?;
    let script = peer_script(args.peer_script.as_deref());
    let job = job(args.tolerance, args.samples_per_pixel);
    let cmp = compare_on_crop(
        &gray,
        n,
        c,
        &args.python,
        &script,
        &job,
        budget(&args),
        dir.path(),
    )
    .map_err(explain)?;
    for p in [&cmp.small_peer, &cmp.peer] {
        for d in p.diagnostics.iter().take(3) {
            eprintln!("image-to-gcode output: {d}");
        }
    }
    let (half, small_peer, peer, ours_crop) = (cmp.half, &cmp.small_peer, &cmp.peer, &cmp.ours);
    // image-to-gcode places tool centres only where the whole tool window fits: it works on
    // (side − window)² pixels, so that is what its cost is per.
    let window = peer_window();
    let worked = peer_worked_pixels;
    let peer_rate = peer.seconds / worked(c);
    let peer_cpu_rate = peer.cpu / worked(c);
    let (ours_q, peer_q) = (&cmp.ours_quality, &cmp.peer_quality);

    println!();
    println!(
        "Time (tool surface + toolpath + G-code text; image-to-gcode's convert() writing its \
         program, headless). 2 cores shared: wall times are noisy, CPU (getrusage, all threads) less so."
    );
    println!(
        "{:<44} {:>9} {:>9} {:>12} {:>12}",
        "", "wall s", "CPU s", "ns/px wall", "ns/px CPU"
    );
    let row = |name: String, c: Cost, pixels: f64| {
        println!(
            "{:<44} {:>9.3} {:>9.3} {:>12.1} {:>12.1}",
            name,
            c.wall,
            c.cpu,
            c.wall / pixels * 1e9,
            c.cpu / pixels * 1e9
        )
    };
    row(
        format!("oficina, full {n} x {n}: surface + path"),
        ours.plan,
        px,
    );
    row(
        format!("oficina, full {n} x {n}: G-code text"),
        ours.post,
        px,
    );
    row(format!("oficina, full {n} x {n}: total"), ours_total, px);
    let crop_px = (c * c) as f64;
    row(
        format!("oficina, crop {c} x {c}: total"),
        ours_crop.plan.plus(ours_crop.post),
        crop_px,
    );
    for (p, side) in [(small_peer, half), (peer, c)] {
        row(
            format!("image-to-gcode, crop {side} x {side}"),
            Cost {
                wall: p.seconds,
                cpu: p.cpu,
            },
            (side * side) as f64,
        );
    }
    let small_rate = small_peer.cpu / worked(half);
    println!(
        "image-to-gcode CPU per pixel it works on ((side - {window})^2): {:.0} ns at {half}^2, \
         {:.0} ns at {c}^2 (ratio {:.2}: {})",
        small_rate * 1e9,
        peer_cpu_rate * 1e9,
        peer_cpu_rate / small_rate,
        if (0.8..1.25).contains(&(peer_cpu_rate / small_rate)) {
            "linear in pixels, so its crop rate scales to the full image"
        } else {
            "NOT linear: the scaled figure below is only indicative"
        }
    );
    println!(
        "image-to-gcode, {n} x {n} SCALED from the {c}^2 crop: {:.0} s wall, {:.0} s CPU",
        peer_rate * worked(n),
        peer_cpu_rate * worked(n)
    );
    println!(
        "speed-up, oficina full image vs image-to-gcode scaled to it: {:.0}x wall, {:.0}x CPU; \
         on the same {c}^2 crop: {:.0}x wall, {:.0}x CPU",
        peer_rate * worked(n) / ours_total.wall,
        peer_cpu_rate * worked(n) / ours_total.cpu,
        peer.seconds / ours_crop.plan.plus(ours_crop.post).wall,
        peer.cpu / ours_crop.plan.plus(ours_crop.post).cpu
    );
    println!();
    println!(
        "Quality on the crop, both programs read by the interpreter and replayed on the \
         simulated stock (tool-diameter margin excluded; peer's G64 blending not modelled). \
         'best possible' is the ideal surface of the same tool (design dilated then eroded): \
         what no non-gouging program can go below; leftover under it needs gouging."
    );
    println!(
        "{:<16} {:>10} {:>16} {:>10} {:>10} {:>12} {:>12}",
        "", "gouge mm", "area > 1 um", "left max", "left mean", "scallop max", "scallop mean"
    );
    let best = (cmp.best.clone(), 0.0);
    for (name, (q, gouged)) in [
        ("oficina", ours_q),
        ("image-to-gcode", peer_q),
        ("best possible", &best),
    ] {
        println!(
            "{:<16} {:>10.4} {:>15.2}% {:>10.3} {:>10.4} {:>12.3} {:>12.4}",
            name,
            q.max_gouge,
            gouged * 100.0,
            q.leftover_max,
            q.leftover_mean,
            q.scallop_max,
            q.scallop_mean
        );
    }
    if peer_q.0.max_gouge > 0.0 {
        println!(
            "image-to-gcode's deepest gouge at X{:.2} Y{:.2} (crop interior frame)",
            peer_q.0.gouge_at[0], peer_q.0.gouge_at[1]
        );
    }
    println!(
        "programs: oficina {} lines, image-to-gcode {} lines ({} interpreter diagnostics)",
        ours_crop.program.lines().count(),
        peer.lines,
        peer.diagnostics.len()
    );
    print_peak_memory();
    Ok(())
}

/// The mesh case: the same points dropped by both, time, memory and agreement side by side.
fn run_mesh(args: &Args, path: &std::path::Path) -> Result<()> {
    use oficina_app::bench::carve_mesh::{
        agreement, drop_ours, drop_peer, grid_points, peer_cutter,
    };
    let tool: oficina_cam::Tool = args
        .mesh_tool
        .parse()
        .map_err(|e| anyhow::anyhow!("--mesh-tool {}: {e}", args.mesh_tool))?;
    let cutter = peer_cutter(&tool).map_err(explain)?;
    let before_kb = bench::peak_memory_kb();
    let mesh = oficina_io::load_mesh(path, budget(args))
        .map_err(|e| anyhow::anyhow!("{}", oficina_app::Error::chain(&e)))?;
    let points = grid_points(&mesh, tool.radius(), args.grid_step).map_err(explain)?;
    let cores = std::thread::available_parallelism().map_or(0, |n| n.get());
    println!(
        "Mesh drop-cutter benchmark: {} ({} triangles), tool {}, {} points every {} mm over the \
         model's box grown by the tool radius; {cores} cores, load {}",
        path.display(),
        mesh.triangles.len(),
        tool.spec(),
        points.len(),
        args.grid_step,
        bench::load_average().unwrap_or_else(|| "?".into())
    );
    let ours = drop_ours(&mesh, &tool, &points);
    let ours_kb = bench::peak_memory_kb();
    let script = oficina_app::bench::carve_mesh::peer_script(args.ocl_script.as_deref());
    let peer = drop_peer(&args.ocl_python, &script, path, cutter, &points).map_err(explain)?;
    let a = agreement(&points, &ours.z, &peer.z);
    println!(
        "Time: building the search structure + dropping at every point (OpenCAMLib: setSTL, \
         setCutter, appendPoint, run). CPU from getrusage / process_time, all threads."
    );
    println!(
        "{:<34} {:>9} {:>9} {:>12} {:>14} {:>16}",
        "", "wall s", "CPU s", "us/pt CPU", "peak MB", "peak - base MB"
    );
    let mb = |kb: u64| kb as f64 / 1024.0;
    let n = points.len() as f64;
    let row = |name: &str, c: oficina_app::bench::Cost, peak: Option<u64>, base: Option<u64>| {
        let show = |v: Option<f64>| v.map_or("?".to_string(), |v| format!("{v:.1}"));
        println!(
            "{:<34} {:>9.3} {:>9.3} {:>12.2} {:>14} {:>16}",
            name,
            c.wall,
            c.cpu,
            c.cpu / n * 1e6,
            show(peak.map(mb)),
            show(peak.zip(base).map(|(p, b)| mb(p.saturating_sub(b))))
        )
    };
    row("oficina DropCutter", ours.cost, ours_kb, before_kb);
    row(
        "OpenCAMLib BatchDropCutter",
        peer.cost,
        Some(peer.peak_kb),
        Some(peer.base_kb),
    );
    println!(
        "(base: oficina before reading the mesh; OpenCAMLib after importing it, before reading \
         the mesh. Each side's peak includes its copy of the points.)"
    );
    println!(
        "speed-up: {:.1}x wall, {:.1}x CPU",
        peer.cost.wall / ours.cost.wall,
        peer.cost.cpu / ours.cost.cpu
    );
    println!(
        "agreement: max |dz| {:.6} mm at X{:.3} Y{:.3} over {} points both touch; {} above \
         0.001 mm; {} touched by one only (the rim of the reach)",
        a.max_dz, a.at[0], a.at[1], a.both, a.over_micron, a.one_only
    );
    Ok(())
}

/// The process's peak resident memory (VmHWM): the whole benchmark's.
fn print_peak_memory() {
    match bench::peak_memory_kb() {
        Some(kb) => println!("peak memory (VmHWM): {:.0} MB", kb as f64 / 1024.0),
        None => println!("peak memory: unavailable (no /proc/self/status)"),
    }
}
