//! `bench carve`'s workload: a generated relief, Oficina's finishing pass over it, LinuxCNC's
//! image-to-gcode on a crop of the same picture with the same tool and step, and both
//! programs replayed on the simulated stock for gouge and leftover.

use super::{failed, measure, BenchError, Cost};
use oficina_cam::memory::{self, Budget, Lever};
use oficina_cam::relief::{plan_within, Cutter, Direction, Pass, ReliefError, ReliefJob};
use oficina_cam::{Feeds, Tool};
use oficina_canon::{Canon, CanonOp};
use oficina_io::{luminance_to_heights, DepthMapping, Heightmap};
use oficina_post::{program_text, PostDialect, PostOptions};
use oficina_sim::{compare, ideal_surface, replay, Report};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

/// mm per pixel of the generated relief.
pub const PIXEL: f64 = 0.1;
/// Depth of black, mm.
pub const DEPTH: f64 = 10.0;
/// Diameter of the ball-nose tool both programs use, mm.
pub const BALL_DIAMETER: f64 = 6.0;
/// Rows 5 pixels (0.5 mm) apart for both programs: image-to-gcode steps in whole pixels.
pub const STEP_PX: usize = 5;
/// Largest side of the generated relief, pixels.
pub const MAX_SIZE: usize = 20_000;
/// Depth below the design that counts as a gouge, mm.
pub const GOUGE_LIMIT: f64 = 0.001;

/// Refuses a relief of `n` × `n` pixels whose picture, luminance and heights (1 + 4 + 4
/// bytes a pixel) would not fit in `budget` bytes.
pub fn check_size(n: usize, budget: u64) -> Result<(), BenchError> {
    memory::check(
        || format!("the generated {n} x {n} relief"),
        memory::grid_bytes(n, n).saturating_mul(2) + (n * n) as u64,
        budget,
        Lever::PixelSize,
    )
    .map_err(|e| BenchError::OverMemory(e.to_string()))
}

