//! The built-in virtual machine: executes planned motion against a clock (real time, scaled
//! or instant), with feed hold that decelerates on the planned path, resume, stop, jog and
//! soft limits checked on the whole job before any motion.

use crate::job::{canon_stream_with, check_start_line, Job, Pace, ResumeFrom};
use crate::{Command, Event, Machine, MachineError, MachineInfo, State, Status};
use oficina_canon::{Canon, CanonOp};
use oficina_gcode::ToolTable;
use oficina_motion::Cut;
use oficina_motion::Overrides;
use oficina_motion::VelocityProfile;
use oficina_motion::{estimate_with, plan, PlanOptions, Profile, Segment, SegmentKind};
use std::sync::mpsc::{channel, Receiver, RecvTimeoutError, Sender};
use std::sync::{Arc, Mutex};
use std::thread;
use std::time::{Duration, Instant};

/// Machine-time step of the execution loop.
const TICK: f64 = 0.005;

/// The built-in simulated machine: runs jobs through the planner in (scaled) real time.
pub struct VirtualMachine {
    profile: Arc<Profile>,
    status: Arc<Mutex<Status>>,
    cmd_tx: Option<Sender<Command>>,
    ev_rx: Option<Receiver<Event>>,
    ev_tx: Sender<Event>,
    ev_rx_own: Option<Receiver<Event>>,
    connected: bool,
    /// Longest program line accepted, bytes (0: the interpreter's default).
    max_line_len: usize,
    /// Tool table for G43 and M6 (empty: every tool has no offset).
    tools: ToolTable,
    /// Parameters every job starts with besides the profile's (e.g. G55…G59 offsets).
    params: Vec<(i64, f64)>,
    /// The motion running is a jog (what `JogCancel` may stop).
    jogging: bool,
    /// The spindle override asked for; the virtual machine has no spindle to slow, so it
    /// is only kept and confirmed.
    spindle_override: f64,
}

impl VirtualMachine {
    /// A virtual machine with `profile`'s axes and limits, not yet connected.
    pub fn new(profile: Profile) -> VirtualMachine {
        let (ev_tx, ev_rx) = channel();
        let status = Status::idle(profile.start);
        VirtualMachine {
            profile: Arc::new(profile),
            status: Arc::new(Mutex::new(status)),
            cmd_tx: None,
            ev_rx: None,
            ev_tx,
            ev_rx_own: Some(ev_rx),
            connected: false,
            max_line_len: 0,
            tools: ToolTable::default(),
            params: Vec::new(),
            jogging: false,
            spindle_override: 1.0,
        }
    }

    /// Run programs with this tool table: G43's tool length offsets reach the motion.
    pub fn with_tool_table(mut self, tools: ToolTable) -> VirtualMachine {
        self.tools = tools;
        self
    }

    /// Every job starts with these parameters too, after the profile's (LinuxCNC numbering,
    /// machine mm): the G55…G59 offsets in #5241…, say, kept by whoever drives the machine.
    pub fn with_initial_params(mut self, params: Vec<(i64, f64)>) -> VirtualMachine {
        self.params = params;
        self
    }

    /// Accept program lines up to `bytes` long (the interpreter's own default otherwise).
    pub fn with_max_line_len(mut self, bytes: usize) -> VirtualMachine {
        self.max_line_len = bytes;
        self
    }
}

fn lock(s: &Mutex<Status>) -> std::sync::MutexGuard<'_, Status> {
    s.lock().unwrap_or_else(|e| e.into_inner())
}

impl Machine for VirtualMachine {
    fn connect(&mut self) -> Result<MachineInfo, MachineError> {
        self.connected = true;
        if self.ev_rx.is_none() {
            self.ev_rx = self.ev_rx_own.take();
        }
        Ok(MachineInfo {
            name: self.profile.name.clone(),
            firmware: "oficina virtual machine".into(),
        })
    }

