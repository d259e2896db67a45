//! [`MarlinLink`]: a connection to Marlin 2.x (and Makelangelo's Marlin) that streams a
//! program one numbered, checksummed line at a time.
//!
//! Marlin's reader (`GCodeQueue::get_serial_commands`) accepts line `N` only when it is
//! the last accepted number + 1 and its checksum holds; otherwise it prints `Error:…`,
//! `Resend: <last+1>` and `ok`, and empties its input. So a line is never executed twice,
//! and one line in flight is enough to know which line an `ok` belongs to: every received
//! line, accepted or refused, is answered by exactly one `ok`. A line (or its `ok`) lost on
//! the wire shows as silence: after `reply_timeout` without any reply — `busy:` keep-alives
//! count as replies, so a long `G28` or an `M0` never times out — the line is sent again;
//! if it had arrived, Marlin refuses the copy by its number and asks for the next one.

use super::frame::{frame, Reply};
use crate::job::StreamProgram;
use crate::journal::Journal;
use crate::link::{Link, LinkEvent};
use crate::transport::Endpoint;
use std::collections::VecDeque;
use std::io;
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

/// How the link waits.
#[derive(Clone, Debug)]
pub struct MarlinOptions {
    /// No reply at all for this long means the line or its `ok` was lost: send it again.
    /// Marlin's keep-alive (`M113`, 2 s by default) must be shorter.
    pub reply_timeout: Duration,
    /// How long to wait for `start` after opening (a board that resets on connect boots).
    pub banner_wait: Duration,
    /// Give up after this many silent timeouts in a row.
    pub max_timeouts: u32,
}

impl Default for MarlinOptions {
    fn default() -> Self {
        MarlinOptions {
            reply_timeout: Duration::from_secs(5),
            banner_wait: Duration::from_millis(2500),
            max_timeouts: 5,
        }
    }
}

/// Operator requests during a stream.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MarlinControl {
    /// Send no new line (the planner runs dry: the pen stops within Marlin's 16 blocks).
    Hold,
    /// Leave a hold, or an `M0`/`M1` pause (sends `M108`).
    Resume,
    /// `M410` quickstop: the planned moves are dropped at once; the stream ends.
    Stop,
    /// `M112` emergency stop: Marlin halts and must be reset.
    Kill,
}

/// What the link tells its observer while streaming.
#[derive(Clone, Debug, PartialEq)]
pub enum MarlinNotice {
    /// Program lines `..acked` are acknowledged, of `total`.
    Progress {
        /// One past the last acknowledged line.
        acked: usize,
        /// Lines in the program.
        total: usize,
    },
    /// Marlin waits for the user at an `M0`/`M1` (file line, its text): resume sends `M108`.
    Pause {
        /// File line of the `M0`/`M1`.
        file_line: usize,
        /// The line, with its message.
        text: String,
    },
    /// A line went again: Marlin asked for it (`Resend`) or nothing came back in time.
    Resent {
        /// The line number on the wire.
        n: u32,
        /// Why.
        why: String,
    },
    /// A note from the firmware (`echo:`), or from the link.
    Message(String),
}

/// How a stream ended.
#[derive(Clone, Debug, PartialEq)]
pub enum MarlinEnd {
    /// Every line acknowledged and the moves finished (`M400`).
    Completed,
    /// Stopped by the operator (`M410`).
    Stopped,
    /// `M112` sent, or Marlin halted by itself (`Error:Printer halted`).
    Killed(String),
    /// The connection failed or Marlin restarted.
    LinkLost(String),
    /// Marlin stopped answering, or asked for a line this stream never sent.
    Failed(String),
}

/// What a stream did.
#[derive(Clone, Debug, PartialEq)]
pub struct MarlinReport {
    /// How it ended.
    pub end: MarlinEnd,
    /// One past the last acknowledged program line.
    pub acked: usize,
    /// One past the last program line written to the wire.
    pub sent_end: usize,
    /// Lines sent again because Marlin asked (`Resend`).
    pub resends: u32,
    /// Lines sent again because nothing came back.
    pub timeouts: u32,
    /// Numbered lines written, copies included.
    pub lines_written: u64,
    /// Where Marlin said it was at the end (`M114`), mm.
    pub position: Option<[f64; 3]>,
}

/// A line awaiting its `ok`.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pending {
    /// Program line `index`, sent as number `n`.
    Line { n: u32, index: usize },
    /// An unnumbered command (`M108`, `M410`, `M400`, `M114`).
    Aux,
}

