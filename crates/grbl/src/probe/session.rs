//! A routine's exchange with the firmware: the modal state it gives back, each line's
//! reply read for alarms and errors, `[PRB:…]` and `$#` parsed, a surface found by a
//! search and a slow touch.

use super::{Approach, ProbeError, ProbeLink};
use crate::messages;
use crate::response::Response;
use oficina_machine::RawReply;
use std::time::Duration;

/// A number for a G-code word: 4 decimals (0.1 µm), no trailing zeros.
pub(super) fn num(v: f64) -> String {
    let s = format!("{v:.4}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".into()
    } else {
        s.into()
    }
}

/// A routine's lines over one link: the modal state to restore, and the reading of each
/// reply.
pub(super) struct Session<'a, L: ?Sized> {
    link: &'a mut L,
    /// Units and distance mode before the routine, e.g. `G21 G90`.
    restore: String,
}

/// A reply to an ordinary line comes at once; a move's after it is queued.
const PATIENCE: Duration = Duration::from_secs(30);

impl<'a, L: ProbeLink + ?Sized> Session<'a, L> {
    /// Reads the modal state (`$G`) and switches to mm and incremental moves.
    pub(super) fn begin(link: &'a mut L) -> Result<Self, ProbeError> {
        let mut s = Session {
            link,
            restore: String::new(),
        };
        let reply = s.send("$G")?;
        let modes = reply
            .lines
            .iter()
            .find_map(|l| match Response::parse(l) {
                Response::ParserState(p) => Some(p),
                _ => None,
            })
            .ok_or_else(|| {
                ProbeError::Firmware(format!(
                    "`$G` gave no parser state ([GC:…]) but {:?}",
                    reply.lines
                ))
            })?;
        let word = |a: &str, b: &str| {
            if modes.split_whitespace().any(|w| w == b) {
                b.to_string()
            } else {
                a.to_string()
            }
        };
        s.restore = format!("{} {}", word("G21", "G20"), word("G90", "G91"));
        s.send("G21 G91")?;
        Ok(s)
    }

    /// Runs a routine's lines; when they fail without an alarm (the firmware still takes
    /// lines), the units and distance mode are given back before the error.
    pub(super) fn run<T>(
        mut self,
        lines: impl FnOnce(&mut Self) -> Result<T, ProbeError>,
    ) -> Result<T, ProbeError> {
        let result = lines(&mut self);
        if let Err(ProbeError::Input(_) | ProbeError::Firmware(_)) = &result {
            let restore = self.restore.clone();
            let _ = self.link.line(&restore, PATIENCE);
        }
        result
    }

    /// Sends one line; an alarm or an error in its reply ends the routine, explained.
    pub(super) fn send(&mut self, line: &str) -> Result<RawReply, ProbeError> {
        self.send_waiting(line, PATIENCE)
    }

    fn send_waiting(&mut self, line: &str, patience: Duration) -> Result<RawReply, ProbeError> {
        let reply = self
            .link
            .line(line, patience)
            .map_err(|e| ProbeError::Firmware(format!("`{line}`: {e}")))?;
        for l in &reply.lines {
            if let Response::Alarm(code) = Response::parse(l) {
                return Err(alarm(code, line));
            }
        }
        if let Some(e) = &reply.error {
            return Err(ProbeError::Firmware(format!(
                "the firmware refused `{line}`: {e}"
            )));
        }
        Ok(reply)
    }

    /// One probing line that may travel `distance` at `feed`: where it stopped, and
    /// whether the probe touched there (its `[PRB:x,y,z:ok]`).
    pub(super) fn probe(
        &mut self,
        line: &str,
        distance: f64,
        feed: f64,
    ) -> Result<([f64; 3], bool), ProbeError> {
        let patience = Duration::from_secs_f64(distance / feed * 60.0 * 1.5 + 10.0);
        let reply = self.send_waiting(line, patience)?;
        reply
            .lines
            .iter()
            .find_map(|l| parse_prb(l))
            .ok_or_else(|| {
                ProbeError::Firmware(format!(
                    "`{line}` was answered without a probe report ([PRB:…]): {:?}",
                    reply.lines
                ))
            })
    }

