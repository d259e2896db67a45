//! `oficina plan FILE --trace OUT.csv`: the planned motion sampled every millisecond of machine
//! time (docs/trace-format.md), and the total time.

use crate::machine_profile;
use anyhow::{bail, Context};
use oficina_machine::job::canon_stream;
use oficina_machine::{Job, Pace};
use oficina_motion::profile::Shape;
use oficina_motion::trace::TraceWriter;
use oficina_motion::{plan, PlanOptions};
use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::Arc;

#[derive(clap::Args)]
pub struct Args {
    /// G-code program.
    file: PathBuf,
    /// Machine profile: a TOML file or a bundled name.
    #[arg(long, default_value = machine_profile::DEFAULT)]
    machine: String,
    /// Write the sampled motion here (CSV).
    #[arg(long)]
    trace: Option<PathBuf>,
    /// Sampling period, milliseconds of machine time.
    #[arg(long, default_value_t = 1.0)]
    period_ms: f64,
    /// Jerk-limited S-curve velocity profile instead of the profile's own.
    #[arg(long)]
    scurve: bool,
}

pub fn run(args: Args) -> anyhow::Result<ExitCode> {
    if !(args.period_ms.is_finite() && args.period_ms >= 0.01) {
        bail!("--period-ms must be at least 0.01");
    }
    let profile = machine_profile::resolve(&args.machine)?;
    let text = std::fs::read_to_string(&args.file)
        .with_context(|| format!("reading {}", args.file.display()))?;
    let job = Job {
        name: args.file.display().to_string(),
        text: Arc::new(text),
        start_line: None,
        pace: Pace::Instant,
    };
    let ops = canon_stream(&job);
    let interp_error = ops.error.clone();
    let opts = PlanOptions {
        shape: args.scurve.then_some(Shape::SCurve),
        ..PlanOptions::default()
    };
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
    let (mut total, mut segments, mut distance) = (0.0, 0u64, 0.0);
    for seg in planner {
        let seg = seg.map_err(|e| anyhow::anyhow!("{}: {e}", job.name))?;
        total += seg.duration();
        distance += seg.motion.length;
        segments += 1;
        if let Some(w) = writer.as_mut() {
            w.segment(&seg)?;
        }
    }
    if let Some(e) = interp_error
        .lock()
        .unwrap_or_else(|e| e.into_inner())
        .take()
    {
        bail!("{e}");
    }
    let rows = writer.as_ref().map_or(0, |w| w.rows);
    if let Some(w) = writer {
        w.finish()?;
    }
    println!("machine: {}", profile.name);
    println!("segments: {segments}  path: {distance:.3} mm");
    println!("total time: {total:.3} s ({})", hms(total));
    if let Some(p) = &args.trace {
        println!(
            "trace: {rows} rows every {} ms → {}",
            args.period_ms,
            p.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn hms(s: f64) -> String {
    let r = s.round() as u64;
    format!("{}:{:02}:{:02}", r / 3600, r / 60 % 60, r % 60)
}
