//! [`GrblDevice`]: grbl-family firmware behind Oficina's [`oficina_machine::Machine`] trait,
//! so `oficina run FILE --machine grbl:/dev/ttyUSB0` drives a real board exactly as it drives
//! the virtual machine. A job runs on a worker thread that owns the link; operator commands
//! reach it over a channel and its progress comes back as the trait's events.

use crate::eta;
use crate::job::StreamProgram;
use crate::machine::{GrblMachine, RunOutcome, RunSettings, Start};
use crate::messages;
use crate::realtime::Realtime;
use crate::sender::{Control, Mode, Notice, SenderOptions, StreamEnd};
use crate::status::{GrblState, StatusReport};
use crate::transport::Endpoint;
use crate::worker::{lock, Worker};
use oficina_machine::{
    Command, Event, Job, JobReport, Machine, MachineError, MachineInfo, RawReply, ResumePoint,
    State, Status,
};
use std::time::{Duration, Instant};

mod routine;
pub use routine::Routine;

/// A grbl board as an [`oficina_machine::Machine`]: jobs run on a thread of their own.
pub struct GrblDevice {
    /// Where the board is.
    pub endpoint: Endpoint,
    /// How jobs are run (resume approach, reconnect policy, journal).
    pub settings: RunSettings,
    /// How the link streams (character counting or send-response).
    pub options: SenderOptions,
    /// The link while no job runs, the job's thread, its events and report.
    jobs: Worker<GrblMachine, Control>,
    /// When the idle firmware was last asked for its status ([`Machine::next_event`]).
    last_idle_poll: Option<Instant>,
}

/// An idle board is asked for its status at most this often. Without a limit an idle
/// board always has a fresh status, and a caller draining events until none is left (the
/// server's pump) would never stop.
const IDLE_POLL_PERIOD: Duration = Duration::from_millis(50);

impl GrblDevice {
    /// `uri`: `grbl:/dev/ttyUSB0`, `/dev/ttyACM0@250000`, `tcp://192.168.1.5:23`. Nothing is
    /// opened until [`Machine::connect`].
    pub fn new(uri: &str) -> Result<GrblDevice, String> {
        Ok(GrblDevice::at(uri.parse()?, SenderOptions::default()))
    }

    /// A device at `endpoint` whose link streams with `options`; nothing is opened until
    /// [`Machine::connect`].
    pub fn at(endpoint: Endpoint, options: SenderOptions) -> GrblDevice {
        GrblDevice {
            endpoint,
            settings: RunSettings::default(),
            options,
            jobs: Worker::new(),
            last_idle_poll: None,
        }
    }

    /// How the connected link streams, `None` before [`Machine::connect`] and while a job
    /// holds the link.
    pub fn link_mode(&self) -> Option<Mode> {
        lock(&self.jobs.idle).as_ref().map(|m| m.sender.mode)
    }

    /// Hands the idle link over to a caller that talks to the firmware itself (a raw
    /// terminal); the device is then disconnected.
    pub fn take_link(&mut self) -> Option<GrblMachine> {
        lock(&self.jobs.idle).take()
    }

    /// One of grbl's real-time keys the trait's [`Command`]s do not name (rapid overrides,
    /// spindle stop, coolant toggles, override steps): to the running job, or straight to
    /// the idle firmware.
    pub fn realtime(&mut self, key: Realtime) -> Result<(), MachineError> {
        if self.job_running() {
            let control = self
                .jobs
                .control
                .as_ref()
                .ok_or(MachineError::NotConnected)?;
            return control
                .send(Control::Realtime(key))
                .map_err(|_| MachineError::NotConnected);
        }
        self.with_idle(|m| m.sender.realtime(key).map_err(|e| e.to_string()))
    }

