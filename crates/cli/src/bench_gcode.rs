//! `oficina bench gcode`: interpreter throughput on a large generated program, beside
//! LinuxCNC's `rs274` on the same file in the same run.
//!
//! Two inputs are generated: a mixed program (G1/G2/G3 with parameters and expressions, the
//! work a real interpreter does) and a plain one (`G1 X… Y…` lines only, which measures raw
//! reading speed in MB/s). Both are deterministic, so figures from different runs compare.

use anyhow::{bail, Context};
use oficina_app::bench::programs::{write_mixed_program, write_plain_program};
use oficina_app::bench::{cpu_seconds, load_average, CpuOf};
use oficina_gcode::Rs274Printer;
use oficina_gcode::RunOptions;
use oficina_gcode::{Diagnostic, Severity};
use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

#[derive(clap::Args, Debug)]
pub struct BenchGcodeArgs {
    /// Number of blocks (lines) in each generated program.
    #[arg(long, default_value_t = 1_000_000)]
    pub blocks: u64,
    /// Keep the generated mixed program at this path instead of a temporary file.
    #[arg(long)]
    pub keep: Option<PathBuf>,
}

fn generate(
    path: &Path,
    blocks: u64,
    writer: fn(&mut BufWriter<File>, u64) -> std::io::Result<()>,
) -> anyhow::Result<u64> {
    let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut out = BufWriter::new(file);
    writer(&mut out, blocks)
        .and_then(|_| out.flush())
        .with_context(|| format!("cannot write {}", path.display()))?;
    Ok(std::fs::metadata(path)?.len())
}

/// One interpreter's time on one file, or why there is none.
enum Timing {
    /// Wall time, and CPU seconds (user + system) of the process that did the work.
    Took {
        wall: Duration,
        cpu: f64,
    },
    Unavailable(String),
}

/// Read and write buffers of Oficina's runs: large enough that system calls cost little
/// beside the work (8 KiB would make one per 200 lines).
const IO_BUFFER: usize = 256 * 1024;

/// How often Oficina's runs are repeated; the fastest run counts (the machine is shared).
const REPEATS: usize = 3;

fn own_cpu() -> f64 {
    cpu_seconds(CpuOf::Process)
}

/// The fastest of `REPEATS` runs of `f` (by CPU; errors end the repeats at once).
fn best_of(mut f: impl FnMut() -> anyhow::Result<Timing>) -> anyhow::Result<Timing> {
    let mut best = f()?;
    for _ in 1..REPEATS {
        let Timing::Took { cpu: best_cpu, .. } = best else {
            break;
        };
        let next = f()?;
        if matches!(next, Timing::Took { cpu, .. } if cpu < best_cpu) {
            best = next;
        }
    }
    Ok(best)
}

/// Times `rs274 -g -t TOOLS FILE OUT`; its canonical output goes to a file, as Oficina's
/// counting sink pays no printing cost either way beyond formatting.
fn time_rs274(program: &Path, tools: &Path, output: &Path) -> Timing {
    let children = CpuOf::Children;
    let cpu_before = cpu_seconds(children);
    let started = Instant::now();
    // rs274 keeps its tool table in `$HOME/.tool.mmap`: a private HOME keeps a concurrent
    // rs274 (a test run, another bench) from corrupting this one.
    let home = output.with_extension("home");
    let _ = std::fs::create_dir_all(&home);
    let status = Command::new("rs274")
        .env("HOME", &home)
        .arg("-g")
        .arg("-t")
        .arg(tools)
        .arg(program)
        .arg(output)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .output();
    let elapsed = started.elapsed();
    let cpu = cpu_seconds(children) - cpu_before;
    match status {
        Err(e) => Timing::Unavailable(format!("rs274 not runnable ({e}); install linuxcnc-uspace")),
        Ok(out) if !out.status.success() => {
            let msg = String::from_utf8_lossy(&out.stderr).replace("executing", "");
            match out.status.code() {
                Some(_) => {
                    Timing::Unavailable(format!("rs274 rejected the program: {}", msg.trim()))
                }
                None => Timing::Unavailable(format!("rs274 died ({}): {}", out.status, msg.trim())),
            }
        }
        Ok(_) => Timing::Took { wall: elapsed, cpu },
    }
}

