//! [`MarlinDevice`]: Marlin firmware behind Oficina's [`Machine`] trait. A job runs on a
//! worker thread that owns the link; operator commands reach it over a channel, progress
//! comes back as the trait's events (the line, the position and the time left from the
//! program's motion model, as acknowledged lines come in).

use super::program::{marlin_program, model};
use super::resume::plan_resume;
use super::sender::{MarlinControl, MarlinEnd, MarlinLink, MarlinNotice, MarlinOptions};
use crate::eta;
use crate::interp::Interp;
use crate::journal::Journal;
use crate::transport::Endpoint;
use crate::worker::{lock, Worker};
use oficina_machine::{
    Command, Event, Job, JobReport, Machine, MachineError, MachineInfo, RawReply, ResumePoint,
    State, Status,
};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Marlin 2.x's default `BAUDRATE` (Configuration.h), used when the URI names none.
pub(crate) const MARLIN_BAUD: u32 = 250_000;

/// The link address in a Marlin machine URI: `marlin:/dev/ttyUSB0[@baud]` (250000 baud
/// unless given) or `marlin+tcp://HOST:PORT` (a network serial bridge, ESP3D).
pub fn marlin_endpoint(uri: &str) -> Result<Endpoint, String> {
    if let Some(rest) = uri.strip_prefix("marlin+") {
        return match rest.parse()? {
            e @ Endpoint::Tcp { .. } => Ok(e),
            _ => Err(format!("{uri}: marlin+ is for marlin+tcp://HOST:PORT")),
        };
    }
    let Some(path) = uri.strip_prefix("marlin:") else {
        return Err(format!(
            "{uri}: a Marlin machine is marlin:/dev/ttyUSB0[@baud] or marlin+tcp://HOST:PORT"
        ));
    };
    if path.starts_with("tcp://") || path.starts_with("telnet://") {
        return path.parse();
    }
    let with_baud = if path.contains('@') {
        path.to_string()
    } else {
        format!("{path}@{MARLIN_BAUD}")
    };
    with_baud.parse()
}

/// A Marlin board as an [`oficina_machine::Machine`].
pub struct MarlinDevice {
    /// Where the board is.
    pub endpoint: Endpoint,
    /// How the link waits.
    pub options: MarlinOptions,
    /// The journal; default: the job's name with `.journal` appended.
    pub journal: Option<PathBuf>,
    /// Start the next job where its journal says the last run stopped.
    pub resume: bool,
    /// The operator held the job: no new line goes out (shown as [`State::Hold`]).
    held: Arc<AtomicBool>,
    /// The link while no job runs, the job's thread, its events and report.
    jobs: Worker<MarlinLink, MarlinControl>,
}

impl MarlinDevice {
    /// `uri`: see [`marlin_endpoint`]. Nothing is opened until [`Machine::connect`].
    pub fn new(uri: &str) -> Result<MarlinDevice, String> {
        Ok(MarlinDevice {
            endpoint: marlin_endpoint(uri)?,
            options: MarlinOptions::default(),
            journal: None,
            resume: false,
            held: Arc::new(AtomicBool::new(false)),
            jobs: Worker::new(),
        })
    }
}

impl Machine for MarlinDevice {
    fn connect(&mut self) -> Result<MachineInfo, MachineError> {
        let mut link = MarlinLink::connect(&self.endpoint, self.options.clone())
            .map_err(|e| MachineError::Refused(format!("cannot talk to Marlin: {e}")))?;
        if let Ok(p) = link.position() {
            *lock(&self.jobs.status) = Status::idle(p);
        }
        let info = MachineInfo {
            name: format!("Marlin at {}", self.endpoint),
            firmware: link.firmware.clone(),
        };
        *lock(&self.jobs.idle) = Some(link);
        Ok(info)
    }