/// A deterministic relief: gentle waves, domes and a steep-walled ring, 8-bit gray.
pub fn relief_image(n: usize) -> Vec<u8> {
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

/// The top-left `c` × `c` pixels of an `n` × `n` picture.
pub fn crop(img: &[u8], n: usize, c: usize) -> Vec<u8> {
    (0..c)
        .flat_map(|r| img[r * n..r * n + c].iter().copied())
        .collect()
}

/// The heights of an `n` × `n` gray picture: white is the stock top, black [`DEPTH`] deep.
pub fn design(gray: &[u8], n: usize) -> Heightmap {
    let luma: Vec<f32> = gray.iter().map(|&v| v as f32 / 255.0).collect();
    luminance_to_heights(n, n, &luma, PIXEL, DepthMapping::new(DEPTH))
}

/// The ball-nose tool of [`BALL_DIAMETER`].
pub fn tool() -> Tool {
    Tool::new(oficina_cam::CutterShape::Ball, BALL_DIAMETER).expect("valid built-in tool")
}

/// One finishing pass, as image-to-gcode does: rows along X, zig-zag, one level.
pub fn job(tolerance: f64, samples_per_pixel: usize) -> ReliefJob {
    ReliefJob {
        safe_z: 5.0,
        clearance: 1.0,
        tolerance,
        samples_per_pixel,
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

/// Oficina's run: what planning and posting cost, the program and its move count.
pub struct Ours {
    /// Tool surface + toolpath.
    pub plan: Cost,
    /// Writing the G-code text (image-to-gcode's time includes writing its program too).
    pub post: Cost,
    /// The LinuxCNC program.
    pub program: String,
    /// Moves in the toolpath.
    pub moves: usize,
}

/// Plans `job` over `map` within `budget` bytes and posts it for LinuxCNC, timing both.
pub fn plan_and_post(map: &Heightmap, job: &ReliefJob, budget: u64) -> Result<Ours, BenchError> {
    // Each move is kept as a move and as a line of text.
    let budget = Budget {
        bytes: budget,
        reserved: 0,
        per_move: oficina_sim::carve::bytes_per_move(),
    };
    let (planned, plan_cost) = measure(|| plan_within(map, job, budget, &|_, _| {}));
    let planned = planned.map_err(|e| match e {
        ReliefError::Memory(_) => BenchError::OverMemory(e.to_string()),
        e => failed(e),
    })?;
    let post = PostOptions {
        dialect: PostDialect::LinuxCnc,
        allow_m6: false,
        title: "bench carve".into(),
        settings: vec![],
    };
    let (program, post_cost) = measure(|| program_text(&planned.toolpath, &post));
    Ok(Ours {
        plan: plan_cost,
        post: post_cost,
        program: program.map_err(failed)?,
        moves: planned.toolpath.move_count(),
    })
}

/// The part both programs machine: image-to-gcode's tool centres stop a tool radius inside
/// the picture, so a margin of one tool diameter is left out.
pub fn inner(h: &Heightmap) -> Heightmap {
    let m = (BALL_DIAMETER / PIXEL).ceil() as usize;
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

/// The simulator's report of a program over the inner part, and the share of it gouged.
pub fn judge(canon: &[Canon], map: &Heightmap) -> Result<(Report, f64), BenchError> {
    let tools = HashMap::from([(1, tool())]);
    let mut stock = Heightmap::flat(map.width, map.height, map.pixel, 0.0);
    replay(canon, &tools, &mut stock, [0.0, 0.0, 5.0]).map_err(failed)?;
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

/// The best any non-gouging program can do over the inner part: the tool's ideal surface.
pub fn best_possible(map: &Heightmap) -> Report {
    let ideal = inner(&ideal_surface(map, &tool()));
    compare(&ideal, &inner(map), &ideal)
}

/// Oficina's program read back by the interpreter (for [`judge`]).
pub fn read_back(program: &str) -> Result<Vec<Canon>, BenchError> {
    let post = PostOptions {
        dialect: PostDialect::LinuxCnc,
        allow_m6: false,
        title: String::new(),
        settings: vec![],
    };
    oficina_sim::carve::interpret(program, &post).map_err(failed)
}

/// image-to-gcode's run on one crop.
pub struct Peer {
    /// Its own wall seconds for convert() and writing.
    pub seconds: f64,
    /// Its CPU seconds.
    pub cpu: f64,
    /// Its program read by the interpreter, in the image grid's frame.
    pub canon: Vec<Canon>,
    /// What the interpreter said of its program.
    pub diagnostics: Vec<String>,
    /// Lines in its program.
    pub lines: usize,
}

/// The driver script: `given`, else the repository's `scripts/image_to_gcode_peer.py`.
pub fn peer_script(given: Option<&Path>) -> PathBuf {
    super::repo_file(given, "scripts/image_to_gcode_peer.py")
}

/// Runs image-to-gcode (through `python` and `script`) on the `c` × `c` picture `gray`,
/// working in `dir`, and reads its program into the image grid's frame.
pub fn run_peer(
    python: &Path,
    script: &Path,
    gray: &[u8],
    c: usize,
    dir: &Path,
) -> Result<Peer, BenchError> {
    let raw = dir.join("crop.gray");
    let out = dir.join("peer.ngc");
    std::fs::write(&raw, gray).map_err(failed)?;
    let run = std::process::Command::new(python)
        .arg(script)
        .arg(&raw)
        .args([c.to_string(), c.to_string()])
        .args([PIXEL, DEPTH, BALL_DIAMETER].map(|v| v.to_string()))
        .arg(STEP_PX.to_string())
        .arg(&out)
        .output()
        .map_err(|e| super::cannot_run(python, script, e))?;
    if !run.status.success() {
        return Err(failed(format!(
            "image-to-gcode failed: {}",
            String::from_utf8_lossy(&run.stderr)
        )));
    }
    let stdout = String::from_utf8_lossy(&run.stdout);
    let field = |key: &str| -> Result<Vec<f64>, BenchError> {
        let line = stdout
            .lines()
            .find(|l| l.starts_with(key))
            .ok_or_else(|| failed(format!("peer printed no {key}: {stdout}")))?;
        line.split_whitespace()
            .skip(1)
            .map(|v| {
                v.parse()
                    .map_err(|_| failed(format!("bad {key} line: {line}")))
            })
            .collect()
    };
    let seconds = field("SECONDS")?[0];
    let cpu = field("CPU")?[0];
    let offset = field("OFFSET")?;
    let text = std::fs::read_to_string(&out).map_err(failed)?;
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
    Ok(Peer {
        seconds,
        cpu,
        canon,
        diagnostics: diags.iter().map(|d| d.to_string()).collect(),
        lines: text.lines().count(),
    })
}

/// image-to-gcode places tool centres only where the whole tool window fits: it works on
/// (side − window)² pixels, so that is what its cost is per.
pub fn peer_window() -> usize {
    (BALL_DIAMETER / PIXEL + 0.5) as usize
}

/// The pixels image-to-gcode works on for a picture of `side` × `side`.
pub fn peer_worked_pixels(side: usize) -> f64 {
    (side.saturating_sub(peer_window()).max(1) as f64).powi(2)
}

/// Both programs on the top-left crop of the generated picture: image-to-gcode on the crop
/// and on a crop half its side (equal cost per pixel shows its cost is linear, so scaling
/// its rate to the full image is fair), Oficina on the crop, and each program's quality.
pub struct CropComparison {
    /// The crop's side, pixels.
    pub side: usize,
    /// The smaller crop's side, pixels.
    pub half: usize,
    /// image-to-gcode on the smaller crop.
    pub small_peer: Peer,
    /// image-to-gcode on the crop.
    pub peer: Peer,
    /// Oficina on the crop.
    pub ours: Ours,
    /// The design of the crop.
    pub design: Heightmap,
    /// Oficina's program replayed: the report and the share gouged.
    pub ours_quality: (Report, f64),
    /// image-to-gcode's program replayed.
    pub peer_quality: (Report, f64),
    /// The tool's ideal surface over the crop: what no non-gouging program beats.
    pub best: Report,
}

/// Run [`CropComparison`] on the `c` × `c` crop of the `n` × `n` picture `gray`, the peer
/// through `python` and `script`, Oficina with `job` within `budget` bytes, working in `dir`.
#[allow(clippy::too_many_arguments)]
pub fn compare_on_crop(
    gray: &[u8],
    n: usize,
    c: usize,
    python: &Path,
    script: &Path,
    job: &ReliefJob,
    budget: u64,
    dir: &Path,
) -> Result<CropComparison, BenchError> {
    let half = (c / 2).max(64);
    let small_peer = run_peer(python, script, &crop(gray, n, half), half, dir)?;
    let small = crop(gray, n, c);
    let design = self::design(&small, c);
    let ours = plan_and_post(&design, job, budget)?;
    let peer = run_peer(python, script, &small, c, dir)?;
    let ours_quality = judge(&read_back(&ours.program)?, &design)?;
    let peer_quality = judge(&peer.canon, &design)?;
    let best = best_possible(&design);
    Ok(CropComparison {
        side: c,
        half,
        small_peer,
        peer,
        ours,
        design,
        ours_quality,
        peer_quality,
        best,
    })
}
