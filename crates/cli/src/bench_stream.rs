//! `oficina bench stream`: stream a program of 0.1 mm segments to the grbl emulator over a
//! pseudo-terminal whose wire is paced at 115200 baud (11520 bytes/s), and print the
//! achieved character rate as a fraction of the line rate and how often the planner ran dry.
//!
//! Two runs: "link-bound" at a feed the motion could sustain faster than the wire delivers
//! (measures the sender: goal ≥ 95 % of the line rate), and "motion-bound" at 90 % of the
//! feed the wire can feed (the firmware keeps up: goal zero planner starvation).

use anyhow::Context;
use oficina_grbl::Endpoint;
use oficina_grbl::StreamProgram;
use oficina_grbl::{Mode, Notice, Sender, SenderOptions, StreamEnd};
use oficina_grbl_emu::{Config, Emulator};
use std::time::Instant;

#[derive(clap::Args, Debug)]
pub(crate) struct Args {
    /// Program length in lines (0.1 mm segments).
    #[arg(long, default_value_t = 200_000)]
    pub lines: usize,
    /// Emulated serial line rate, bits/s.
    #[arg(long, default_value_t = 115_200)]
    pub baud: u32,
    /// Which run: link, motion or both.
    #[arg(long, default_value = "both")]
    pub run: String,
}

/// A zig-zag raster of 0.1 mm segments: rows of 100 mm, 0.5 mm apart.
fn program(lines: usize, feed: f64) -> String {
    let mut s = format!("G21G90G94\nG1Z-0.2F{feed:.0}\n");
    for i in 0..lines {
        let row = i / 1000;
        let k = i % 1000 + 1;
        let x = if row % 2 == 0 {
            k as f64 * 0.1
        } else {
            100.0 - k as f64 * 0.1
        };
        let y = row as f64 * 0.5 + if k == 1000 { 0.5 } else { 0.0 };
        s += &format!("G1X{x:.3}Y{y:.3}\n");
    }
    s
}

struct Figures {
    chars_per_s: f64,
    line_rate: f64,
    starvations: u64,
    host_late: u64,
    sender_stalls: u32,
    starved_s: f64,
    overflows: u64,
    max_rx: usize,
    seconds: f64,
    lines: usize,
}

fn one_run(lines: usize, baud: u32, feed: f64) -> anyhow::Result<Figures> {
    let emu = Emulator::start(Config {
        baud: Some(baud),
        // The emulator plans with acceleration over its 15 blocks (1.5 mm of 0.1 mm
        // segments, which must hold a stop): fast axes and 100 m/s² let the motion outrun
        // the wire, so the link is what is measured.
        settings: vec![
            (110, 100_000.0),
            (111, 100_000.0),
            (112, 100_000.0),
            (120, 100_000.0),
            (121, 100_000.0),
            (122, 100_000.0),
        ],
        ..Config::default()
    });
    let path = emu.serve_pty().context("cannot open a pseudo-terminal")?;
    let mut sender = Sender::connect(&Endpoint::Serial { path, baud }, SenderOptions::default())
        .context("cannot connect to the emulator")?;
    let Mode::CharCounting(window) = sender.mode else {
        anyhow::bail!("emulator did not report its RX buffer")
    };
    let job =
        StreamProgram::from_text("bench.nc", &program(lines, feed)).map_err(anyhow::Error::msg)?;
    let start = Instant::now();
    let mut last_ack = start;
    let mut bytes = 0u64;
    let report = sender.stream(&job, 0, None, None, &mut |n| {
        if let Notice::Progress { bytes_acked, .. } = n {
            bytes = bytes_acked;
            last_ack = Instant::now();
        }
    });
    if report.end != StreamEnd::Completed {
        anyhow::bail!("bench stream did not complete: {}", report.describe(&job));
    }
    let secs = (last_ack - start).as_secs_f64();
    let st = emu.stats();
    let _ = window;
    Ok(Figures {
        chars_per_s: bytes as f64 / secs,
        line_rate: baud as f64 / 10.0,
        starvations: st.starvations,
        host_late: st.starvations_host_late,
        sender_stalls: report.sender_stalls,
        starved_s: st.starved_seconds,
        overflows: st.rx_overflows,
        max_rx: st.max_rx_used,
        seconds: secs,
        lines: job.len(),
    })
}

fn print(name: &str, feed: f64, f: &Figures) {
    println!(
        "{name:<13} F{feed:<7.0} {:>7} lines in {:>7.2} s: {:>8.0} chars/s = {:>5.1}% of the line rate ({:.0} B/s); planner ran dry {} times ({:.2} s; {} of them while the emulator's host was late; the sender's host held it back {} times); RX max {} of 127 bytes, {} overflows",
        f.lines,
        f.seconds,
        f.chars_per_s,
        100.0 * f.chars_per_s / f.line_rate,
        f.line_rate,
        f.starvations,
        f.starved_s,
        f.host_late,
        f.sender_stalls,
        f.max_rx,
        f.overflows
    );
}

pub(crate) fn run(args: Args) -> anyhow::Result<()> {
    if args.lines == 0 {
        anyhow::bail!("--lines must be at least 1");
    }
    let sample =
        StreamProgram::from_text("b", &program(args.lines, 1000.0)).map_err(anyhow::Error::msg)?;
    let bytes_per_line = sample.bytes_from(2) as f64 / args.lines as f64;
    // Feed at which 0.1 mm segments consume exactly what the wire delivers.
    let wire_feed = (args.baud as f64 / 10.0) / bytes_per_line * 0.1 * 60.0;
    println!(
        "streaming {} lines of 0.1 mm ({bytes_per_line:.1} bytes/line) over a pty at {} baud; the wire can feed {wire_feed:.0} mm/min",
        args.lines, args.baud
    );
    if args.run == "link" || args.run == "both" {
        let feed = 3.0 * wire_feed;
        print("link-bound", feed, &one_run(args.lines, args.baud, feed)?);
    }
    if args.run == "motion" || args.run == "both" {
        let feed = 0.9 * wire_feed;
        print("motion-bound", feed, &one_run(args.lines, args.baud, feed)?);
    }
    if !matches!(args.run.as_str(), "link" | "motion" | "both") {
        anyhow::bail!("--run {}: use link, motion or both", args.run);
    }
    crate::peak_memory::print();
    Ok(())
}