    fn start(&mut self, job: Job) -> Result<(), MachineError> {
        let program = marlin_program(&job.name, &job.text).map_err(MachineError::Refused)?;
        let journal_path = self
            .journal
            .clone()
            .unwrap_or_else(|| format!("{}.journal", job.name).into());
        let (mut link, ctl_rx) = self.jobs.take_link("a job is running")?;
        let mut from = match job.start_line {
            Some(n) => program
                .index_of_file_line(n as usize)
                .unwrap_or(program.len()),
            None => 0,
        };
        if self.resume {
            let resumed = Journal::load(&journal_path, &program).and_then(|state| {
                let at = link.position()?;
                let plan = plan_resume(&program, &state, at);
                for cmd in &plan.preamble {
                    link.command(cmd)?;
                }
                Ok(plan)
            });
            match resumed {
                Ok(plan) => {
                    let _ = self.jobs.events_tx.send(Event::Message(format!(
                        "resuming at file line {}: {}",
                        program.lines.get(plan.index).map_or(0, |l| l.file_line),
                        plan.reason
                    )));
                    from = plan.index;
                }
                Err(e) => {
                    *lock(&self.jobs.idle) = Some(link);
                    return Err(MachineError::Refused(format!("cannot resume: {e}")));
                }
            }
        }
        let mut journal = Journal::open(&journal_path, &program).map_err(|e| {
            MachineError::Refused(format!(
                "{}: cannot write the journal: {e}",
                journal_path.display()
            ))
        })?;
        // Marlin's feeds govern (G0 moves at the modal feed too): no axis cap in the model.
        let motion = model(&program);
        let no_caps: BTreeMap<u16, f64> = [(110, 1e9), (111, 1e9), (112, 1e9)].into();
        let cumulative = eta::cumulative_seconds(&motion, &no_caps);
        *lock(&self.jobs.report) = None;
        self.held.store(false, Ordering::Relaxed);
        let held = self.held.clone();
        let (idle, status, events, report) = (
            self.jobs.idle.clone(),
            self.jobs.status.clone(),
            self.jobs.events_tx.clone(),
            self.jobs.report.clone(),
        );
        {
            let mut s = lock(&status);
            s.state = State::Run;
            s.total = cumulative.last().copied().unwrap_or(0.0);
            s.elapsed = 0.0;
        }
        self.jobs.thread = Some(std::thread::spawn(move || {
            let start = Instant::now();
            // The motion model follows the acknowledged lines: the position shown.
            let mut tracked = crate::resume::replay(&motion, from);
            let mut tracked_to = from;
            let mut observer = |n: MarlinNotice| match n {
                MarlinNotice::Progress { acked, .. } => {
                    while tracked_to < acked {
                        let _ = tracked.execute(&motion.lines[tracked_to].text);
                        tracked_to += 1;
                    }
                    let s = {
                        let mut s = lock(&status);
                        s.state = if held.load(Ordering::Relaxed) {
                            State::Hold
                        } else {
                            State::Run
                        };
                        s.line = motion.lines[acked - 1].file_line as u32;
                        s.machine_pos = tracked.pos;
                        s.work_pos = work(&tracked);
                        s.feed = tracked.feed;
                        s.elapsed = start.elapsed().as_secs_f64();
                        s.total = s.elapsed + eta::remaining(&cumulative, from, acked, s.elapsed);
                        s.clone()
                    };
                    let _ = events.send(Event::Status(s));
                }
                MarlinNotice::Pause { file_line, text } => {
                    let s = {
                        let mut s = lock(&status);
                        s.state = State::Paused;
                        s.line = file_line as u32;
                        s.clone()
                    };
                    let _ = events.send(Event::Status(s));
                    let _ = events.send(Event::Message(format!(
                        "Marlin waits for you at file line {file_line}: {text}"
                    )));
                }
                MarlinNotice::Resent { .. } => {}
                MarlinNotice::Message(m) => {
                    let _ = events.send(Event::Message(m));
                }
            };
            let r = link.stream(
                &program,
                from,
                Some(&mut journal),
                Some(&ctl_rx),
                &mut observer,
            );
            let seconds = start.elapsed().as_secs_f64();
            let next_line = program.lines.get(r.acked).map(|l| l.file_line as u32);
            let summary = format!(
                "{}: {} of {} lines acknowledged, {} resent on request, {} after silence; {:?}",
                program.name,
                r.acked,
                program.len(),
                r.resends,
                r.timeouts,
                r.end
            );
            let completed = r.end == MarlinEnd::Completed;
            *lock(&report) = Some(JobReport {
                summary: summary.clone(),
                completed,
                resume: next_line
                    .filter(|_| !completed)
                    .map(|file_line| ResumePoint {
                        file_line,
                        within_line: false,
                    }),
                link_lost: matches!(r.end, MarlinEnd::LinkLost(_)),
            });
            {
                let mut s = lock(&status);
                if let Some(p) = r.position {
                    s.machine_pos = p;
                    s.work_pos = p;
                }
                s.state = match &r.end {
                    MarlinEnd::Completed | MarlinEnd::Stopped => State::Idle,
                    other => State::Alarm(format!("{other:?}")),
                };
                s.elapsed = seconds;
                let _ = events.send(Event::Status(s.clone()));
            }
            match &r.end {
                MarlinEnd::Completed => {}
                MarlinEnd::Stopped => {
                    let _ = events.send(Event::Message(summary));
                }
                _ => {
                    let _ = events.send(Event::Alarm(summary));
                }
            }
            *lock(&idle) = Some(link);
            let _ = events.send(Event::JobEnd { completed, seconds });
        }));
        Ok(())
    }

