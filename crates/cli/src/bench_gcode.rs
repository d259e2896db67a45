//! `oficina bench gcode`: interpreter throughput on a large generated program, beside
//! LinuxCNC's `rs274` on the same file in the same run.
//!
//! Two inputs are generated: a mixed program (G1/G2/G3 with parameters and expressions, the
//! work a real interpreter does) and a plain one (`G1 X… Y…` lines only, which measures raw
//! reading speed in MB/s). Both are deterministic, so figures from different runs compare.
//! The measurements are `oficina_app::bench::gcode`'s.

use anyhow::{bail, Context};
use oficina_app::bench::gcode::{compare, generate, Timing, REPEATS};
use oficina_app::bench::load_average;
use oficina_app::bench::programs::{write_mixed_program, write_plain_program};
use std::fs::File;
use std::io::BufWriter;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub(crate) struct BenchGcodeArgs {
    /// Number of blocks (lines) in each generated program.
    #[arg(long, default_value_t = 1_000_000)]
    pub blocks: u64,
    /// Keep the generated mixed program at this path instead of a temporary file.
    #[arg(long)]
    pub keep: Option<PathBuf>,
}

fn print_row(who: &str, timing: &Timing, blocks: u64, bytes: u64) {
    match timing {
        Timing::Took { wall, cpu } => {
            let s = wall.as_secs_f64();
            println!(
                "  {who:<22} wall {s:>7.3} s {:>11.0} blocks/s {:>8.2} MB/s | CPU {cpu:>7.3} s {:>11.0} blocks/s {:>8.2} MB/s",
                blocks as f64 / s,
                bytes as f64 / s / 1e6,
                blocks as f64 / cpu.max(1e-9),
                bytes as f64 / cpu.max(1e-9) / 1e6
            );
        }
        Timing::Unavailable(why) => println!("  {who:<22} unavailable: {why}"),
    }
}

fn print_ratio(label: &str, ours: &Timing, peer: &Timing) {
    if let (
        Timing::Took {
            wall: ours_wall,
            cpu: ours_cpu,
        },
        Timing::Took {
            wall: peer_wall,
            cpu: peer_cpu,
        },
    ) = (ours, peer)
    {
        println!(
            "  oficina ({label}) runs at {:.2}x the speed of rs274 by wall time, {:.2}x by CPU time",
            peer_wall.as_secs_f64() / ours_wall.as_secs_f64(),
            peer_cpu / ours_cpu.max(1e-9)
        );
    }
}

/// CPU seconds, their ratio and peak memory of Oficina (counting) and rs274, on one line.
fn print_side_by_side(ours: &Timing, peer: &Timing, own_kb: Option<u64>, peer_kb: Option<u64>) {
    let (Timing::Took { cpu: o, .. }, Timing::Took { cpu: p, .. }) = (ours, peer) else {
        return;
    };
    let mb =
        |kb: Option<u64>| kb.map_or("?".to_string(), |k| format!("{:.1} MB", k as f64 / 1024.0));
    println!(
        "  CPU: oficina {o:.3} s, rs274 {p:.3} s, ratio {:.1}x | peak memory: oficina {} (whole bench), rs274 {} (largest run so far)",
        p / o.max(1e-9),
        mb(own_kb),
        mb(peer_kb)
    );
}

pub(crate) fn run(args: BenchGcodeArgs) -> anyhow::Result<()> {
    if args.blocks < 10 {
        bail!("--blocks {} is too small: use at least 10", args.blocks);
    }
    println!(
        "machine load (1-minute average) {} on {} cores; oficina: fastest of {REPEATS} runs, rs274: one run; \
         CPU = user + system time (getrusage), steadier than wall time on a shared machine",
        load_average().unwrap_or_else(|| "unknown".into()),
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    println!(
        "both sides read the whole program into canonical operations (text, parameters, \
         expressions, modal state, offsets): oficina into a sink that counts them (\"counting\") \
         and printing rs274's text to a file (\"printing\"), rs274 -g printing its calls to a file; \
         a spline is one operation on both sides (rs274's NURBS_FEED, oficina's with its control \
         points), traced into feeds only where something moves along it"
    );
    let dir = tempfile::tempdir().context("cannot create a temporary directory")?;
    let mixed = args
        .keep
        .clone()
        .unwrap_or_else(|| dir.path().join("mixed.ngc"));
    let plain = dir.path().join("plain.ngc");

    for (label, path, writer) in [
        (
            "mixed G1/G2/G3 with parameters and expressions, G5/G5.1/G5.2 splines in 1 block of 20",
            &mixed,
            write_mixed_program as fn(&mut BufWriter<File>, u64) -> _,
        ),
        ("plain G1 X Y lines", &plain, write_plain_program),
    ] {
        let bytes = generate(path, args.blocks, writer)?;
        println!(
            "{label}: {} blocks, {:.1} MB ({})",
            args.blocks,
            bytes as f64 / 1e6,
            path.display()
        );
        let c = compare(path, dir.path())?;
        let (counting, printing, peer, ops) = (c.counting, c.printing, c.peer, c.ops);
        print_row("oficina, counting ops", &counting, args.blocks, bytes);
        print_row("oficina, printing", &printing, args.blocks, bytes);
        print_row("rs274 -g, printing", &peer, args.blocks, bytes);
        print_ratio("counting", &counting, &peer);
        print_ratio("printing", &printing, &peer);
        print_side_by_side(&counting, &peer, c.own_peak_kb, c.peer_peak_kb);
        println!("  ({ops} canonical operations)");
    }
    if let Some(kept) = &args.keep {
        println!("kept the mixed program at {}", kept.display());
    }
    crate::peak_memory::print();
    Ok(())
}
