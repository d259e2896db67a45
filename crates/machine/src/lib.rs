//! Machines: one trait for every machine (the built-in virtual machine now, grbl-family
//! firmware over serial or TCP later): connect, stream a job, real-time commands and status
//! events.
//!
//! ```
//! use oficina_machine::{Event, Job, Machine, Pace, State, VirtualMachine};
//! use std::{sync::Arc, time::Duration};
//!
//! let mut profile = oficina_motion::resolve("grbl-router").unwrap();
//! profile.work_offset = [0.0; 3]; // the program is in machine coordinates
//! let mut vm = VirtualMachine::new(profile);
//! vm.connect().unwrap();
//! let text = "G21 G90\nG0 X10 Y10\nG1 X40 Y50 F3000\nM2\n";
//! let text = Arc::new(text.to_string());
//! let job = Job { name: "move.nc".into(), text, start_line: None, pace: Pace::Instant };
//! vm.start(job).unwrap();
//! // Status events stream in until the job ends.
//! let completed = loop {
//!     match vm.next_event(Duration::from_secs(30)).expect("an event") {
//!         Event::JobEnd { completed, .. } => break completed,
//!         _ => {}
//!     }
//! };
//! assert!(completed);
//! assert_eq!(vm.status().state, State::Idle);
//! let [x, y, _] = vm.status().machine_pos;
//! assert!((x - 40.0).abs() < 1e-6 && (y - 50.0).abs() < 1e-6, "{x} {y}");
//! ```

pub mod job;
#[cfg(feature = "virtual")]
pub mod virtual_machine;

pub use job::{Job, Pace};
use std::time::Duration;
#[cfg(feature = "virtual")]
pub use virtual_machine::VirtualMachine;

/// What the machine is doing.
#[derive(Clone, Debug, PartialEq)]
pub enum State {
    /// At rest, ready for a job or a jog.
    Idle,
    /// Running a job.
    Run,
    /// Decelerating to a feed hold.
    Holding,
    /// Stopped by a feed hold, waiting for resume.
    Hold,
    /// M0/M1, or a tool change ([`Event::ToolChange`]): waiting for resume.
    Paused,
    /// Jogging.
    Jog,
    /// Running its homing cycle (grbl's `$H`): seeking the limit switches.
    Home,
    /// In alarm (says why): unlock or reset to continue.
    Alarm(String),
}

/// A snapshot of the machine.
#[derive(Clone, Debug, PartialEq)]
pub struct Status {
    /// What the machine is doing.
    pub state: State,
    /// Machine position, mm.
    pub machine_pos: [f64; 3],
    /// Work position (machine minus the active G5x and G92 offsets), mm.
    pub work_pos: [f64; 3],
    /// Current path speed, mm/min.
    pub feed: f64,
    /// Source line being executed.
    pub line: u32,
    /// Planned segments waiting in the look-ahead buffer.
    pub buffer: usize,
    /// Machine time executed and planned total, seconds.
    pub elapsed: f64,
    /// Planned total machine time, seconds.
    pub total: f64,
    /// Feed override factor in force (1.0 = 100 %).
    pub feed_override: f64,
    /// Rotary axes A, B, C, degrees, counting whole turns (0 on a machine without them).
    pub rotary_pos: [f64; 3],
}

impl Status {
    /// A machine at rest at `pos` (mm), nothing planned.
    pub fn idle(pos: [f64; 3]) -> Status {
        Status {
            state: State::Idle,
            machine_pos: pos,
            work_pos: pos,
            feed: 0.0,
            line: 0,
            buffer: 0,
            elapsed: 0.0,
            total: 0.0,
            feed_override: 1.0,
            rotary_pos: [0.0; 3],
        }
    }
}

/// Real-time commands, honoured while a job runs.
#[derive(Clone, Debug, PartialEq)]
pub enum Command {
    /// Feed hold: decelerate on the planned path and wait.
    Hold,
    /// Leave a hold or an M0 pause.
    Resume,
    /// Decelerate and abandon the job.
    Stop,
    /// Jog by `delta` mm at `feed` mm/min (idle only; soft limits checked first).
    Jog {
        /// Displacement, mm.
        delta: [f64; 3],
        /// Feed, mm/min.
        feed: f64,
    },
    /// Feed override factor for motion not yet started (0.1 … 2.0).
    FeedOverride(f64),
    /// End a jog now, decelerating (a continuous jog's button released, or its page gone);
    /// nothing when no jog moves, and never a program's motion.
    JogCancel,
    /// Spindle speed override factor (0.1 … 2.0, grbl's 10–200 %).
    SpindleOverride(f64),
    /// Leave the alarm state.
    Unlock,
}

