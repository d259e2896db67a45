//! `oficina`: the command line. Each subcommand lives in its own module and only wires
//! arguments to the library crates; no domain logic here.

mod bench_cam;
mod bench_carve;
mod bench_gcode;
mod bench_motion;
mod bench_plot;
mod bench_stitch;
mod bench_stream;
mod carve;
mod check;
mod console;
mod console_probe;
mod design;
mod embroider;
mod emulate;
mod emulate_probe;
mod emulate_seed;
mod fit;
mod gcode_canon;
mod gcode_input;
mod level;
mod machine_profile;
mod mill;
mod mill_job;
mod peak_memory;
mod plan;
mod plot;
mod progress;
mod run;
mod serve;
mod simulate;
mod sole;
mod tool_change;
mod tools_cmd;

use clap::{Parser, Subcommand};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "oficina",
    version,
    about = "Open CNC workshop: from design to a moving machine"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Benchmarks that print figures beside the named peer's on the same input.
    #[command(subcommand)]
    Bench(BenchCommand),
    /// Check a G-code program: every error with its place, then extents, lengths, tools, time.
    Check(check::Args),
    /// G-code tools.
    #[command(subcommand)]
    Gcode(GcodeCommand),
    /// Relief carving from a grayscale elevation image: program, preview and time estimate.
    Carve(carve::Args),
    /// Terminal to grbl-family firmware, and the job runner with hold/resume/stop and resume-from-line.
    Console(console::Args),
    /// The design editor's file (`*.oficina.json`): export as SVG/DXF, offset contours.
    #[command(subcommand)]
    Design(design::Command),
    /// Emulate a grbl 1.1 (or Marlin 2.x) board on a pseudo-terminal or TCP port, for dry runs.
    Emulate(emulate::Args),
    /// Fit a digitised contour by every method: blocks and deviation of each.
    Fit(fit::Args),
    /// Auto-levelling: probe a height map on grbl firmware, or level a program with one.
    #[command(subcommand)]
    Level(level::Command),
    /// Run a program on the virtual machine or grbl firmware: progress, ETA, keyboard hold/resume/stop.
    Run(run::Args),
    /// Plan a program: total time, and the motion sampled every millisecond (--trace).
    Plan(plan::Args),
    /// 2.5D milling of an SVG/DXF drawing: pocket, profile, drill → program, preview, check, time.
    Mill(mill::Args),
    /// Shoe-sole molds (seed 001): digitised contour → graded, mirrored insert and cavity programs.
    Sole(sole::Args),
    /// Pen plotting: SVG / DXF / HPGL / image / text → optimised G-code, joint-space or HPGL.
    Plot(plot::Args),
    /// Simulate any program on a box of stock with its tools' shapes: render, removed
    /// volume, rapids into material, cuts below the bottom, gouge against a design.
    Simulate(simulate::Args),
    /// The web workbench: editor, preview and machine panel in the browser (127.0.0.1:7878).
    Serve(serve::Args),
    /// Embroidery: SVG/DXF → running/satin/fill stitches → hoop, sheet, DST/EXP, table run.
    Embroider(embroider::Args),
    /// The tool library: feeds and speeds from chip load × flutes × rpm.
    #[command(subcommand)]
    Tools(ToolsCommand),
}

#[derive(Subcommand)]
enum ToolsCommand {
    /// Feed and cutting speed of a library tool for a material, or of numbers given by hand.
    Feeds(tools_cmd::FeedsArgs),
}

#[derive(Subcommand)]
enum GcodeCommand {
    /// Print the canonical operations in the text of LinuxCNC's `rs274 -g`.
    Canon(gcode_canon::Args),
}

#[derive(Subcommand)]
enum BenchCommand {
    /// Interpreter throughput on a generated 1,000,000-block program, beside LinuxCNC's rs274.
    Gcode(bench_gcode::BenchGcodeArgs),
    /// Streaming to the grbl emulator over a 115200-baud pty: chars/s vs line rate, planner starvation.
    Stream(bench_stream::Args),
    /// Planner segments/s on a 1,000,000-segment relief program, steps/s, peak memory.
    Motion(bench_motion::Args),
    /// Relief toolpath generation on a generated 4000 x 4000 image, beside LinuxCNC's image-to-gcode.
    Carve(bench_carve::Args),
    /// Path optimisation of a generated 100,000-path drawing, beside vpype linemerge linesort.
    Plot(bench_plot::Args),
    /// 59 offsets of a 10,000-vertex contour beside shapely and pyclipper; pockets of a 1,000-shape DXF.
    Cam(bench_cam::Args),
    /// Fill and routing of a ~100,000-stitch design to DST and PES, beside pyembroidery
    /// reading and writing the same stitches.
    Stitch(bench_stitch::Args),
}

/// An error already printed in full where it happened (a rendered diagnostic says "error"
/// itself): `main` only fails, without printing it again.
#[derive(Debug)]
pub struct Reported;

impl std::fmt::Display for Reported {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("reported above")
    }
}

impl std::error::Error for Reported {}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result: anyhow::Result<ExitCode> = match cli.command {
        Command::Check(args) => check::run(args),
        Command::Gcode(GcodeCommand::Canon(args)) => gcode_canon::run(args),
        Command::Carve(args) => carve::run(args),
        Command::Console(args) => console::run(args),
        Command::Design(cmd) => design::run(cmd),
        Command::Emulate(args) => emulate::run(args),
        Command::Fit(args) => fit::run(args),
        Command::Run(args) => run::run(args),
        Command::Level(cmd) => level::run(cmd),
        Command::Plan(args) => plan::run(args),
        Command::Mill(args) => mill::run(args),
        Command::Sole(args) => sole::run(args),
        Command::Plot(args) => plot::run(args),
        Command::Serve(args) => serve::run(args),
        Command::Simulate(args) => simulate::run(args),
        Command::Embroider(args) => embroider::run(args),
        Command::Tools(ToolsCommand::Feeds(args)) => tools_cmd::feeds(args),
        Command::Bench(which) => match which {
            BenchCommand::Gcode(args) => bench_gcode::run(args).map(|()| ExitCode::SUCCESS),
            BenchCommand::Stream(args) => bench_stream::run(args).map(|()| ExitCode::SUCCESS),
            BenchCommand::Carve(args) => bench_carve::run(args).map(|()| ExitCode::SUCCESS),
            BenchCommand::Motion(args) => bench_motion::run(args).map(|()| ExitCode::SUCCESS),
            BenchCommand::Plot(args) => bench_plot::run(args).map(|()| ExitCode::SUCCESS),
            BenchCommand::Cam(args) => bench_cam::run(args).map(|()| ExitCode::SUCCESS),
            BenchCommand::Stitch(args) => bench_stitch::run(args).map(|()| ExitCode::SUCCESS),
        },
    };
    match result {
        Ok(code) => code,
        // Printed in full already (a diagnostic with its own "error:").
        Err(e) if e.is::<Reported>() => ExitCode::FAILURE,
        Err(e) => {
            eprintln!("oficina: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
