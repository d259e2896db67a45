//! `oficina bench carve`: tool surface + toolpath generation for a generated relief, beside
//! LinuxCNC's image-to-gcode on a crop of the same image with the same tool and step, and
//! both programs replayed through the interpreter and the stock simulator for gouge.

use crate::carve::interpret;
use anyhow::{bail, Context, Result};
use clap::Args as ClapArgs;
use oficina_cam::raster::Feeds;
use oficina_cam::relief::{plan, Cutter, Direction, Job, Pass};
use oficina_cam::Tool;
use oficina_canon::{Canon, CanonOp};
use oficina_io::image_in::luminance_to_heights;
use oficina_io::{DepthMapping, Heightmap};
use oficina_post::{program_text, Dialect, PostOptions};
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
fn job() -> Job {
    Job {
        safe_z: 5.0,
        clearance: 1.0,
        tolerance: 0.005,
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

/// Seconds to build the tool surface and the toolpath; the toolpath's move count.
fn time_ours(map: &Heightmap) -> Result<(f64, Vec<u8>, usize)> {
    let start = Instant::now();
    let planned = plan(map, &job(), &|_, _| {})?;
    let seconds = start.elapsed().as_secs_f64();
    let post = PostOptions {
        dialect: Dialect::LinuxCnc,
        allow_m6: false,
        title: "bench carve".into(),
        settings: vec![],
    };
    let moves = planned.toolpath.move_count();
    Ok((
        seconds,
        program_text(&planned.toolpath, &post).into_bytes(),
        moves,
    ))
}

/// The report over the part both programs machine: image-to-gcode's tool centres stop a
/// tool radius inside the picture, so a margin of one tool diameter is left out.
fn judge(canon: &[Canon], map: &Heightmap) -> Result<(Report, f64)> {
    let tools = HashMap::from([(1, tool())]);
    let mut stock = Heightmap::flat(map.width, map.height, map.pixel, 0.0);
    replay(canon, &tools, &mut stock, [0.0, 0.0, 5.0])?;
    let m = (BALL_DIAMETER / PIXEL).ceil() as usize;
    let inner = |h: &Heightmap| {
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
    };
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
    let offset = field("OFFSET")?;
    let text = std::fs::read_to_string(&out)?;
    let opts = oficina_gcode::program::RunOptions::default();
    let mut canon = vec![Canon {
        line: 0,
        op: CanonOp::ChangeTool(1),
    }];
    let diags = oficina_gcode::program::run_text(&text, &opts, &mut |mut c| {
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
    let gray = relief_image(n);
    let full = design(&gray, n);
    let (ours_s, _, ours_moves) = time_ours(&full)?;
    let ours_rate = ours_s / (n * n) as f64;
    println!(
        "oficina, full {n} x {n}: {ours_s:.2} s ({:.1} ns/pixel), {ours_moves} moves",
        ours_rate * 1e9
    );
    if args.no_peer {
        return Ok(());
    }
    let small = crop(&gray, n, c);
    let crop_map = design(&small, c);
    let (ours_crop_s, ours_text, _) = time_ours(&crop_map)?;
    let dir = tempfile::tempdir()?;
    let peer = run_peer(&args, &small, c, dir.path())?;
    let peer_rate = peer.seconds / (c * c) as f64;
    let post = PostOptions {
        dialect: Dialect::LinuxCnc,
        allow_m6: false,
        title: String::new(),
        settings: vec![],
    };
    let ours_canon = interpret(&String::from_utf8(ours_text)?, &post)?;
    let ours_q = judge(&ours_canon, &crop_map)?;
    let peer_q = judge(&peer.canon, &crop_map)?;

    println!();
    println!("Time (tool surface + toolpath; image-to-gcode's Converter.convert, headless):");
    println!("{:<44} {:>12} {:>14}", "", "seconds", "ns per pixel");
    println!(
        "{:<44} {:>12.2} {:>14.1}",
        format!("oficina, full {n} x {n} (measured)"),
        ours_s,
        ours_rate * 1e9
    );
    println!(
        "{:<44} {:>12.3} {:>14.1}",
        format!("oficina, crop {c} x {c} (measured)"),
        ours_crop_s,
        ours_crop_s / (c * c) as f64 * 1e9
    );
    println!(
        "{:<44} {:>12.2} {:>14.1}",
        format!("image-to-gcode, crop {c} x {c} (measured)"),
        peer.seconds,
        peer_rate * 1e9
    );
    println!(
        "{:<44} {:>12.0} {:>14.1}",
        format!("image-to-gcode, {n} x {n} (SCALED from crop)"),
        peer_rate * (n * n) as f64,
        peer_rate * 1e9
    );
    println!(
        "speed-up: {:.0}x per pixel (oficina full image vs image-to-gcode crop rate), {:.0}x on the same crop",
        peer_rate / ours_rate,
        peer.seconds / ours_crop_s
    );
    println!();
    println!(
        "Quality on the crop, both programs read by the interpreter and replayed on the \
         simulated stock (tool-diameter margin excluded; peer's G64 blending not modelled):"
    );
    println!(
        "{:<16} {:>10} {:>16} {:>10} {:>10} {:>12} {:>12}",
        "", "gouge mm", "area > 1 um", "left max", "left mean", "scallop max", "scallop mean"
    );
    for (name, (q, gouged)) in [("oficina", &ours_q), ("image-to-gcode", &peer_q)] {
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
        "image-to-gcode program: {} lines, {} interpreter diagnostics",
        peer.lines, peer.diagnostics
    );
    Ok(())
}
