//! `oficina bench stitch`: fill and routing of a generated design of large fills (about
//! 100,000 stitches, four threads) into DST and PES, beside pyembroidery reading both files
//! and writing them again, in the same run; stitch counts from both sides, peak memory.

use anyhow::Result;
use oficina_app::bench::stitch::{design_svg, ours, pyembroidery};
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// About how many stitches the generated design has.
    #[arg(long, default_value_t = 100_000)]
    pub stitches: usize,
    /// Skip pyembroidery.
    #[arg(long)]
    pub no_peer: bool,
    /// The Python that has pyembroidery.
    #[arg(long, default_value = "python3")]
    pub python: String,
    /// Keep the generated files in this folder (default: a temporary one).
    #[arg(long)]
    pub dir: Option<PathBuf>,
}

fn line(label: &str, secs: f64, stitches: Option<usize>) {
    let n = stitches.map_or(String::new(), |n| format!("  stitches {n:>8}"));
    println!("{label:<40} {secs:>8.3} s{n}");
}

pub(crate) fn run(a: Args) -> Result<()> {
    if a.stitches < 100 || a.stitches > 1_500_000 {
        anyhow::bail!("--stitches {}: use 100..1500000", a.stitches);
    }
    let tmp = tempfile::tempdir()?;
    let dir = a.dir.clone().unwrap_or_else(|| tmp.path().to_path_buf());
    std::fs::create_dir_all(&dir)?;
    let svg = dir.join("bench-stitch.svg");
    std::fs::write(&svg, design_svg(a.stitches))?;
    let (dst, pes) = (dir.join("bench-stitch.dst"), dir.join("bench-stitch.pes"));
    let o = ours(&svg, &dst, &pes)?;
    let plan = &o.generated.plan;
    let c = plan.counts();
    let b = plan.bounds().unwrap_or_default();
    println!(
        "design: {} fills, {} colours, {:.0} x {:.0} mm, {}",
        o.generated.fills,
        plan.blocks.len(),
        b[2] - b[0],
        b[3] - b[1],
        svg.display()
    );
    line("oficina read SVG", o.read_design.wall, None);
    line("oficina fill + routing", o.generate.wall, Some(c.stitches));
    line("oficina write DST + PES", o.write.wall, None);
    let (dn, pn) = (o.dst_plan.counts().stitches, o.pes_plan.counts().stitches);
    line("oficina read DST + PES", o.read.wall, Some(dn));
    println!("  PES read back: {pn} stitches");
    let total = o.generate.wall + o.write.wall;
    println!(
        "oficina fill + routing + write          {total:>8.3} s  ({}: goal under 1 s)",
        if total < 1.0 { "met" } else { "not met" }
    );
    let peak = crate::peak_memory::vm_hwm_kb();
    println!(
        "oficina peak memory                     {:>8} kB",
        peak.map_or("?".into(), |v| v.to_string())
    );
    if a.no_peer {
        crate::peak_memory::print();
        return Ok(());
    }
    let p = pyembroidery(&a.python, &dst, &pes, &dir.join("pyembroidery-out"))?;
    line(
        "pyembroidery read DST + PES",
        p.read_s,
        Some(p.dst_stitches),
    );
    println!("  PES read back: {} stitches", p.pes_stitches);
    line("pyembroidery write DST + PES", p.write_s, None);
    println!(
        "pyembroidery peak memory                {:>8} kB  (interpreter + import alone {} kB)",
        p.peak_kb, p.baseline_kb
    );
    println!(
        "read + write: oficina {:.3} s vs pyembroidery {:.3} s; stitches: oficina {dn} / {pn}, pyembroidery {} / {} ({})",
        o.read.wall + o.write.wall,
        p.read_s + p.write_s,
        p.dst_stitches,
        p.pes_stitches,
        if dn == p.dst_stitches && pn == p.pes_stitches {
            "agree"
        } else {
            "DIFFER"
        }
    );
    crate::peak_memory::print();
    Ok(())
}
