//! The streaming sender. Character counting (grbl's stream.py method): keep as many lines
//! in flight as fit the firmware's RX buffer, sized from `[OPT:…,rx]`, so the wire never
//! idles and the buffer never overflows; send-response (one line at a time) when the
//! firmware does not say its buffer size.
//!
//! A stream ends in a known state: on a rejected line, a stop or lost bytes the sender
//! holds, waits for the machine to rest, reads where it is, then resets to flush whatever
//! is still queued; the position and the journal tell exactly where to resume.

use crate::job::StreamProgram;
use crate::journal::Journal;
use crate::link::{Link, LinkEvent};
use crate::messages;
use crate::realtime::Realtime;
use crate::report::after_rejection;
pub(crate) use crate::report::{StreamEnd, StreamReport};
use crate::response::Response;
use crate::resume::{self, Located};
use crate::status::{GrblState, StatusReport};
use crate::track::PathTracker;
use crate::transport::Endpoint;
use std::collections::VecDeque;
use std::io;
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

/// How lines are paced to the firmware.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mode {
    /// Lines in flight up to this many bytes (RX buffer size − 1).
    CharCounting(usize),
    /// One line at a time: the next waits for the `ok`.
    SendResponse,
}

/// How the sender talks to the firmware.
#[derive(Clone, Debug)]
pub struct SenderOptions {
    /// `None`: character counting when the firmware reports its RX size, else send-response.
    pub mode: Option<Mode>,
    /// Time between status queries.
    pub status_interval: Duration,
    /// The firmware idle this long while lines await their `ok` means bytes were lost.
    pub stall_after: Duration,
    /// Longest wait for one reply to a command, or for the machine to come to rest.
    pub reply_timeout: Duration,
    /// A firmware that answers nothing (not even status queries) this long is lost.
    pub silence_timeout: Duration,
}

impl Default for SenderOptions {
    fn default() -> Self {
        SenderOptions {
            mode: None,
            status_interval: Duration::from_millis(200),
            stall_after: Duration::from_millis(1500),
            reply_timeout: Duration::from_secs(30),
            silence_timeout: Duration::from_secs(10),
        }
    }
}

/// Operator requests during a stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// Feed hold.
    Hold,
    /// Resume after a hold.
    Resume,
    /// Stop: hold, then reset, and end the stream.
    Stop,
    /// Any other real-time command (overrides).
    Realtime(Realtime),
}

/// What the sender tells its observer while streaming.
#[derive(Clone, Debug, PartialEq)]
pub enum Notice {
    /// Lines and bytes acknowledged so far.
    Progress {
        /// Lines acknowledged.
        acked: usize,
        /// Lines in the job.
        total: usize,
        /// Bytes acknowledged.
        bytes_acked: u64,
        /// Bytes in the job.
        bytes_total: u64,
    },
    /// A status report.
    Status(StatusReport),
    /// The machine was seen on the path of job line `index` (sent earlier than the status
    /// report that follows). The acknowledged count runs ahead of this by the firmware's
    /// buffer — on grblHAL a short program is acknowledged whole before it moves.
    Running {
        /// The job line the machine is on.
        index: usize,
    },
    /// A firmware line that is not part of the protocol (line noise, a fork's extra).
    Unexpected(String),
    /// A message for the operator (the firmware's `[MSG:…]`, or the sender's own).
    Message(String),
    /// Streaming stopped before an `M6` line, every line before it executed: the operator
    /// changes the tool, then resumes ([`Control::Resume`]); a stop ends the job there.
    ToolChange {
        /// The tool to put in.
        tool: u32,
        /// The file line of the `M6`.
        file_line: usize,
        /// What the operator is asked.
        prompt: String,
    },
    /// The operator resumed after the change to `tool`; the sender goes on (measuring the
    /// tool first under `remeasure`).
    ToolChangeDone {
        /// The tool put in.
        tool: u32,
    },
}

