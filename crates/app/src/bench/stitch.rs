//! `bench stitch`'s workload: a generated design of large fills (tatami with underlay, four
//! threads) sewn by the stitch crate — fill and routing — into DST and PES files, which are
//! read back by us and by pyembroidery, which also writes them again, so both sides read and
//! write the same stitches.

use super::{failed, measure, BenchError, Cost};
use oficina_stitch::{generate, Format, Generated, Params, StitchPlan};
use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

/// Stitches per mm² of fill at the default parameters (rows 0.4 mm apart, 3 mm stitches,
/// with the underlay), measured; the design is sized from it.
const STITCHES_PER_MM2: f64 = 1.14;

/// Shapes a side of the design's grid.
pub const GRID: usize = 6;

/// The design: a 6 × 6 grid of filled shapes (discs, frames with a round hole, stars,
/// ellipses) in four threads interleaved across the grid, so routing has to group the colours
/// and order and trim the shapes; sized so that about `stitches` are sewn.
pub fn design_svg(stitches: usize) -> String {
    const COLOURS: [&str; 4] = ["#c0392b", "#1f6fb2", "#f1c40f", "#27ae60"];
    // The shapes cover about 0.62 of their cells.
    let area = stitches as f64 / STITCHES_PER_MM2 / 0.62;
    let cell = (area / (GRID * GRID) as f64).sqrt();
    let gap = (cell * 0.15).max(1.0);
    let size = GRID as f64 * (cell + gap) + gap;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{size:.2}mm\" height=\"{size:.2}mm\" viewBox=\"0 0 {size:.2} {size:.2}\">"
    );
    let c = |i: usize| gap + (i as f64 + 0.5) * cell + i as f64 * gap;
    let r = cell / 2.0;
    for row in 0..GRID {
        for col in 0..GRID {
            let (cx, cy) = (c(col), c(row));
            let fill = COLOURS[(row * 3 + col) % 4];
            match (row + col) % 4 {
                0 => {
                    let _ = writeln!(
                        s,
                        "<circle cx=\"{cx:.3}\" cy=\"{cy:.3}\" r=\"{r:.3}\" fill=\"{fill}\"/>"
                    );
                }
                1 => {
                    // A square frame with a round hole (even-odd).
                    let h = r * 0.45;
                    let _ = writeln!(
                        s,
                        "<path fill-rule=\"evenodd\" fill=\"{fill}\" d=\"M{x0:.3} {y0:.3}h{w:.3}v{w:.3}h{mw:.3}z M{hx:.3} {cy:.3}a{h:.3} {h:.3} 0 1 0 {d:.3} 0a{h:.3} {h:.3} 0 1 0 {md:.3} 0z\"/>",
                        x0 = cx - r,
                        y0 = cy - r,
                        w = 2.0 * r,
                        mw = -2.0 * r,
                        hx = cx - h,
                        d = 2.0 * h,
                        md = -2.0 * h
                    );
                }
                2 => {
                    let mut d = String::new();
                    for k in 0..10 {
                        let a = std::f64::consts::PI * (k as f64 / 5.0 - 0.5);
                        let rr = if k % 2 == 0 { r } else { r * 0.55 };
                        let _ = write!(
                            d,
                            "{}{:.3} {:.3}",
                            if k == 0 { "M" } else { "L" },
                            cx + rr * a.cos(),
                            cy + rr * a.sin()
                        );
                    }
                    let _ = writeln!(s, "<path fill=\"{fill}\" d=\"{d}z\"/>");
                }
                _ => {
                    let _ = writeln!(
                        s,
                        "<ellipse cx=\"{cx:.3}\" cy=\"{cy:.3}\" rx=\"{r:.3}\" ry=\"{:.3}\" fill=\"{fill}\"/>",
                        r * 0.7
                    );
                }
            }
        }
    }
    s += "</svg>\n";
    s
}

/// What our side did and what it cost.
pub struct Ours {
    /// The generated stitches.
    pub generated: Generated,
    /// Fill and routing (the stitch crate's `generate`), from the design already read.
    pub generate: Cost,
    /// Reading the SVG design.
    pub read_design: Cost,
    /// Writing the DST and PES files.
    pub write: Cost,
    /// Reading both back.
    pub read: Cost,
    /// The DST as read back.
    pub dst_plan: StitchPlan,
    /// The PES as read back.
    pub pes_plan: StitchPlan,
}