    fn start(&mut self, job: Job) -> Result<(), MachineError> {
        if !self.connected {
            return Err(MachineError::NotConnected);
        }
        let state = lock(&self.status).state.clone();
        match state {
            State::Idle => {}
            State::Alarm(a) => {
                return Err(MachineError::Refused(format!(
                    "in alarm: {a}; unlock first"
                )))
            }
            s => return Err(MachineError::Busy(format!("{s:?}"))),
        }
        if let Some(line) = job.start_line {
            check_start_line(&job.text, line).map_err(MachineError::Refused)?;
        }
        self.jogging = false;
        let (tx, rx) = channel();
        self.cmd_tx = Some(tx);
        let (profile, status, events, max_line_len, tools, params) = (
            self.profile.clone(),
            self.status.clone(),
            self.ev_tx.clone(),
            self.max_line_len,
            self.tools.clone(),
            self.params.clone(),
        );
        lock(&status).state = State::Run;
        thread::spawn(move || {
            Runner {
                profile,
                status,
                events,
                cmds: rx,
                override_: 1.0,
                max_line_len,
                tools,
                params,
            }
            .run_job(job)
        });
        Ok(())
    }

    fn command(&mut self, cmd: Command) -> Result<(), MachineError> {
        let state = lock(&self.status).state.clone();
        match (&cmd, &state) {
            (Command::Unlock, State::Alarm(_)) => {
                lock(&self.status).state = State::Idle;
                Ok(())
            }
            (Command::Jog { delta, feed }, State::Idle) => {
                let pos = lock(&self.status).machine_pos;
                let to = [pos[0] + delta[0], pos[1] + delta[1], pos[2] + delta[2]];
                // G53: the target is in machine coordinates, whatever work offset is stored.
                let text = format!(
                    "G90 G53 G1 X{:.6} Y{:.6} Z{:.6} F{:.3}\nM2\n",
                    to[0], to[1], to[2], feed
                );
                self.start(Job {
                    name: "jog".into(),
                    text: Arc::new(text),
                    start_line: None,
                    pace: Pace::Speed(1.0),
                })?;
                self.jogging = true;
                Ok(())
            }
            (Command::Jog { .. }, s) => Err(MachineError::Busy(format!("cannot jog while {s:?}"))),
            (Command::JogCancel, State::Run | State::Holding) if self.jogging => {
                match &self.cmd_tx {
                    Some(tx) => tx
                        .send(Command::Stop)
                        .map_err(|_| MachineError::NotConnected),
                    None => Ok(()),
                }
            }
            (Command::JogCancel, _) => Ok(()),
            (Command::SpindleOverride(f), _) => {
                if !(0.1..=2.0).contains(f) {
                    return Err(MachineError::Refused(format!(
                        "spindle override {f} is outside 0.1 … 2.0"
                    )));
                }
                self.spindle_override = *f;
                let _ = self.ev_tx.send(Event::Message(format!(
                    "spindle override {:.0} % (the virtual machine has no spindle to slow)",
                    f * 100.0
                )));
                Ok(())
            }
            _ => match &self.cmd_tx {
                Some(tx) if tx.send(cmd.clone()).is_ok() => Ok(()),
                _ => Err(MachineError::Refused(format!("{cmd:?}: no job is running"))),
            },
        }
    }

    fn next_event(&mut self, timeout: Duration) -> Option<Event> {
        match self.ev_rx.as_ref()?.recv_timeout(timeout) {
            Ok(e) => Some(e),
            Err(RecvTimeoutError::Timeout) | Err(RecvTimeoutError::Disconnected) => None,
        }
    }

    fn status(&self) -> Status {
        lock(&self.status).clone()
    }

    fn disconnect(&mut self) {
        if let Some(tx) = &self.cmd_tx {
            let _ = tx.send(Command::Stop);
        }
        self.connected = false;
    }
}

/// The job thread.
struct Runner {
    profile: Arc<Profile>,
    status: Arc<Mutex<Status>>,
    events: Sender<Event>,
    cmds: Receiver<Command>,
    override_: f64,
    max_line_len: usize,
    tools: ToolTable,
    params: Vec<(i64, f64)>,
}

/// Live commands waiting for the instant they can be applied, and the hold in progress.
#[derive(Default)]
struct Live {
    feed: Option<f64>,
    hold_asked: bool,
    /// Braking towards the planner's Hold segment.
    holding: bool,
    /// The job ends at that Hold segment instead of waiting for resume.
    stop: bool,
}

/// The clock of one job: machine time executed, wall time spent waiting in holds.
struct Run {
    clock: Instant,
    elapsed: f64,
    wall_paused: Duration,
    live: Live,
}