/// The streaming protocol over a link: handshake, character counting or send-response, status
/// polling.
pub struct Sender {
    pub(crate) link: Link,
    /// The options it was made with.
    pub options: SenderOptions,
    /// Character counting or send-response.
    pub mode: Mode,
    /// The firmware's welcome line.
    pub firmware: String,
    /// Planner blocks the firmware reports (or grbl's default).
    pub planner_blocks: usize,
    /// The latest status report.
    pub last_status: Option<StatusReport>,
    /// The last work offset grbl reported (it sends `WCO:` only every so many reports).
    pub(crate) last_wco: Option<Vec<f64>>,
    /// `$12` arc tolerance, to count the planner blocks an arc makes as grbl does.
    pub arc_tolerance: f64,
    /// Every `$N` setting read at connect (empty if the machine was busy).
    pub settings: std::collections::BTreeMap<u16, f64>,
    /// `$13=1`: the firmware reports positions in inches.
    pub reports_inches: bool,
}

fn err(kind: io::ErrorKind, msg: String) -> io::Error {
    io::Error::new(kind, msg)
}

impl Sender {
    /// Connects to `endpoint` and reads the firmware's welcome and options.
    pub fn connect(endpoint: &Endpoint, options: SenderOptions) -> io::Result<Sender> {
        Sender::handshake(Link::open(endpoint)?, options)
    }

    /// Learns the firmware and its buffer sizes without disturbing a running machine
    /// (no reset is sent: a job may be running after a reconnect).
    pub fn handshake(link: Link, options: SenderOptions) -> io::Result<Sender> {
        let mut s = Sender {
            link,
            mode: Mode::SendResponse,
            options,
            firmware: String::new(),
            planner_blocks: 15,
            last_status: None,
            last_wco: None,
            arc_tolerance: 0.002,
            settings: Default::default(),
            reports_inches: false,
        };
        // Boards that reset on open (Arduino DTR) print the banner within ~2 s.
        let deadline = Instant::now() + Duration::from_secs(3);
        s.link.send_realtime(Realtime::StatusQuery)?;
        let mut last_query = Instant::now();
        while s.last_status.is_none() {
            if Instant::now() > deadline {
                return Err(err(io::ErrorKind::TimedOut, format!("{}: no grbl status report within 3 s; is this a grbl board, and is the baud rate right?", s.link.description)));
            }
            if last_query.elapsed() > Duration::from_millis(500) {
                s.link.send_realtime(Realtime::StatusQuery)?;
                last_query = Instant::now();
            }
            match s.link.recv(Duration::from_millis(50)) {
                Some(LinkEvent::Line(Response::Welcome { version, .. }, _)) => s.firmware = version,
                Some(LinkEvent::Line(Response::Status(st), _)) => s.note_status(st),
                Some(LinkEvent::Closed(why)) => {
                    return Err(err(
                        io::ErrorKind::ConnectionAborted,
                        format!("{}: {why}", s.link.description),
                    ))
                }
                _ => {}
            }
        }
        s.learn_firmware();
        Ok(s)
    }

    /// Asks `$I` (version, `[OPT:…,blocks,rx]`) and `$$` (arc tolerance, report units) and
    /// sizes the streaming window. Both need an idle machine: when connecting to a busy one
    /// the window falls back to send-response until [`Sender::recover`] asks again.
    fn learn_firmware(&mut self) {
        let mut rx = None;
        if let Ok(reply) = self.command("$I") {
            for l in &reply.lines {
                match Response::parse(l) {
                    Response::Version(v) => {
                        self.firmware = v.split(':').next().unwrap_or("").to_string()
                    }
                    Response::Options {
                        blocks, rx_bytes, ..
                    } => {
                        if let Some(b) = blocks {
                            self.planner_blocks = b as usize;
                        }
                        rx = rx_bytes;
                    }
                    _ => {}
                }
            }
        }
        // Settings can only be listed at rest; a machine caught mid-job keeps the defaults.
        if !self.is_moving() {
            if let Ok(reply) = self.command("$$") {
                for l in &reply.lines {
                    if let Response::Setting { number, value } = Response::parse(l) {
                        if let Ok(v) = value.parse::<f64>() {
                            self.settings.insert(number, v);
                        }
                        match (number, value.parse::<f64>()) {
                            (12, Ok(v)) if v > 0.0 => self.arc_tolerance = v,
                            (13, Ok(v)) => self.reports_inches = v != 0.0,
                            _ => {}
                        }
                    }
                }
            }
        }
        let rx = rx.or_else(|| {
            self.last_status
                .as_ref()
                .and_then(|st| st.buffer)
                .filter(|_| !self.is_moving())
                .map(|b| b.1)
        });
        self.mode = match (self.options.mode, rx) {
            (Some(m), _) => m,
            (None, Some(n)) if n > 1 => Mode::CharCounting(n as usize - 1),
            _ => Mode::SendResponse,
        };
    }