    /// Starts streaming a program already made into grbl lines (a levelled program, whose
    /// lines keep their source line numbers), from the first line at or after
    /// `start_line` when given; progress arrives as the trait's events, as for
    /// [`Machine::start`].
    pub fn start_program(
        &mut self,
        grbl_job: StreamProgram,
        start_line: Option<u32>,
    ) -> Result<(), MachineError> {
        let (mut machine, ctl_rx) = self.jobs.take_link("a job is running")?;
        let cumulative = eta::cumulative_seconds(&grbl_job, &machine.sender.settings);
        let mut settings = self.settings.clone();
        settings.start = match start_line {
            Some(n) => Start::FileLine(n as usize),
            None => settings.start,
        };
        let journal = settings
            .journal
            .clone()
            .unwrap_or_else(|| format!("{}.journal", grbl_job.name).into());
        *lock(&self.jobs.report) = None;
        let (idle, status, events, last_report) = (
            self.jobs.idle.clone(),
            self.jobs.status.clone(),
            self.jobs.events_tx.clone(),
            self.jobs.report.clone(),
        );
        self.jobs.thread = Some(std::thread::spawn(move || {
            let start = Instant::now();
            let mut wco = vec![0.0; 3];
            // (first acknowledged line of this run, last acknowledged line)
            let mut lines: Option<(usize, usize)> = None;
            // The line the machine was last seen on: what the page shows and the time left
            // counts from (acknowledged lines may be a whole buffer ahead).
            let mut running: Option<usize> = None;
            // Waiting for a tool change: the machine idles, the job is paused.
            let mut tool_wait = false;
            let mut observer = |n: Notice| match n {
                Notice::Status(st) => {
                    if let Some(w) = &st.wco {
                        wco = w.clone();
                    }
                    let mut s = lock(&status);
                    translate_status(&st, &wco, &mut s);
                    if tool_wait && s.state == State::Idle {
                        s.state = State::Paused;
                    }
                    s.elapsed = start.elapsed().as_secs_f64();
                    // Elapsed plus grbl's timing model for the rest, at the pace seen so far.
                    if let Some((first, acked)) = lines {
                        let done = running.map_or(acked, |r| r.min(acked));
                        s.total = s.elapsed + eta::remaining(&cumulative, first, done, s.elapsed);
                    }
                    let _ = events.send(Event::Status(s.clone()));
                }
                Notice::Progress { acked, .. } => {
                    let first = lines.map(|l| l.0).unwrap_or(acked.saturating_sub(1));
                    lines = Some((first, acked));
                    // Until the machine is seen on the path, the last acknowledged line.
                    if running.is_none() {
                        if let Some(l) = grbl_job.lines.get(acked.saturating_sub(1)) {
                            lock(&status).line = l.file_line as u32;
                        }
                    }
                }
                Notice::Running { index } => {
                    running = Some(index);
                    if let Some(l) = grbl_job.lines.get(index) {
                        lock(&status).line = l.file_line as u32;
                    }
                }
                Notice::Message(m) => {
                    let _ = events.send(Event::Message(m));
                }
                Notice::Unexpected(u) => {
                    let _ = events.send(Event::Message(format!(
                        "ignored unexpected firmware line: {u:?}"
                    )));
                }
                Notice::ToolChange {
                    tool,
                    file_line,
                    prompt,
                } => {
                    tool_wait = true;
                    let line = file_line as u32;
                    // The event is queued under the status lock, before the pause: whoever
                    // sees the pause finds its reason queued (not an M0), and whoever gets
                    // the event and asks finds the machine paused.
                    let s = {
                        let mut s = lock(&status);
                        let _ = events.send(Event::ToolChange { tool, line, prompt });
                        s.state = State::Paused;
                        s.line = line;
                        s.clone()
                    };
                    let _ = events.send(Event::Status(s));
                }
                Notice::ToolChangeDone { tool } => {
                    tool_wait = false;
                    // The change is over: no longer paused, though the firmware may say
                    // nothing until the sender asks again (a remeasure's touches).
                    let s = {
                        let mut s = lock(&status);
                        s.state = State::Run;
                        s.clone()
                    };
                    let _ = events.send(Event::Status(s));
                    let _ = events.send(Event::Message(format!("tool T{tool} in place: going on")));
                }
            };
            let result = machine.run(&grbl_job, &journal, &settings, Some(&ctl_rx), &mut observer);
            let seconds = start.elapsed().as_secs_f64();
            // The report is in place before its summary goes out as a message or an alarm.
            *lock(&last_report) = match &result {
                Ok(outcome) => Some(job_report(outcome, &grbl_job)),
                Err(_) => None,
            };
            let end = match result {
                Ok(RunOutcome::AlreadyDone) => Event::JobEnd {
                    completed: true,
                    seconds,
                },
                Ok(RunOutcome::Streamed(report)) => {
                    let text = report.describe(&grbl_job);
                    match report.end {
                        StreamEnd::Completed => Event::JobEnd {
                            completed: true,
                            seconds,
                        },
                        StreamEnd::Stopped => {
                            let _ = events.send(Event::Message(text));
                            Event::JobEnd {
                                completed: false,
                                seconds,
                            }
                        }
                        _ => {
                            let _ = events.send(Event::Alarm(text));
                            Event::JobEnd {
                                completed: false,
                                seconds,
                            }
                        }
                    }
                }
                // Every job ends with a JobEnd, an error too (after its alarm): a waiting
                // shell (`oficina run`, the server) learns the job is over.
                Err(e) => {
                    let _ = events.send(Event::Alarm(e));
                    Event::JobEnd {
                        completed: false,
                        seconds,
                    }
                }
            };
            // Where the job left the machine, before saying it ended.
            if let Ok(st) = machine.sender.status() {
                let mut s = lock(&status);
                translate_status(&st, &wco, &mut s);
                s.elapsed = seconds;
                let _ = events.send(Event::Status(s.clone()));
            }
            // The link goes back before the end is announced, so a start right after the
            // event finds it.
            *lock(&idle) = Some(machine);
            let _ = events.send(end);
        }));
        Ok(())
    }

