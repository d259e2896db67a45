//! `oficina bench plot`: path optimisation of a generated drawing of 100,000 paths (random
//! short strokes plus grid networks cut into pieces), beside vpype's `linemerge linesort` on
//! the same SVG file in the same run. Both outputs are measured by our own SVG reader, so
//! pen-up and pen-down lengths are computed one way (`oficina_app::bench::plot`).

use anyhow::Result;
use oficina_app::bench::peak_memory_kb;
use oficina_app::bench::plot::{children_maxrss_kb, generate, read_svg, run_vpype, write_svg};
use oficina_geom::Point;
use oficina_plot::{optimise, Optimise, Plot};
use std::path::PathBuf;
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
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

pub(crate) fn run(a: Args) -> Result<()> {
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
    line("oficina optimise", t_opt, peak_memory_kb(), &plot);
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
    let inp = input.to_string_lossy().to_string();
    let out = peer_out.to_string_lossy().to_string();
    let t_io = run_vpype(&a.vpype, &["read", &inp, "write", &out])?;
    let t_full = run_vpype(
        &a.vpype,
        &["read", &inp, "linemerge", "linesort", "write", &out],
    )?;
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
