//! `bench stream`'s workload: a raster of 0.1 mm segments streamed to the grbl emulator over
//! a pseudo-terminal paced at a serial line rate, with the emulator's and the sender's
//! figures (character rate, planner starvation, RX use).

use super::{failed, BenchError};
use oficina_grbl::Endpoint;
use oficina_grbl::StreamProgram;
use oficina_grbl::{Mode, Notice, Sender, SenderOptions, StreamEnd};
use oficina_grbl_emu::{Config, Emulator};
use std::time::Instant;

/// A zig-zag raster of 0.1 mm segments: rows of 100 mm, 0.5 mm apart.
pub fn program(lines: usize, feed: f64) -> String {
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

/// One run's figures.
pub struct Figures {
    /// Characters acknowledged per second.
    pub chars_per_s: f64,
    /// The wire's rate, bytes/s.
    pub line_rate: f64,
    /// Times the emulator's planner ran dry.
    pub starvations: u64,
    /// Of them, while the emulator's host was late.
    pub host_late: u64,
    /// Times the sender's host held it back.
    pub sender_stalls: u32,
    /// Seconds the planner was dry.
    pub starved_s: f64,
    /// RX buffer overflows.
    pub overflows: u64,
    /// Most of the RX buffer used, bytes.
    pub max_rx: usize,
    /// Seconds from the start to the last acknowledgement.
    pub seconds: f64,
    /// Lines streamed.
    pub lines: usize,
}

/// Stream `program(lines, feed)` to a fresh emulator on a pty paced at `baud`.
pub fn one_run(lines: usize, baud: u32, feed: f64) -> Result<Figures, BenchError> {
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
    let path = emu
        .serve_pty()
        .map_err(|e| failed(format!("cannot open a pseudo-terminal: {e}")))?;
    let mut sender = Sender::connect(&Endpoint::Serial { path, baud }, SenderOptions::default())
        .map_err(|e| failed(format!("cannot connect to the emulator: {e}")))?;
    let Mode::CharCounting(window) = sender.mode else {
        return Err(failed("emulator did not report its RX buffer"));
    };
    let job = StreamProgram::from_text("bench.nc", &program(lines, feed)).map_err(failed)?;
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
        return Err(failed(format!(
            "bench stream did not complete: {}",
            report.describe(&job)
        )));
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

/// Bytes a line of [`program`] takes on the wire, on average, and the feed (mm/min) at
/// which its 0.1 mm segments consume exactly what a `baud` wire delivers.
pub fn wire_feed(lines: usize, baud: u32) -> Result<(f64, f64), BenchError> {
    let sample = StreamProgram::from_text("b", &program(lines, 1000.0)).map_err(failed)?;
    let bytes_per_line = sample.bytes_from(2) as f64 / lines as f64;
    Ok((
        bytes_per_line,
        (baud as f64 / 10.0) / bytes_per_line * 0.1 * 60.0,
    ))
}
