//! A tool change while a job streams: wait for rest, spindle and coolant off, park, ask
//! the operator and wait for Resume, measure the new tool under `remeasure`, then restore
//! the program's state before the `M6` so streaming goes on.

use super::{ToolPolicy, ToolStop};
use crate::interp::Spindle;
use crate::job::StreamProgram;
use crate::journal::Journal;
use crate::link::LinkEvent;
use crate::messages;
use crate::probe::{run_tool_setter, ProbeError, ToolSetter};
use crate::realtime::Realtime;
use crate::response::Response;
use crate::resume::{self, num, ResumeOptions};
use crate::sender::{Control, Notice, Sender};
use std::sync::mpsc::{Receiver, TryRecvError};
use std::time::{Duration, Instant};

/// Why a tool change did not finish.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum ToolError {
    /// The operator stopped the job while it waited.
    Stopped,
    /// The firmware raised an alarm (grbl's ALARM:4 probe already touching, ALARM:5 no touch).
    Alarm(u8),
    /// The link was lost.
    Lost(String),
    /// A line was refused or an answer did not come; says which.
    Failed(String),
}

impl std::fmt::Display for ToolError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ToolError::Stopped => f.write_str("stopped by the operator"),
            ToolError::Alarm(c) => f.write_str(&messages::describe_alarm(*c)),
            ToolError::Lost(why) => write!(f, "connection lost: {why}"),
            ToolError::Failed(why) => f.write_str(why),
        }
    }
}

/// Sends one line and waits for its `ok`; an `error:N` or an `ALARM:N` ends the wait at
/// once. `motion` is how long the line's own motion may take, on top of the sender's reply
/// timeout.
pub(crate) fn send_line(
    sender: &mut Sender,
    line: &str,
    motion: Duration,
) -> Result<(), ToolError> {
    sender
        .link
        .send_line(line)
        .map_err(|e| ToolError::Lost(e.to_string()))?;
    let wait = sender.options.reply_timeout + motion;
    let deadline = Instant::now() + wait;
    loop {
        if Instant::now() > deadline {
            return Err(ToolError::Failed(format!(
                "no answer to `{line}` within {:.0} s",
                wait.as_secs_f64()
            )));
        }
        match sender.link.recv(Duration::from_millis(50)) {
            Some(LinkEvent::Line(Response::Ok, _)) => return Ok(()),
            Some(LinkEvent::Line(Response::Error(c), _)) => {
                return Err(ToolError::Failed(format!(
                    "grbl refused `{line}`: {}",
                    messages::describe_error(c)
                )))
            }
            Some(LinkEvent::Line(Response::Alarm(c), _)) => return Err(ToolError::Alarm(c)),
            Some(LinkEvent::Line(Response::Welcome { .. }, _)) => {
                return Err(ToolError::Failed(format!(
                    "the firmware reset while running `{line}`"
                )))
            }
            Some(LinkEvent::Closed(why)) => return Err(ToolError::Lost(why)),
            _ => {}
        }
    }
}

/// The lines that park the machine: up first, then across (machine coordinates, mm).
pub(crate) fn park_lines(park: [f64; 3]) -> Vec<String> {
    vec![
        "G21G90".into(),
        format!("G53G0Z{}", num(park[2])),
        format!("G53G0X{}Y{}", num(park[0]), num(park[1])),
    ]
}

/// What a run knows of tool lengths under `remeasure`.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct ToolLengths {
    /// The first tool's touch on the setter, machine Z (mm).
    pub reference: Option<f64>,
    /// The `G43.1` offset in force (None: none applied).
    pub offset: Option<f64>,
}

/// Sends `lines` one by one, each waiting for its `ok`.
fn send_all(sender: &mut Sender, lines: &[String]) -> Result<(), ToolError> {
    for l in lines {
        send_line(sender, l, Duration::from_secs(120))?;
    }
    Ok(())
}