/// An open connection to Marlin, its line numbering reset.
pub struct MarlinLink {
    link: Link,
    /// The firmware's name (`M115`'s `FIRMWARE_NAME`, else the banner).
    pub firmware: String,
    /// How it waits.
    pub options: MarlinOptions,
    /// The number the next numbered line gets.
    next_n: u32,
}

impl MarlinLink {
    /// Opens `endpoint`, waits for Marlin's `start`, resets the line number (`M110 N0`) and
    /// asks its name (`M115`).
    pub fn connect(endpoint: &Endpoint, options: MarlinOptions) -> io::Result<MarlinLink> {
        let link = Link::open(endpoint)?;
        MarlinLink::over(link, options)
            .map_err(|e| io::Error::new(io::ErrorKind::TimedOut, format!("{endpoint}: {e}")))
    }

    /// The handshake of [`MarlinLink::connect`] on an open link.
    pub fn over(link: Link, options: MarlinOptions) -> Result<MarlinLink, String> {
        let mut m = MarlinLink {
            link,
            firmware: String::new(),
            options,
            next_n: 1,
        };
        // The banner: `start`, then `echo:Marlin 2.1.2 …`; a board that does not reset on
        // connect says nothing, which is fine too.
        let until = Instant::now() + m.options.banner_wait;
        while Instant::now() < until {
            match m.link.recv(Duration::from_millis(20)) {
                Some(LinkEvent::Line(_, text)) => {
                    if let Some(name) = text.strip_prefix("echo:").filter(|t| t.contains("Marlin"))
                    {
                        m.firmware = name.trim().to_string();
                        break;
                    }
                }
                Some(LinkEvent::Closed(why)) => return Err(why),
                None => {}
            }
        }
        let mut last = String::new();
        for _ in 0..3 {
            match m.command("M110 N0") {
                Ok(_) => {
                    last.clear();
                    break;
                }
                Err(e) => last = e,
            }
        }
        if !last.is_empty() {
            return Err(format!("Marlin did not answer M110 N0 ({last})"));
        }
        m.next_n = 1;
        if let Ok(lines) = m.command("M115") {
            if let Some(name) = lines.iter().find_map(|l| firmware_name(l)) {
                m.firmware = name;
            }
        }
        if m.firmware.is_empty() {
            m.firmware = "Marlin".into();
        }
        Ok(m)
    }

    /// Sends one unnumbered command and waits for its `ok`; returns the lines before it.
    /// Keep-alives extend the wait; an `Error:` is the error.
    pub fn command(&mut self, cmd: &str) -> Result<Vec<String>, String> {
        self.link
            .send_line(cmd)
            .map_err(|e| format!("cannot write {cmd}: {e}"))?;
        let mut lines = Vec::new();
        let mut heard = Instant::now();
        loop {
            match self.link.recv(Duration::from_millis(20)) {
                Some(LinkEvent::Line(_, text)) => {
                    heard = Instant::now();
                    match Reply::parse(&text) {
                        Reply::Ok => return Ok(lines),
                        Reply::Error(e) => return Err(format!("{cmd}: Marlin says {e}")),
                        Reply::Busy(_) => {}
                        _ => lines.push(text),
                    }
                }
                Some(LinkEvent::Closed(why)) => return Err(why),
                None if heard.elapsed() > self.options.reply_timeout => {
                    return Err(format!(
                        "no ok to {cmd} in {:.1} s",
                        self.options.reply_timeout.as_secs_f64()
                    ))
                }
                None => {}
            }
        }
    }

    /// Where Marlin is (`M114`), mm.
    pub fn position(&mut self) -> Result<[f64; 3], String> {
        let lines = self.command("M114")?;
        lines
            .iter()
            .find_map(|l| match Reply::parse(l) {
                Reply::Position(p) => Some(p),
                _ => None,
            })
            .ok_or_else(|| format!("M114 gave no position: {lines:?}"))
    }

