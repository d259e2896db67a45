//! A session with one machine: the job it runs, real-time commands, jog, and a snapshot that
//! a page (or a terminal) shows (typed lines, home, reset and work offsets: `controls`). Events are drained by the caller; the
//! machine runs its job on its own thread, so whoever watches may come and go.

use crate::offsets::WorkOffsets;
use crate::{machine_uri, profile, Error};
use oficina_gcode::ToolTable;
use oficina_machine::{Command, Event, Job, Machine, MachineInfo, Pace, State};
use oficina_motion::Profile;
use serde::Serialize;
use std::sync::Arc;
use std::time::Duration;

mod probing;
pub use probing::{Probing, ProbingResult};

/// A job to start: the program, where to begin and how fast the virtual machine runs.
pub struct JobRequest {
    /// The program's name.
    pub name: String,
    /// The program.
    pub text: Arc<String>,
    /// Resume from this source line.
    pub from_line: Option<u32>,
    /// Wall time = machine time / speed on the virtual machine; `None`: no waiting at all.
    pub speed: Option<f64>,
}

#[derive(Clone, Debug, PartialEq, Serialize)]
#[serde(tag = "type", rename_all = "snake_case")]
/// What happened on the machine, for the page.
pub enum SessionEvent {
    /// A message from the machine or the program.
    Message {
        /// Its text.
        text: String,
    },
    /// An alarm.
    Alarm {
        /// The machine's words.
        message: String,
        /// What it means.
        meaning: String,
    },
    /// The job ended.
    JobEnd {
        /// True when it ran to its end.
        completed: bool,
        /// Machine time, s.
        seconds: f64,
    },
}

/// The job as the page shows it.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct JobView {
    pub name: String,
    pub lines: usize,
    pub from_line: Option<u32>,
    pub speed: Option<f64>,
    /// Set once the job has ended: true when it ran to its end.
    pub completed: Option<bool>,
}

/// A tool change the job waits for (grbl has no tool changer): what to put in, and Resume.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToolChangeView {
    /// The tool to put in.
    pub tool: u32,
    /// The source line of the `M6`.
    pub line: u32,
    /// What the operator is asked.
    pub prompt: String,
}

/// The machine and its job as the page shows them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Snapshot {
    /// The machine's URI.
    pub uri: String,
    /// The machine's name.
    pub machine: String,
    /// Its firmware.
    pub firmware: String,
    /// idle, run, holding, hold, paused, jog, home or alarm.
    pub state: &'static str,
    /// The alarm, when in alarm.
    pub alarm: Option<String>,
    /// What the alarm means.
    pub alarm_meaning: Option<String>,
    /// Machine position, mm.
    pub machine_pos: [f64; 3],
    /// Work position, mm.
    pub work_pos: [f64; 3],
    /// mm/min
    pub feed: f64,
    /// Source line running.
    pub line: u32,
    /// Machine time done and planned, seconds.
    pub elapsed: f64,
    /// Machine time planned, seconds.
    pub total: f64,
    /// Wall time left at the job's speed, seconds (`None` when not known).
    pub remaining: Option<f64>,
    /// Feed override factor.
    pub feed_override: f64,
    /// The job, when there is one.
    pub job: Option<JobView>,
    /// True on the virtual machine (no firmware `$` commands; its profile can change, its
    /// job speed factor applies).
    pub is_virtual: bool,
    /// The work offsets as last known (read again after every change).
    pub offsets: WorkOffsets,
    /// The tool change the job waits for (state `paused`), if any.
    pub tool_change: Option<ToolChangeView>,
}