    /// A job holds the link: the worker took it and has not given it back.
    fn job_running(&self) -> bool {
        self.jobs.job_running()
    }

    /// Runs `f` on the idle link, or says why it cannot.
    fn with_idle<R>(
        &self,
        f: impl FnOnce(&mut GrblMachine) -> Result<R, String>,
    ) -> Result<R, MachineError> {
        let mut guard = lock(&self.jobs.idle);
        match guard.as_mut() {
            Some(m) => f(m).map_err(MachineError::Refused),
            // (The lock is held: ask the worker directly rather than through job_running.)
            None if self.jobs.alive() => Err(MachineError::Busy("a job is running".into())),
            None => Err(MachineError::NotConnected),
        }
    }
}

/// grbl's status in the trait's terms. `wco` is the last work offset grbl reported.
pub(crate) fn translate_status(st: &StatusReport, wco: &[f64], into: &mut Status) {
    into.state = match &st.state {
        GrblState::Idle | GrblState::Check | GrblState::Sleep => State::Idle,
        GrblState::Run => State::Run,
        GrblState::Home => State::Home,
        GrblState::Hold(0) | GrblState::Door(0) | GrblState::Door(1) => State::Hold,
        GrblState::Hold(_) | GrblState::Door(_) => State::Holding,
        GrblState::Jog => State::Jog,
        GrblState::Alarm => State::Alarm("grbl is in alarm: home ($H) or unlock ($X)".into()),
        GrblState::Other(s) => State::Alarm(format!("unknown grbl state {s}")),
    };
    let pick = |v: Option<Vec<f64>>| v.filter(|v| v.len() >= 3).map(|v| [v[0], v[1], v[2]]);
    let machine = st.machine_position(Some(wco));
    // grblHAL prints as many axes as it drives (N_AXIS): a 4th is A, in degrees.
    if let Some(a) = machine.as_ref().and_then(|v| v.get(3)) {
        into.rotary_pos[0] = *a;
    }
    if let Some(m) = pick(machine) {
        into.machine_pos = m;
    }
    if let Some(w) = pick(st.work_position(Some(wco))) {
        into.work_pos = w;
    }
    if let Some(f) = st.feed {
        into.feed = f;
    }
    if let Some((feed, _, _)) = st.overrides {
        into.feed_override = feed as f64 / 100.0;
    }
}