    /// Streams `job` from line `from`: every line numbered and checksummed, one in flight,
    /// refused lines sent again, `M0`/`M1` waiting for [`MarlinControl::Resume`]. The
    /// journal records every line sent and acknowledged.
    pub fn stream(
        &mut self,
        job: &StreamProgram,
        from: usize,
        mut journal: Option<&mut Journal>,
        control: Option<&Receiver<MarlinControl>>,
        observer: &mut dyn FnMut(MarlinNotice),
    ) -> MarlinReport {
        let mut st = Stream {
            next: from.min(job.len()),
            pending: VecDeque::new(),
            numbered: Vec::new(),
            resend_to: None,
            heard: Instant::now(),
            silent: 0,
            held: false,
            paused: false,
            stopping: false,
            finishing: false,
            asked_position: false,
            report: MarlinReport {
                end: MarlinEnd::Completed,
                acked: from,
                sent_end: from,
                resends: 0,
                timeouts: 0,
                lines_written: 0,
                position: None,
            },
        };
        let end = loop {
            if let Err(end) = self.step(job, &mut st, &mut journal, control, observer) {
                break end;
            }
        };
        st.report.end = end;
        if let Some(j) = journal {
            if st.report.end == MarlinEnd::Completed {
                let _ = j.completed(job.len());
            }
            let _ = j.end(&format!("{:?}", st.report.end));
        }
        st.report
    }

    /// One turn of the stream: operator requests, a line out, a reply in. `Some` when over.
    fn step(
        &mut self,
        job: &StreamProgram,
        st: &mut Stream,
        journal: &mut Option<&mut Journal>,
        control: Option<&Receiver<MarlinControl>>,
        observer: &mut dyn FnMut(MarlinNotice),
    ) -> Result<(), MarlinEnd> {
        while let Some(c) = control.and_then(|rx| rx.try_recv().ok()) {
            match c {
                MarlinControl::Hold => st.held = true,
                MarlinControl::Resume if st.paused => self.aux(st, "M108")?,
                MarlinControl::Resume => st.held = false,
                MarlinControl::Stop if !st.stopping => {
                    st.stopping = true;
                    // An M0 blocks Marlin's queue: release it so the quickstop's ok comes.
                    if st.paused {
                        self.aux(st, "M108")?;
                    }
                    self.aux(st, "M410")?;
                }
                MarlinControl::Stop => {}
                MarlinControl::Kill => {
                    let _ = self.link.send_line("M112");
                    return Err(MarlinEnd::Killed("M112 sent: reset the board".into()));
                }
            }
        }
        let line_in_flight = st.pending.iter().any(|p| matches!(p, Pending::Line { .. }));
        if !line_in_flight && !st.held && !st.stopping && st.next < job.len() {
            let index = st.next;
            let n = self.next_n;
            self.write_line(n, &job.lines[index].text, st)?;
            st.pending.push_back(Pending::Line { n, index });
            st.numbered.push((n, index));
            self.next_n += 1;
            st.next += 1;
            st.report.sent_end = st.report.sent_end.max(st.next);
            if let Some(j) = journal.as_deref_mut() {
                let _ = j.sent(index);
            }
        }
        // Everything acknowledged: wait for the moves (M400), then ask where Marlin is.
        if st.pending.is_empty() && (st.stopping || st.next >= job.len()) {
            if !st.stopping && !st.finishing {
                st.finishing = true;
                self.aux(st, "M400")?;
            } else if !st.asked_position {
                st.asked_position = true;
                self.aux(st, "M114")?;
            } else {
                return Err(if st.stopping {
                    MarlinEnd::Stopped
                } else {
                    MarlinEnd::Completed
                });
            }
        }
        let event = self.link.recv(Duration::from_millis(20));
        let Some(event) = event else {
            if st.heard.elapsed() <= self.options.reply_timeout || st.pending.is_empty() {
                return Ok(());
            }
            st.heard = Instant::now();
            st.silent += 1;
            if st.silent > self.options.max_timeouts {
                return Err(MarlinEnd::Failed(format!(
                    "Marlin answered nothing for {} timeouts of {:.1} s",
                    st.silent - 1,
                    self.options.reply_timeout.as_secs_f64()
                )));
            }
            match st.pending.front().copied() {
                // The line or its ok was lost: a copy is refused by number if it arrived.
                Some(Pending::Line { n, index }) => {
                    st.report.timeouts += 1;
                    observer(MarlinNotice::Resent {
                        n,
                        why: "no reply in time".into(),
                    });
                    self.write_line(n, &job.lines[index].text, st)?;
                }
                _ => {
                    st.pending.pop_front();
                }
            }
            return Ok(());
        };
        let text = match event {
            LinkEvent::Line(_, text) => text,
            LinkEvent::Closed(why) => return Err(MarlinEnd::LinkLost(why)),
        };
        st.heard = Instant::now();
        st.silent = 0;
        match Reply::parse(&text) {
            Reply::Ok => match st.pending.pop_front() {
                Some(Pending::Line { index, .. }) => match st.resend_to.take() {
                    Some(r) => return self.rewind(st, r, observer),
                    None => {
                        st.paused = false;
                        st.report.acked = st.report.acked.max(index + 1);
                        if let Some(j) = journal.as_deref_mut() {
                            let _ = j.acked(index);
                        }
                        observer(MarlinNotice::Progress {
                            acked: st.report.acked,
                            total: job.len(),
                        });
                    }
                },
                Some(Pending::Aux) | None => {}
            },
            Reply::Resend(r) => st.resend_to = Some(r),
            Reply::Busy(what) => {
                if what.contains("paused for user") && !st.paused {
                    st.paused = true;
                    if let Some(Pending::Line { index, .. }) = st.pending.front() {
                        let l = &job.lines[*index];
                        observer(MarlinNotice::Pause {
                            file_line: l.file_line,
                            text: l.text.clone(),
                        });
                    }
                }
            }
            Reply::Error(e) if e.contains("halted") || e.contains("kill") => {
                return Err(MarlinEnd::Killed(format!("Marlin: {e}")))
            }
            Reply::Error(e) => observer(MarlinNotice::Message(format!("Marlin: Error:{e}"))),
            Reply::Start => {
                return Err(MarlinEnd::LinkLost(
                    "Marlin restarted (start): its queue and position are gone".into(),
                ))
            }
            Reply::Position(p) => st.report.position = Some(p),
            Reply::Other(t) => observer(MarlinNotice::Message(t)),
        }
        Ok(())
    }