/// A machine opened from a URI and the job it runs, driven by the page.
pub struct Session {
    uri: String,
    pub(crate) machine: Box<dyn Machine>,
    info: MachineInfo,
    /// The virtual machine's profile (none for real firmware).
    profile: Option<Profile>,
    /// Where the virtual machine homes to: the profile's start.
    pub(crate) home: [f64; 3],
    pub(crate) job: Option<JobView>,
    /// The virtual machine's tool table (G43 H, G41 D, M6).
    tools: ToolTable,
    /// The last tool change asked for ([`Event::ToolChange`]); shown while paused.
    tool_change: Option<ToolChangeView>,
    /// The last alarm the machine named with its number (`ALARM:5 …`): grbl's status says
    /// only `Alarm`, so the snapshot shows this while the machine stays in alarm.
    last_alarm: Option<String>,
    /// Work offsets: the virtual machine's own (G54 is its profile's), or the firmware's
    /// as its last `$#` and `$G` replies said.
    pub(crate) offsets: WorkOffsets,
}

/// Feed overrides outside this range are refused (the virtual machine's and grbl's range).
const FEED_OVERRIDE: std::ops::RangeInclusive<f64> = 0.1..=2.0;

impl Session {
    /// Connect to the machine `uri` names (see [`machine_uri::open_machine`]).
    pub fn open(uri: &str) -> Result<Session, Error> {
        Session::open_with(uri, oficina_grbl::ToolChange::default())
    }

    /// [`Session::open`], real firmware handling `M6` as `tool_change` says (the virtual
    /// machine changes tools itself).
    pub fn open_with(uri: &str, tool_change: oficina_grbl::ToolChange) -> Result<Session, Error> {
        let profile = if machine_uri::is_firmware(uri) {
            None
        } else {
            Some(profile::resolve(machine_uri::virtual_name(uri))?)
        };
        let mut machine = if machine_uri::is_firmware(uri) {
            machine_uri::open_firmware(uri, tool_change)?
        } else {
            machine_uri::open_machine(uri, None)?
        };
        let info = machine.connect().map_err(Error::from_display)?;
        let home = profile.as_ref().map_or([0.0; 3], |p| p.start);
        let mut offsets = WorkOffsets::default();
        if let Some(p) = &profile {
            offsets.systems[0] = p.work_offset;
            offsets.known = true;
        }
        let mut session = Session {
            uri: uri.to_string(),
            machine,
            info,
            profile,
            home,
            job: None,
            tools: ToolTable::default(),
            last_alarm: None,
            tool_change: None,
            offsets,
        };
        if session.profile.is_none() {
            // The firmware's table from the start (a board in alarm still lists it).
            let _ = session.read_offsets();
        }
        Ok(session)
    }

    /// Gives the virtual machine a tool table (idle only; it stays where it is). Real
    /// firmware keeps its own tool data: refused.
    pub fn set_tools(&mut self, tools: ToolTable) -> Result<(), Error> {
        if self.tools == tools {
            return Ok(());
        }
        let Some(mut profile) = self.profile.clone() else {
            return Err(Error(
                "real firmware has no tool table (grbl ignores G43 H)".into(),
            ));
        };
        let status = self.machine.status();
        if status.state != State::Idle {
            return Err(Error(format!(
                "the tool table changes when idle, not while {}",
                state_name(&status.state)
            )));
        }
        profile.start = status.machine_pos;
        self.tools = tools;
        self.rebuild(profile)
    }

    /// A new virtual machine on `profile` (its start = where the old one stood), with the
    /// session's tool table and work offsets (G54 is the profile's; G55…G59 go to every job
    /// as the parameters #5241… that LinuxCNC keeps them in).
    pub(crate) fn rebuild(&mut self, profile: Profile) -> Result<(), Error> {
        let params = (1..6)
            .flat_map(|s| (0..3).map(move |i| (s, i)))
            .map(|(s, i)| (5221 + 20 * s as i64 + i as i64, self.offsets.systems[s][i]))
            .collect();
        let vm = oficina_machine::VirtualMachine::new(profile.clone())
            .with_tool_table(self.tools.clone())
            .with_initial_params(params);
        let mut machine: Box<dyn Machine> = Box::new(vm);
        self.info = machine.connect().map_err(Error::from_display)?;
        self.machine.disconnect();
        self.machine = machine;
        self.offsets.systems[0] = profile.work_offset;
        self.profile = Some(profile);
        Ok(())
    }

