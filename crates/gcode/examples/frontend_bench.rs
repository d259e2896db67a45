//! Front-end throughput: generate a straight `G1 X… Y…` program, stream it through the
//! executor from a file, print blocks/s and MB/s.
//!
//! `cargo run --release -p oficina-gcode --example frontend_bench -- [blocks] [file]`

use oficina_gcode::Block;
use oficina_gcode::Dialect;
use oficina_gcode::Executor;
use oficina_gcode::Params;
use std::io::{BufReader, BufWriter, Write};
use std::time::Instant;

/// CPU time of this thread in seconds (Linux), so a loaded machine does not distort the
/// figure; `None` elsewhere.
fn cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns / 1e9)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let blocks: u64 = args
        .get(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(1_000_000);
    let path = args.get(2).cloned().unwrap_or_else(|| {
        std::env::temp_dir()
            .join("oficina_frontend_bench.ngc")
            .display()
            .to_string()
    });

    // A deterministic pseudo-random walk with the usual 3-decimal coordinates.
    let mut out = BufWriter::new(std::fs::File::create(&path)?);
    writeln!(out, "G21 G90 G17 F1200")?;
    let mut random = oficina_testkit::random::Xorshift::new(0x9E37_79B9_7F4A_7C15);
    for i in 0..blocks {
        let seed = random.next_u64();
        let x = (seed % 200_000) as f64 / 1000.0;
        let y = ((seed >> 20) % 200_000) as f64 / 1000.0;
        if i % 1000 == 0 {
            writeln!(out, "G1 X{x:.3} Y{y:.3} (segment {i})")?;
        } else {
            writeln!(out, "G1 X{x:.3} Y{y:.3}")?;
        }
    }
    writeln!(out, "M2")?;
    out.flush()?;
    drop(out);
    let bytes = std::fs::metadata(&path)?.len();

    for round in 0..3 {
        let file = std::fs::File::open(&path)?;
        let mut exec = Executor::new(BufReader::with_capacity(1 << 16, file), Dialect::LinuxCnc);
        let mut params = Params::new();
        let mut block = Block::default();
        let start = Instant::now();
        let cpu0 = cpu_seconds();
        let (mut n, mut sum) = (0u64, 0.0f64);
        while exec.read_block(&mut params, &mut block)? {
            n += 1;
            sum += block.words.iter().map(|w| w.value).sum::<f64>();
        }
        let t = start.elapsed().as_secs_f64();
        let cpu = cpu_seconds().zip(cpu0).map_or(t, |(a, b)| a - b);
        println!(
            "round {round}: {n} blocks, wall {t:.3} s, cpu {cpu:.3} s: {:.0} blocks/s, {:.0} MB/s by cpu time (read_block, checksum {sum:.3})",
            n as f64 / cpu,
            bytes as f64 / cpu / 1e6
        );
    }
    // The allocating API, as the interpreter uses it.
    let file = std::fs::File::open(&path)?;
    let mut exec = Executor::new(BufReader::with_capacity(1 << 16, file), Dialect::LinuxCnc);
    let mut params = Params::new();
    let start = Instant::now();
    let cpu0 = cpu_seconds();
    let mut n = 0u64;
    while let Some(b) = exec.next_block(&mut params) {
        b?;
        n += 1;
    }
    let t = start.elapsed().as_secs_f64();
    let cpu = cpu_seconds().zip(cpu0).map_or(t, |(a, b)| a - b);
    println!(
        "next_block: {n} blocks, wall {t:.3} s, cpu {cpu:.3} s: {:.0} blocks/s, {:.0} MB/s by cpu time",
        n as f64 / cpu,
        bytes as f64 / cpu / 1e6
    );
    std::fs::remove_file(&path)?;

    // The full path: a while loop of expressions and assignments, run by seeking back.
    let iterations = (blocks / 2).max(1);
    let text = format!(
        "#1=0\no100 while [#1 LT {iterations}]\n  G1 X[#1*0.01] Y[SIN[#1]*10] F[600+#1 MOD 7]\n  #1=[#1+1]\no100 endwhile\nM2\n"
    );
    let mut exec = Executor::from_text(&text, Dialect::LinuxCnc);
    let mut params = Params::new();
    let mut block = Block::default();
    let start = Instant::now();
    let cpu0 = cpu_seconds();
    let mut n = 0u64;
    while exec.read_block(&mut params, &mut block)? {
        n += 1;
    }
    let t = start.elapsed().as_secs_f64();
    let cpu = cpu_seconds().zip(cpu0).map_or(t, |(a, b)| a - b);
    println!(
        "o-word loop with expressions: {n} blocks, wall {t:.3} s, cpu {cpu:.3} s: {:.0} blocks/s by cpu time",
        n as f64 / cpu
    );
    Ok(())
}