    /// Marlin refused the line in flight and asks for line `r`: the lines from `r` go again
    /// under the same numbers.
    fn rewind(
        &mut self,
        st: &mut Stream,
        r: u32,
        observer: &mut dyn FnMut(MarlinNotice),
    ) -> Result<(), MarlinEnd> {
        if r == self.next_n {
            // It wants the line after the last sent: the one in flight had arrived.
            return Ok(());
        }
        let Some(k) = st.numbered.iter().position(|(n, _)| *n == r) else {
            return Err(MarlinEnd::Failed(format!(
                "Marlin asked for line {r}, which this stream never sent (next is {})",
                self.next_n
            )));
        };
        st.next = st.numbered[k].1;
        st.numbered.truncate(k);
        self.next_n = r;
        st.report.resends += 1;
        observer(MarlinNotice::Resent {
            n: r,
            why: "Marlin asked (Resend)".into(),
        });
        Ok(())
    }

    fn write_line(&mut self, n: u32, cmd: &str, st: &mut Stream) -> Result<(), MarlinEnd> {
        st.report.lines_written += 1;
        self.link
            .send_line(&frame(n, cmd))
            .map_err(|e| MarlinEnd::LinkLost(format!("write failed: {e}")))
    }

    /// Writes an unnumbered command whose `ok` is awaited in turn.
    fn aux(&mut self, st: &mut Stream, cmd: &str) -> Result<(), MarlinEnd> {
        st.pending.push_back(Pending::Aux);
        self.link
            .send_line(cmd)
            .map_err(|e| MarlinEnd::LinkLost(format!("cannot write {cmd}: {e}")))
    }
}

/// The stream's working state.
struct Stream {
    /// The program line to send next.
    next: usize,
    pending: VecDeque<Pending>,
    /// (number, program line) of each numbered line sent, for `Resend`.
    numbered: Vec<(u32, usize)>,
    /// Marlin asked for this line; the `ok` that follows belongs to the refused line.
    resend_to: Option<u32>,
    heard: Instant,
    silent: u32,
    held: bool,
    paused: bool,
    stopping: bool,
    finishing: bool,
    asked_position: bool,
    report: MarlinReport,
}

/// `FIRMWARE_NAME:Marlin 2.1.2 (…) SOURCE_CODE_URL:…`: the name up to the next key.
fn firmware_name(line: &str) -> Option<String> {
    let rest = line.split("FIRMWARE_NAME:").nth(1)?;
    let end = rest
        .find(" SOURCE_CODE_URL:")
        .or_else(|| rest.find(" PROTOCOL_VERSION:"));
    Some(rest[..end.unwrap_or(rest.len())].trim().to_string())
}