    /// The virtual machine's profile (none for real firmware).
    pub fn profile(&self) -> Option<&Profile> {
        self.profile.as_ref()
    }

    /// Start the job `req` asks for. Real firmware runs at its own pace: the speed factor
    /// is the virtual machine's only, so a firmware job's times are wall times.
    pub fn start(&mut self, mut req: JobRequest) -> Result<(), Error> {
        if self.profile.is_none() {
            req.speed = Some(1.0);
        }
        if let Some(s) = req.speed {
            if !(s.is_finite() && s > 0.0 && s <= 1e6) {
                return Err(Error(format!(
                    "speed {s}: the factor must be > 0 and at most 1e6"
                )));
            }
        }
        if req.from_line == Some(0) {
            return Err(Error("resume from line 0: lines count from 1".into()));
        }
        let lines = req.text.lines().count();
        if let Some(l) = req.from_line {
            if l as usize > lines {
                return Err(Error(format!(
                    "resume from line {l}: the program has {lines} lines"
                )));
            }
        }
        self.machine
            .start(Job {
                name: req.name.clone(),
                text: req.text.clone(),
                start_line: req.from_line,
                pace: req.speed.map_or(Pace::Instant, Pace::Speed),
            })
            .map_err(Error::from_display)?;
        self.job = Some(JobView {
            name: req.name,
            lines,
            from_line: req.from_line,
            speed: req.speed,
            completed: None,
        });
        Ok(())
    }

    /// Hold, resume, stop, unlock or a feed override.
    pub fn command(&mut self, cmd: Command) -> Result<(), Error> {
        match cmd {
            Command::FeedOverride(f) if !FEED_OVERRIDE.contains(&f) => Err(Error(format!(
                "feed override {f}: between {} and {}",
                FEED_OVERRIDE.start(),
                FEED_OVERRIDE.end()
            ))),
            Command::Jog { delta, feed } => self.jog(delta, feed),
            Command::SpindleOverride(f) if !FEED_OVERRIDE.contains(&f) => Err(Error(format!(
                "spindle override {f}: between {} and {}",
                FEED_OVERRIDE.start(),
                FEED_OVERRIDE.end()
            ))),
            cmd => self.machine.command(cmd).map_err(Error::from_display),
        }
    }

    /// Move by `delta` mm at `feed` mm/min (idle only; the machine checks its soft limits).
    pub fn jog(&mut self, delta: [f64; 3], feed: f64) -> Result<(), Error> {
        if !delta.iter().all(|d| d.is_finite() && d.abs() <= 10_000.0) {
            return Err(Error(format!("jog {delta:?}: each step within ±10000 mm")));
        }
        if !(feed.is_finite() && feed > 0.0 && feed <= 100_000.0) {
            return Err(Error(format!(
                "jog feed {feed}: > 0 and at most 100000 mm/min"
            )));
        }
        self.machine
            .command(Command::Jog { delta, feed })
            .map_err(Error::from_display)
    }