/// A finished run in the trait's terms: its summary and where to continue.
fn job_report(outcome: &RunOutcome, job: &StreamProgram) -> JobReport {
    let report = match outcome {
        RunOutcome::AlreadyDone => {
            return JobReport {
                summary: format!(
                    "{}: nothing left to run: the job already completed",
                    job.name
                ),
                completed: true,
                resume: None,
                link_lost: false,
            }
        }
        RunOutcome::Streamed(r) => r,
    };
    let resume = report.resume.as_ref().and_then(|r| {
        // At a tool stop the M6 line itself: a resume there asks for the tool again.
        let stop = job.tool_stop_at(r.index).map(|s| s.file_line);
        let line = stop.or_else(|| job.lines.get(r.index).map(|l| l.file_line));
        line.map(|file_line| ResumePoint {
            file_line: file_line as u32,
            within_line: r.entry.is_some(),
        })
    });
    JobReport {
        summary: report.describe(job),
        completed: report.end == StreamEnd::Completed,
        link_lost: report.resume.is_none() && matches!(report.end, StreamEnd::Disconnected(_)),
        resume,
    }
}

/// The real-time bytes that take grbl's feed override from 100 % to `factor` (10–200 %,
/// in grbl's 10 % and 1 % steps).
pub(crate) fn feed_override_bytes(factor: f64) -> Result<Vec<Realtime>, String> {
    override_bytes(
        "feed",
        factor,
        [
            Realtime::FeedOverrideReset,
            Realtime::FeedOverridePlus10,
            Realtime::FeedOverrideMinus10,
            Realtime::FeedOverridePlus1,
            Realtime::FeedOverrideMinus1,
        ],
    )
}

/// The real-time bytes (0x99 reset, then 0x9A/0x9B ±10 %, 0x9C/0x9D ±1 %) that take grbl's
/// spindle override from 100 % to `factor` (10–200 %).
pub(crate) fn spindle_override_bytes(factor: f64) -> Result<Vec<Realtime>, String> {
    override_bytes(
        "spindle",
        factor,
        [
            Realtime::SpindleOverrideReset,
            Realtime::SpindleOverridePlus10,
            Realtime::SpindleOverrideMinus10,
            Realtime::SpindleOverridePlus1,
            Realtime::SpindleOverrideMinus1,
        ],
    )
}

/// Reset to 100 %, then tens and ones towards the target: `[reset, +10, -10, +1, -1]`.
fn override_bytes(what: &str, factor: f64, keys: [Realtime; 5]) -> Result<Vec<Realtime>, String> {
    if !(0.1..=2.0).contains(&factor) {
        return Err(format!(
            "{what} override {factor} is outside grbl's 0.1 … 2.0"
        ));
    }
    let [reset, plus10, minus10, plus1, minus1] = keys;
    let target = (factor * 100.0).round() as i32;
    let mut out = vec![reset];
    let diff = target - 100;
    let (tens, ones) = (diff / 10, diff % 10);
    let (ten, one) = if diff >= 0 {
        (plus10, plus1)
    } else {
        (minus10, minus1)
    };
    out.extend(std::iter::repeat_n(ten, tens.unsigned_abs() as usize));
    out.extend(std::iter::repeat_n(one, ones.unsigned_abs() as usize));
    Ok(out)
}

impl Machine for GrblDevice {
    fn connect(&mut self) -> Result<MachineInfo, MachineError> {
        if self.job_running() {
            return Err(MachineError::Busy("a job is running".into()));
        }
        let m = GrblMachine::connect_to(self.endpoint.clone(), self.options.clone())
            .map_err(MachineError::Refused)?;
        let info = MachineInfo {
            name: format!("grbl at {}", self.endpoint),
            firmware: format!("grbl {}", m.sender.firmware),
        };
        *lock(&self.jobs.idle) = Some(m);
        Ok(info)
    }

