//! Planning a program on a machine profile without running it (`oficina plan`): the total
//! time, and on request the motion sampled every period (docs/trace-format.md), every motor
//! step (exact step times, or seed 002's DDA), and the motion invariant checker's verdict.

use crate::Error;
use oficina_gcode::RunOptions;
use oficina_machine::job::{canon_stream_with, CanonStream};
use oficina_machine::{Job, Pace};
use oficina_motion::{
    dda_steps, format_hms, motor_names, plan, CheckReport, DdaSummary, Estimate, Kinematics,
    PlanOptions, Profile, StepCount, StepFiles, StepGenerator, TraceWriter, VelocityProfile,
    MOTORS,
};
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex};

/// Who makes the motor steps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "clap", derive(clap::ValueEnum))]
pub enum Interpolator {
    /// The planned motion's exact step times.
    Exact,
    /// Seed 002's linear and circular DDA on a cartesian machine, no ramps.
    Dda,
}

/// The files a plan writes; none is created before the output size is checked.
#[derive(Clone, Debug, Default)]
pub struct PlanOutputs {
    /// The sampled motion (CSV).
    pub trace: Option<PathBuf>,
    /// Every motor step (CSV: motor, time in s, direction).
    pub steps: Option<PathBuf>,
    /// The steps as Klipper queue_step runs.
    pub steps_compressed: Option<PathBuf>,
}

/// What to plan and how.
pub struct PlanRequest {
    /// The program's name in messages (its path).
    pub name: String,
    /// The program.
    pub text: Arc<String>,
    /// The machine.
    pub profile: Profile,
    /// The interpreter's options (dialect, offsets, tool table).
    pub interp: RunOptions,
    /// Sampling period of the trace, ms of machine time.
    pub period_ms: f64,
    /// Jerk-limited S-curve velocity profile instead of the profile's own.
    pub scurve: bool,
    /// Who makes the steps.
    pub interpolator: Interpolator,
    /// Run the motion invariant checker over the whole plan.
    pub check: bool,
    /// Largest output file, MB.
    pub max_output_mb: u64,
    /// The files to write.
    pub outputs: PlanOutputs,
}

/// The planned motion's figures.
#[derive(Clone, Debug)]
pub struct PlanSummary {
    /// Motor steps written, when steps were asked for.
    pub steps: Option<u64>,
    /// Planned segments.
    pub segments: u64,
    /// Path length, mm.
    pub distance: f64,
    /// Machine time, s.
    pub seconds: f64,
    /// Rows written to the trace, when one was asked for.
    pub trace_rows: Option<u64>,
    /// The checker's report, or every violation, when the check was asked for.
    pub check: Option<Result<CheckReport, Vec<String>>>,
}

/// How a plan ended.
#[derive(Clone, Debug)]
pub enum PlanOutcome {
    /// Planned by the look-ahead planner.
    Planned(PlanSummary),
    /// Stepped by seed 002's DDA (no planner).
    Stepped(DdaSummary),
    /// The interpreter stopped on an error, rendered like `check` renders it.
    InterpreterFailed(String),
}