    /// Every event waiting now (waits up to `timeout` for the first).
    pub fn poll(&mut self, timeout: Duration) -> Vec<SessionEvent> {
        let mut out = Vec::new();
        let mut wait = timeout;
        while let Some(e) = self.machine.next_event(wait) {
            wait = Duration::ZERO;
            match e {
                Event::Message(text) => out.push(SessionEvent::Message { text }),
                Event::Status(st) if !matches!(st.state, State::Alarm(_)) => {
                    self.last_alarm = None;
                }
                Event::Status(_) => {}
                Event::Alarm(message) => {
                    if message.contains("ALARM:") {
                        self.last_alarm = Some(message.clone());
                    }
                    out.push(SessionEvent::Alarm {
                        meaning: alarm_meaning(&message),
                        message,
                    })
                }
                // The page gets the prompt as a message, and the snapshot's `tool_change`.
                Event::ToolChange { tool, line, prompt } => {
                    out.push(SessionEvent::Message {
                        text: prompt.clone(),
                    });
                    self.tool_change = Some(ToolChangeView { tool, line, prompt });
                }
                Event::JobEnd { completed, seconds } => {
                    self.tool_change = None;
                    // Only a job the session started ends as a job: a jog or a homing move
                    // of the virtual machine runs as a small job of its own, and is no news.
                    if let Some(j) = self.job.as_mut().filter(|j| j.completed.is_none()) {
                        j.completed = Some(completed);
                        // Firmware links say how the lines went (Marlin: acknowledged,
                        // resent); the console shows it as `oficina run` prints it.
                        if let Some(r) = self.machine.job_report().filter(|_| completed) {
                            out.push(SessionEvent::Message { text: r.summary });
                        }
                        out.push(SessionEvent::JobEnd { completed, seconds });
                    }
                }
            }
        }
        out
    }

    /// The machine's state now, as the page shows it.
    pub fn snapshot(&self) -> Snapshot {
        let mut s = self.machine.status();
        let running = self.job.as_ref().is_some_and(|j| j.completed.is_none());
        // Between jobs the virtual machine's work position is the session's active system
        // (its status still shows the last job's).
        if self.profile.is_some() && !running {
            s.work_pos = self.offsets.work_position(s.machine_pos);
        }
        let alarm = match (&s.state, &self.last_alarm) {
            (State::Alarm(a), Some(named)) if !a.contains("ALARM:") => {
                Some(format!("{named} ({a})"))
            }
            (State::Alarm(a), _) => Some(a.clone()),
            _ => None,
        };
        let remaining = match self.job.as_ref().and_then(|j| j.speed) {
            Some(speed) if running && s.total > 0.0 => Some((s.total - s.elapsed).max(0.0) / speed),
            _ => None,
        };
        Snapshot {
            uri: self.uri.clone(),
            machine: self.info.name.clone(),
            firmware: self.info.firmware.clone(),
            state: state_name(&s.state),
            alarm_meaning: alarm.as_deref().map(alarm_meaning),
            alarm,
            machine_pos: s.machine_pos,
            work_pos: s.work_pos,
            feed: s.feed,
            line: s.line,
            elapsed: s.elapsed,
            total: s.total,
            remaining,
            feed_override: s.feed_override,
            job: self.job.clone(),
            is_virtual: self.profile.is_some(),
            offsets: self.offsets.clone(),
            tool_change: self
                .tool_change
                .clone()
                .filter(|_| s.state == State::Paused),
        }
    }
}

impl Drop for Session {
    fn drop(&mut self) {
        self.machine.disconnect();
    }
}

pub(crate) fn state_name(s: &State) -> &'static str {
    match s {
        State::Idle => "idle",
        State::Run => "run",
        State::Holding => "holding",
        State::Hold => "hold",
        State::Paused => "paused",
        State::Jog => "jog",
        State::Home => "home",
        State::Alarm(_) => "alarm",
    }
}

