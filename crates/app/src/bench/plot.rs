//! `bench plot`'s workload: a generated drawing of many short paths written as SVG, and
//! vpype's `linemerge linesort` run on the same file; both outputs read by our own SVG reader,
//! so pen-up and pen-down lengths are measured one way.

use super::{failed, BenchError};
use oficina_geom::Point;
use oficina_plot::{PenBy, Plot};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

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
pub fn write_svg(plot: &Plot, path: &Path) -> Result<(), BenchError> {
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
    std::fs::write(path, s).map_err(|e| failed(format!("writing {}: {e}", path.display())))
}

/// A drawing read as a plot, one pen a layer.
pub fn read_svg(path: &Path) -> Result<Plot, BenchError> {
    let d = oficina_io::load_drawing(path).map_err(|e| failed(format!("{e:#}")))?;
    Ok(Plot::from_drawing(&d.drawing, PenBy::Layer, 0.01))
}

/// Peak resident memory of the largest child waited for so far, kB.
pub fn children_maxrss_kb() -> Option<u64> {
    nix::sys::resource::getrusage(nix::sys::resource::UsageWho::RUSAGE_CHILDREN)
        .ok()
        .map(|u| u.max_rss() as u64)
}

/// Runs `vpype ARGS`; its wall seconds.
pub fn run_vpype(vpype: &str, args: &[&str]) -> Result<f64, BenchError> {
    let t = Instant::now();
    let st = Command::new(vpype).args(args).status().map_err(|e| {
        failed(format!(
            "running {vpype} (pip install vpype, or --no-peer): {e}"
        ))
    })?;
    if !st.success() {
        return Err(failed(format!("{vpype} {args:?} failed: {st}")));
    }
    Ok(t.elapsed().as_secs_f64())
}
