//! `oficina bench carve`: tool surface + toolpath generation for a generated relief, beside
//! LinuxCNC's image-to-gcode on a crop of the same image with the same tool and step, and
//! both programs replayed through the interpreter and the stock simulator for gouge.

use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use oficina_cam::memory::{self, Budget, Lever};
use oficina_cam::relief::{plan_within, Cutter, Direction, Job, Pass, ReliefError};
use oficina_cam::Feeds;
use oficina_cam::Tool;
use oficina_canon::{Canon, CanonOp};
use oficina_io::luminance_to_heights;
use oficina_io::{DepthMapping, Heightmap};
use oficina_post::{program_text, Dialect, PostOptions};
use oficina_sim::carve::interpret;
use oficina_sim::{compare, ideal_surface, replay, Report};
use std::collections::HashMap;
use std::path::PathBuf;
use std::time::Instant;

#[derive(ClapArgs, Debug)]
pub struct Args {
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
}

const PIXEL: f64 = 0.1;
const DEPTH: f64 = 10.0;
const BALL_DIAMETER: f64 = 6.0;
/// Rows 5 pixels (0.5 mm) apart for both programs: image-to-gcode steps in whole pixels.
const STEP_PX: usize = 5;
const MAX_SIZE: usize = 20_000;

/// A deterministic relief: gentle waves, domes and a steep-walled ring, 8-bit gray.
fn relief_image(n: usize) -> Vec<u8> {
    let mut out = Vec::with_capacity(n * n);
    let s = 4000.0 / n.max(1) as f64;
    for row in 0..n {
        for col in 0..n {
            let (x, y) = (col as f64 * s * PIXEL, row as f64 * s * PIXEL);
            let waves = 0.25 * (1.0 + (x * 0.07).sin() * (y * 0.05).cos());
            let dome = |cx: f64, cy: f64, r: f64| {
                let d2 = ((x - cx).powi(2) + (y - cy).powi(2)) / (r * r);
                (1.0 - d2).max(0.0).sqrt()
            };
            let domes = 0.4 * dome(120.0, 130.0, 60.0) + 0.3 * dome(290.0, 260.0, 80.0);
            let rd = ((x - 200.0).powi(2) + (y - 200.0).powi(2)).sqrt();
            let ring = if (150.0..170.0).contains(&rd) {
                0.3
            } else {
                0.0
            };
            let v = 1.0 - (waves + domes + ring).min(1.0);
            out.push((v * 255.0).round() as u8);
        }
    }
    out
}

fn crop(img: &[u8], n: usize, c: usize) -> Vec<u8> {
    (0..c)
        .flat_map(|r| img[r * n..r * n + c].iter().copied())
        .collect()
}

fn design(gray: &[u8], n: usize) -> Heightmap {
    let luma: Vec<f32> = gray.iter().map(|&v| v as f32 / 255.0).collect();
    luminance_to_heights(n, n, &luma, PIXEL, DepthMapping::new(DEPTH))
}

fn tool() -> Tool {
    Tool::new(oficina_cam::Shape::Ball, BALL_DIAMETER).expect("valid built-in tool")
}

/// One finishing pass, as image-to-gcode does: rows along X, zig-zag, one level.
fn job(args: &Args) -> Job {
    Job {
        safe_z: 5.0,
        clearance: 1.0,
        tolerance: args.tolerance,
        samples_per_pixel: args.samples_per_pixel,
        passes: vec![Pass {
            name: "finish".into(),
            cutter: Cutter {
                number: 1,
                tool: tool(),
                feeds: Feeds {
                    cut: 2000.0 / 60.0,
                    plunge: 500.0 / 60.0,
                    rapid: 5000.0 / 60.0,
                },
                spindle_rpm: 18000.0,
            },
            stepover: STEP_PX as f64 * PIXEL,
            stepdown: 1000.0,
            allowance: 0.0,
            direction: Direction::X,
            zigzag: true,
            rest_only: false,
            min_cut: 0.001,
        }],
        simulate_last: false,
    }
}

/// Wall and CPU seconds (CPU: every thread of this process, from getrusage).
#[derive(Clone, Copy, Debug, Default)]
struct Cost {
    wall: f64,
    cpu: f64,
}

impl Cost {
    fn plus(self, o: Cost) -> Cost {
        Cost {
            wall: self.wall + o.wall,
            cpu: self.cpu + o.cpu,
        }
    }
}