/// Times Oficina's whole pipeline (read, expressions, interpreter) into a sink that only
/// counts the operations.
fn time_oficina_counting(program: &Path) -> anyhow::Result<(Timing, u64)> {
    let file = File::open(program).with_context(|| format!("cannot open {}", program.display()))?;
    let mut ops = 0u64;
    let (started, cpu) = (Instant::now(), own_cpu());
    let input = BufReader::with_capacity(IO_BUFFER, file);
    let diagnostics = oficina_gcode::run(input, &RunOptions::default(), &mut |_| ops += 1);
    Ok((finish_timing(started, cpu, &diagnostics), ops))
}

/// Times the same pipeline printing rs274's text to a file: the work rs274 does in the run
/// it is compared with.
fn time_oficina_printing(program: &Path, output: &Path) -> anyhow::Result<Timing> {
    let file = File::open(program).with_context(|| format!("cannot open {}", program.display()))?;
    let out =
        File::create(output).with_context(|| format!("cannot create {}", output.display()))?;
    let mut out = BufWriter::with_capacity(IO_BUFFER, out);
    let mut printer = Rs274Printer::new().numbered();
    let mut write_error = None;
    let (started, cpu) = (Instant::now(), own_cpu());
    let input = BufReader::with_capacity(IO_BUFFER, file);
    let diagnostics = oficina_gcode::run(input, &RunOptions::default(), &mut |c| {
        if write_error.is_none() {
            write_error = printer.print(&c, &mut out).err();
        }
    });
    if let Some(e) = write_error.or_else(|| out.flush().err()) {
        bail!("cannot write {}: {e}", output.display());
    }
    Ok(finish_timing(started, cpu, &diagnostics))
}

