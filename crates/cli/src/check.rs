//! `oficina check FILE`: every diagnostic with its place (the check goes on after errors),
//! then what the program does: extents, path length, tools and a time estimate.

use crate::gcode_input::{print_diagnostics, ProgramArgs};
use oficina_canon::summary::{Extents, Summarizer, Summary};
use oficina_canon::Pos;
use oficina_gcode::Severity;
use std::process::ExitCode;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub program: ProgramArgs,
    /// Rapid rate for the feed-rate estimate, mm/min.
    #[arg(long, default_value_t = 5000.0)]
    pub rapid_rate: f64,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    let opts = args.program.run_options(true)?;
    let source = args.program.open()?;
    let mut summarizer = Summarizer::new(Pos::ZERO, args.rapid_rate);
    let mut ops = 0u64;
    let diags = oficina_gcode::program::run(source, &opts, &mut |c| {
        ops += 1;
        summarizer.add(&c.op);
    });
    print_diagnostics(&args.program.file, &diags);
    let errors = diags
        .iter()
        .filter(|d| d.severity == Severity::Error)
        .count();
    let warnings = diags.len() - errors;
    let summary = summarizer.finish();
    println!(
        "{}: {} error{}, {} warning{}, {} canonical operations",
        args.program.file.display(),
        errors,
        plural(errors),
        warnings,
        plural(warnings),
        ops
    );
    print_summary(&summary);
    Ok(if errors > 0 {
        ExitCode::FAILURE
    } else {
        ExitCode::SUCCESS
    })
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

fn print_summary(s: &Summary) {
    println!(
        "  extents (mm, machine)   {:>22} {:>22} {:>22}",
        "X", "Y", "Z"
    );
    print_extents("feed", &s.feed_extents);
    print_extents("rapid", &s.rapid_extents);
    println!(
        "  path length             feed {:.3} mm in {} moves ({} arcs), rapid {:.3} mm in {} moves",
        s.feed_length, s.feed_moves, s.arcs, s.rapid_length, s.rapid_moves
    );
    let tools: Vec<String> = s.tools.iter().map(|t| format!("T{t}")).collect();
    println!(
        "  tools                   {}",
        if tools.is_empty() {
            "none changed".into()
        } else {
            tools.join(" ")
        }
    );
    print!(
        "  time estimate           {} (feed rates only, no acceleration",
        hms(s.feed_rate_seconds)
    );
    if s.untimed_moves > 0 {
        print!(
            "; {} feed moves without a feed rate not counted",
            s.untimed_moves
        );
    }
    println!(")");
}

fn print_extents(name: &str, e: &Extents) {
    if e.is_empty() {
        println!("  {name:<22}  none");
        return;
    }
    let cell = |i: usize| format!("{:.3} … {:.3}", e.min[i], e.max[i]);
    println!(
        "  {name:<22}  {:>22} {:>22} {:>22}",
        cell(0),
        cell(1),
        cell(2)
    );
}

/// Seconds as h:mm:ss.s
pub fn hms(seconds: f64) -> String {
    let total = seconds.max(0.0);
    let h = (total / 3600.0).floor();
    let m = ((total - h * 3600.0) / 60.0).floor();
    let s = total - h * 3600.0 - m * 60.0;
    format!("{}:{:02}:{:04.1}", h as u64, m as u64, s)
}