/// Measures the tool in the spindle on the setter ([`run_tool_setter`]) and makes its tip
/// the reference's: the first measurement of a job is the reference itself (offset 0). Then
/// back up to the setter's safe Z. Journalled, told to the operator.
pub(crate) fn remeasure(
    sender: &mut Sender,
    setter: &ToolSetter,
    lengths: &mut ToolLengths,
    stop_index: Option<usize>,
    journal: &mut Journal,
    observer: &mut dyn FnMut(Notice),
) -> Result<(), ToolError> {
    let mut p = *setter;
    p.reference = lengths.reference.or(setter.reference);
    let measured = run_tool_setter(sender, &p).map_err(|e| match e {
        ProbeError::AlreadyTriggered(_) => ToolError::Alarm(4),
        ProbeError::NoContact(_) => ToolError::Alarm(5),
        other => ToolError::Failed(format!("tool setter: {other}")),
    })?;
    let z = measured.measured_z;
    let reference = match p.reference {
        Some(r) => r,
        None => {
            let _ = journal.tool_reference(z);
            z
        }
    };
    lengths.reference = Some(reference);
    let delta = z - reference;
    if measured.tool_offset.is_none() {
        apply_offset(sender, Some(delta))?;
    }
    let up = format!("G90G53G0Z{}", num(setter.safe_z));
    send_line(sender, &up, Duration::from_secs(60))?;
    lengths.offset = Some(delta);
    if let Some(i) = stop_index {
        let _ = journal.tool_length(i, delta);
    }
    observer(Notice::Message(format!(
        "tool setter touched at machine Z{}; the first tool's touch: Z{}; tool length offset G43.1 Z{}",
        num(z),
        num(reference),
        num(delta)
    )));
    Ok(())
}

/// Puts a tool length offset in force (`G43.1`, mm), or clears it (`G49`).
pub(crate) fn apply_offset(sender: &mut Sender, offset: Option<f64>) -> Result<(), ToolError> {
    let line = match offset {
        Some(d) => format!("G21G43.1Z{}", num(d)),
        None => "G49".to_string(),
    };
    send_line(sender, &line, Duration::ZERO)
}

/// The tool change at `stop`: wait for rest, spindle and coolant off, park, ask the operator
/// and wait for Resume, measure under `remeasure`, then restore the program's state before
/// the `M6` (the resume preamble) so streaming goes on as if nothing happened.
#[allow(clippy::too_many_arguments)]
pub(crate) fn change_tool(
    sender: &mut Sender,
    job: &StreamProgram,
    stop: &ToolStop,
    resume_opts: &ResumeOptions,
    lengths: &mut ToolLengths,
    journal: &mut Journal,
    control: Option<&Receiver<Control>>,
    observer: &mut dyn FnMut(Notice),
) -> Result<(), ToolError> {
    let tc = &job.tool_change;
    // Measuring this tool needs the first tool's touch unless this is where it is taken.
    let first = job.tool_stops.first().map(|s| s.index) == Some(stop.index) && !tc.measure_at_start;
    if tc.policy == ToolPolicy::Remeasure && lengths.reference.is_none() && !first {
        let at = job.tool_stops.first().map(|s| s.file_line).unwrap_or(0);
        let from = if tc.measure_at_start {
            "the start".to_string()
        } else {
            format!("line {at} (the first M6)")
        };
        return Err(ToolError::Failed(format!(
            "the first tool's touch on the tool setter is not known (not in the journal): run from {from} so it is measured"
        )));
    }
    sender
        .wait_at_rest()
        .map_err(|e| ToolError::Failed(e.to_string()))?;
    let st = resume::replay(job, stop.index);
    let mut off = Vec::new();
    if st.modal.spindle != Spindle::Off {
        off.push("M5".to_string());
    }
    if st.modal.mist || st.modal.flood {
        off.push("M9".to_string());
    }
    send_all(sender, &off)?;
    let park = match tc.policy {
        ToolPolicy::ParkPause | ToolPolicy::Remeasure => tc.park,
        _ => None,
    };
    if let Some(p) = park {
        send_all(sender, &park_lines(p))?;
        sender
            .wait_at_rest()
            .map_err(|e| ToolError::Failed(e.to_string()))?;
    }
    let _ = journal.completed(stop.index);
    // Only a Resume given after the prompt counts: one sent before (for a hold) is dropped.
    drain_controls(sender, control)?;
    observer(Notice::ToolChange {
        tool: stop.tool,
        file_line: stop.file_line,
        prompt: stop.prompt(tc.policy),
    });
    wait_for_resume(sender, control, observer)?;
    observer(Notice::ToolChangeDone { tool: stop.tool });
    if let (ToolPolicy::Remeasure, Some(setter)) = (tc.policy, &tc.setter) {
        remeasure(sender, setter, lengths, Some(stop.index), journal, observer)?;
    }
    sender
        .run_preamble_at(job, stop.index, None, resume_opts)
        .map_err(ToolError::Failed)
}

