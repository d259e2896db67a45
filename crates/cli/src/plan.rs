//! `oficina plan FILE --trace OUT.csv`: the planned motion sampled every millisecond of machine
//! time (docs/trace-format.md), and the total time.

use crate::gcode_input::{
    load_tool_table, machine_for, read_program, LineLimit, DEFAULT_MAX_PROGRAM_MB,
};
use crate::machine_profile;
use anyhow::{bail, Context};
use oficina_canon::Units;
use oficina_gcode::Dialect;
use oficina_machine::job::{canon_stream_with, CanonStream};
use oficina_machine::{Job, Pace};
use oficina_motion::dda_steps;
use oficina_motion::format_hms;
use oficina_motion::Kinematics;
use oficina_motion::StepFiles;
use oficina_motion::TraceWriter;
use oficina_motion::VelocityProfile;
use oficina_motion::{motor_names, StepCount, StepGenerator, MOTORS};
use oficina_motion::{plan, PlanOptions, Profile};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;

#[derive(clap::Args)]
pub struct Args {
    /// G-code program.
    file: PathBuf,
    /// Machine profile: a TOML file or a bundled name. Default: the program's
    /// `(machine: NAME)` opening comment, else grbl-router.
    #[arg(long)]
    machine: Option<String>,
    /// Work zero in machine coordinates, X,Y,Z mm (default: the profile's stored G54).
    #[arg(long, value_parser = machine_profile::parse_xyz)]
    work_offset: Option<[f64; 3]>,
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
    /// G-code dialect: linuxcnc (default), grbl or legacy-2006 (seed 002's programs).
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
    #[command(flatten)]
    line_limit: LineLimit,
    /// Largest program held in memory, MB.
    #[arg(long, default_value_t = DEFAULT_MAX_PROGRAM_MB)]
    max_program_mb: u64,
    /// Run the motion invariant checker over the whole plan (every joint's speed,
    /// acceleration and step rate, the path, the feeds, every junction) and fail on any
    /// violation. Holds the program's canon and segments in memory.
    #[arg(long)]
    check: bool,
}

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolator {
    Exact,
    Dda,
}

/// The step outputs' files.
type StepOutput = StepFiles<BufWriter<File>>;