/// Plan `req`: size the outputs first and refuse any larger than the limit, then plan, write
/// and check.
pub fn plan_program(req: &PlanRequest) -> Result<PlanOutcome, Error> {
    if !(req.period_ms.is_finite() && req.period_ms >= 0.01) {
        return Err(Error("--period-ms must be at least 0.01".into()));
    }
    let job = Job {
        name: req.name.clone(),
        text: req.text.clone(),
        start_line: None,
        pace: Pace::Instant,
    };
    if req.interpolator == Interpolator::Dda {
        return run_dda(req, canon_stream_with(&job, req.interp.clone()));
    }
    let profile = &req.profile;
    let opts = PlanOptions {
        shape: req.scurve.then_some(VelocityProfile::SCurve),
        ..PlanOptions::default()
    };
    let out = &req.outputs;
    if out.trace.is_some() || out.steps.is_some() || out.steps_compressed.is_some() {
        // Planned once to size the output; the interpreter's error, if any, is reported by
        // the run that follows.
        let sizing = canon_stream_with(&job, req.interp.clone());
        if let Ok(e) = oficina_motion::estimate_with(sizing, profile, opts, false) {
            check_output_size(req, &e)?;
        }
    }
    let named = |e: &dyn std::fmt::Display| Error(format!("{}: {e}", job.name));
    let check_ops: Option<Vec<_>> = req
        .check
        .then(|| canon_stream_with(&job, req.interp.clone()).collect());
    let mut checked = Vec::new();
    let ops = canon_stream_with(&job, req.interp.clone());
    let interp_error = ops.error.clone();
    let planner = plan(ops, profile, opts).map_err(|e| named(&e))?;
    let mut writer = match &out.trace {
        Some(p) => Some(
            TraceWriter::new(
                create(p)?,
                req.period_ms / 1000.0,
                profile.kinematics.joint_names(),
            )
            .map_err(|e| Error::chain(&e))?,
        ),
        None => None,
    };
    let mut steps = match step_files(out, motor_names(profile))? {
        None => None,
        Some(files) => {
            let q = oficina_motion::for_profile(profile)
                .joints(profile.start)
                .map_err(|e| Error(format!("{}: start position: {e}", profile.name)))?;
            Some((StepGenerator::new(profile, q), files))
        }
    };
    let (mut seconds, mut segments, mut distance) = (0.0, 0u64, 0.0);
    for seg in planner {
        let seg = seg.map_err(|e| named(&e))?;
        seconds += seg.duration();
        distance += seg.motion.length;
        segments += 1;
        if let Some(w) = writer.as_mut() {
            w.segment(&seg).map_err(|e| Error::chain(&e))?;
        }
        if let Some((g, files)) = steps.as_mut() {
            g.segment(&seg, files).map_err(|e| named(&e))?;
        }
        if req.check {
            checked.push(seg);
        }
    }
    if let Some(e) = interp_failed(&interp_error) {
        return Ok(PlanOutcome::InterpreterFailed(e));
    }
    let trace_rows = writer.as_ref().map(|w| w.rows);
    if let Some(w) = writer {
        w.finish().map_err(|e| Error::chain(&e))?;
    }
    let steps = steps
        .map(|(_, f)| f.finish())
        .transpose()
        .map_err(|e| Error::chain(&e))?;
    let check = check_ops.map(|ops| {
        let shape = opts.shape.unwrap_or(profile.shape);
        oficina_motion::check(&ops, &checked, profile, shape, 1.0)
    });
    Ok(PlanOutcome::Planned(PlanSummary {
        steps,
        segments,
        distance,
        seconds,
        trace_rows,
        check,
    }))
}

fn create(p: &Path) -> Result<BufWriter<File>, Error> {
    let f = File::create(p).map_err(|e| Error(format!("creating {}: {e}", p.display())))?;
    Ok(BufWriter::new(f))
}

/// The interpreter's error, already rendered like `check` renders it.
fn interp_failed(error: &Mutex<Option<String>>) -> Option<String> {
    error.lock().unwrap_or_else(|e| e.into_inner()).take()
}

/// Refuse outputs that would be larger than `max_output_mb`, from the planned motion.
fn check_output_size(req: &PlanRequest, e: &Estimate) -> Result<(), Error> {
    let limit = req.max_output_mb.saturating_mul(1_000_000);
    let mb = |b: f64| b / 1e6;
    if let Some(p) = &req.outputs.trace {
        let rows = (e.seconds / (req.period_ms / 1000.0)).floor() + 1.0;
        let bytes = rows * TraceWriter::<File>::ROW_BYTES as f64;
        if bytes > limit as f64 {
            return Err(Error(format!(
                "--trace {}: {:.0} rows every {} ms of {} of machine time make about {:.0} MB,                  more than --max-output-mb {} (raise it, or sample less often with --period-ms)",
                p.display(),
                rows,
                req.period_ms,
                format_hms(e.seconds, 0),
                mb(bytes),
                req.max_output_mb
            )));
        }
    }
    let out = &req.outputs;
    if let Some(p) = out.steps.as_ref().or(out.steps_compressed.as_ref()) {
        // A compressed run holds at least one step: its file is never larger than the CSV.
        let bytes = e.steps * StepOutput::ROW_BYTES as f64;
        if bytes > limit as f64 {
            return Err(Error(format!(
                "{}: about {:.0} motor steps make up to {:.0} MB, more than --max-output-mb {} \
                 (raise it)",
                p.display(),
                e.steps,
                mb(bytes),
                req.max_output_mb
            )));
        }
    }
    Ok(())
}