    /// Whether a report says the planner holds no blocks (`true` when it does not say).
    fn planner_drained(&self, st: &StatusReport) -> bool {
        st.buffer
            .is_none_or(|(free, _)| free as usize >= self.planner_blocks)
    }

    fn is_moving(&self) -> bool {
        self.last_status
            .as_ref()
            .is_some_and(|s| s.state.is_moving())
    }

    fn note_status(&mut self, st: StatusReport) {
        if let Some(w) = &st.wco {
            self.last_wco = Some(w.clone());
        }
        self.last_status = Some(st);
    }

    /// The link underneath.
    pub fn link(&mut self) -> &mut Link {
        &mut self.link
    }

    /// Sends a real-time command.
    pub fn realtime(&mut self, r: Realtime) -> io::Result<()> {
        self.link.send_realtime(r)
    }

    /// Sends one line and waits for its `ok`/`error:N`, collecting the lines before it.
    pub fn command(&mut self, line: &str) -> io::Result<Reply> {
        self.link.send_line(line)?;
        let deadline = Instant::now() + self.options.reply_timeout;
        let mut lines = Vec::new();
        loop {
            if Instant::now() > deadline {
                return Err(err(
                    io::ErrorKind::TimedOut,
                    format!(
                        "{}: no reply to `{line}` within {:?}",
                        self.link.description, self.options.reply_timeout
                    ),
                ));
            }
            match self.link.recv(Duration::from_millis(50)) {
                Some(LinkEvent::Line(Response::Ok, _)) => return Ok(Reply { lines, error: None }),
                Some(LinkEvent::Line(Response::Error(c), _)) => {
                    return Ok(Reply {
                        lines,
                        error: Some(c),
                    })
                }
                Some(LinkEvent::Line(Response::Status(st), _)) => self.note_status(st),
                Some(LinkEvent::Line(Response::Welcome { .. }, raw)) => {
                    // A reset answers nothing more: `$C` leaving check mode ends like this.
                    lines.push(raw);
                }
                Some(LinkEvent::Line(_, raw)) => lines.push(raw),
                Some(LinkEvent::Closed(why)) => {
                    return Err(err(
                        io::ErrorKind::ConnectionAborted,
                        format!("{}: {why}", self.link.description),
                    ))
                }
                None => {}
            }
        }
    }

    /// A fresh status report. Replies to earlier queries still in the channel are skipped.
    pub fn status(&mut self) -> io::Result<StatusReport> {
        while let Some(ev) = self.link.recv(Duration::ZERO) {
            match ev {
                LinkEvent::Line(Response::Status(st), _) => self.note_status(st),
                LinkEvent::Closed(why) => return Err(err(io::ErrorKind::ConnectionAborted, why)),
                _ => {}
            }
        }
        // A query can be lost (a busy firmware's real-time flags, a noisy link): ask again
        // every 250 ms until the bound.
        let deadline = Instant::now() + Duration::from_secs(2);
        let mut last_query: Option<Instant> = None;
        while Instant::now() < deadline {
            if last_query.is_none_or(|t| t.elapsed() >= Duration::from_millis(250)) {
                self.link.send_realtime(Realtime::StatusQuery)?;
                last_query = Some(Instant::now());
            }
            match self.link.recv(Duration::from_millis(50)) {
                Some(LinkEvent::Line(Response::Status(st), _)) => {
                    self.note_status(st.clone());
                    return Ok(st);
                }
                Some(LinkEvent::Closed(why)) => {
                    return Err(err(io::ErrorKind::ConnectionAborted, why))
                }
                _ => {}
            }
        }
        Err(err(
            io::ErrorKind::TimedOut,
            format!("{}: no status report within 2 s", self.link.description),
        ))
    }