fn finish_timing(started: Instant, cpu_before: f64, diagnostics: &[Diagnostic]) -> Timing {
    let wall = started.elapsed();
    let cpu = own_cpu() - cpu_before;
    match diagnostics.iter().find(|d| d.severity == Severity::Error) {
        Some(d) => Timing::Unavailable(format!("oficina rejected the program: {d}")),
        None => Timing::Took { wall, cpu },
    }
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

pub fn run(args: BenchGcodeArgs) -> anyhow::Result<()> {
    if args.blocks < 10 {
        bail!("--blocks {} is too small: use at least 10", args.blocks);
    }
    println!(
        "machine load (1-minute average) {} on {} cores; oficina: fastest of {REPEATS} runs, rs274: one run; \
         CPU = user + system time (getrusage), steadier than wall time on a shared machine",
        load_average().unwrap_or_else(|| "unknown".into()),
        std::thread::available_parallelism().map_or(0, |n| n.get())
    );
    let dir = tempfile::tempdir().context("cannot create a temporary directory")?;
    let mixed = args
        .keep
        .clone()
        .unwrap_or_else(|| dir.path().join("mixed.ngc"));
    let plain = dir.path().join("plain.ngc");
    let tools = dir.path().join("tool.tbl");
    std::fs::write(&tools, "T1 P1 D0.125 Z0.5 ;\n").context("cannot write the tool table")?;
    let rs274_out = dir.path().join("rs274.out");
    let oficina_out = dir.path().join("oficina.out");

    for (label, path, writer) in [
        (
            "mixed G1/G2/G3 with parameters and expressions",
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
        let mut ops = 0;
        let counting = best_of(|| {
            let (timing, n) = time_oficina_counting(path)?;
            ops = n;
            Ok(timing)
        })?;
        let printing = best_of(|| time_oficina_printing(path, &oficina_out))?;
        let peer = time_rs274(path, &tools, &rs274_out);
        print_row("oficina, counting ops", &counting, args.blocks, bytes);
        print_row("oficina, printing", &printing, args.blocks, bytes);
        print_row("rs274 -g, printing", &peer, args.blocks, bytes);
        print_ratio("counting", &counting, &peer);
        print_ratio("printing", &printing, &peer);
        println!("  ({ops} canonical operations)");
    }
    if let Some(kept) = &args.keep {
        println!("kept the mixed program at {}", kept.display());
    }
    crate::peak_memory::print();
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mixed(blocks: u64) -> String {
        let mut v = Vec::new();
        write_mixed_program(&mut v, blocks).unwrap();
        String::from_utf8(v).unwrap()
    }

    /// The number after `letter` in a generated line, reading `L[v + #1]` as v.
    fn word(line: &str, letter: char) -> Option<f64> {
        let rest = &line[line.find(letter)? + 1..];
        let rest = rest.strip_prefix('[').unwrap_or(rest);
        let end = rest.find([' ', ']']).unwrap_or(rest.len());
        rest[..end].parse().ok()
    }

    #[test]
    fn programs_have_the_requested_block_count_and_are_deterministic() {
        let a = mixed(5000);
        assert_eq!(a.lines().count(), 5000);
        assert_eq!(a, mixed(5000));
        assert!(a.ends_with("M2\n"));
        let mut plain = Vec::new();
        write_plain_program(&mut plain, 1234).unwrap();
        assert_eq!(String::from_utf8(plain).unwrap().lines().count(), 1234);
    }

    #[test]
    fn every_arc_ends_on_its_circle() {
        // Re-reads the text and checks each arc from the written numbers alone.
        let (mut x, mut y, mut arcs) = (0.0, 0.0, 0);
        for line in mixed(20_000).lines() {
            if line.starts_with("G2 ") || line.starts_with("G3 ") {
                let (ex, ey) = (word(line, 'X').unwrap(), word(line, 'Y').unwrap());
                let (cx, cy) = (x + word(line, 'I').unwrap(), y + word(line, 'J').unwrap());
                let r_start = ((x - cx) * (x - cx) + (y - cy) * (y - cy)).sqrt();
                let r_end = ((ex - cx) * (ex - cx) + (ey - cy) * (ey - cy)).sqrt();
                assert!(
                    (r_start - r_end).abs() < 2e-4,
                    "{line}: radii {r_start} and {r_end}"
                );
                arcs += 1;
            }
            if line.starts_with('G') && line.contains('X') {
                (x, y) = (word(line, 'X').unwrap(), word(line, 'Y').unwrap());
            }
        }
        assert!(arcs > 5000, "only {arcs} arcs");
    }

    #[test]
    fn rs274_runs_the_generated_programs() {
        if Command::new("rs274").arg("-h").output().is_err() {
            eprintln!("rs274 not installed: generated programs not checked against it");
            return;
        }
        let dir = tempfile::tempdir().unwrap();
        let tools = dir.path().join("tool.tbl");
        std::fs::write(&tools, "T1 P1 D0.125 Z0.5 ;\n").unwrap();
        let out = dir.path().join("out");
        for (name, writer) in [
            (
                "mixed.ngc",
                write_mixed_program as fn(&mut BufWriter<File>, u64) -> _,
            ),
            ("plain.ngc", write_plain_program),
        ] {
            let path = dir.path().join(name);
            generate(&path, 3000, writer).unwrap();
            match time_rs274(&path, &tools, &out) {
                Timing::Took { .. } => {}
                Timing::Unavailable(why) => panic!("{name}: {why}"),
            }
            let calls = std::fs::read_to_string(&out).unwrap();
            assert!(
                calls.lines().filter(|l| l.contains("_FEED(")).count() > 2500,
                "{name}"
            );
        }
    }

    #[test]
    fn oficina_runs_the_generated_programs() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("mixed.ngc");
        generate(&path, 3000, write_mixed_program).unwrap();
        let (timing, ops) = time_oficina_counting(&path).unwrap();
        if let Timing::Unavailable(why) = timing {
            panic!("{why}");
        }
        // Every motion block yields one operation; parameter lines yield none.
        let motion_lines = std::fs::read_to_string(&path)
            .unwrap()
            .lines()
            .filter(|l| l.starts_with("G1") || l.starts_with("G2") || l.starts_with("G3"))
            .count() as u64;
        assert!(
            ops >= motion_lines,
            "{ops} operations for {motion_lines} moves"
        );
    }
}