fn create(p: &Path) -> anyhow::Result<BufWriter<File>> {
    let f = File::create(p).with_context(|| format!("creating {}", p.display()))?;
    Ok(BufWriter::new(f))
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if !(args.period_ms.is_finite() && args.period_ms >= 0.01) {
        bail!("--period-ms must be at least 0.01");
    }
    let machine = machine_for(args.machine.as_deref(), &args.file);
    let profile = machine_profile::resolve_with_offset(&machine, args.work_offset)?;
    let text = match read_program(&args.file, args.max_program_mb)? {
        Ok(text) => text,
        Err(code) => return Ok(code),
    };
    let job = Job {
        name: args.file.display().to_string(),
        text: Arc::new(text),
        start_line: None,
        pace: Pace::Instant,
    };
    let mut interp_opts =
        oficina_app::run_options_for(&profile, args.dialect, args.line_limit.bytes());
    if let Some(path) = &args.tool_table {
        interp_opts.tool_table = load_tool_table(path, Units::Mm)?;
    } else if let Some(t) = oficina_app::profile::tool_table(&profile, &machine, Units::Mm)? {
        interp_opts.tool_table = t;
    }
    if args.interpolator == Interpolator::Dda {
        let ops = canon_stream_with(&job, interp_opts);
        return run_dda(&args, ops, &profile, &job.name);
    }
    let opts = PlanOptions {
        shape: args.scurve.then_some(VelocityProfile::SCurve),
        ..PlanOptions::default()
    };
    if args.trace.is_some() || args.steps.is_some() || args.steps_compressed.is_some() {
        // Planned once to size the output; the interpreter's error, if any, is reported by
        // the run that follows.
        let sizing = canon_stream_with(&job, interp_opts.clone());
        if let Ok(e) = oficina_motion::estimate_with(sizing, &profile, opts, false) {
            check_output_size(&args, &e)?;
        }
    }
    let check_ops: Option<Vec<_>> = args
        .check
        .then(|| canon_stream_with(&job, interp_opts.clone()).collect());
    let mut checked = Vec::new();
    let ops = canon_stream_with(&job, interp_opts);
    let interp_error = ops.error.clone();
    let planner = plan(ops, &profile, opts).map_err(|e| anyhow::anyhow!("{}: {e}", job.name))?;
    let mut writer = match &args.trace {
        Some(p) => {
            let f =
                std::fs::File::create(p).with_context(|| format!("creating {}", p.display()))?;
            Some(TraceWriter::new(
                std::io::BufWriter::new(f),
                args.period_ms / 1000.0,
                profile.kinematics.joint_names(),
            )?)
        }
        None => None,
    };
    let names = motor_names(&profile);
    let mut steps = match step_files(&args, names)? {
        None => None,
        Some(files) => {
            let q = oficina_motion::for_profile(&profile)
                .joints(profile.start)
                .map_err(|e| anyhow::anyhow!("{}: start position: {e}", profile.name))?;
            Some((StepGenerator::new(&profile, q), files))
        }
    };
    let (mut total, mut segments, mut distance) = (0.0, 0u64, 0.0);
    for seg in planner {
        let seg = seg.map_err(|e| anyhow::anyhow!("{}: {e}", job.name))?;
        total += seg.duration();
        distance += seg.motion.length;
        segments += 1;
        if let Some(w) = writer.as_mut() {
            w.segment(&seg)?;
        }
        if let Some((g, files)) = steps.as_mut() {
            g.segment(&seg, files)
                .map_err(|e| anyhow::anyhow!("{}: {e}", job.name))?;
        }
        if args.check {
            checked.push(seg);
        }
    }
    if let Some(code) = interp_failed(&interp_error) {
        return Ok(code);
    }
    let rows = writer.as_ref().map_or(0, |w| w.rows);
    if let Some(w) = writer {
        w.finish()?;
    }
    let step_count = steps.map(|(_, f)| f.finish()).transpose()?;
    println!("machine: {}", profile.name);
    if let Some(n) = step_count {
        println!("steps: {n}");
    }
    println!("segments: {segments}  path: {distance:.3} mm");
    println!("total time: {total:.3} s ({})", format_hms(total, 0));
    if let Some(ops) = &check_ops {
        let shape = opts.shape.unwrap_or(profile.shape);
        match oficina_motion::check(ops, &checked, &profile, shape, 1.0) {
            Ok(r) => println!(
                "check: ok, {} segments; peak joint speed {:.1} %, acceleration {:.1} % of \
                 the limits; path within {:.4} mm",
                r.segments,
                r.max_speed_ratio * 100.0,
                r.max_accel_ratio * 100.0,
                r.max_path_deviation
            ),
            Err(bad) => {
                for b in &bad {
                    eprintln!("check: {b}");
                }
                eprintln!("check: {} violation(s) in {}", bad.len(), job.name);
                return Ok(ExitCode::FAILURE);
            }
        }
    }
    if let Some(p) = &args.trace {
        println!(
            "trace: {rows} rows every {} ms → {}",
            args.period_ms,
            p.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

/// The interpreter's error, already rendered like `check` renders it: printed as it is (not
/// as "error: …: error: …") and the command fails.
fn interp_failed(error: &std::sync::Mutex<Option<String>>) -> Option<ExitCode> {
    let e = error.lock().unwrap_or_else(|e| e.into_inner()).take()?;
    eprint!("{e}");
    Some(ExitCode::FAILURE)
}

/// Refuse outputs that would be larger than `--max-output-mb`, from the planned motion.
fn check_output_size(args: &Args, e: &oficina_motion::Estimate) -> anyhow::Result<()> {
    let limit = args.max_output_mb.saturating_mul(1_000_000);
    let mb = |b: f64| b / 1e6;
    if let Some(p) = &args.trace {
        let rows = (e.seconds / (args.period_ms / 1000.0)).floor() + 1.0;
        let bytes = rows * TraceWriter::<File>::ROW_BYTES as f64;
        if bytes > limit as f64 {
            bail!(
                "--trace {}: {:.0} rows every {} ms of {} of machine time make about {:.0} MB,                  more than --max-output-mb {} (raise it, or sample less often with --period-ms)",
                p.display(),
                rows,
                args.period_ms,
                format_hms(e.seconds, 0),
                mb(bytes),
                args.max_output_mb
            );
        }
    }
    if let Some(p) = args.steps.as_ref().or(args.steps_compressed.as_ref()) {
        // A compressed run holds at least one step: its file is never larger than the CSV.
        let bytes = e.steps * StepOutput::ROW_BYTES as f64;
        if bytes > limit as f64 {
            bail!(
                "{}: about {:.0} motor steps make up to {:.0} MB, more than --max-output-mb {} \
                 (raise it)",
                p.display(),
                e.steps,
                mb(bytes),
                args.max_output_mb
            );
        }
    }
    Ok(())
}

/// The step outputs asked for (`--steps`, `--steps-compressed`), created with their headers.
fn step_files(args: &Args, names: [&'static str; MOTORS]) -> anyhow::Result<Option<StepOutput>> {
    if args.steps.is_none() && args.steps_compressed.is_none() {
        return Ok(None);
    }
    let csv = args.steps.as_deref().map(create).transpose()?;
    let runs = args.steps_compressed.as_deref().map(create).transpose()?;
    Ok(Some(StepFiles::new(names, csv, runs)?))
}

/// `--interpolator dda`: the program stepped by seed 002's interpolators, no planner.
fn run_dda(
    args: &Args,
    ops: CanonStream,
    profile: &Profile,
    name: &str,
) -> anyhow::Result<ExitCode> {
    if args.trace.is_some() || args.scurve {
        bail!("--interpolator dda makes steps only: --trace and --scurve belong to the planned motion (drop them or use --interpolator exact)");
    }
    let interp_error = ops.error.clone();
    let mut files = step_files(args, motor_names(profile))?;
    let summary = match files.as_mut() {
        Some(f) => dda_steps(ops, profile, f),
        None => dda_steps(ops, profile, &mut StepCount::default()),
    }
    .map_err(|e| anyhow::anyhow!("{name}: --interpolator dda: {e}"))?;
    if let Some(code) = interp_failed(&interp_error) {
        return Ok(code);
    }
    if let Some(f) = files {
        f.finish()?;
    }
    println!("machine: {}", profile.name);
    println!("interpolator: seed 002 DDA");
    println!("steps: {}", summary.steps);
    println!("moves: {}  path: {:.3} mm", summary.moves, summary.distance);
    println!(
        "total time: {:.3} s ({})",
        summary.seconds,
        format_hms(summary.seconds, 0)
    );
    Ok(ExitCode::SUCCESS)
}