    /// Polls until the machine rests (not moving, and not mid-hold), then returns the
    /// work position, waiting for a report that carries the work offset if needed.
    pub fn wait_at_rest(&mut self) -> io::Result<[f64; 3]> {
        let mut deadline = Instant::now() + self.options.reply_timeout;
        let mut last_pos: Option<Vec<f64>> = None;
        let mut rest: Option<Vec<f64>> = None;
        loop {
            // A lost report is not the end of the wait: only the deadline is.
            let st = match self.status() {
                Ok(st) => st,
                Err(e) if e.kind() == io::ErrorKind::TimedOut => {
                    if Instant::now() > deadline {
                        return Err(err(
                            io::ErrorKind::TimedOut,
                            format!(
                                "{}: no status report for {:?}",
                                self.link.description, self.options.reply_timeout
                            ),
                        ));
                    }
                    continue;
                }
                Err(e) => return Err(e),
            };
            // A long last move is progress, not a hang: the deadline follows motion.
            let pos = st.machine_position(self.last_wco.as_deref());
            if pos.is_some() && pos != last_pos {
                deadline = Instant::now() + self.options.reply_timeout;
                last_pos = pos;
            }
            // Two reports at rest at the same place: a reply to an older query that was
            // still on the wire cannot pass for the final position.
            // Idle with blocks still planned is the moment before a cycle starts; a hold at
            // rest keeps its blocks.
            let settled = st.state != GrblState::Idle || self.planner_drained(&st);
            if !st.state.is_moving() && st.state != GrblState::Run && settled {
                if let Some(w) = st.work_position(self.last_wco.as_deref()) {
                    if w.len() >= 3 && rest.as_ref() == Some(&w) {
                        let k = if self.reports_inches { 25.4 } else { 1.0 };
                        return Ok([w[0] * k, w[1] * k, w[2] * k]);
                    }
                    rest = Some(w);
                }
            } else {
                rest = None;
            }
            if Instant::now() > deadline {
                return Err(err(
                    io::ErrorKind::TimedOut,
                    format!(
                        "{}: the machine did not come to rest within {:?} of its last move; last report: {:?} at {:?}",
                        self.link.description, self.options.reply_timeout, st.state, st.mpos.as_deref().or(st.wpos.as_deref()).unwrap_or(&[])
                    ),
                ));
            }
            std::thread::sleep(Duration::from_millis(40));
        }
    }

    /// Soft reset, wait for the banner, then for a status report: the firmware has finished
    /// its restart and answers again. Safe at rest: grbl keeps its position. The wait is
    /// `reply_timeout`, not a few seconds: a banner arriving after the wait gave up would
    /// end the next stream as a firmware reset.
    pub fn reset(&mut self) -> io::Result<()> {
        self.link.send_realtime(Realtime::SoftReset)?;
        let deadline = Instant::now() + self.options.reply_timeout;
        loop {
            if Instant::now() > deadline {
                return Err(err(
                    io::ErrorKind::TimedOut,
                    format!(
                        "{}: no banner within {:?} of a soft reset",
                        self.link.description, self.options.reply_timeout
                    ),
                ));
            }
            match self.link.recv(Duration::from_millis(50)) {
                Some(LinkEvent::Line(Response::Welcome { .. }, _)) => break,
                Some(LinkEvent::Closed(why)) => {
                    return Err(err(io::ErrorKind::ConnectionAborted, why))
                }
                _ => {}
            }
        }
        // The alarm message that may follow the banner is read on the way.
        while Instant::now() < deadline {
            match self.status() {
                Ok(_) => return Ok(()),
                Err(e) if e.kind() == io::ErrorKind::TimedOut => continue,
                Err(e) => return Err(e),
            }
        }
        Err(err(
            io::ErrorKind::TimedOut,
            format!(
                "{}: no status report within {:?} of the reset banner",
                self.link.description, self.options.reply_timeout
            ),
        ))
    }

    /// Streams `job` from line `from`, keeping the RX buffer full but never over.
    pub fn stream(
        &mut self,
        job: &StreamProgram,
        from: usize,
        journal: Option<&mut Journal>,
        control: Option<&Receiver<Control>>,
        observer: &mut dyn FnMut(Notice),
    ) -> StreamReport {
        self.stream_range(job, from, job.len(), journal, control, observer)
    }