/// User + system CPU seconds used so far by this process.
fn cpu_now() -> f64 {
    use nix::sys::resource::{getrusage, UsageWho};
    getrusage(UsageWho::RUSAGE_SELF).map_or(0.0, |u| {
        let t = |v: nix::sys::time::TimeVal| v.tv_sec() as f64 + v.tv_usec() as f64 * 1e-6;
        t(u.user_time()) + t(u.system_time())
    })
}

fn measure<T>(f: impl FnOnce() -> T) -> (T, Cost) {
    let (wall, cpu) = (Instant::now(), cpu_now());
    let out = f();
    let cost = Cost {
        wall: wall.elapsed().as_secs_f64(),
        cpu: cpu_now() - cpu,
    };
    (out, cost)
}

struct Ours {
    /// Tool surface + toolpath.
    plan: Cost,
    /// Writing the G-code text (image-to-gcode's time includes writing its program too).
    post: Cost,
    program: String,
    moves: usize,
}

fn time_ours(map: &Heightmap, args: &Args) -> Result<Ours> {
    // Each move is kept as a move and as a line of text.
    let budget = Budget {
        bytes: args.memory_mb.saturating_mul(1 << 20),
        reserved: 0,
        per_move: oficina_sim::carve::bytes_per_move(),
    };
    let (planned, plan_cost) = measure(|| plan_within(map, &job(args), budget, &|_, _| {}));
    let planned = planned.map_err(|e| match e {
        ReliefError::Memory(_) => anyhow::anyhow!("{e} (options: --size, --memory-mb)"),
        e => e.into(),
    })?;
    let post = PostOptions {
        dialect: Dialect::LinuxCnc,
        allow_m6: false,
        title: "bench carve".into(),
        settings: vec![],
    };
    let (program, post_cost) = measure(|| program_text(&planned.toolpath, &post));
    let program = program?;
    Ok(Ours {
        plan: plan_cost,
        post: post_cost,
        program,
        moves: planned.toolpath.move_count(),
    })
}

/// The part both programs machine: image-to-gcode's tool centres stop a tool radius inside
/// the picture, so a margin of one tool diameter is left out.
fn inner(h: &Heightmap) -> Heightmap {
    let m = (BALL_DIAMETER / PIXEL).ceil() as usize;
    {
        let (w, hh) = (h.width - 2 * m, h.height - 2 * m);
        let z = (m..m + hh)
            .flat_map(|iy| h.row(iy)[m..m + w].iter().copied())
            .collect();
        Heightmap {
            width: w,
            height: hh,
            pixel: h.pixel,
            z,
        }
    }
}

/// The simulator's report of a program over the inner part, and the share of it gouged.
fn judge(canon: &[Canon], map: &Heightmap) -> Result<(Report, f64)> {
    let tools = HashMap::from([(1, tool())]);
    let mut stock = Heightmap::flat(map.width, map.height, map.pixel, 0.0);
    replay(canon, &tools, &mut stock, [0.0, 0.0, 5.0])?;
    let ideal = ideal_surface(map, &tool());
    let (stock, design) = (inner(&stock), inner(map));
    let gouged = stock
        .z
        .iter()
        .zip(&design.z)
        .filter(|(s, d)| **s < **d - GOUGE_LIMIT as f32)
        .count() as f64
        / design.z.len() as f64;
    Ok((compare(&stock, &design, &inner(&ideal)), gouged))
}

/// Depth below the design that counts as a gouge, mm.
const GOUGE_LIMIT: f64 = 0.001;

struct Peer {
    seconds: f64,
    cpu: f64,
    canon: Vec<Canon>,
    diagnostics: usize,
    lines: usize,
}