impl Runner {
    fn ops(
        &self,
        job: &Job,
        start: [f64; 3],
    ) -> (Box<dyn Iterator<Item = Canon>>, Arc<Mutex<Option<String>>>) {
        let opts = oficina_gcode::RunOptions {
            initial_params: [self.profile.initial_params(), self.params.clone()].concat(),
            max_line_len: self.max_line_len,
            tool_table: self.tools.clone(),
            ..Default::default()
        };
        let s = canon_stream_with(job, opts);
        let err = s.error.clone();
        let it: Box<dyn Iterator<Item = Canon>> = match job.start_line {
            Some(l) => Box::new(ResumeFrom::new(s, l, start)),
            None => Box::new(s),
        };
        (it, err)
    }

    fn alarm(&self, msg: String) {
        lock(&self.status).state = State::Alarm(msg.clone());
        let _ = self.events.send(Event::Alarm(msg));
        let _ = self.events.send(Event::JobEnd {
            completed: false,
            seconds: 0.0,
        });
    }

    fn run_job(mut self, job: Job) {
        let start = lock(&self.status).machine_pos;
        let mut profile = (*self.profile).clone();
        profile.start = start;
        // First pass: the whole job is planned (soft limits, reachability, interpreter
        // errors) and timed before anything moves.
        let (ops, err) = self.ops(&job, start);
        let opts = PlanOptions {
            overrides: Overrides {
                feed: self.override_,
                rapid: 1.0,
            },
            shape: None,
        };
        let total = match estimate_with(ops, &profile, opts, false) {
            Ok(e) => e.seconds,
            Err(e) => return self.alarm(format!("{}: {e}; nothing was moved", job.name)),
        };
        if let Some(e) = err.lock().unwrap_or_else(|e| e.into_inner()).take() {
            // The interpreter's diagnostic is rendered over several lines: said first.
            return self.alarm(format!("nothing was moved: {}", e.trim_end()));
        }
        lock(&self.status).total = total;
        let (ops, _) = self.ops(&job, start);
        let offsets = Arc::new(Mutex::new(([0.0; 3], [0.0; 3])));
        let off = offsets.clone();
        let messages = self.events.clone();
        let ops = ops.inspect(move |c| {
            let mut o = off.lock().unwrap_or_else(|e| e.into_inner());
            match c.op {
                CanonOp::SetG5xOffset { offset, .. } => o.0 = [offset.x, offset.y, offset.z],
                CanonOp::SetG92Offset(p) => o.1 = [p.x, p.y, p.z],
                CanonOp::Message(ref m) => {
                    let _ = messages.send(Event::Message(m.clone()));
                }
                _ => {}
            }
        });
        let mut planner = match plan(ops, &profile, opts) {
            Ok(p) => p,
            Err(e) => return self.alarm(e.to_string()),
        };
        let mut run = Run {
            clock: Instant::now(),
            elapsed: 0.0,
            wall_paused: Duration::ZERO,
            live: Live::default(),
        };
        let completed = loop {
            let seg = match planner.next() {
                None => break true,
                Some(Err(e)) => {
                    self.alarm(e.to_string());
                    break false;
                }
                Some(Ok(s)) => s,
            };
            let buffered = planner.buffered();
            match self.execute(&seg, &mut run, &job, buffered, &offsets, profile.shape) {
                Ok(cut) => {
                    // A command waiting for a safe instant: re-plan the rest from here.
                    if let Some(f) = run.live.feed.take() {
                        if run.live.holding {
                            run.live.feed = Some(f);
                        } else {
                            planner.set_feed_override(f, cut);
                        }
                    }
                    if run.live.hold_asked && !run.live.holding {
                        run.live.hold_asked = false;
                        run.live.holding = true;
                        planner.hold(cut);
                    }
                }
                Err(stopped) => break !stopped,
            }
        };
        let mut st = lock(&self.status);
        if !matches!(st.state, State::Alarm(_)) {
            st.state = State::Idle;
        }
        st.feed = 0.0;
        drop(st);
        let _ = self.events.send(Event::JobEnd {
            completed,
            seconds: run.elapsed,
        });
    }