    /// A surface along `axis` in `direction`: search, back off, touch slowly, back off.
    /// Returns the slow touch's machine position; the tool ends `retract` away from it.
    pub(super) fn touch(
        &mut self,
        axis: char,
        direction: f64,
        a: &Approach,
    ) -> Result<[f64; 3], ProbeError> {
        let sign = if direction < 0.0 { "-" } else { "" };
        let back = if direction < 0.0 { "" } else { "-" };
        let search = format!("G91 G38.2 {axis}{sign}{} F{}", num(a.travel), num(a.feed));
        let (_, touched) = self.probe(&search, a.travel, a.feed)?;
        if !touched {
            return Err(ProbeError::NoContact(format!(
                "`{search}` ended without contact"
            )));
        }
        self.send(&format!("G0 {axis}{back}{}", num(a.retract)))?;
        let slow = 2.0 * a.retract;
        let line = format!("G38.2 {axis}{sign}{} F{}", num(slow), num(a.slow_feed));
        let (at, touched) = self.probe(&line, slow, a.slow_feed)?;
        if !touched {
            return Err(ProbeError::NoContact(format!(
                "`{line}` ended without contact"
            )));
        }
        Ok(at)
    }

    /// Restores the modal state, waits for the machine to stop (`G4 P0` answers once the
    /// planner is empty) and reads back the offset of coordinate system `wcs`.
    pub(super) fn finish(&mut self, wcs: u8) -> Result<[f64; 3], ProbeError> {
        let restore = self.restore.clone();
        self.send(&restore)?;
        self.send("G4 P0")?;
        let tag = format!("G{}", 53 + wcs);
        let reply = self.send("$#")?;
        reply
            .lines
            .iter()
            .find_map(|l| match Response::parse(l) {
                Response::Feedback { tag: t, value } if t == tag => parse_xyz(&value),
                _ => None,
            })
            .ok_or_else(|| {
                ProbeError::Firmware(format!("`$#` did not report [{tag}:…]: {:?}", reply.lines))
            })
    }
}

/// `[PRB:x,y,z:ok]` → the position and whether it touched.
pub(super) fn parse_prb(line: &str) -> Option<([f64; 3], bool)> {
    match Response::parse(line) {
        Response::Feedback { tag, value } if tag == "PRB" => {
            let (xyz, ok) = value.rsplit_once(':')?;
            Some((parse_xyz(xyz)?, ok.trim() == "1"))
        }
        _ => None,
    }
}

/// `x,y,z[,a…]` → the first three (grblHAL adds its other axes).
fn parse_xyz(s: &str) -> Option<[f64; 3]> {
    let v: Vec<f64> = s
        .split(',')
        .map(|x| x.trim().parse().ok())
        .collect::<Option<_>>()?;
    (v.len() >= 3 && v.iter().all(|x| x.is_finite())).then(|| [v[0], v[1], v[2]])
}

/// An alarm during `line`, in plain words with grbl's own text.
fn alarm(code: u8, line: &str) -> ProbeError {
    let after = "The machine is in alarm: unlock it with $X (the routine had switched to G91 \
                 incremental moves: send G90 before absolute moves), or reset it.";
    let grbl = messages::describe_alarm(code);
    match code {
        4 => ProbeError::AlreadyTriggered(format!(
            "the probe was already closed before `{line}` moved: the tool is touching the plate, the clip is on the plate, or the probe input is shorted. {after} [{grbl}]"
        )),
        5 => ProbeError::NoContact(format!(
            "no contact within the travel of `{line}`: is the plate (or setter) under the tool, is the clip on the tool, is the travel long enough? {after} [{grbl}]"
        )),
        _ => ProbeError::Firmware(format!("alarm during `{line}`: {grbl}. {after}")),
    }
}