    /// [`Sender::stream`] of the lines `from..until` only: it completes once they are all
    /// acknowledged and the machine rests where line `until - 1` ends (a tool change waits
    /// there).
    pub(crate) fn stream_range(
        &mut self,
        job: &StreamProgram,
        from: usize,
        until: usize,
        mut journal: Option<&mut Journal>,
        control: Option<&Receiver<Control>>,
        observer: &mut dyn FnMut(Notice),
    ) -> StreamReport {
        let until = until.min(job.len());
        let start = Instant::now();
        let capacity = match self.mode {
            Mode::CharCounting(n) => n,
            Mode::SendResponse => usize::MAX,
        };
        let mut next = from;
        let mut inflight: VecDeque<(usize, usize)> = VecDeque::new();
        let mut tracker = PathTracker::new(job, from, self.arc_tolerance);
        // Every line acknowledged: the job is done only once reports confirm the machine
        // rests, and until then hold, stop and overrides still act.
        let mut all_acked = false;
        let mut rest_seen: Option<Vec<f64>> = None;
        let mut confirmed_rest: Option<[f64; 3]> = None;
        let mut at_rest_confirmed = false;
        let mut used = 0usize;
        let mut max_in_flight = 0usize;
        let mut acked_end = from;
        let mut certain = from;
        let mut bytes_sent = 0u64;
        let mut bytes_acked = 0u64;
        let bytes_total = job.bytes_from(from) as u64;
        let mut last_query = Instant::now() - self.options.status_interval;
        let mut idle_since: Option<Instant> = None;
        let mut last_heard = Instant::now();
        let mut holding = false;
        let mut journal_failed = false;
        let mut jrec = |j: &mut Option<&mut Journal>,
                        f: &dyn Fn(&mut Journal) -> io::Result<()>,
                        observer: &mut dyn FnMut(Notice)| {
            if let Some(j) = j.as_deref_mut() {
                if let Err(e) = f(j) {
                    if !journal_failed {
                        observer(Notice::Message(format!("journal {} cannot be written ({e}); resume after a crash will not know the position", j.path.display())));
                        journal_failed = true;
                    }
                }
            }
        };
        // Nothing left to send is a finished job, not a wait for acknowledgements that
        // will never come.
        let nothing_left = from >= until;
        let mut sender_stalls = 0u32;
        let mut last_turn = Instant::now();
        let end: StreamEnd = 'outer: loop {
            // One turn of this loop takes at most ~5 ms (the receive timeout) when the host
            // lets us run.
            if last_turn.elapsed() > Duration::from_millis(20) {
                sender_stalls += 1;
            }
            last_turn = Instant::now();
            if nothing_left {
                break 'outer StreamEnd::Completed;
            }
            if let Some(rx) = control {
                while let Ok(c) = rx.try_recv() {
                    let r = match c {
                        Control::Hold => {
                            holding = true;
                            self.link.send_realtime(Realtime::FeedHold)
                        }
                        Control::Resume => {
                            holding = false;
                            self.link.send_realtime(Realtime::CycleStart)
                        }
                        Control::Stop => break 'outer StreamEnd::Stopped,
                        Control::Realtime(r) => self.link.send_realtime(r),
                    };
                    if let Err(e) = r {
                        break 'outer StreamEnd::Disconnected(e.to_string());
                    }
                }
            }
            // Fill the firmware's buffer.
            while next < until {
                let len = job.lines[next].text.len() + 1;
                let fits = match self.mode {
                    Mode::CharCounting(_) => used + len <= capacity,
                    Mode::SendResponse => inflight.is_empty(),
                };
                if !fits {
                    break;
                }
                let i = next;
                jrec(&mut journal, &|j| j.sent(i), observer);
                if let Err(e) = self.link.send_line(&job.lines[next].text) {
                    break 'outer StreamEnd::Disconnected(format!("write failed: {e}"));
                }
                inflight.push_back((next, len));
                tracker.sent(next, &job.lines[next].text);
                used += len;
                max_in_flight = max_in_flight.max(used);
                bytes_sent += len as u64;
                next += 1;
            }
            if last_query.elapsed() >= self.options.status_interval {
                if let Err(e) = self.link.send_realtime(Realtime::StatusQuery) {
                    break 'outer StreamEnd::Disconnected(format!("write failed: {e}"));
                }
                last_query = Instant::now();
            }
            let Some(ev) = self.link.recv(Duration::from_millis(5)) else {
                if last_heard.elapsed() > self.options.silence_timeout {
                    break 'outer StreamEnd::Disconnected(format!(
                        "the firmware answered nothing, not even status queries, for {:.0} s",
                        self.options.silence_timeout.as_secs_f64()
                    ));
                }
                continue;
            };
            last_heard = Instant::now();
            match ev {
                LinkEvent::Line(Response::Ok, raw) => match inflight.pop_front() {
                    Some((i, len)) => {
                        used -= len;
                        bytes_acked += len as u64;
                        acked_end = i + 1;
                        idle_since = None;
                        jrec(&mut journal, &|j| j.acked(i), observer);
                        observer(Notice::Progress {
                            acked: acked_end,
                            total: job.len(),
                            bytes_acked,
                            bytes_total,
                        });
                        all_acked = acked_end == until;
                    }
                    None => observer(Notice::Unexpected(raw)),
                },
                LinkEvent::Line(Response::Error(code), raw) => match inflight.pop_front() {
                    Some((i, _)) => {
                        acked_end = i + 1;
                        jrec(&mut journal, &|j| j.error(i, code), observer);
                        break 'outer StreamEnd::Rejected { index: i, code };
                    }
                    None => observer(Notice::Unexpected(raw)),
                },
                LinkEvent::Line(Response::Alarm(code), _) => break 'outer StreamEnd::Alarm(code),
                LinkEvent::Line(Response::Welcome { .. }, _) => {
                    break 'outer StreamEnd::FirmwareReset
                }
                LinkEvent::Line(Response::Status(st), _) => {
                    let at_rest = st.state == GrblState::Idle;
                    let work = st.work_position(self.last_wco.as_deref());
                    if at_rest && inflight.is_empty() && self.planner_drained(&st) {
                        certain = acked_end;
                        jrec(&mut journal, &|j| j.completed(certain), observer);
                    } else {
                        certain = certain.max(self.certain_bound(job, acked_end, certain));
                        if let Some(w) = work.as_ref().filter(|w| w.len() >= 3) {
                            let k = if self.reports_inches { 25.4 } else { 1.0 };
                            if let Some(seen) = tracker.observe([w[0] * k, w[1] * k, w[2] * k]) {
                                observer(Notice::Running { index: seen.index });
                            }
                            certain = certain.max(tracker.done_before.min(acked_end));
                        }
                    }
                    // Done means at rest: two reports in a row, idle with an empty planner,
                    // at the same place (a reply to an older query cannot pass for it).
                    if all_acked && at_rest && self.planner_drained(&st) {
                        // Machine position: a report always has one, the work offset not.
                        let m = st.machine_position(self.last_wco.as_deref());
                        if let Some(m) = m.or_else(|| st.mpos.clone()) {
                            if rest_seen.as_ref() == Some(&m) {
                                at_rest_confirmed = true;
                                confirmed_rest = work.filter(|w| w.len() >= 3).map(|w| {
                                    let k = if self.reports_inches { 25.4 } else { 1.0 };
                                    [w[0] * k, w[1] * k, w[2] * k]
                                });
                            }
                            rest_seen = Some(m);
                        }
                    } else {
                        rest_seen = None;
                    }
                    if at_rest && !inflight.is_empty() && !holding {
                        let since = *idle_since.get_or_insert_with(Instant::now);
                        // A dwell may legitimately show Idle while its line waits.
                        let dwell = inflight
                            .front()
                            .map(|(i, _)| dwell_seconds(&job.lines[*i].text))
                            .unwrap_or(0.0);
                        if since.elapsed()
                            >= self.options.stall_after + Duration::from_secs_f64(dwell)
                        {
                            self.note_status(st);
                            break 'outer StreamEnd::Stalled;
                        }
                    } else {
                        idle_since = None;
                    }
                    observer(Notice::Status(st.clone()));
                    self.note_status(st);
                    if at_rest_confirmed {
                        break 'outer StreamEnd::Completed;
                    }
                }
                LinkEvent::Line(Response::Message(m), _) => observer(Notice::Message(m)),
                LinkEvent::Line(Response::Unknown(u), _) => observer(Notice::Unexpected(u)),
                LinkEvent::Line(_, raw) => observer(Notice::Message(raw)),
                LinkEvent::Closed(why) => break 'outer StreamEnd::Disconnected(why),
            }
        };
        let sent_end = next;
        let mut report = StreamReport {
            end,
            acked_end,
            sent_end,
            certain,
            work_pos: None,
            resume: None,
            recovery_error: None,
            bytes_sent,
            elapsed: start.elapsed(),
            max_in_flight,
            sender_stalls,
        };
        match report.end.clone() {
            StreamEnd::Completed => {
                let rest = match confirmed_rest {
                    Some(p) => Ok(p),
                    None => self.wait_at_rest(),
                };
                if let Err(e) = &rest {
                    report.recovery_error = Some(e.to_string());
                }
                if let Ok(pos) = rest {
                    report.work_pos = Some(pos);
                    report.certain = until;
                    jrec(&mut journal, &|j| j.completed(until), observer);
                    let expected = resume::replay(job, until).work_pos();
                    // Only the axes the program has named so far have a known place.
                    let named = resume::axes_named(job, until);
                    if (0..3).any(|a| {
                        named[a] && (expected[a] - pos[a]).abs() > resume::POSITION_TOLERANCE
                    }) {
                        report.end = StreamEnd::PositionMismatch {
                            expected,
                            actual: pos,
                        };
                    }
                }
            }
            StreamEnd::Rejected { .. } | StreamEnd::Stopped | StreamEnd::Stalled => {
                let _ = self.link.send_realtime(Realtime::FeedHold);
                match self.wait_at_rest() {
                    Ok(p) => {
                        report.work_pos = Some(p);
                        tracker.observe(p);
                        report.certain = report.certain.max(tracker.done_before.min(acked_end));
                    }
                    Err(e) => report.recovery_error = Some(e.to_string()),
                }
                // Queued blocks are flushed only once the reset is answered: without that,
                // a resume would run behind whatever the firmware still holds.
                if let Err(e) = self.reset() {
                    report.work_pos = None;
                    report.recovery_error = Some(format!("reset after the stop: {e}"));
                }
            }
            StreamEnd::Alarm(_) | StreamEnd::FirmwareReset => {
                // Let the banner/alarm messages arrive, then read where the machine is.
                match self.wait_at_rest() {
                    Ok(p) => report.work_pos = Some(p),
                    Err(e) => report.recovery_error = Some(e.to_string()),
                }
            }
            StreamEnd::Disconnected(_) | StreamEnd::PositionMismatch { .. } => {}
        }
        if let Some(pos) = report.work_pos {
            if report.end != StreamEnd::Completed {
                let mut at =
                    resume::locate(job, report.certain, report.sent_end, report.acked_end, pos);
                if let StreamEnd::Rejected { index, .. } = report.end {
                    at = after_rejection(job, index, at);
                }
                report.resume = Some(at);
            }
        }
        // What the position told: `--resume` starts its search for the stop point there.
        if report.certain > from && report.end != StreamEnd::Completed {
            let certain = report.certain;
            jrec(&mut journal, &|j| j.completed(certain), observer);
        }
        let note = format!("{:?}", report.end);
        jrec(&mut journal, &|j| j.end(&note), observer);
        report.elapsed = start.elapsed();
        report
    }

    /// Lines before the returned index have completed: at most `planner_blocks` motion
    /// lines (each at least one block) can still be queued behind the last `ok`, plus the
    /// tails of two blocks grblHAL already took out of its planner into its step segments.
    fn certain_bound(&self, job: &StreamProgram, acked_end: usize, floor: usize) -> usize {
        let mut motion = 0;
        let mut i = acked_end;
        while i > floor {
            i -= 1;
            let t = &job.lines[i].text;
            if t.contains(['X', 'Y', 'Z']) || t.starts_with("G4") {
                motion += 1;
                if motion > self.planner_blocks + 2 {
                    return i;
                }
            }
        }
        floor
    }

    /// After a stream ended in any way (or after reconnecting): wait until the machine
    /// rests, read its position, reset to flush half-received lines and queued blocks,
    /// unlock an alarm if allowed, and find the line to resume from. `certain`, `sent_end`
    /// and `acked_end` come from the [`StreamReport`] or, after a crash, the journal.
    pub fn recover(
        &mut self,
        job: &StreamProgram,
        certain: usize,
        sent_end: usize,
        acked_end: usize,
        unlock_alarm: bool,
    ) -> Result<Located, String> {
        let pos = self.wait_at_rest().map_err(|e| e.to_string())?;
        self.reset().map_err(|e| e.to_string())?;
        let st = self.status().map_err(|e| e.to_string())?;
        if self.options.mode.is_none() && self.mode == Mode::SendResponse {
            // Connected while the machine was busy: size the window now that it rests.
            self.learn_firmware();
        }
        if st.state == GrblState::Alarm {
            if !unlock_alarm {
                return Err("the machine is in alarm: check it, home it ($H) or unlock it ($X), then resume".into());
            }
            let reply = self.command("$X").map_err(|e| e.to_string())?;
            if let Some(code) = reply.error {
                return Err(format!(
                    "unlock ($X) refused: {}",
                    messages::describe_error(code)
                ));
            }
        }
        Ok(resume::locate(job, certain, sent_end, acked_end, pos))
    }

    /// [`Sender::recover`] after a stream that ended on a rejected line.
    pub fn recover_rejected(
        &mut self,
        job: &StreamProgram,
        report: &StreamReport,
        unlock_alarm: bool,
    ) -> Result<Located, String> {
        let at = self.recover(
            job,
            report.certain,
            report.sent_end,
            report.acked_end,
            unlock_alarm,
        )?;
        Ok(match report.end {
            StreamEnd::Rejected { index, .. } => after_rejection(job, index, at),
            _ => at,
        })
    }

    /// Runs the resume preamble (modal state, spindle, safe approach) line by line.
    pub fn run_preamble(
        &mut self,
        job: &StreamProgram,
        index: usize,
        opts: &resume::ResumeOptions,
    ) -> Result<(), String> {
        self.run_preamble_at(job, index, None, opts)
    }

    /// [`Sender::run_preamble`] approaching `entry`, the point on line `index` where the
    /// machine stopped ([`Located::entry`]), so the line is finished from there.
    pub fn run_preamble_at(
        &mut self,
        job: &StreamProgram,
        index: usize,
        entry: Option<[f64; 3]>,
        opts: &resume::ResumeOptions,
    ) -> Result<(), String> {
        let lines = resume::preamble_at(job, index, entry, opts)?;
        for l in lines {
            let reply = self.command(&l).map_err(|e| e.to_string())?;
            if let Some(code) = reply.error {
                return Err(format!(
                    "resume preamble line `{l}` rejected: {}",
                    messages::describe_error(code)
                ));
            }
        }
        Ok(())
    }
}

/// Seconds of a `G4 P…` line (0 for any other line).
fn dwell_seconds(text: &str) -> f64 {
    let Ok(words) = crate::gline::words(text) else {
        return 0.0;
    };
    if !words.iter().any(|(l, v)| *l == 'G' && *v == 4.0) {
        return 0.0;
    }
    words
        .iter()
        .find(|(l, _)| *l == 'P')
        .map(|(_, p)| p.max(0.0).min(1e6))
        .unwrap_or(0.0)
}

/// The answer to one command.
#[derive(Clone, Debug, PartialEq)]
pub struct Reply {
    /// Lines before the `ok`/`error` (settings, `[GC:…]`, messages).
    pub lines: Vec<String>,
    /// The error code instead of `ok`, if any.
    pub error: Option<u8>,
}

#[cfg(test)]
mod tests {
    use super::dwell_seconds;

    #[test]
    fn dwell_allowance() {
        assert_eq!(dwell_seconds("G4P2.5"), 2.5);
        assert_eq!(dwell_seconds("G1X1F100"), 0.0);
        assert_eq!(dwell_seconds("G4"), 0.0);
        assert_eq!(dwell_seconds("#garbage"), 0.0);
    }
}