/// What a machine reports while connected.
#[derive(Clone, Debug, PartialEq)]
pub enum Event {
    /// A status snapshot (sent periodically while a job runs).
    Status(Status),
    /// `(MSG,…)` or an operator message.
    Message(String),
    /// The job could not start or had to stop; the machine is in alarm. A running job
    /// then ends with [`Event::JobEnd`] (`completed` false), on every machine.
    Alarm(String),
    /// The job stopped for a tool change the machine cannot make itself (`M6` on grbl):
    /// every line before the `M6` has run, the state is [`State::Paused`], and
    /// [`Command::Resume`] goes on once the operator has put the tool in (a
    /// [`Command::Stop`] ends the job there; it resumes at the `M6` line).
    ToolChange {
        /// The tool to put in (the `T` word; 0 when the program gave none).
        tool: u32,
        /// The source line of the `M6`.
        line: u32,
        /// What the operator is asked, e.g. "change to tool T2 (…), then resume".
        prompt: String,
    },
    /// The job ended: `completed` false when stopped.
    JobEnd {
        /// The job ran to its end.
        completed: bool,
        /// Machine time the job took, seconds.
        seconds: f64,
    },
}

/// Why a machine refused a call.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum MachineError {
    /// No connection: call [`Machine::connect`] first.
    #[error("not connected")]
    NotConnected,
    /// Something else runs (a job, a jog); says what.
    #[error("busy: {0}")]
    Busy(String),
    /// The machine refused the request; says why.
    #[error("{0}")]
    Refused(String),
}

/// What a connection reports about the machine.
#[derive(Clone, Debug, PartialEq)]
pub struct MachineInfo {
    /// The machine's name (profile or board).
    pub name: String,
    /// The firmware and its version.
    pub firmware: String,
}

/// Every machine, virtual or real: connect, stream a job, real-time commands and events.
pub trait Machine: Send {
    /// Opens the connection and says what answered.
    fn connect(&mut self) -> Result<MachineInfo, MachineError>;
    /// Starts streaming a job; progress arrives as events.
    fn start(&mut self, job: Job) -> Result<(), MachineError>;
    /// Sends a real-time command.
    fn command(&mut self, cmd: Command) -> Result<(), MachineError>;
    /// Waits up to `timeout` for the next event.
    fn next_event(&mut self, timeout: Duration) -> Option<Event>;
    /// The latest status snapshot.
    fn status(&self) -> Status;
    /// Closes the connection (a running job stops).
    fn disconnect(&mut self);

    /// Sends one line in the firmware's own language (a `$` command, or G-code typed at a
    /// console) while no job runs, and waits for its acknowledgement. Machines without such a
    /// language (the virtual machine) refuse.
    fn raw_line(&mut self, line: &str) -> Result<RawReply, MachineError> {
        Err(MachineError::Refused(format!(
            "`{line}`: this machine takes no firmware lines"
        )))
    }

    /// Soft reset (grbl's Ctrl-X, 0x18): the firmware stops at once, drops what it had
    /// queued and restarts; a machine that was moving goes to alarm (its position may be
    /// lost). Machines without such a reset refuse.
    fn soft_reset(&mut self) -> Result<(), MachineError> {
        Err(MachineError::Refused(
            "this machine has no soft reset: stop it instead".into(),
        ))
    }

    /// The firmware's settings as (number, value), in its own numbering (grbl's `$$`).
    fn firmware_settings(&mut self) -> Result<Vec<(u16, f64)>, MachineError> {
        Err(MachineError::Refused(
            "this machine has no firmware settings; its profile says how it moves".into(),
        ))
    }

    /// Changes one firmware setting (grbl's `$N=V`), checked against the firmware's table
    /// first; the machine must be idle.
    fn write_firmware_setting(&mut self, number: u16, value: f64) -> Result<(), MachineError> {
        Err(MachineError::Refused(format!(
            "${number}={value}: this machine has no firmware settings"
        )))
    }

    /// How the last job ended, for a shell to tell the operator: the machine's own summary
    /// and, when the job did not finish, where it can be picked up again. Available once
    /// [`Event::JobEnd`] arrived (and before, once the summary was sent as a message or an
    /// alarm); `None` while a job runs, after a job that could not run at all, and on
    /// machines that keep no such record.
    fn job_report(&mut self) -> Option<JobReport> {
        None
    }

    /// The machine as [`std::any::Any`], for a shell that drives one kind further (grbl
    /// firmware's tool-change policy, probing routines, levelled programs); `None` by default.
    fn as_any_mut(&mut self) -> Option<&mut dyn std::any::Any> {
        None
    }
}

/// See [`Machine::job_report`].
#[derive(Clone, Debug, PartialEq)]
pub struct JobReport {
    /// One paragraph: what ran, what did not and why.
    pub summary: String,
    /// The job ran to its end.
    pub completed: bool,
    /// Where an unfinished job can continue.
    pub resume: Option<ResumePoint>,
    /// The link to the machine was lost before a resume point could be named: after
    /// reconnecting, resume from the job's journal.
    pub link_lost: bool,
}

/// Where an unfinished job continues.
#[derive(Clone, Debug, PartialEq)]
pub struct ResumePoint {
    /// Source line to continue from.
    pub file_line: u32,
    /// The machine stopped inside that line and its journal says where: resuming from the
    /// journal finishes the line from there, restarting at `file_line` re-cuts it whole.
    pub within_line: bool,
}

/// What the firmware answered to a [`Machine::raw_line`]: the lines before its
/// acknowledgement, and the error it gave instead of `ok`, explained.
#[derive(Clone, Debug, PartialEq)]
pub struct RawReply {
    /// The lines the firmware sent before its acknowledgement.
    pub lines: Vec<String>,
    /// The error the firmware gave instead of `ok`, explained.
    pub error: Option<String>,
}