/// The step outputs' files.
type StepOutput = StepFiles<BufWriter<File>>;

/// The step outputs asked for, created with their headers.
fn step_files(
    out: &PlanOutputs,
    names: [&'static str; MOTORS],
) -> Result<Option<StepOutput>, Error> {
    if out.steps.is_none() && out.steps_compressed.is_none() {
        return Ok(None);
    }
    let csv = out.steps.as_deref().map(create).transpose()?;
    let runs = out.steps_compressed.as_deref().map(create).transpose()?;
    Ok(Some(
        StepFiles::new(names, csv, runs).map_err(|e| Error::chain(&e))?,
    ))
}

/// The program stepped by seed 002's interpolators, no planner.
fn run_dda(req: &PlanRequest, ops: CanonStream) -> Result<PlanOutcome, Error> {
    if req.outputs.trace.is_some() || req.scurve {
        return Err(Error("--interpolator dda makes steps only: --trace and --scurve belong to the planned motion (drop them or use --interpolator exact)".into()));
    }
    let profile = &req.profile;
    let interp_error = ops.error.clone();
    let mut files = step_files(&req.outputs, motor_names(profile))?;
    let summary = match files.as_mut() {
        Some(f) => dda_steps(ops, profile, f),
        None => dda_steps(ops, profile, &mut StepCount::default()),
    }
    .map_err(|e| Error(format!("{}: --interpolator dda: {e}", req.name)))?;
    if let Some(e) = interp_failed(&interp_error) {
        return Ok(PlanOutcome::InterpreterFailed(e));
    }
    if let Some(f) = files {
        f.finish().map_err(|e| Error::chain(&e))?;
    }
    Ok(PlanOutcome::Stepped(summary))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn request(text: &str) -> PlanRequest {
        let profile = crate::profile::resolve("grbl-router").unwrap();
        PlanRequest {
            name: "t.ngc".into(),
            text: Arc::new(text.into()),
            interp: crate::run_options_for(&profile, oficina_gcode::Dialect::LinuxCnc, 1 << 16),
            profile,
            period_ms: 1.0,
            scurve: false,
            interpolator: Interpolator::Exact,
            check: true,
            max_output_mb: 2048,
            outputs: PlanOutputs::default(),
        }
    }

    #[test]
    fn a_line_at_600_mm_per_min_takes_its_length_over_the_feed_and_passes_the_checker() {
        // Incremental, so nothing but the 50 mm line is planned.
        let req = request("G21 G91\nG1 X50 F600\nM2\n");
        let PlanOutcome::Planned(s) = plan_program(&req).unwrap() else {
            panic!("not planned")
        };
        assert!((s.distance - 50.0).abs() < 1e-9, "{}", s.distance);
        // 5 s at the feed; acceleration only adds to it.
        assert!(s.seconds > 5.0 && s.seconds < 6.0, "{}", s.seconds);
        assert!(matches!(s.check, Some(Ok(_))), "{:?}", s.check);
        assert_eq!((s.steps, s.trace_rows), (None, None));
    }

    #[test]
    fn an_interpreter_error_comes_back_rendered_with_its_line() {
        let req = request("G21\nG1 X10 Qbad F100\nM2\n");
        match plan_program(&req).unwrap() {
            PlanOutcome::InterpreterFailed(e) => assert!(e.contains("t.ngc:2"), "{e}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn outputs_larger_than_the_limit_are_refused_before_any_file_is_made() {
        let dir = std::env::temp_dir().join(format!("oficina-app-plan-{}", std::process::id()));
        let trace = dir.join("never.csv");
        let mut req = request("G21\nG1 X500 F60\nM2\n");
        req.max_output_mb = 0;
        req.outputs.trace = Some(trace.clone());
        let e = plan_program(&req).unwrap_err().to_string();
        assert!(
            e.starts_with("--trace") && e.contains("--max-output-mb 0"),
            "{e}"
        );
        assert!(!trace.exists());
        req.interpolator = Interpolator::Dda;
        let e = plan_program(&req).unwrap_err().to_string();
        assert!(e.contains("--interpolator dda makes steps only"), "{e}");
    }
}