/// What an alarm means and what to do: grbl's own table for `ALARM:N`, else the virtual
/// machine's message (it names the line and the limit) with the way out.
pub fn alarm_meaning(message: &str) -> String {
    if let Some(code) = message
        .split("ALARM:")
        .nth(1)
        .and_then(|r| r.split(|c: char| !c.is_ascii_digit()).next())
        .and_then(|n| n.parse::<u8>().ok())
    {
        return format!(
            "{}. Unlock, then re-home or check the machine before running again.",
            oficina_grbl::describe_alarm(code)
        );
    }
    if message.contains("limit") {
        return "The program goes outside the machine's travel (soft limits, checked before any motion). Nothing moved: fix the work zero or the program, then unlock.".into();
    }
    "The job could not run; nothing after the reported point moved. Read the message, fix the program or the machine setting it names, then unlock.".into()
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Instant;

    fn wait_end(s: &mut Session) -> Vec<SessionEvent> {
        let t = Instant::now();
        let mut all = Vec::new();
        while t.elapsed() < Duration::from_secs(60) {
            let ev = s.poll(Duration::from_millis(20));
            let end = ev.iter().any(|e| matches!(e, SessionEvent::JobEnd { .. }));
            all.extend(ev);
            if end {
                return all;
            }
        }
        panic!("the job did not end: {all:?}");
    }

    fn job(text: &str) -> JobRequest {
        JobRequest {
            name: "t.nc".into(),
            text: Arc::new(text.into()),
            from_line: None,
            speed: None,
        }
    }

    #[test]
    fn a_job_runs_to_its_end_and_the_snapshot_says_so() {
        let mut s = Session::open("virtual").unwrap();
        s.start(job("G90 G0 X0 Y0 Z0\nG1 X10 F600\n(MSG,hello)\nM2\n"))
            .unwrap();
        let ev = wait_end(&mut s);
        assert!(ev.contains(&SessionEvent::Message {
            text: "hello".into()
        }));
        assert!(matches!(
            ev.last(),
            Some(SessionEvent::JobEnd {
                completed: true,
                ..
            })
        ));
        let snap = s.snapshot();
        assert_eq!(snap.state, "idle");
        assert_eq!(snap.job.unwrap().completed, Some(true));
        assert!(
            (snap.work_pos[0] - 10.0).abs() < 1e-6,
            "{:?}",
            snap.work_pos
        );
    }

    #[test]
    fn bad_requests_are_refused_with_their_reason() {
        let mut s = Session::open("virtual").unwrap();
        let mut j = job("G0 X1\n");
        j.from_line = Some(5);
        assert!(s.start(j).unwrap_err().0.contains("1 lines"));
        let mut j = job("G0 X1\n");
        j.speed = Some(f64::NAN);
        assert!(s.start(j).is_err());
        assert!(s.command(Command::FeedOverride(7.0)).is_err());
        assert!(s.jog([f64::INFINITY, 0.0, 0.0], 100.0).is_err());
        assert!(s.jog([1.0, 0.0, 0.0], -5.0).is_err());
    }

    #[test]
    fn zero_sets_work_coordinates_and_home_returns() {
        let mut s = Session::open("virtual").unwrap();
        let home = s.snapshot().machine_pos;
        s.start(job("G90 G0 X5 Y5 Z0\nM2\n")).unwrap();
        wait_end(&mut s);
        s.zero([true, true, true]).unwrap();
        let snap = s.snapshot();
        assert_eq!(snap.work_pos, [0.0; 3], "{snap:?}");
        s.home().unwrap();
        let t = Instant::now();
        let mut news = Vec::new();
        let back = loop {
            news.extend(s.poll(Duration::from_millis(20)));
            let snap = s.snapshot();
            let there = (0..3).all(|i| (snap.machine_pos[i] - home[i]).abs() < 1e-6);
            if there && snap.state == "idle" {
                break snap.machine_pos;
            }
            assert!(t.elapsed() < Duration::from_secs(60), "not home: {snap:?}");
        };
        for i in 0..3 {
            assert!((back[i] - home[i]).abs() < 1e-6, "{back:?} vs {home:?}");
        }
        // The homing move is not a job: nothing ended.
        news.extend(s.poll(Duration::from_millis(200)));
        assert!(
            !news
                .iter()
                .any(|e| matches!(e, SessionEvent::JobEnd { .. })),
            "{news:?}"
        );
        assert_eq!(s.snapshot().job.unwrap().completed, Some(true));
    }

    #[test]
    fn alarms_are_explained() {
        assert!(alarm_meaning("ALARM:2").contains("ALARM:2 ("));
        assert!(alarm_meaning("soft limit on X at line 3").contains("travel"));
    }
}