    fn command(&mut self, cmd: Command) -> Result<(), MachineError> {
        match cmd {
            Command::Hold | Command::Resume => {
                let hold = cmd == Command::Hold;
                self.jobs.send(if hold {
                    MarlinControl::Hold
                } else {
                    MarlinControl::Resume
                })?;
                self.held.store(hold, Ordering::Relaxed);
                let mut s = lock(&self.jobs.status);
                s.state = if hold { State::Hold } else { State::Run };
                Ok(())
            }
            Command::Stop => self.jobs.send(MarlinControl::Stop),
            other => Err(MachineError::Refused(format!(
                "{other:?}: not over Marlin's serial link (hold, resume and stop are)"
            ))),
        }
    }

    fn next_event(&mut self, timeout: Duration) -> Option<Event> {
        self.jobs.events_rx.recv_timeout(timeout).ok()
    }

    fn status(&self) -> Status {
        lock(&self.jobs.status).clone()
    }

    fn disconnect(&mut self) {
        self.jobs.close(MarlinControl::Stop);
    }

    fn raw_line(&mut self, line: &str) -> Result<RawReply, MachineError> {
        let mut guard = lock(&self.jobs.idle);
        let link = guard.as_mut().ok_or_else(|| {
            // (The lock is held: ask the worker directly.)
            if self.jobs.alive() {
                MachineError::Busy("a job is running".into())
            } else {
                MachineError::NotConnected
            }
        })?;
        Ok(match link.command(line) {
            Ok(lines) => RawReply { lines, error: None },
            Err(e) => RawReply {
                lines: Vec::new(),
                error: Some(e),
            },
        })
    }

    /// `M112`: Marlin halts at once and must be reset (there is no soft reset).
    fn soft_reset(&mut self) -> Result<(), MachineError> {
        if self.jobs.job_running() {
            return self.jobs.send(MarlinControl::Kill);
        }
        self.raw_line("M112").map(|_| ())
    }

    fn job_report(&mut self) -> Option<JobReport> {
        lock(&self.jobs.report).clone()
    }

    fn as_any_mut(&mut self) -> Option<&mut dyn std::any::Any> {
        Some(self)
    }
}

/// The work position of the model: machine minus the G92 offset (Marlin has no G5x here).
fn work(i: &Interp) -> [f64; 3] {
    let w = i.wco();
    [i.pos[0] - w[0], i.pos[1] - w[1], i.pos[2] - w[2]]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uris() {
        assert_eq!(
            marlin_endpoint("marlin:/dev/ttyUSB0").unwrap(),
            Endpoint::Serial {
                path: "/dev/ttyUSB0".into(),
                baud: 250_000
            }
        );
        assert_eq!(
            marlin_endpoint("marlin:/dev/ttyACM0@115200").unwrap(),
            Endpoint::Serial {
                path: "/dev/ttyACM0".into(),
                baud: 115_200
            }
        );
        assert_eq!(
            marlin_endpoint("marlin+tcp://10.0.0.7:8888").unwrap(),
            Endpoint::Tcp {
                addr: "10.0.0.7:8888".into()
            }
        );
        assert!(marlin_endpoint("marlin+/dev/x").is_err());
        assert!(marlin_endpoint("grbl:/dev/x").is_err());
    }
}