    fn start(&mut self, job: Job) -> Result<(), MachineError> {
        let grbl_job =
            StreamProgram::with_tool_change(&job.name, &job.text, &self.settings.tool_change)
                .map_err(MachineError::Refused)?;
        self.start_program(grbl_job, job.start_line)
    }

    fn command(&mut self, cmd: Command) -> Result<(), MachineError> {
        if self.job_running() {
            let control = self
                .jobs
                .control
                .as_ref()
                .ok_or(MachineError::NotConnected)?;
            let send = |c: Control| control.send(c).map_err(|_| MachineError::NotConnected);
            return match cmd {
                Command::Hold => send(Control::Hold),
                Command::Resume => send(Control::Resume),
                Command::Stop => send(Control::Stop),
                Command::FeedOverride(f) => {
                    for r in feed_override_bytes(f).map_err(MachineError::Refused)? {
                        send(Control::Realtime(r))?;
                    }
                    Ok(())
                }
                Command::Jog { .. } => {
                    Err(MachineError::Busy("jogging needs an idle machine".into()))
                }
                // A program moves, not a jog: nothing to cancel.
                Command::JogCancel => Ok(()),
                Command::SpindleOverride(f) => {
                    for r in spindle_override_bytes(f).map_err(MachineError::Refused)? {
                        send(Control::Realtime(r))?;
                    }
                    Ok(())
                }
                Command::Unlock => Err(MachineError::Busy("a job is running".into())),
            };
        }
        self.with_idle(|m| {
            let s = &mut m.sender;
            let io = |e: std::io::Error| e.to_string();
            match cmd {
                Command::Hold => s.realtime(Realtime::FeedHold).map_err(io),
                Command::Resume => s.realtime(Realtime::CycleStart).map_err(io),
                Command::Stop => s.realtime(Realtime::FeedHold).map_err(io),
                Command::FeedOverride(f) => {
                    for r in feed_override_bytes(f)? {
                        s.realtime(r).map_err(io)?;
                    }
                    Ok(())
                }
                Command::Jog { delta, feed } => {
                    let line = format!(
                        "$J=G91G21X{:.4}Y{:.4}Z{:.4}F{feed:.1}",
                        delta[0], delta[1], delta[2]
                    );
                    match s.command(&line).map_err(io)?.error {
                        Some(code) => {
                            Err(format!("jog refused: {}", messages::describe_error(code)))
                        }
                        None => Ok(()),
                    }
                }
                // 0x85: grbl drops the jog motion planned and decelerates to a stop.
                Command::JogCancel => s.realtime(Realtime::JogCancel).map_err(io),
                Command::SpindleOverride(f) => {
                    for r in spindle_override_bytes(f)? {
                        s.realtime(r).map_err(io)?;
                    }
                    Ok(())
                }
                Command::Unlock => match s.command("$X").map_err(io)?.error {
                    Some(code) => Err(format!(
                        "unlock refused: {}",
                        messages::describe_error(code)
                    )),
                    None => Ok(()),
                },
            }
        })
    }

    fn next_event(&mut self, timeout: Duration) -> Option<Event> {
        match self.jobs.events_rx.recv_timeout(timeout) {
            Ok(e) => Some(e),
            Err(_) => {
                // Idle: poll the firmware so status keeps flowing between jobs.
                if self.job_running() {
                    return None;
                }
                if self
                    .last_idle_poll
                    .is_some_and(|t| t.elapsed() < IDLE_POLL_PERIOD)
                {
                    return None;
                }
                self.last_idle_poll = Some(Instant::now());
                let mut guard = lock(&self.jobs.idle);
                let m = guard.as_mut()?;
                let st = m.sender.status().ok()?;
                let mut s = lock(&self.jobs.status);
                // grbl sends `WCO:` only every so many reports: the last one it sent holds.
                let wco = st
                    .wco
                    .clone()
                    .or(m.sender.last_wco.clone())
                    .unwrap_or_default();
                translate_status(&st, if wco.len() >= 3 { &wco } else { &[0.0; 3] }, &mut s);
                Some(Event::Status(s.clone()))
            }
        }
    }

