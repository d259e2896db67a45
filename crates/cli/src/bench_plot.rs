//! `oficina bench plot`: path optimisation of a generated drawing of 100,000 paths (random
//! short strokes plus grid networks cut into pieces), beside vpype's `linemerge linesort` on
//! the same SVG file in the same run. Both outputs are measured by our own SVG reader, so
//! pen-up and pen-down lengths are computed one way.

use anyhow::{bail, Context, Result};
use oficina_geom::Point;
use oficina_plot::{optimise, Optimise, PenBy, Plot};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Number of paths in the generated drawing.
    #[arg(long, default_value_t = 100_000)]
    pub paths: usize,
    /// Skip vpype.
    #[arg(long)]
    pub no_peer: bool,
    /// The vpype command.
    #[arg(long, default_value = "vpype")]
    pub vpype: String,
    /// Keep the generated files in this folder (default: a temporary one).
    #[arg(long)]
    pub dir: Option<PathBuf>,
}

/// The generated drawing: 60 % random strokes of 2–5 points in a 400 mm square, 40 % unit
/// pieces of grid lines (which merge into long strokes).
pub fn generate(n: usize) -> Plot {
    let mut x = 0x9e37_79b9_7f4a_7c15u64;
    let mut rnd = move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut plot = Plot::default();
    let pen = plot.pen_mut("#000000");
    let grid = n * 2 / 5;
    let side = ((grid / 2) as f64).sqrt().ceil() as usize;
    let pitch = 400.0 / side as f64;
    let mut k = 0;
    'g: for line in 0..side {
        for piece in 0..side {
            for horizontal in [true, false] {
                if k == grid {
                    break 'g;
                }
                let (a, b) = (line as f64 * pitch, piece as f64 * pitch);
                let s = if horizontal {
                    vec![Point::new(b, a), Point::new(b + pitch, a)]
                } else {
                    vec![Point::new(a, b), Point::new(a, b + pitch)]
                };
                pen.strokes.push(s);
                k += 1;
            }
        }
    }
    while pen.strokes.len() < n {
        let mut p = Point::new(rnd() * 400.0, rnd() * 400.0);
        let m = 2 + (rnd() * 4.0) as usize;
        let mut s = vec![p];
        for _ in 1..m {
            p = Point::new(p.x + rnd() * 4.0 - 2.0, p.y + rnd() * 4.0 - 2.0);
            s.push(p);
        }
        pen.strokes.push(s);
    }
    // Shuffle so the file order carries no locality.
    let len = pen.strokes.len();
    for i in (1..len).rev() {
        let j = (rnd() * (i + 1) as f64) as usize;
        pen.strokes.swap(i, j.min(i));
    }
    plot
}

/// An SVG in mm (viewBox units = mm), Y down as SVG has it.
fn write_svg(plot: &Plot, path: &Path) -> Result<()> {
    let mut s = String::from(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"410mm\" height=\"410mm\" viewBox=\"0 0 410 410\">\n",
    );
    for st in plot.strokes() {
        s.push_str("<path fill=\"none\" stroke=\"black\" d=\"");
        for (i, p) in st.iter().enumerate() {
            let _ = write!(
                s,
                "{}{:.4} {:.4}",
                if i == 0 { "M" } else { " L" },
                p.x,
                p.y
            );
        }
        s.push_str("\"/>\n");
    }
    s.push_str("</svg>\n");
    std::fs::write(path, s).with_context(|| format!("writing {}", path.display()))
}

fn read_svg(path: &Path) -> Result<Plot> {
    let d = oficina_io::load_drawing(path)?;
    Ok(Plot::from_drawing(&d.drawing, PenBy::Layer, 0.01))
}

fn vm_hwm_kb() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let l = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    l.split_whitespace().nth(1)?.parse().ok()
}

/// Peak resident memory of the largest child waited for so far, kB.
fn children_maxrss_kb() -> Option<u64> {
    nix::sys::resource::getrusage(nix::sys::resource::UsageWho::RUSAGE_CHILDREN)
        .ok()
        .map(|u| u.max_rss() as u64)
}

fn line(label: &str, secs: f64, mem_kb: Option<u64>, plot: &Plot) {
    let l = plot.lengths();
    println!(
        "{label:<34} {secs:>8.3} s  peak {:>8} kB  strokes {:>7}  pen-down {:>10.1} mm  pen-up {:>10.1} mm",
        mem_kb.map_or("?".into(), |v| v.to_string()),
        l.strokes,
        l.pen_down,
        l.pen_up
    );
}

pub fn run(a: Args) -> Result<()> {
    let tmp = tempfile::tempdir()?;
    let dir = a.dir.clone().unwrap_or_else(|| tmp.path().to_path_buf());
    std::fs::create_dir_all(&dir)?;
    let input = dir.join("bench-plot.svg");
    write_svg(&generate(a.paths), &input)?;
    println!("drawing: {} paths, {}", a.paths, input.display());

    let t = Instant::now();
    let mut plot = read_svg(&input)?;
    let t_read = t.elapsed().as_secs_f64();
    line("input (as read)", t_read, None, &plot);
    let t = Instant::now();
    let r = optimise(&mut plot, &Optimise::default(), Point::ORIGIN);
    let t_opt = t.elapsed().as_secs_f64();
    line("oficina optimise", t_opt, vm_hwm_kb(), &plot);
    println!(
        "  oficina read + optimise {:.3} s; strokes {} -> {}, {} duplicates",
        t_read + t_opt,
        r.before.strokes,
        r.after.strokes,
        r.duplicates
    );
    if a.no_peer {
        return Ok(());
    }
    let peer_out = dir.join("vpype-out.svg");
    let run_vpype = |args: &[&str]| -> Result<f64> {
        let t = Instant::now();
        let st = Command::new(&a.vpype)
            .args(args)
            .status()
            .with_context(|| format!("running {} (pip install vpype, or --no-peer)", a.vpype))?;
        if !st.success() {
            bail!("{} {:?} failed: {st}", a.vpype, args);
        }
        Ok(t.elapsed().as_secs_f64())
    };
    let inp = input.to_string_lossy().to_string();
    let out = peer_out.to_string_lossy().to_string();
    let t_io = run_vpype(&["read", &inp, "write", &out])?;
    let t_full = run_vpype(&["read", &inp, "linemerge", "linesort", "write", &out])?;
    let peer = read_svg(&peer_out)?;
    line(
        "vpype read linemerge linesort write",
        t_full,
        children_maxrss_kb(),
        &peer,
    );
    println!(
        "  vpype read+write alone {t_io:.3} s, so linemerge + linesort ≈ {:.3} s",
        (t_full - t_io).max(0.0)
    );
    let (ours, theirs) = (plot.lengths().pen_up, peer.lengths().pen_up);
    println!(
        "pen-up: oficina {ours:.1} mm vs vpype {theirs:.1} mm ({:+.1} %); optimise time: oficina {t_opt:.3} s vs vpype ≈ {:.3} s",
        (ours / theirs - 1.0) * 100.0,
        (t_full - t_io).max(0.0)
    );
    Ok(())
}
