//! How a stream ended, told to the user: what happened, at which file line, what grbl said,
//! and where to resume.

use crate::job::StreamProgram;
use crate::messages;
use crate::resume::Located;
use std::time::Duration;

/// How a stream ended.
#[derive(Clone, Debug, PartialEq)]
pub enum StreamEnd {
    /// Every line acknowledged and the machine at rest.
    Completed,
    /// The operator stopped it.
    Stopped,
    /// The firmware answered `error:code` to job line `index`.
    Rejected {
        /// Index of the job line.
        index: usize,
        /// grbl's error code.
        code: u8,
    },
    /// The firmware raised this alarm.
    Alarm(u8),
    /// The firmware restarted (banner seen): everything in flight was discarded.
    FirmwareReset,
    /// The link was lost; says how.
    Disconnected(String),
    /// The firmware went idle with lines unacknowledged: bytes were lost on the link.
    Stalled,
    /// The job completed but the machine is not where the program ends.
    PositionMismatch {
        /// Where the program ends, work mm.
        expected: [f64; 3],
        /// Where the machine is, work mm.
        actual: [f64; 3],
    },
}

/// What a stream did: how it ended, how far it got, where to resume.
#[derive(Clone, Debug, PartialEq)]
pub struct StreamReport {
    /// How it ended.
    pub end: StreamEnd,
    /// Lines `from..acked_end` were acknowledged in this stream.
    pub acked_end: usize,
    /// Nothing at or after this index reached the wire.
    pub sent_end: usize,
    /// Lines before this index certainly completed.
    pub certain: usize,
    /// Where the machine rested at the end (work mm), when it could be read.
    pub work_pos: Option<[f64; 3]>,
    /// Where to continue, when the end allows it.
    pub resume: Option<Located>,
    /// Why the machine's rest position could not be read, or the reset after a stop was not
    /// answered (then no resume point is offered: the machine's state is not known).
    pub recovery_error: Option<String>,
    /// Bytes written to the link.
    pub bytes_sent: u64,
    /// Wall-clock time of the stream.
    pub elapsed: Duration,
    /// Largest number of bytes in flight (never above the RX capacity).
    pub max_in_flight: usize,
    /// Times the sender itself did not run for over 20 ms (its host was busy): while it
    /// sleeps, the firmware's buffers drain whatever the link could carry.
    pub sender_stalls: u32,
}

impl StreamReport {
    /// One paragraph for the user: what happened, where, what grbl said, what to do.
    pub fn describe(&self, job: &StreamProgram) -> String {
        let line = |i: usize| match (job.tool_stop_at(i), job.lines.get(i)) {
            // A resume there asks for the tool again: name the M6 line.
            (Some(s), _) => format!("{}:{} (M6 T{})", job.name, s.file_line, s.tool),
            (None, Some(l)) => format!("{}:{} `{}`", job.name, l.file_line, l.text),
            (None, None) => "end of program".into(),
        };
        let mut s = match &self.end {
            StreamEnd::Completed => format!("{}: all {} lines done", job.name, job.len()),
            StreamEnd::Stopped => "stopped by the operator".to_string(),
            StreamEnd::Rejected { index, code } => format!("grbl rejected {}: {}", line(*index), messages::describe_error(*code)),
            StreamEnd::Alarm(c) => format!("grbl raised {}", messages::describe_alarm(*c)),
            StreamEnd::FirmwareReset => "the firmware restarted during the job (reset, power or USB reconnect); lines in its buffer were lost".to_string(),
            StreamEnd::Disconnected(why) => format!("connection lost: {why}"),
            StreamEnd::Stalled => "the firmware went idle while lines were still unacknowledged: bytes were lost on the link".to_string(),
            StreamEnd::PositionMismatch { expected, actual } => format!(
                "the job ran to its end but the machine is at {:.3},{:.3},{:.3} instead of {:.3},{:.3},{:.3}: bytes were corrupted on the link",
                actual[0], actual[1], actual[2], expected[0], expected[1], expected[2]
            ),
        };
        if let Some(why) = &self.recovery_error {
            s += &format!(". Where the machine is could not be learned ({why}): check it, home it ($H) and set the work origin again before resuming");
        }
        if let Some(r) = &self.resume {
            if r.index < job.len() {
                s += &format!(". Resume from {} ({}).", line(r.index), r.reason);
            }
        }
        s
    }
}

/// grbl goes on executing the lines already in its buffer after rejecting one, so the
/// machine may have moved past the rejected line on a path that skipped it. Resuming at the
/// rejected line (once fixed) re-traces those lines from the right starting point.
pub(crate) fn after_rejection(job: &StreamProgram, rejected: usize, at: Located) -> Located {
    if at.index <= rejected {
        return at;
    }
    let l = |i: usize| job.lines.get(i).map(|l| l.file_line).unwrap_or(0);
    Located {
        index: rejected,
        reason: format!(
            "the firmware ran file lines {}..{} after rejecting line {} before the hold took effect; they are run again after it",
            l(rejected + 1),
            l(at.index.saturating_sub(1)),
            l(rejected)
        ),
        entry: None,
    }
}