    fn status(&self) -> Status {
        lock(&self.jobs.status).clone()
    }

    fn raw_line(&mut self, line: &str) -> Result<RawReply, MachineError> {
        self.with_idle(|m| {
            let reply = m.sender.command(line).map_err(|e| e.to_string())?;
            Ok(RawReply {
                lines: reply.lines,
                error: reply.error.map(messages::describe_error),
            })
        })
    }

    fn soft_reset(&mut self) -> Result<(), MachineError> {
        // A running job hears it through its stream (which then reports the restart).
        self.realtime(Realtime::SoftReset)
    }

    fn firmware_settings(&mut self) -> Result<Vec<(u16, f64)>, MachineError> {
        self.with_idle(|m| {
            let all = crate::settings::read(&mut m.sender)?;
            Ok(all.into_iter().map(|s| (s.number, s.value)).collect())
        })
    }

    fn write_firmware_setting(&mut self, number: u16, value: f64) -> Result<(), MachineError> {
        self.with_idle(|m| crate::settings::write(&mut m.sender, number, value).map(|_| ()))
    }

    fn job_report(&mut self) -> Option<JobReport> {
        // (Cleared when a job starts, set just before its summary goes out.)
        lock(&self.jobs.report).clone()
    }

    fn as_any_mut(&mut self) -> Option<&mut dyn std::any::Any> {
        Some(self)
    }

    fn disconnect(&mut self) {
        self.jobs.close(Control::Stop);
    }
}

impl Drop for GrblDevice {
    fn drop(&mut self) {
        self.disconnect();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn feed_override_steps() {
        use Realtime::*;
        assert_eq!(feed_override_bytes(1.0).unwrap(), vec![FeedOverrideReset]);
        assert_eq!(
            feed_override_bytes(1.23).unwrap(),
            vec![
                FeedOverrideReset,
                FeedOverridePlus10,
                FeedOverridePlus10,
                FeedOverridePlus1,
                FeedOverridePlus1,
                FeedOverridePlus1
            ]
        );
        assert_eq!(
            feed_override_bytes(0.8).unwrap(),
            vec![FeedOverrideReset, FeedOverrideMinus10, FeedOverrideMinus10]
        );
        assert!(feed_override_bytes(3.0).is_err());
    }
}

#[cfg(test)]
mod override_tests {
    use super::*;

    fn bytes(v: Vec<Realtime>) -> Vec<u8> {
        v.into_iter().map(Realtime::byte).collect()
    }

    #[test]
    fn spindle_override_is_reset_then_tens_then_ones_in_grbls_bytes() {
        // grbl 1.1 doc: 0x99 reset to 100 %, 0x9A +10 %, 0x9B -10 %, 0x9C +1 %, 0x9D -1 %.
        assert_eq!(
            bytes(spindle_override_bytes(1.23).unwrap()),
            [0x99, 0x9A, 0x9A, 0x9C, 0x9C, 0x9C]
        );
        assert_eq!(
            bytes(spindle_override_bytes(0.78).unwrap()),
            [0x99, 0x9B, 0x9B, 0x9D, 0x9D]
        );
        assert_eq!(bytes(spindle_override_bytes(1.0).unwrap()), [0x99]);
        assert!(spindle_override_bytes(2.5).is_err());
        assert!(spindle_override_bytes(f64::NAN).is_err());
        // The feed override keeps its own bytes.
        assert_eq!(bytes(feed_override_bytes(1.1).unwrap()), [0x90, 0x91]);
        assert_eq!(Realtime::JogCancel.byte(), 0x85);
    }
}
