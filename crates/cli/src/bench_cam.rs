//! `oficina bench cam`: (1) 59 successive inward offsets of 1.5 mm (each from the last, as
//! pocket rings are made) of a 10,000-vertex contour,
//! beside shapely (GEOS) and pyclipper (Clipper1) doing the same offsets in the same run, with
//! the areas compared; (2) pocket toolpaths for a DXF of 1,000 shapes. Wall and CPU seconds,
//! peak memory (max RSS) of each process.

use anyhow::{bail, Result};
use clap::Args as ClapArgs;
use oficina_app::bench::offsets::{
    contour, our_offsets, pocket_shapes, relative_diff, run_peer, shapes_dxf, Peer,
};
use oficina_app::bench::{cpu_seconds, max_rss_mb, CpuOf};
use std::io::Write;
use std::time::Instant;

#[derive(ClapArgs, Debug)]
pub(crate) struct Args {
    /// Vertices of the contour.
    #[arg(long, default_value_t = 10_000)]
    pub vertices: usize,
    /// Number of successive offsets.
    #[arg(long, default_value_t = 59)]
    pub offsets: usize,
    #[arg(long, default_value_t = 1.5)]
    pub step: f64,
    /// Shapes in the pocketing DXF.
    #[arg(long, default_value_t = 1000)]
    pub shapes: usize,
    /// Chord tolerance of round joins, mm (all three libraries).
    #[arg(long, default_value_t = 0.01)]
    pub tolerance: f64,
    /// Skip the python peers.
    #[arg(long)]
    pub no_peers: bool,
}

pub(crate) fn run(args: Args) -> Result<()> {
    if args.vertices < 3 || args.vertices > 10_000_000 || args.offsets == 0 || args.offsets > 10_000
    {
        bail!("--vertices 3..=10000000 and --offsets 1..=10000");
    }
    let pts = contour(args.vertices);
    let dir = tempfile::tempdir()?;
    let file = dir.path().join("contour.txt");
    let mut f = std::fs::File::create(&file)?;
    for p in &pts {
        writeln!(f, "{} {}", p[0], p[1])?;
    }
    drop(f);
    println!(
        "1. {} offsets at {} mm steps of a {}-vertex contour, round joins within {} mm; the same \
         operation in each library: every inset made from the last, round joins, chords within \
         the tolerance",
        args.offsets, args.step, args.vertices, args.tolerance
    );
    // Peers first: a child inherits the parent's peak RSS at fork (Linux signal->maxrss), so
    // they run while this process is still small.
    let peers: Vec<(&str, Result<Peer, oficina_app::bench::BenchError>)> = if args.no_peers {
        vec![]
    } else {
        ["shapely", "pyclipper"]
            .into_iter()
            .map(|w| {
                (
                    w,
                    run_peer(w, &file, args.offsets, args.step, args.tolerance),
                )
            })
            .collect()
    };
    let (c0, t0) = (cpu_seconds(CpuOf::Process), Instant::now());
    let (ours, regions_total) = our_offsets(&pts, args.offsets, args.step, args.tolerance)?;
    let wall = t0.elapsed().as_secs_f64();
    let (c1, rss) = (cpu_seconds(CpuOf::Process), max_rss_mb());
    println!(
        "   {:<28} {:>9} {:>9} {:>10} {:>11} {:>11}",
        "library", "wall s", "cpu s", "peak MB", "max diff %", "all diff %"
    );
    println!(
        "   {:<28} {wall:>9.3} {:>9.3} {rss:>10.1} {:>11} {:>11}",
        "oficina (i_overlay)",
        c1 - c0,
        "—",
        "—"
    );
    let ok: Vec<(&str, Peer)> = peers
        .into_iter()
        .filter_map(|(which, peer)| match peer {
            Ok(p) => Some((which, p)),
            Err(e) => {
                println!("   {which}: not run: {e}");
                None
            }
        })
        .collect();
    // Relative area difference per step, |ours − peer| / peer, and over all steps together
    // (the summed areas, i.e. the material the rings enclose in all).
    let rel = relative_diff;
    let total: f64 = ours.iter().sum();
    for (which, p) in &ok {
        let max = ours
            .iter()
            .zip(&p.areas)
            .map(|(a, b)| rel(*a, *b).abs())
            .fold(0.0f64, f64::max);
        let name = if *which == "shapely" {
            "shapely (GEOS)"
        } else {
            "pyclipper (Clipper 1)"
        };
        println!(
            "   {:<28} {:>9.3} {:>9.3} {:>10.1} {:>11.4} {:>+11.4}",
            name,
            p.wall,
            p.cpu,
            p.rss_mb,
            max * 100.0,
            rel(total, p.areas.iter().sum()) * 100.0
        );
    }
    println!("     ({regions_total} regions in all)");
    if let [(_, a), (_, b)] = &ok[..] {
        // The peers' own disagreement: on the last, tiny insets the chords alone make a few %.
        let max = a
            .areas
            .iter()
            .zip(&b.areas)
            .map(|(x, y)| rel(*x, *y).abs())
            .fold(0.0f64, f64::max);
        println!(
            "     (shapely against pyclipper: max diff {:.4} %, all {:+.4} %)",
            max * 100.0,
            rel(a.areas.iter().sum(), b.areas.iter().sum()) * 100.0
        );
    }
    if !ok.is_empty() {
        print!("   {:>4} {:>12}", "step", "oficina mm²");
        for (which, _) in &ok {
            print!(" {which:>12} {:>9}", "diff %");
        }
        println!();
        for (k, a) in ours.iter().enumerate() {
            print!("   {:>4} {a:>12.3}", k + 1);
            for (_, p) in &ok {
                let b = p.areas.get(k).copied().unwrap_or(f64::NAN);
                print!(" {b:>12.3} {:>+9.4}", rel(*a, b) * 100.0);
            }
            println!();
        }
    }
    println!("2. pocket toolpaths for a DXF of {} shapes (flat:3, 3 mm deep in one pass, offsets from the centre out)", args.shapes);
    let dxf = dir.path().join("shapes.dxf");
    std::fs::write(&dxf, shapes_dxf(args.shapes))?;
    let (c0, t0) = (cpu_seconds(CpuOf::Process), Instant::now());
    let pocketed = pocket_shapes(&dxf)?;
    let wall = t0.elapsed().as_secs_f64();
    let (c1, rss) = (cpu_seconds(CpuOf::Process), max_rss_mb());
    println!(
        "   {} paths imported in {:.3} s; {} moves; {wall:.3} s wall, {:.3} s CPU in all; peak {rss:.1} MB",
        pocketed.paths,
        pocketed.import_seconds,
        pocketed.moves,
        c1 - c0
    );
    Ok(())
}
