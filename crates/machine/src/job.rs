//! A job: G-code text plus how to run it. The interpreter runs in its own thread and hands
//! canon ops over a bounded channel, so memory stays flat however long the program is.

#[cfg(feature = "virtual")]
use oficina_canon::{Canon, CanonOp, Pos};
#[cfg(feature = "virtual")]
use oficina_gcode::RunOptions;
#[cfg(feature = "virtual")]
use oficina_gcode::Severity;
use std::sync::Arc;
#[cfg(feature = "virtual")]
use std::sync::Mutex;

/// How fast the virtual machine runs relative to the clock.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Pace {
    /// Wall time = machine time / factor (1.0 = real time).
    Speed(f64),
    /// No waiting at all.
    Instant,
}

/// A G-code program to run, with how fast to feed it.
#[derive(Clone, Debug)]
pub struct Job {
    /// A name for reports (usually the file name).
    pub name: String,
    /// The program text.
    pub text: Arc<String>,
    /// Resume from this source line: earlier motion is skipped and the machine goes to the
    /// point where that line starts, at a safe height, with rapids.
    pub start_line: Option<u32>,
    /// How machine time relates to wall-clock time.
    pub pace: Pace,
}

#[cfg(feature = "virtual")]
/// Canon ops of a job, in a bounded stream; the first interpreter error ends the stream and
/// is left in `error`.
pub struct CanonStream {
    inner: oficina_gcode::CanonStream,
    name: String,
    text: Arc<String>,
    /// The interpreter error that ended the stream, if any.
    pub error: Arc<Mutex<Option<String>>>,
}

#[cfg(feature = "virtual")]
impl Iterator for CanonStream {
    type Item = Canon;
    fn next(&mut self) -> Option<Canon> {
        let next = self.inner.next();
        if next.is_none() {
            let diags = self.inner.diagnostics();
            if let Some(d) = diags.iter().find(|d| d.severity == Severity::Error) {
                let line = self
                    .text
                    .lines()
                    .nth(d.span.line.saturating_sub(1) as usize);
                *self.error.lock().unwrap_or_else(|e| e.into_inner()) =
                    Some(d.render(&self.name, line));
            }
        }
        next
    }
}

/// Refuse a resume line the program does not have (lines count from 1; a last line without a
/// newline counts).
pub fn check_start_line(text: &str, line: u32) -> Result<(), String> {
    let lines = text.lines().count();
    if line == 0 {
        return Err("--from-line 0: lines are counted from 1".into());
    }
    if line as usize > lines {
        return Err(format!(
            "--from-line {line}: the program has {lines} line{}",
            if lines == 1 { "" } else { "s" }
        ));
    }
    Ok(())
}

#[cfg(feature = "virtual")]
/// `initial_params`: what the machine holds before the program (e.g. its stored G54 offset,
/// [`oficina_motion::Profile::initial_params`]).
pub fn canon_stream(job: &Job, initial_params: Vec<(i64, f64)>) -> CanonStream {
    canon_stream_with(
        job,
        RunOptions {
            initial_params,
            ..RunOptions::default()
        },
    )
}

#[cfg(feature = "virtual")]
/// [`canon_stream`] with every interpreter option (dialect, start feed, …).
pub fn canon_stream_with(job: &Job, opts: RunOptions) -> CanonStream {
    let source = std::io::Cursor::new(ArcText(job.text.clone()));
    CanonStream {
        inner: oficina_gcode::CanonStream::spawn(source, opts),
        name: job.name.clone(),
        text: job.text.clone(),
        error: Arc::new(Mutex::new(None)),
    }
}

#[cfg(feature = "virtual")]
/// The job's text, shared with the interpreter thread without a copy.
struct ArcText(Arc<String>);

#[cfg(feature = "virtual")]
impl AsRef<[u8]> for ArcText {
    fn as_ref(&self) -> &[u8] {
        self.0.as_bytes()
    }
}

#[cfg(feature = "virtual")]
/// Skips the motion before `line` and replaces it by rapids: up to a safe height, across,
/// down to the point where `line` starts. State ops (feed, modes, offsets, the tool in the
/// spindle) still pass; what waits for or talks to the operator before `line` (M0/M1 pauses,
/// `(MSG,…)` prompts, dwells) is dropped: those steps were done in the run being resumed.
pub struct ResumeFrom<I> {
    ops: I,
    line: u32,
    start: [f64; 3],
    pos: Option<Pos>,
    queue: Vec<Canon>,
    resumed: bool,
}

#[cfg(feature = "virtual")]
impl<I: Iterator<Item = Canon>> ResumeFrom<I> {
    /// Skips `ops` up to source line `line`, coming from the machine position `start` (mm).
    pub fn new(ops: I, line: u32, start: [f64; 3]) -> Self {
        ResumeFrom {
            ops,
            line,
            start,
            pos: None,
            queue: Vec::new(),
            resumed: false,
        }
    }
}

#[cfg(feature = "virtual")]
impl<I: Iterator<Item = Canon>> Iterator for ResumeFrom<I> {
    type Item = Canon;
    fn next(&mut self) -> Option<Canon> {
        if let Some(c) = self.queue.pop() {
            return Some(c);
        }
        loop {
            let c = self.ops.next()?;
            if !self.resumed && c.line < self.line && is_operator_step(&c.op) {
                continue;
            }
            if self.resumed || c.line < self.line && !c.op.is_motion() {
                return Some(c);
            }
            if c.line < self.line {
                self.pos = Some(match c.op {
                    CanonOp::StraightTraverse { to } | CanonOp::StraightFeed { to } => to,
                    CanonOp::ArcFeed { end, .. } => end,
                    _ => continue,
                });
                continue;
            }
            self.resumed = true;
            let Some(p) = self.pos else { return Some(c) };
            let z = p.z.max(self.start[2]);
            let l = c.line;
            // Pushed in reverse: popped up, across, down, then the op itself.
            self.queue.push(c);
            self.queue.push(Canon {
                line: l,
                op: CanonOp::StraightTraverse { to: p },
            });
            self.queue.push(Canon {
                line: l,
                op: CanonOp::StraightTraverse { to: Pos { z, ..p } },
            });
            let up = Pos::xyz(self.start[0], self.start[1], z);
            return Some(Canon {
                line: l,
                op: CanonOp::StraightTraverse { to: up },
            });
        }
    }
}

#[cfg(feature = "virtual")]
/// Operations that only wait for the operator or tell them something: nothing of the machine's
/// state changes with them.
fn is_operator_step(op: &CanonOp) -> bool {
    matches!(
        op,
        CanonOp::ProgramStop
            | CanonOp::OptionalProgramStop
            | CanonOp::Message(_)
            | CanonOp::Dwell(_)
    )
}