    /// Runs one segment, or the part of it before a live command can be applied (then the
    /// cut is returned so the planner re-plans the rest). `Err(true)` when the operator
    /// stopped the job.
    fn execute(
        &mut self,
        seg: &Segment,
        run: &mut Run,
        job: &Job,
        buffered: usize,
        offsets: &Arc<Mutex<([f64; 3], [f64; 3])>>,
        shape: VelocityProfile,
    ) -> Result<Option<Cut>, bool> {
        match seg.kind {
            SegmentKind::Pause => {
                lock(&self.status).state = State::Paused;
                let _ = self.events.send(Event::Message(format!(
                    "line {}: program pause (M0/M1); resume to go on",
                    seg.line
                )));
                if self.wait_resume(run) {
                    return Err(true);
                }
                lock(&self.status).state = State::Run;
                return Ok(None);
            }
            SegmentKind::Hold => {
                run.live.holding = false;
                let state = if run.live.stop {
                    State::Idle
                } else {
                    State::Hold
                };
                self.publish(seg, 0.0, 0.0, run.elapsed, buffered, offsets, state);
                if run.live.stop || self.wait_resume(run) {
                    return Err(true);
                }
                return Ok(None);
            }
            _ => {}
        }
        let m = &seg.motion;
        let moving = matches!(seg.kind, SegmentKind::Move(_));
        let mut t = 0.0;
        loop {
            while let Ok(c) = self.cmds.try_recv() {
                match c {
                    Command::Hold => run.live.hold_asked = true,
                    Command::Stop => {
                        run.live.hold_asked = true;
                        run.live.stop = true;
                    }
                    Command::FeedOverride(f) if f.is_finite() => {
                        let f = f.clamp(0.1, 2.0);
                        self.override_ = f;
                        run.live.feed = Some(f);
                    }
                    _ => {}
                }
            }
            let wants_cut = !run.live.holding && (run.live.feed.is_some() || run.live.hold_asked);
            let (s, v, a) = m.at(t);
            // S-curve motion is re-planned only where the acceleration is zero, so the jerk
            // limit holds across the cut (at most one ramp of delay); a trapezoid anywhere.
            if wants_cut
                && moving
                && t < m.duration
                && (shape == VelocityProfile::Trapezoid || a == 0.0)
            {
                return Ok(Some(Cut { s, v }));
            }
            let dt = (t + TICK).min(m.duration) - t;
            t += dt;
            run.elapsed += dt.max(0.0);
            let (s, v, _) = m.at(t);
            let state = if run.live.holding {
                State::Holding
            } else {
                State::Run
            };
            self.publish(seg, s, v, run.elapsed, buffered, offsets, state);
            if let Pace::Speed(f) = job.pace {
                let due = Duration::from_secs_f64(run.elapsed / f.max(1e-3)) + run.wall_paused;
                if let Some(wait) = due.checked_sub(run.clock.elapsed()) {
                    thread::sleep(wait);
                }
            }
            if t >= m.duration {
                return Ok(None);
            }
        }
    }

    /// Waits in hold for Resume (false) or Stop (true); wall time spent is not machine time.
    /// A feed override given meanwhile applies when motion starts again.
    fn wait_resume(&mut self, run: &mut Run) -> bool {
        let since = Instant::now();
        let r = loop {
            match self.cmds.recv() {
                Ok(Command::Resume) => break false,
                Ok(Command::Stop) | Err(_) => break true,
                Ok(Command::FeedOverride(f)) if f.is_finite() => {
                    self.override_ = f.clamp(0.1, 2.0);
                    run.live.feed = Some(self.override_);
                }
                _ => {}
            }
        };
        run.wall_paused += since.elapsed();
        r
    }

    #[allow(clippy::too_many_arguments)]
    fn publish(
        &self,
        seg: &Segment,
        s: f64,
        v: f64,
        elapsed: f64,
        buffered: usize,
        offsets: &Arc<Mutex<([f64; 3], [f64; 3])>>,
        state: State,
    ) {
        let f = if seg.motion.length > 0.0 {
            s / seg.motion.length
        } else {
            1.0
        };
        let p = oficina_motion::lerp3(seg.start, seg.end, f);
        let rotary = oficina_motion::lerp3(seg.rot0, seg.rot1, f);
        let (g5x, g92) = *offsets.lock().unwrap_or_else(|e| e.into_inner());
        let mut st = lock(&self.status);
        st.state = state;
        st.machine_pos = p;
        st.rotary_pos = rotary;
        st.work_pos = std::array::from_fn(|i| p[i] - g5x[i] - g92[i]);
        st.feed = v * 60.0;
        st.line = seg.line;
        st.buffer = buffered;
        st.elapsed = elapsed.min(st.total.max(elapsed));
        st.feed_override = self.override_;
        let snapshot = st.clone();
        drop(st);
        let _ = self.events.send(Event::Status(snapshot));
    }
}
