//! `oficina plan FILE --trace OUT.csv`: the planned motion sampled every millisecond of machine
//! time (docs/trace-format.md), and the total time. The job is `oficina_app::plan_program`.

use crate::gcode_input::{machine_for, tool_table_for, HeldProgram};
use crate::machine_profile;
use oficina_app::{plan_program, Interpolator, PlanOutcome, PlanOutputs, PlanRequest, PlanSummary};
use oficina_canon::Units;
use oficina_gcode::Dialect;
use oficina_motion::format_hms;
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

#[derive(clap::Args)]
pub(crate) struct Args {
    #[command(flatten)]
    program: HeldProgram,
    /// Machine profile: a TOML file or a bundled name. Default: the program's
    /// `(machine: NAME)` opening comment, else grbl-router.
    #[arg(long)]
    machine: Option<String>,
    /// Write the sampled motion here (CSV).
    #[arg(long)]
    trace: Option<PathBuf>,
    /// Sampling period, milliseconds of machine time.
    #[arg(long, default_value_t = 1.0)]
    period_ms: f64,
    /// Jerk-limited S-curve velocity profile instead of the profile's own.
    #[arg(long)]
    scurve: bool,
    /// Write every motor step here (CSV: motor, time in s, direction).
    #[arg(long)]
    steps: Option<PathBuf>,
    /// Write the steps compressed as Klipper queue_step runs (motor, interval, count, add, dir).
    #[arg(long)]
    steps_compressed: Option<PathBuf>,
    /// Who makes the steps: `exact` (the planned motion's exact step times) or `dda` (seed
    /// 002's linear and circular DDA on a cartesian machine, no ramps; docs/trace-format.md).
    #[arg(long, value_enum, default_value_t = Interpolator::Exact)]
    interpolator: Interpolator,
    /// G-code dialect: linuxcnc (default), grbl, marlin (Marlin 2.x plotters) or legacy-2006 (seed 002's programs).
    #[arg(long, default_value = "linuxcnc")]
    dialect: Dialect,
    /// Largest output file (--trace, --steps) written, MB: the size is estimated by planning
    /// the program once before anything is written, and a larger output is refused.
    #[arg(long, default_value_t = 2048)]
    max_output_mb: u64,
    /// A LinuxCNC tool table (.tbl) for G43 and M6, lengths in mm: tool length offsets move
    /// the planned motion as they move the machine.
    #[arg(long)]
    tool_table: Option<PathBuf>,
    /// Run the motion invariant checker over the whole plan (every joint's speed,
    /// acceleration and step rate, the path, the feeds, every junction) and fail on any
    /// violation. Holds the program's canon and segments in memory.
    #[arg(long)]
    check: bool,
}

pub(crate) fn run(args: Args) -> anyhow::Result<ExitCode> {
    let machine = machine_for(args.machine.as_deref(), &args.program.file);
    let profile = machine_profile::resolve_with_offset(&machine, args.program.work_offset)?;
    let text = args.program.read()?;
    let mut interp =
        oficina_app::run_options_for(&profile, args.dialect, args.program.line_limit.bytes());
    if let Some(t) = tool_table_for(args.tool_table.as_deref(), &profile, &machine, Units::Mm)? {
        interp.tool_table = t;
    }
    let name = args.program.file.display().to_string();
    let machine_name = profile.name.clone();
    let request = PlanRequest {
        name: name.clone(),
        text: Arc::new(text),
        profile,
        interp,
        period_ms: args.period_ms,
        scurve: args.scurve,
        interpolator: args.interpolator,
        check: args.check,
        max_output_mb: args.max_output_mb,
        outputs: PlanOutputs {
            trace: args.trace.clone(),
            steps: args.steps.clone(),
            steps_compressed: args.steps_compressed.clone(),
        },
    };
    match plan_program(&request)? {
        // Already rendered like `check` renders it: printed as it is (not as
        // "error: …: error: …") and the command fails.
        PlanOutcome::InterpreterFailed(e) => {
            eprint!("{e}");
            Ok(ExitCode::FAILURE)
        }
        PlanOutcome::Stepped(s) => {
            println!("machine: {machine_name}");
            println!("interpolator: seed 002 DDA");
            println!("steps: {}", s.steps);
            println!("moves: {}  path: {:.3} mm", s.moves, s.distance);
            println!(
                "total time: {:.3} s ({})",
                s.seconds,
                format_hms(s.seconds, 0)
            );
            Ok(ExitCode::SUCCESS)
        }
        PlanOutcome::Planned(s) => Ok(print_planned(&args, &machine_name, &name, &s)),
    }
}

fn print_planned(args: &Args, machine: &str, name: &str, s: &PlanSummary) -> ExitCode {
    println!("machine: {machine}");
    if let Some(n) = s.steps {
        println!("steps: {n}");
    }
    println!("segments: {}  path: {:.3} mm", s.segments, s.distance);
    println!(
        "total time: {:.3} s ({})",
        s.seconds,
        format_hms(s.seconds, 0)
    );
    match &s.check {
        Some(Ok(r)) => println!(
            "check: ok, {} segments; peak joint speed {:.1} %, acceleration {:.1} % of \
             the limits; path within {:.4} mm",
            r.segments,
            r.max_speed_ratio * 100.0,
            r.max_accel_ratio * 100.0,
            r.max_path_deviation
        ),
        Some(Err(bad)) => {
            for b in bad {
                eprintln!("check: {b}");
            }
            eprintln!("check: {} violation(s) in {name}", bad.len());
            return ExitCode::FAILURE;
        }
        None => {}
    }
    if let (Some(p), Some(rows)) = (&args.trace, s.trace_rows) {
        println!(
            "trace: {rows} rows every {} ms → {}",
            args.period_ms,
            p.display()
        );
    }
    ExitCode::SUCCESS
}