/// The design at `svg` sewn, written to `dst` and `pes`, and read back.
pub fn ours(svg: &Path, dst: &Path, pes: &Path) -> Result<Ours, BenchError> {
    let (imported, read_design) = measure(|| oficina_io::load_drawing(svg));
    let imported = imported.map_err(|e| failed(format!("{e:#}")))?;
    let p = Params::default();
    let (generated, gen_cost) =
        measure(|| generate(&imported.drawing, "bench", &p, &mut |_, _| {}));
    let generated = generated.map_err(|e| failed(e.0))?;
    let (files, write) = measure(|| {
        Ok::<_, oficina_stitch::FormatError>((
            Format::Dst.write(&generated.plan)?,
            Format::Pes.write(&generated.plan)?,
        ))
    });
    let (d, e) = files.map_err(|e| failed(e.to_string()))?;
    std::fs::write(dst, &d).map_err(|e| failed(format!("{}: {e}", dst.display())))?;
    std::fs::write(pes, &e).map_err(|e| failed(format!("{}: {e}", pes.display())))?;
    let (back, read) = measure(|| {
        let d = std::fs::read(dst).map_err(|e| e.to_string())?;
        let e = std::fs::read(pes).map_err(|e| e.to_string())?;
        Ok::<_, String>((
            Format::Dst.read(&d, "bench").map_err(|e| e.to_string())?,
            Format::Pes.read(&e, "bench").map_err(|e| e.to_string())?,
        ))
    });
    let (dst_plan, pes_plan) = back.map_err(failed)?;
    Ok(Ours {
        generated,
        generate: gen_cost,
        read_design,
        write,
        read,
        dst_plan,
        pes_plan,
    })
}

/// pyembroidery's figures on the same files.
#[derive(Clone, Debug, Default)]
pub struct Peer {
    /// Reading the DST and the PES, s.
    pub read_s: f64,
    /// Writing the DST's pattern as DST and PES again, s.
    pub write_s: f64,
    /// Sewn stitches in the DST and in the PES as it reads them.
    pub dst_stitches: usize,
    /// See `dst_stitches`.
    pub pes_stitches: usize,
    /// Colour changes in the DST as read.
    pub color_changes: usize,
    /// Its peak resident memory, kB (ru_maxrss, the interpreter included).
    pub peak_kb: u64,
    /// The interpreter and imports alone, kB.
    pub baseline_kb: u64,
}

const PEER: &str = r#"
import resource, sys, time
import pyembroidery as pe
dst, pes, out = sys.argv[1], sys.argv[2], sys.argv[3]
base = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
t = time.perf_counter()
a = pe.read(dst)
b = pe.read(pes)
r = time.perf_counter() - t
t = time.perf_counter()
pe.write(a, out + ".dst")
pe.write(a, out + ".pes")
w = time.perf_counter() - t
n = lambda p, c: sum(1 for s in p.stitches if s[2] & pe.COMMAND_MASK == c)
print(r, w, n(a, pe.STITCH), n(b, pe.STITCH), n(a, pe.COLOR_CHANGE),
      resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, base)
"#;

/// Runs pyembroidery (`python -c …`) on `dst` and `pes`, writing to `out`.dst/.pes.
pub fn pyembroidery(python: &str, dst: &Path, pes: &Path, out: &Path) -> Result<Peer, BenchError> {
    let o = Command::new(python)
        .arg("-c")
        .arg(PEER)
        .arg(dst)
        .arg(pes)
        .arg(out)
        .output()
        .map_err(|e| failed(format!("running {python} (or --no-peer): {e}")))?;
    if !o.status.success() {
        return Err(failed(format!(
            "pyembroidery failed (pip install pyembroidery, or --no-peer): {}",
            String::from_utf8_lossy(&o.stderr)
        )));
    }
    let text = String::from_utf8_lossy(&o.stdout);
    let v: Vec<&str> = text.split_whitespace().collect();
    let bad = || failed(format!("pyembroidery's answer: {text}"));
    if v.len() != 7 {
        return Err(bad());
    }
    let f = |i: usize| v[i].parse::<f64>().map_err(|_| bad());
    Ok(Peer {
        read_s: f(0)?,
        write_s: f(1)?,
        dst_stitches: f(2)? as usize,
        pes_stitches: f(3)? as usize,
        color_changes: f(4)? as usize,
        peak_kb: f(5)? as u64,
        baseline_kb: f(6)? as u64,
    })
}