fn run_peer(args: &Args, gray: &[u8], c: usize, dir: &std::path::Path) -> Result<Peer> {
    let script = args.peer_script.clone().unwrap_or_else(|| {
        let local = PathBuf::from("scripts/image_to_gcode_peer.py");
        if local.exists() {
            local
        } else {
            PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../scripts/image_to_gcode_peer.py")
        }
    });
    let raw = dir.join("crop.gray");
    let out = dir.join("peer.ngc");
    std::fs::write(&raw, gray)?;
    let run = std::process::Command::new(&args.python)
        .arg(&script)
        .arg(&raw)
        .args([c.to_string(), c.to_string()])
        .args([PIXEL, DEPTH, BALL_DIAMETER].map(|v| v.to_string()))
        .arg(STEP_PX.to_string())
        .arg(&out)
        .output()
        .with_context(|| format!("cannot run {} {}", args.python.display(), script.display()))?;
    if !run.status.success() {
        bail!(
            "image-to-gcode failed: {}",
            String::from_utf8_lossy(&run.stderr)
        );
    }
    let stdout = String::from_utf8_lossy(&run.stdout);
    let field = |key: &str| -> Result<Vec<f64>> {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(key))
            .with_context(|| format!("peer printed no {key}: {stdout}"))?;
        line.split_whitespace()
            .skip(1)
            .map(|v| v.parse().with_context(|| format!("bad {key} line: {line}")))
            .collect()
    };
    let seconds = field("SECONDS")?[0];
    let cpu = field("CPU")?[0];
    let offset = field("OFFSET")?;
    let text = std::fs::read_to_string(&out)?;
    let opts = oficina_gcode::RunOptions::default();
    let mut canon = vec![Canon {
        line: 0,
        op: CanonOp::ChangeTool(1),
    }];
    let diags = oficina_gcode::run_text(&text, &opts, &mut |mut c| {
        // Into the image grid's frame (see the script).
        match &mut c.op {
            CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => {
                to.x += offset[0];
                to.y += offset[1];
            }
            CanonOp::ArcFeed { end, center, .. } => {
                end.x += offset[0];
                end.y += offset[1];
                center[0] += offset[0];
                center[1] += offset[1];
            }
            _ => {}
        }
        canon.push(c)
    });
    for d in diags.iter().take(3) {
        eprintln!("image-to-gcode output: {d}");
    }
    Ok(Peer {
        seconds,
        cpu,
        canon,
        diagnostics: diags.len(),
        lines: text.lines().count(),
    })
}

pub fn run(args: Args) -> Result<()> {
    if !(64..=MAX_SIZE).contains(&args.size) {
        bail!(
            "--size must be between 64 and {MAX_SIZE} pixels, got {}",
            args.size
        );
    }
    let c = args.peer_crop;
    if !args.no_peer && !(64..=args.size).contains(&c) {
        bail!(
            "--peer-crop must be between 64 and --size ({}), got {c}",
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
    memory::check(
        || format!("the generated {n} x {n} relief"),
        memory::grid_bytes(n, n).saturating_mul(2) + (n * n) as u64,
        args.memory_mb.saturating_mul(1 << 20),
        Lever::PixelSize,
    )
    .map_err(|e| anyhow::anyhow!("{e} (options: --size, --memory-mb)"))?;
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
    // The peer on two crop sizes: equal cost per pixel shows it is linear, so scaling its
    // crop rate to the full image is fair.
    let dir = tempfile::tempdir()?;
    let half = (c / 2).max(64);
    let small_peer = run_peer(&args, &crop(&gray, n, half), half, dir.path())?;
    let small = crop(&gray, n, c);
    let crop_map = design(&small, c);
    let ours_crop = time_ours(&crop_map, &args)?;
    let peer = run_peer(&args, &small, c, dir.path())?;
    // image-to-gcode places tool centres only where the whole tool window fits: it works on
    // (side − window)² pixels, so that is what its cost is per.
    let window = (BALL_DIAMETER / PIXEL + 0.5) as usize;
    let worked = |side: usize| (side.saturating_sub(window).max(1) as f64).powi(2);
    let peer_rate = peer.seconds / worked(c);
    let peer_cpu_rate = peer.cpu / worked(c);
    let post = PostOptions {
        dialect: Dialect::LinuxCnc,
        allow_m6: false,
        title: String::new(),
        settings: vec![],
    };
    let ours_canon = interpret(&ours_crop.program, &post)?;
    let ours_q = judge(&ours_canon, &crop_map)?;
    let peer_q = judge(&peer.canon, &crop_map)?;

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
    for (p, side) in [(&small_peer, half), (&peer, c)] {
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
    let ideal = inner(&ideal_surface(&crop_map, &tool()));
    let best = compare(&ideal, &inner(&crop_map), &ideal);
    for (name, (q, gouged)) in [
        ("oficina", &ours_q),
        ("image-to-gcode", &peer_q),
        ("best possible", &(best, 0.0)),
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
        peer.diagnostics
    );
    print_peak_memory();
    Ok(())
}

/// The process's peak resident memory (VmHWM): the whole benchmark's, since the kernel
/// keeps the high-water mark.
fn print_peak_memory() {
    let peak = std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            let line = s.lines().find(|l| l.starts_with("VmHWM:"))?.to_owned();
            line.split_whitespace().nth(1)?.parse::<u64>().ok()
        });
    match peak {
        Some(kb) => println!("peak memory (VmHWM): {:.0} MB", kb as f64 / 1024.0),
        None => println!("peak memory: unavailable (no /proc/self/status)"),
    }
}
