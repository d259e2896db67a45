//! `oficina bench stream`: stream a program of 0.1 mm segments to the grbl emulator over a
//! pseudo-terminal whose wire is paced at 115200 baud (11520 bytes/s), and print the
//! achieved character rate as a fraction of the line rate and how often the planner ran dry.
//!
//! Two runs: "link-bound" at a feed the motion could sustain faster than the wire delivers
//! (measures the sender: goal ≥ 95 % of the line rate), and "motion-bound" at 90 % of the
//! feed the wire can feed (the firmware keeps up: goal zero planner starvation).

use oficina_app::bench::stream::{one_run, wire_feed, Figures};

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
    // Feed at which 0.1 mm segments consume exactly what the wire delivers.
    let (bytes_per_line, wire_feed) = wire_feed(args.lines, args.baud)?;
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