/// The operator's requests waiting now: a Stop ends the change, overrides go on to the
/// firmware, Hold and Resume are dropped.
fn drain_controls(
    sender: &mut Sender,
    control: Option<&Receiver<Control>>,
) -> Result<(), ToolError> {
    let Some(control) = control else {
        return Ok(());
    };
    loop {
        match control.try_recv() {
            Ok(Control::Stop) | Err(TryRecvError::Disconnected) => return Err(ToolError::Stopped),
            Ok(Control::Realtime(r)) => sender
                .realtime(r)
                .map_err(|e| ToolError::Lost(e.to_string()))?,
            Ok(Control::Hold | Control::Resume) => {}
            Err(TryRecvError::Empty) => return Ok(()),
        }
    }
}

/// Waits for the operator's Resume (or Stop) while the machine rests, keeping status reports
/// (and overrides) flowing and watching the link.
fn wait_for_resume(
    sender: &mut Sender,
    control: Option<&Receiver<Control>>,
    observer: &mut dyn FnMut(Notice),
) -> Result<(), ToolError> {
    let Some(control) = control else {
        return Err(ToolError::Failed(
            "a tool change needs an operator to resume, and this run takes no commands".into(),
        ));
    };
    let lost = |e: std::io::Error| ToolError::Lost(e.to_string());
    let mut last_query: Option<Instant> = None;
    let mut last_heard = Instant::now();
    loop {
        loop {
            match control.try_recv() {
                Ok(Control::Resume) => return Ok(()),
                // Nobody left to resume: the job ends here.
                Ok(Control::Stop) | Err(TryRecvError::Disconnected) => {
                    return Err(ToolError::Stopped)
                }
                // Already at rest: nothing to hold.
                Ok(Control::Hold) => {}
                Ok(Control::Realtime(r)) => sender.realtime(r).map_err(lost)?,
                Err(TryRecvError::Empty) => break,
            }
        }
        if last_query.is_none_or(|t| t.elapsed() >= sender.options.status_interval) {
            sender.realtime(Realtime::StatusQuery).map_err(lost)?;
            last_query = Some(Instant::now());
        }
        match sender.link.recv(Duration::from_millis(20)) {
            Some(LinkEvent::Line(Response::Status(st), _)) => {
                last_heard = Instant::now();
                observer(Notice::Status(st));
            }
            Some(LinkEvent::Line(Response::Alarm(c), _)) => return Err(ToolError::Alarm(c)),
            Some(LinkEvent::Line(Response::Message(m), _)) => observer(Notice::Message(m)),
            Some(LinkEvent::Line(_, raw)) => {
                last_heard = Instant::now();
                observer(Notice::Unexpected(raw));
            }
            Some(LinkEvent::Closed(why)) => return Err(ToolError::Lost(why)),
            None => {
                if last_heard.elapsed() > sender.options.silence_timeout {
                    return Err(ToolError::Lost(format!(
                        "the firmware answered nothing, not even status queries, for {:.0} s",
                        sender.options.silence_timeout.as_secs_f64()
                    )));
                }
            }
        }
    }
}
